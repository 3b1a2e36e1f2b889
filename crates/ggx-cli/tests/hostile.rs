//! The defects a hostile trial of the release binary found, each reproduced as it was
//! reported (see issue "Hostile input and faults"): these tests failed before the fixes.

mod support;

use std::process::{Command, Output, Stdio};

use support::{GGX, TempDir, Watchdog, ggx, scene};

fn stderr_of(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// `ggx render SCENE -o OUT` at 16x12, 1 spp, plus `extra`.
fn render(scene: &str, out: &std::path::Path, extra: &[&str]) -> Output {
    let mut args = vec!["render", scene, "-o", out.to_str().unwrap(), "--spp", "1", "--width", "16", "--height", "12"];
    args.extend_from_slice(extra);
    ggx(&args)
}

#[test]
fn a_huge_time_budget_is_no_budget_not_a_panic() {
    let dir = TempDir::new("huge-time");
    let out = render(&scene("furnace.toml"), &dir.path().join("t.png"), &["--time", "2e19"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr_of(&out));
    // And a scene's own `time = 1e38`.
    let file = dir.path().join("t.toml");
    let text = std::fs::read_to_string(scene("furnace.toml")).unwrap();
    let with_time = text.replacen("[integrator]", "[integrator]\ntime = 1e38", 1);
    assert_ne!(with_time, text, "furnace.toml has an [integrator] table");
    std::fs::write(&file, with_time).unwrap();
    let out = render(file.to_str().unwrap(), &dir.path().join("u.png"), &[]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr_of(&out));
}

#[test]
fn time_zero_means_no_budget_and_negative_time_says_why() {
    let dir = TempDir::new("time-zero");
    let out = render(&scene("furnace.toml"), &dir.path().join("t.png"), &["--time", "0"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr_of(&out));
    let out = render(&scene("furnace.toml"), &dir.path().join("t.png"), &["--time", "-1"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr_of(&out).contains("must be a finite number of seconds >= 0"), "{}", stderr_of(&out));
}

#[test]
fn an_unwritable_output_fails_before_rendering() {
    let dir = TempDir::new("unwritable");
    let long = dir.path().join(format!("{}.png", "x".repeat(300)));
    for (bad, why) in
        [(std::path::PathBuf::from("/proc/ggx.png"), "cannot create a file in /proc"), (long, "name too long")]
    {
        let out = render(&scene("cornell.toml"), &bad, &[]);
        let err = stderr_of(&out);
        assert_eq!(out.status.code(), Some(1), "{err}");
        assert!(err.contains(why), "{err}");
        assert!(!err.lines().any(|l| l.starts_with("rendering ")), "the render must not start: {err}");
    }
}

#[test]
fn the_scene_is_never_overwritten_by_the_output() {
    let dir = TempDir::new("input-output");
    let input = dir.path().join("x.png");
    let text = std::fs::read_to_string(scene("furnace.toml")).unwrap();
    std::fs::write(&input, &text).unwrap();
    let out = render(input.to_str().unwrap(), &input, &[]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr_of(&out));
    assert!(stderr_of(&out).contains("refusing to overwrite"), "{}", stderr_of(&out));
    assert_eq!(std::fs::read_to_string(&input).unwrap(), text);
}

#[test]
fn seeds_beyond_32_bits_are_refused() {
    let dir = TempDir::new("seed");
    for seed in ["4294967296", "9223372036854775808", "18446744073709551615"] {
        let out = render(&scene("furnace.toml"), &dir.path().join("s.png"), &["--seed", seed]);
        assert_eq!(out.status.code(), Some(2), "seed {seed}: {}", stderr_of(&out));
    }
    let out = render(&scene("furnace.toml"), &dir.path().join("s.png"), &["--seed", "4294967295"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr_of(&out));
}

#[test]
fn exposure_scales_exr_output() {
    let dir = TempDir::new("exposure");
    let (plain, bright) = (dir.path().join("a.exr"), dir.path().join("b.exr"));
    assert!(render(&scene("furnace.toml"), &plain, &[]).status.success());
    let out = render(&scene("furnace.toml"), &bright, &["--exposure", "1"]);
    assert!(out.status.success(), "{}", stderr_of(&out));
    let (_, _, a) = ggx_film::read_exr(&plain).unwrap();
    let (_, _, b) = ggx_film::read_exr(&bright).unwrap();
    assert!(a.iter().any(|p| p.x > 0.0));
    // Scaling by 2 is exact in floating point.
    assert!(a.iter().zip(&b).all(|(a, b)| *a * 2.0 == *b), "EXR not scaled by 2^1");
}

#[cfg(unix)]
#[test]
fn special_files_are_refused_at_once() {
    let dir = TempDir::new("special");
    let fifo = dir.path().join("scene.toml");
    let status = Command::new("mkfifo").arg(&fifo).status().expect("mkfifo runs");
    assert!(status.success());
    for input in ["/dev/zero", fifo.to_str().unwrap()] {
        // Without a writer, opening the FIFO would block forever: the watchdog kills ggx then.
        let child = Command::new(GGX).args(["info", input]).stdout(Stdio::null()).stderr(Stdio::piped()).spawn();
        let child = child.expect("ggx starts");
        let watchdog = Watchdog::new(child.id(), 60);
        let out = child.wait_with_output().unwrap();
        drop(watchdog);
        assert_eq!(out.status.code(), Some(1), "{input}: {}", stderr_of(&out));
        assert!(stderr_of(&out).contains("not a regular file"), "{input}: {}", stderr_of(&out));
    }
}

#[test]
fn memory_limit_is_checked_and_named() {
    let dir = TempDir::new("memory");
    let path = dir.path().join("m.png");
    let out = ggx(&[
        "render",
        &scene("cornell.toml"),
        "-o",
        path.to_str().unwrap(),
        "--width",
        "4096",
        "--max-memory",
        "64M",
    ]);
    let err = stderr_of(&out);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("over the limit of 64.0 MiB") && err.contains("--max-memory"), "{err}");
    let out = ggx(&["info", &scene("cornell.toml")]);
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(text.lines().any(|l| l.starts_with("memory:") && l.contains("MiB")), "{text}");
    assert!(text.lines().any(|l| l.starts_with("limits:") && l.contains("--max-memory")), "{text}");
}

/// Runs `ggx render --backend BACKEND` on the furnace without `XDG_RUNTIME_DIR`; `None` (a
/// loud skip) where no adapter exists outside CI.
fn render_on(backend: &str, dir: &TempDir) -> Option<Output> {
    let out = Command::new(GGX)
        .args(["render", &scene("furnace.toml"), "-o", dir.path().join("w.png").to_str().unwrap()])
        .args(["--spp", "1", "--width", "16", "--height", "12", "--backend", backend])
        .env_remove("XDG_RUNTIME_DIR")
        .output()
        .expect("ggx runs");
    if stderr_of(&out).contains("no GPU adapter") && std::env::var("CI").as_deref() != Ok("true") {
        eprintln!("\n*** SKIPPING the --backend {backend} test: no adapter (set CI=true to make this a failure)\n");
        return None;
    }
    Some(out)
}

#[test]
fn mesa_runtime_dir_noise_never_reaches_the_user() {
    let dir = TempDir::new("xdg");
    let Some(out) = render_on("wgpu", &dir) else { return };
    let err = stderr_of(&out);
    assert_eq!(out.status.code(), Some(0), "{err}");
    assert!(!err.contains("XDG_RUNTIME_DIR"), "{err}");
}

#[test]
fn auto_prefers_the_cpu_to_a_software_adapter() {
    let dir = TempDir::new("auto");
    let Some(out) = render_on("auto", &dir) else { return };
    let err = stderr_of(&out);
    assert_eq!(out.status.code(), Some(0), "{err}");
    // A software adapter (device type Cpu, as CI's lavapipe): auto must render on the CPU.
    if err.contains(", Cpu, ") {
        assert!(err.contains("is a software renderer: rendering on the CPU backend"), "{err}");
        assert!(err.contains("on the CPU, "), "{err}");
    }
}
