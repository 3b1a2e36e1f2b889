//! End-to-end tests of the `ggx` binary: info, rendering to PNG and EXR, time budgets,
//! errors and their exit codes.

mod support;

use std::time::{Duration, Instant};

use support::{TempDir, ggx, scene, stdout_of};

#[test]
fn info_prints_counts_and_build_times() {
    let out = ggx(&["info", &scene("cornell.toml")]);
    let text = stdout_of(&out);
    assert!(out.status.success(), "{text}\n{}", String::from_utf8_lossy(&out.stderr));
    let triangles = text.lines().find_map(|l| l.strip_prefix("triangles:")).expect("a triangles line");
    let count: usize = triangles.split_whitespace().next().and_then(|n| n.parse().ok()).expect("a triangle count");
    assert!(count > 12, "{text}");
    for key in ["materials:", "lights:", "features:", "integrator:", "camera:", "bvh build:", "silver-smooth"] {
        assert!(text.contains(key), "missing {key}: {text}");
    }
    assert!(text.contains("wide") && text.contains("cwbvh") && text.contains("bvh2"), "{text}");
}

/// `info` says how light samples take the environment: a map from its texels above the
/// mean, a constant one not at all (MIS compensation), a map as it is without MIS.
#[test]
fn info_says_how_the_environment_is_sampled() {
    let environment_line = |args: &[&str]| {
        let out = ggx(args);
        let text = stdout_of(&out);
        assert!(out.status.success(), "{text}");
        text.lines().find_map(|l| l.strip_prefix("environment:")).expect("an environment line").trim().to_owned()
    };
    let map = environment_line(&["info", &scene("bunny.toml")]);
    assert!(map.starts_with("map ") && map.contains("% of texels above its mean (MIS compensation)"), "{map}");
    let constant = environment_line(&["info", &scene("furnace.toml")]);
    assert!(constant.ends_with("left to BSDF sampling (MIS compensation)"), "{constant}");
    // anisotropic.toml reads no file, so a copy elsewhere still loads.
    let dir = TempDir::new("info-env");
    let nee = dir.path().join("nee.toml");
    let text = std::fs::read_to_string(scene("anisotropic.toml")).unwrap();
    std::fs::write(&nee, text.replace("[integrator]", "[integrator]\nlight_strategy = \"nee\"")).unwrap();
    let plain = environment_line(&["info", nee.to_str().unwrap()]);
    assert!(plain.starts_with("map ") && !plain.contains("MIS"), "{plain}");
}

#[test]
fn renders_png_and_exr_at_the_requested_size() {
    let dir = TempDir::new("render");
    for name in ["x.png", "x.exr"] {
        let path = dir.path().join(name);
        let out = ggx(&[
            "render",
            &scene("furnace.toml"),
            "-o",
            path.to_str().unwrap(),
            "--spp",
            "2",
            "--width",
            "32",
            "--height",
            "24",
        ]);
        let text = stdout_of(&out);
        assert_eq!(out.status.code(), Some(0), "{text}\n{}", String::from_utf8_lossy(&out.stderr));
        assert!(text.contains("2 spp") && text.contains("32x24") && text.contains(name), "{text}");
    }
    let png = image::open(dir.path().join("x.png")).unwrap();
    assert_eq!((png.width(), png.height()), (32, 24));
    let (w, h, pixels) = ggx_film::read_exr(&dir.path().join("x.exr")).unwrap();
    assert_eq!((w, h, pixels.len()), (32, 24, 32 * 24));
    // A white furnace: every pixel sees radiance about 1 (background or spheres).
    let mean = pixels.iter().map(|p| p.x + p.y + p.z).sum::<f32>() / (3.0 * pixels.len() as f32);
    assert!((0.5..1.5).contains(&mean), "mean radiance {mean}");
}

/// `--energy-compensation off` darkens the furnace's rough GGX spheres; `on` (the scene's
/// default) keeps every pixel near the environment's 1.
#[test]
fn energy_compensation_switch_changes_the_furnace() {
    let dir = TempDir::new("compensation");
    let mean = |switch: &str| {
        let path = dir.path().join(format!("{switch}.exr"));
        let args = ["--spp", "16", "--width", "96", "--energy-compensation", switch];
        let out = ggx(&[&["render", &scene("furnace.toml"), "-o", path.to_str().unwrap()][..], &args[..]].concat());
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let (_, _, pixels) = ggx_film::read_exr(&path).unwrap();
        pixels.iter().map(|p| p.x).sum::<f32>() / pixels.len() as f32
    };
    let (on, off) = (mean("on"), mean("off"));
    assert!((on - 1.0).abs() < 0.02, "compensated furnace mean {on}");
    assert!(off < on - 0.05, "single scattering {off} vs compensated {on}");
}

