//! The Mitsuba 3 driver process (`mitsuba_driver.py` in the venv's Python): one JSON request
//! per line on its stdin, one JSON reply per line on its stdout, so the peer run can interleave
//! Mitsuba's renders with ggx's rung by rung while Mitsuba keeps its scenes and compiled
//! kernels loaded.
//!
//! It runs with `DRJIT_LIBLLVM_PATH` set to LLVM 19 and `HOME` pointing at an empty directory
//! of this run, so Dr.Jit's kernel cache (`~/.drjit`) starts cold: the first render of each
//! scene and variant includes its JIT compilation, which is reported on its own.

use std::io::{BufRead, BufReader, Write};
use std::path::Path;
use std::process::{Child, ChildStdin, ChildStdout, Command, Stdio};

use serde::Deserialize;
use serde_json::{Value, json};

use super::setup::Setup;

/// Versions reported by the driver.
#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
pub struct Versions {
    /// Mitsuba.
    pub mitsuba: String,
    /// Dr.Jit.
    pub drjit: String,
    /// NumPy.
    pub numpy: String,
    /// Python.
    pub python: String,
}

/// One timed Mitsuba render.
#[derive(Clone, Debug, Deserialize, PartialEq)]
pub struct Rendered {
    /// Wall-clock seconds around the render calls.
    pub seconds: f64,
    /// Of which JIT compilation (0 for scalar variants).
    pub jit_seconds: f64,
    /// Width of the image.
    pub width: u32,
    /// Height of the image.
    pub height: u32,
}

/// Mitsuba's GGX micro-benchmark: operation name -> lanes per second.
#[derive(Clone, Debug, Deserialize, PartialEq)]
pub struct Micro {
    /// Lanes per second by operation (`D`, `sample_wm_vndf`, `sample_reflect`, `eval`, `pdf`,
    /// `sample`).
    pub per_second: std::collections::BTreeMap<String, f64>,
}

/// A render request.
#[derive(Clone, Debug)]
pub struct RenderRequest<'a> {
    /// `llvm_ad_rgb` or `scalar_rgb`.
    pub variant: &'a str,
    /// The exported scene.
    pub scene: &'a Path,
    /// Dr.Jit's thread count.
    pub threads: usize,
    /// Samples per pixel.
    pub spp: u32,
    /// Seed of the first pass (pass `i` uses `seed + i`).
    pub seed: u32,
    /// Largest pass (memory: Mitsuba's wavefront holds every sample of a pass).
    pub max_pass_spp: u32,
    /// Where to write the image (EXR).
    pub out: &'a Path,
}

/// The running driver; dropping it asks it to quit and waits.
pub struct Driver {
    child: Child,
    stdin: ChildStdin,
    stdout: BufReader<ChildStdout>,
}

