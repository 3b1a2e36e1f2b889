//! `cargo xtask <command>`: project automation in Rust, so it runs wherever cargo runs
//! (the rust-analyzer convention). Commands:
//!
//! * `ci`: everything CI checks, in order, stopping at the first failure: a Vulkan driver
//!   (lavapipe is installed with apt-get where none is, see [`system`]), rustfmt, glam's
//!   math through std in the `ggx` binary (see [`glam_math`]), clippy with
//!   `-D warnings`, the `no_std` build proof, the whole test suite under `CI=true` (GPU tests
//!   fail without an adapter), then `stress --quick`, `diff --quick`, `bench --quick`, the
//!   Slurm scenario of `farm --scenario` (with the debug ggx of the test step) and
//!   `farm --manifests`. It runs with `GALLIVM_PERF=nopt` (see [`LAVAPIPE_PASSES`]) unless
//!   `GALLIVM_PERF` is set.
//! * `diff [SCENES...]`: every scene rendered on the CPU and wgpu backends with the same seed,
//!   compared against per-scene tolerances (see [`diff`]).
//! * `bench`: run time against error, the convergence study (see [`bench`]).
//! * `stress [--quick] [--samples N]`: the numerical stability sweep of ggx-core's samplers
//!   (see [`stress`]).
//! * `fuzz [--cases N]`: the mutation tests of every file reader and ggx-core's contract with
//!   a long budget (see [`fuzz`]).
//! * `farm --selftest | --manifests | --scenario`: distributed rendering on a one-node Slurm
//!   cluster started (and stopped) by xtask, Slurm and munge installed with apt-get where
//!   missing; the Kubernetes manifests checked against vendored schemas (see [`farm`]).
//! * `peer [--quick] [...]`: ggx beside Mitsuba 3 on the same scenes in one run (installs
//!   LLVM 19 and a venv with Mitsuba where missing; not part of `ci`; see [`peer`]).
//! * `ab --a BIN --b BIN [...]`: which of two ggx binaries renders faster, both run at once on
//!   CPUs of their own so that the shared machine's load moves both alike (see [`ab`]).
//! * `tables [--check]`: regenerates ggx-core's energy-compensation tables (see [`tables`] and
//!   [`tables_dielectric`]).

mod ab;
mod bench;
mod diff;
mod farm;
mod fuzz;
mod glam_math;
mod peer;
mod render;
mod stress;
mod system;
mod tables;
mod tables_dielectric;

use std::process::{Command, ExitCode};
use std::time::Instant;