#[test]
fn lone_width_keeps_the_aspect_ratio() {
    let dir = TempDir::new("aspect");
    let path = dir.path().join("a.png");
    let out = ggx(&["render", &scene("furnace.toml"), "-o", path.to_str().unwrap(), "--spp", "1", "--width", "60"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let png = image::open(&path).unwrap();
    // furnace.toml is 480x112.
    assert_eq!((png.width(), png.height()), (60, 14));
}

#[test]
fn scene_syntax_error_names_file_line_and_column() {
    let dir = TempDir::new("syntax");
    let bad = dir.path().join("bad.toml");
    std::fs::write(&bad, "[camera]\nposition = [0, 0, 5\nlook_at = [0, 0, 0]\n").unwrap();
    let out_path = dir.path().join("bad.png");
    for args in
        [vec!["info", bad.to_str().unwrap()], vec!["render", bad.to_str().unwrap(), "-o", out_path.to_str().unwrap()]]
    {
        let out = ggx(&args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{err}");
        let location = format!("error: {}:3:1: ", bad.display());
        assert!(err.contains(&location), "{err}");
    }
    assert!(!out_path.exists());
}

#[test]
fn unsupported_extension_fails_before_rendering() {
    let dir = TempDir::new("ext");
    let path = dir.path().join("x.jpg");
    let start = Instant::now();
    // A render this large would take minutes.
    let out = ggx(&["render", &scene("cornell.toml"), "-o", path.to_str().unwrap(), "--spp", "1000000"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("unsupported output format `.jpg` (supported: .exr, .png)"), "{err}");
    assert!(!err.contains("rendering"), "{err}");
    assert!(start.elapsed() < Duration::from_secs(60));
    assert!(!path.exists());
}

#[test]
fn missing_output_directory_is_an_error() {
    let dir = TempDir::new("nodir");
    let path = dir.path().join("no/such/dir/x.png");
    let out = ggx(&["render", &scene("furnace.toml"), "-o", path.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("does not exist"), "{err}");
}

#[test]
fn wgpu_backend_renders_or_reports_the_missing_adapter() {
    let dir = TempDir::new("wgpu");
    for backend in ["wgpu", "auto"] {
        let path = dir.path().join(format!("{backend}.png"));
        let out = ggx(&[
            "render",
            &scene("furnace.toml"),
            "-o",
            path.to_str().unwrap(),
            "--backend",
            backend,
            "--spp",
            "2",
            "--width",
            "16",
            "--height",
            "12",
        ]);
        let err = String::from_utf8_lossy(&out.stderr);
        if err.contains("is a software renderer: rendering on the CPU backend") {
            // `auto` with only a software adapter (CI's lavapipe): the CPU renders.
            assert_eq!((backend, out.status.code()), ("auto", Some(0)), "{err}");
            assert!(path.exists(), "{err}");
        } else if err.contains("wgpu adapter: ") {
            assert_eq!(out.status.code(), Some(0), "{err}");
            assert!(path.exists(), "{err}");
            assert!(String::from_utf8_lossy(&out.stdout).contains("2 spp, 16x12"), "{err}");
        } else {
            // No adapter: only acceptable outside CI. `wgpu` fails, `auto` falls back.
            assert_ne!(std::env::var("CI").as_deref(), Ok("true"), "no GPU adapter in CI: {err}");
            if backend == "wgpu" {
                assert_eq!(out.status.code(), Some(1), "{err}");
                assert!(err.contains("the wgpu backend has no GPU"), "{err}");
                assert!(!path.exists());
            } else {
                assert_eq!(out.status.code(), Some(0), "{err}");
                assert!(err.contains("rendering on the CPU"), "{err}");
                assert!(path.exists());
            }
        }
    }
}

#[test]
fn bad_arguments_are_usage_errors() {
    for args in [&["render", "x.toml"][..], &["render", "x.toml", "-o", "x.png", "--spp", "0"], &["frobnicate"]] {
        let out = ggx(args);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
    }
    let out = ggx(&["--help"]);
    assert!(out.status.success() && stdout_of(&out).contains("Examples:"));
    let out = ggx(&["--version"]);
    assert_eq!(stdout_of(&out).trim(), format!("ggx {}", env!("CARGO_PKG_VERSION")));
}

#[test]
fn time_budget_stops_before_the_requested_spp() {
    let dir = TempDir::new("budget");
    let path = dir.path().join("t.exr");
    let out =
        ggx(&["render", &scene("cornell.toml"), "-o", path.to_str().unwrap(), "--time", "0.5", "--spp", "10000000"]);
    let text = stdout_of(&out);
    assert_eq!(out.status.code(), Some(0), "{text}\n{}", String::from_utf8_lossy(&out.stderr));
    let spp: u32 = text
        .split(", ")
        .find_map(|part| part.strip_suffix(" spp"))
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no spp in {text}"));
    assert!((1..10_000_000).contains(&spp), "{text}");
    let (w, h, _) = ggx_film::read_exr(&path).unwrap();
    assert_eq!((w, h), (256, 256));
}

/// A scene without shapes renders (the environment) but says so on stderr.
#[test]
fn an_empty_scene_renders_with_a_warning() {
    let dir = TempDir::new("empty");
    let file = dir.path().join("empty.toml");
    let text = "[camera]\nposition = [0, 0, 5]\nlook_at = [0, 0, 0]\nresolution = [8, 4]\n\
                [environment]\ntype = \"constant\"\nradiance = [0.5, 0.5, 0.5]\n";
    std::fs::write(&file, text).unwrap();
    let out = ggx(&["render", file.to_str().unwrap(), "-o", dir.path().join("e.exr").to_str().unwrap(), "--spp", "1"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains("warning: ") && stderr.contains("has no shapes: the image shows only the environment"),
        "{stderr}"
    );
}

/// `--stats FILE.json` writes what the render did; a stats path that is not `.json` or is
/// the image itself is refused before anything is rendered.
#[test]
fn stats_file_describes_the_render() {
    let dir = TempDir::new("stats");
    let (image, json) = (dir.path().join("s.png"), dir.path().join("s.json"));
    let args = ["--spp", "4", "--width", "24", "--height", "12", "--stats", json.to_str().unwrap()];
    let out = ggx(&[&["render", &scene("cornell.toml"), "-o", image.to_str().unwrap()][..], &args[..]].concat());
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let stats: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(stats["backend"], "cpu");
    assert_eq!(stats["kernel"], "area");
    assert_eq!((stats["width"].as_u64(), stats["height"].as_u64()), (Some(24), Some(12)));
    assert_eq!((stats["spp"].as_u64(), stats["spp_requested"].as_u64()), (Some(4), Some(4)));
    assert_eq!(stats["camera_samples"].as_u64(), Some(24 * 12 * 4));
    assert!(stats["rays"].as_u64().unwrap() >= 24 * 12 * 4);
    assert!(stats["rays_per_second"].as_f64().unwrap() > 0.0 && stats["seconds"].as_f64().unwrap() > 0.0);
    assert!(stats["adapter"].as_str().unwrap().contains("threads"), "{stats}");
    // The pass schedule 1, 1, 2 spp: cumulative 1, 2, 4, times increasing.
    let passes = stats["passes"].as_array().unwrap();
    let spp: Vec<u64> = passes.iter().map(|p| p["spp"].as_u64().unwrap()).collect();
    assert_eq!(spp, [1, 2, 4]);
    let times: Vec<f64> = passes.iter().map(|p| p["seconds"].as_f64().unwrap()).collect();
    assert!(times.windows(2).all(|w| w[0] <= w[1]), "{times:?}");

    // A link named .json that points at the image is the image.
    std::os::unix::fs::symlink(&image, dir.path().join("link.json")).unwrap();
    for (bad, message) in [("s.txt", "must end in .json"), ("link.json", "is also the image output")] {
        let path = dir.path().join(bad);
        let out =
            ggx(&["render", &scene("cornell.toml"), "-o", image.to_str().unwrap(), "--stats", path.to_str().unwrap()]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{stderr}");
        assert!(stderr.contains(message) && !stderr.contains("loading"), "{stderr}");
    }
}

/// With stderr not a terminal (captured here) progress comes as lines, the last pass always.
#[test]
fn progress_lines_when_stderr_is_not_a_terminal() {
    let dir = TempDir::new("lines");
    let image = dir.path().join("p.png");
    let out = ggx(&["render", &scene("cornell.toml"), "-o", image.to_str().unwrap(), "--spp", "8", "--width", "16"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(stderr.lines().any(|l| l.starts_with("progress: 8/8 spp")), "{stderr}");
    let first = stderr.lines().find(|l| l.starts_with("progress: ")).unwrap_or_default();
    assert!(first.starts_with("progress: 1/8 spp"), "{stderr}");
}