impl Driver {
    /// Starts the driver with the venv's Python, `HOME` set to `jit_home` (created empty).
    pub fn start(setup: &Setup, jit_home: &Path) -> Result<Self, String> {
        let _ = std::fs::remove_dir_all(jit_home);
        std::fs::create_dir_all(jit_home).map_err(|e| format!("{}: {e}", jit_home.display()))?;
        let mut child = Command::new(&setup.python)
            .arg(&setup.driver)
            .env("DRJIT_LIBLLVM_PATH", &setup.llvm)
            .env("HOME", jit_home)
            .env("PYTHONUNBUFFERED", "1")
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit())
            .spawn()
            .map_err(|e| format!("{} {}: {e}", setup.python.display(), setup.driver.display()))?;
        let stdin = child.stdin.take().ok_or("the driver has no stdin")?;
        let stdout = BufReader::new(child.stdout.take().ok_or("the driver has no stdout")?);
        Ok(Self { child, stdin, stdout })
    }

    /// Sends `request` and returns the reply, or the driver's error.
    fn call(&mut self, request: &Value) -> Result<Value, String> {
        let cmd = request.get("cmd").and_then(Value::as_str).unwrap_or("?").to_owned();
        writeln!(self.stdin, "{request}")
            .and_then(|()| self.stdin.flush())
            .map_err(|e| format!("driver {cmd}: {e}"))?;
        let mut line = String::new();
        let n = self.stdout.read_line(&mut line).map_err(|e| format!("driver {cmd}: {e}"))?;
        if n == 0 {
            return Err(format!("the Mitsuba driver exited during `{cmd}` (its messages are above)"));
        }
        parse_reply(&cmd, &line)
    }

    /// Versions of Mitsuba, Dr.Jit, NumPy and Python.
    pub fn hello(&mut self) -> Result<Versions, String> {
        let v = self.call(&json!({"cmd": "hello"}))?;
        serde_json::from_value(v).map_err(|e| format!("driver hello: {e}"))
    }

    /// Renders one image.
    pub fn render(&mut self, r: &RenderRequest) -> Result<Rendered, String> {
        let v = self.call(&json!({
            "cmd": "render",
            "variant": r.variant,
            "scene": r.scene,
            "threads": r.threads,
            "spp": r.spp,
            "seed": r.seed,
            "max_pass_spp": r.max_pass_spp,
            "out": r.out,
        }))?;
        serde_json::from_value(v).map_err(|e| format!("driver render: {e}"))
    }

    /// Mitsuba's GGX micro-benchmark on `lanes` lanes with `threads` threads.
    pub fn microbench(&mut self, threads: usize, lanes: u32, repeats: u32, alpha: f32) -> Result<Micro, String> {
        let v = self.call(&json!({
            "cmd": "microbench", "variant": "llvm_ad_rgb", "threads": threads, "lanes": lanes,
            "repeats": repeats, "alpha": alpha,
        }))?;
        serde_json::from_value(v).map_err(|e| format!("driver microbench: {e}"))
    }
}

impl Drop for Driver {
    fn drop(&mut self) {
        let _ = writeln!(self.stdin, "{}", json!({"cmd": "quit"}));
        let _ = self.stdin.flush();
        let _ = self.child.wait();
    }
}

/// The reply line of `cmd`: its JSON when `"ok": true`, else the driver's error (with the
/// Python traceback).
pub fn parse_reply(cmd: &str, line: &str) -> Result<Value, String> {
    let v: Value = serde_json::from_str(line.trim())
        .map_err(|e| format!("driver {cmd}: not a JSON reply ({e}): {}", line.trim()))?;
    if v.get("ok").and_then(Value::as_bool) == Some(true) {
        Ok(v)
    } else {
        let error = v.get("error").and_then(Value::as_str).unwrap_or("no error message");
        let trace = v.get("traceback").and_then(Value::as_str).unwrap_or("");
        Err(format!("Mitsuba driver `{cmd}` failed: {error}\n{trace}"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn replies_are_checked() {
        let ok = parse_reply(
            "render",
            "{\"ok\": true, \"seconds\": 1.5, \"jit_seconds\": 0.25, \"width\": 4, \"height\": 2}\n",
        );
        let r: Rendered = serde_json::from_value(ok.unwrap()).unwrap();
        assert_eq!((r.seconds, r.jit_seconds, r.width, r.height), (1.5, 0.25, 4, 2));
        let e =
            parse_reply("render", "{\"ok\": false, \"error\": \"RuntimeError: x\", \"traceback\": \"T\"}").unwrap_err();
        assert!(e.contains("`render` failed: RuntimeError: x") && e.ends_with('T'), "{e}");
        assert!(parse_reply("hello", "Traceback (most recent").unwrap_err().contains("not a JSON reply"));
        let m: Micro = serde_json::from_str("{\"ok\": true, \"per_second\": {\"D\": 1e9}}").unwrap();
        assert_eq!(m.per_second["D"], 1e9);
    }
}
