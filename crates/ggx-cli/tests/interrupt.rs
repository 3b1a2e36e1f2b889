//! Ctrl-C during `ggx render`: the image rendered so far is written and the exit code is 130.
#![cfg(unix)]

mod support;

use std::io::{BufRead, BufReader, Read};
use std::process::{Command, Stdio};
use std::time::Duration;

use support::{GGX, TempDir, Watchdog, scene};

/// Reads `stderr` into `log` until a line contains `marker` (or the stream ends).
fn read_until(stderr: &mut impl BufRead, log: &mut String, marker: &str) {
    while !log.contains(marker) {
        let mut line = String::new();
        if stderr.read_line(&mut line).unwrap() == 0 {
            break;
        }
        *log += &line;
    }
    assert!(log.contains(marker), "ggx never printed {marker:?}: {log}");
}

/// A running `ggx render` whose stderr is read as it comes, watched by a [`Watchdog`].
struct Running {
    child: std::process::Child,
    stderr: BufReader<std::process::ChildStderr>,
    log: String,
    watchdog: Watchdog,
}

impl Running {
    /// Starts `ggx args` with both outputs piped.
    fn start(args: &[&str]) -> Self {
        let mut child =
            Command::new(GGX).args(args).stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().expect("ggx starts");
        let watchdog = Watchdog::new(child.id(), 120);
        let stderr = BufReader::new(child.stderr.take().expect("stderr is piped"));
        Self { child, stderr, log: String::new(), watchdog }
    }

    /// Waits until stderr shows `marker`, then sends `signal` (e.g. `-INT`).
    fn signal_after(&mut self, marker: &str, pause: Duration, signal: &str) {
        read_until(&mut self.stderr, &mut self.log, marker);
        std::thread::sleep(pause);
        kill(signal, self.child.id());
    }

    /// Waits for the exit: (exit code, stdout, stderr).
    fn finish(mut self) -> (Option<i32>, String, String) {
        self.stderr.read_to_string(&mut self.log).unwrap();
        let mut stdout = String::new();
        self.child.stdout.take().expect("stdout is piped").read_to_string(&mut stdout).unwrap();
        let status = self.child.wait().unwrap();
        drop(self.watchdog);
        (status.code(), stdout, self.log)
    }
}

/// Sends `signal` (e.g. `-INT`) to process `pid` with the `kill` command.
fn kill(signal: &str, pid: u32) {
    let status = Command::new("kill").args([signal, &pid.to_string()]).status().expect("kill runs");
    assert!(status.success(), "kill {signal} {pid} failed");
}

#[test]
fn sigint_writes_the_partial_image_and_exits_130() {
    let dir = TempDir::new("interrupt");
    let path = dir.path().join("partial.png");
    let scene = scene("cornell.toml");
    let mut ggx = Running::start(&[
        "render",
        &scene,
        "-o",
        path.to_str().unwrap(),
        "--spp",
        "1000000",
        "--width",
        "64",
        "--height",
        "48",
        "--threads",
        "1",
    ]);
    // The handler is installed before "rendering ..." is printed; a 64x48 pass takes
    // milliseconds, so after the pause some passes are done and many remain.
    ggx.signal_after("rendering ", Duration::from_millis(1500), "-INT");
    let (code, stdout, log) = ggx.finish();

    assert_eq!(code, Some(130), "stdout: {stdout}\nstderr: {log}");
    assert!(log.contains("interrupted with "), "{log}");
    assert!(stdout.starts_with("interrupted: "), "{stdout}");
    let png = image::open(&path).unwrap_or_else(|e| panic!("{}: {e}\n{log}", path.display()));
    assert_eq!((png.width(), png.height()), (64, 48));
    // The lit box is not black.
    assert!(png.to_rgb8().pixels().any(|p| p.0.iter().any(|&c| c > 0)));
}

#[test]
fn sigterm_while_loading_exits_at_once() {
    let dir = TempDir::new("interrupt-load");
    // About two million triangles: seconds of tessellation and BVH building.
    let mut text = String::from(
        "[camera]\nposition = [0, 0, 30]\nlook_at = [0, 0, 0]\nresolution = [32, 24]\n\
         [materials.white]\ntype = \"diffuse\"\nalbedo = [0.8, 0.8, 0.8]\n",
    );
    for i in 0..6 {
        text += &format!(
            "[[shapes]]\ntype = \"sphere\"\nmaterial = \"white\"\nsubdivisions = 7\ncenter = [{}, 0, 0]\n",
            3 * i
        );
    }
    let file = dir.path().join("heavy.toml");
    std::fs::write(&file, text).unwrap();
    let out = dir.path().join("heavy.png");
    let mut ggx = Running::start(&["render", file.to_str().unwrap(), "-o", out.to_str().unwrap(), "--spp", "1"]);
    ggx.signal_after("loading ", Duration::ZERO, "-TERM");
    let (code, _, log) = ggx.finish();
    assert_eq!(code, Some(130), "{log}");
    assert!(log.contains("interrupted before rendering started"), "{log}");
    // Before the fix the signal was only noted: loading and the BVH build ran to the end and
    // the render was announced first.
    assert!(!log.lines().any(|l| l.starts_with("rendering ")), "{log}");
    assert!(!out.exists());
}

/// Ctrl-C in the middle of a pass keeps the finished tiles: the film records each pixel's
/// count, and `--resume` completes it into the image of an uninterrupted render, bit for bit.
#[test]
fn an_interrupted_film_resumes_to_the_same_bits() {
    let dir = TempDir::new("interrupt-resume");
    let file = |name: &str| dir.path().join(name).to_str().unwrap().to_owned();
    let scene = scene("cornell.toml");
    let common = ["--width", "48", "--height", "32", "--threads", "1"];
    let mut ggx =
        Running::start(&[&["render", &scene, "-o", &file("cut.exr"), "--samples", "0..400000"][..], &common].concat());
    ggx.signal_after("rendering ", Duration::from_millis(1500), "-INT");
    let (code, _, log) = ggx.finish();
    assert_eq!(code, Some(130), "{log}");
    let (info, cut) = ggx_film::read_film(std::path::Path::new(&file("cut.exr")), 1 << 20).unwrap();
    assert_eq!(info.samples, [0, 400000]);
    let held = cut.pixels().iter().map(|p| p.samples).max().unwrap();
    assert!(held > 0, "{log}");
    // Continue it to a range both can finish quickly: the resume extends or cuts nothing it holds.
    let end = (held + 3).to_string();
    let range = format!("0..{end}");
    let out = support::ggx(
        &[
            &["render", &scene, "-o", &file("resumed.exr"), "--resume", &file("cut.exr"), "--samples", &range][..],
            &common,
        ]
        .concat(),
    );
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let out = support::ggx(&[&["render", &scene, "-o", &file("whole.exr"), "--samples", &range][..], &common].concat());
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let read = |name: &str| ggx_film::read_film(std::path::Path::new(&file(name)), 1 << 20).unwrap().1;
    assert_eq!(read("resumed.exr"), read("whole.exr"));
}