/// Printed for an unknown command or bad arguments.
const USAGE: &str = "usage: cargo xtask <command>

  ci                             rustfmt check, clippy -D warnings, no_std build check, all tests,
                                 stress --quick, diff --quick, bench --quick, farm --scenario, farm --manifests
  diff [--quick] [--width W] [--spp N] [SCENES...]
                                 render each scene (default: all) on the CPU and wgpu backends with the
                                 same seed; EXRs, false-colour difference PNGs and report.md under
                                 target/xtask/diff/; fails when a scene exceeds its tolerances
                                 (scenes/tolerances.toml)
  bench [--quick] [...]          convergence study: error against time and spp per configuration;
                                 CSV, SVG plots and summary.md under target/xtask/bench/ (see --help)
  stress [--quick] [--samples N] numerical stress sweep of ggx-core's samplers: N samples per method
                                 (default 1e8; --quick: 1e6); fails on any NaN/inf or invalid accepted sample
  fuzz [--cases N]               mutation tests of the scene, OBJ, HDR, EXR, glTF and film-file readers and ggx-core's
                                 any-f32 contract with N cases each (default 20000; CI runs a short budget)
  farm --selftest                install Slurm and munge where missing (apt-get), start a one-node cluster
                                 bound to 127.0.0.1 under target/xtask/farm/, run a stand-in job array
                                 (cancel a task mid-run, resubmit it) and the scripts/slurm scenario with a
                                 ggx stub, stop the daemons
  farm --scenario [--ggx PATH] [--scene PATH] [--spp N] [--tasks N] [--width W]
                                 the same scenario with the real ggx: split a render across array tasks,
                                 merge, cancel and resubmit a task, compare bit for bit with one render
  farm --manifests               check scripts/k8s/*.yaml against the vendored Kubernetes JSON schemas
  peer [--quick] [--scenes a,b] [--width W] [--max-spp N] [--ref-spp N] [--single-max-spp N]
                                 ggx beside Mitsuba 3 on scenes/peer/*.toml in one run: installs libllvm19
                                 (apt-get) and a venv with pinned mitsuba/drjit (pip) where missing, exports
                                 each scene with `ggx export --format mitsuba`, renders both at the same thread
                                 counts against their own cached references; samples/s, relMSE at equal time,
                                 efficiency, converged agreement, GGX micro-benchmark; summary.md, CSV and
                                 plots under target/xtask/peer/ (not part of ci: large download; see --help)
  ab --a BIN --b BIN [--runs N] [--spp N] [--width W] [SCENES...]
                                 which of two ggx binaries renders faster: both render each scene at the
                                 same time, one thread each on CPUs 0 and 1 (swapped every run); the median
                                 of the per-run time ratios, its quartiles, and whether the pixels are
                                 identical; report.md under target/xtask/ab/
  tables [--check]               regenerate ggx-core's energy-compensation tables from ggx-core's own code in f64:
                                 the conductor's E(mu, alpha), E_avg(alpha) (crates/ggx-core/src/energy_tables.rs),
                                 the dielectric's E_T(mu, alpha, eta') and the plastic coat's E_R, E_R_avg
                                 (crates/ggx-core/src/energy_dielectric_tables.rs);
                                 --check: fail when a committed file differs";

/// The crate that proves ggx-core builds without std. It must be built on its own: built
/// together with crates that enable ggx-core's `std` feature, feature unification would
/// pull std in and its `#[panic_handler]` would clash with std's.
const NOSTD_CHECK: &str = "ggx-nostd-check";

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = match args.first().map(String::as_str) {
        Some("ci") => ci(),
        Some("diff") => diff::run(&args[1..]),
        Some("ab") => ab::run(&args[1..]),
        Some("bench") => bench::run(&args[1..]),
        Some("fuzz") => fuzz::run(&args[1..]),
        Some("farm") => farm::run(&args[1..]),
        Some("peer") => peer::run(&args[1..]),
        Some("tables") => tables::run(&args[1..]),
        Some("stress") => match stress::Options::parse(&args[1..]) {
            Ok(options) => stress::run(&options),
            Err(e) => {
                eprintln!("xtask: {e}\n\n{USAGE}");
                return ExitCode::from(2);
            }
        },
        _ => {
            eprintln!("{USAGE}");
            return ExitCode::from(2);
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("xtask: {e}");
            ExitCode::FAILURE
        }
    }
}

/// Runs `cargo <args>` and fails with the command line if it fails.
fn cargo(args: &[&str]) -> Result<(), String> {
    cargo_with(args, &[])
}

/// Runs `cargo <args>` with the environment variables `env` set.
fn cargo_with(args: &[&str], env: &[(&str, &str)]) -> Result<(), String> {
    let cargo = cargo_program();
    let vars: Vec<String> = env.iter().map(|(k, v)| format!("{k}={v} ")).collect();
    let line = format!("{}cargo {}", vars.concat(), args.join(" "));
    eprintln!("\n==> {line}");
    let start = Instant::now();
    let status =
        Command::new(cargo).args(args).envs(env.iter().copied()).status().map_err(|e| format!("{line}: {e}"))?;
    eprintln!("<== {line}: {:.1} s", start.elapsed().as_secs_f64());
    if status.success() { Ok(()) } else { Err(format!("`{line}` failed ({status})")) }
}

/// The cargo that runs xtask (`$CARGO`), or `cargo` from `PATH`: every command that starts
/// cargo takes it from here.
fn cargo_program() -> std::ffi::OsString {
    std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into())
}

/// Runs `cargo <args>` and returns its standard output, failing with the command line and its
/// standard error if it fails.
fn cargo_stdout(args: &[&str]) -> Result<String, String> {
    let line = format!("cargo {}", args.join(" "));
    eprintln!("\n==> {line}");
    let out = Command::new(cargo_program()).args(args).output().map_err(|e| format!("{line}: {e}"))?;
    if !out.status.success() {
        return Err(format!("`{line}` failed ({}): {}", out.status, String::from_utf8_lossy(&out.stderr)));
    }
    Ok(String::from_utf8_lossy(&out.stdout).into_owned())
}

/// Runs an xtask command in this process, timed like [`cargo`].
fn in_process(what: &str, f: impl FnOnce() -> Result<(), String>) -> Result<(), String> {
    eprintln!("\n==> {what} (in process)");
    let start = Instant::now();
    let result = f();
    eprintln!("<== {what}: {:.1} s", start.elapsed().as_secs_f64());
    result.map_err(|e| format!("{what}: {e}"))
}

/// Mesa's switch for lavapipe's LLVM optimisation passes, and the value `ci` gives it: the GPU
/// tests render a few pixels, and the passes made up most of a kernel's compile (three-spheres'
/// `area+env+plastic`: 94 s with them, 17 s without, on a 2-vCPU EPYC; same parity figures).
const LAVAPIPE_PASSES: (&str, &str) = ("GALLIVM_PERF", "nopt");

/// `ci` run again as a child with [`LAVAPIPE_PASSES`] set (Mesa reads it once per process, and the
/// in-process steps need it too); `None` where it is set already, by this or by the user.
fn ci_with_lavapipe_passes_off() -> Option<Result<(), String>> {
    let (key, value) = LAVAPIPE_PASSES;
    if std::env::var_os(key).is_some() {
        return None;
    }
    eprintln!("==> xtask ci with {key}={value} (lavapipe's kernels compiled without LLVM's optimisation passes)");
    let run = || -> Result<(), String> {
        let exe = std::env::current_exe().map_err(|e| format!("xtask's own path: {e}"))?;
        let status =
            Command::new(&exe).arg("ci").env(key, value).status().map_err(|e| format!("{}: {e}", exe.display()))?;
        if status.success() { Ok(()) } else { Err(format!("xtask ci ({key}={value}) failed ({status})")) }
    };
    Some(run())
}

fn ci() -> Result<(), String> {
    if let Some(result) = ci_with_lavapipe_passes_off() {
        return result;
    }
    let start = Instant::now();
    system::report_disk(&render::workspace_root().join("target"));
    // The GPU tests need a Vulkan adapter: install lavapipe where none is, before anything runs.
    system::ensure_vulkan()?;
    // `xtask-flip` (a workspace member: clippy and the tests build it) is C++ underneath.
    system::ensure_cxx()?;
    cargo(&["fmt", "--all", "--check"])?;
    // glam's Vec3 math through std, not libm's legacy-SSE sqrtss (see `glam_math`).
    glam_math::check()?;
    cargo(&["clippy", "--workspace", "--all-targets", "--exclude", NOSTD_CHECK, "--", "-D", "warnings"])?;
    // no_std proofs: the core without default features, and a #![no_std] consumer that
    // defines its own panic handler (a duplicate lang item error if std were linked).
    cargo(&["build", "-p", "ggx-core", "--no-default-features"])?;
    cargo(&["clippy", "-p", NOSTD_CHECK, "--", "-D", "warnings"])?;
    // CI=true: a GPU test without an adapter fails instead of skipping.
    cargo_with(&["test", "--workspace", "--exclude", NOSTD_CHECK], &[("CI", "true")])?;
    // In process rather than through cargo: xtask is built already, so nothing else compiles.
    eprintln!("\n==> stress --quick (in process)");
    let stress_start = Instant::now();
    stress::run(&stress::Options::quick())?;
    eprintln!("<== stress --quick: {:.1} s", stress_start.elapsed().as_secs_f64());
    in_process("diff --quick", || diff::run(&["--quick".into()]))?;
    in_process("bench --quick", || bench::run(&["--quick".into()]))?;
    // Distributed rendering on a real one-node Slurm, with the ggx the test step just built.
    let ggx = render::workspace_root().join("target").join("debug").join("ggx");
    let args = ["--scenario".to_owned(), "--ggx".to_owned(), ggx.display().to_string()];
    in_process("farm --scenario", || farm::run(&args))?;
    in_process("farm --manifests", || farm::run(&["--manifests".to_owned()]))?;
    eprintln!("\nxtask ci: all checks passed in {:.0} s", start.elapsed().as_secs_f64());
    Ok(())
}
