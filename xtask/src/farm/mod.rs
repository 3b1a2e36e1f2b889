//! `cargo xtask farm`: distributed rendering on a real Slurm (issue 12), on this machine.
//!
//! A one-node Slurm cluster is started from nothing under `target/xtask/farm/` and always
//! stopped again; the scripts of `scripts/slurm/` run on it. Modules, one purpose each:
//!
//! * [`install`]: Debian's slurm-wlm and munge, installed with apt-get where missing.
//! * [`config`]: the cluster's files: slurm.conf (no cgroups, 127.0.0.1 only), the munge key.
//! * [`daemon`]: a daemon run in the foreground as a child, stopped and reaped when dropped.
//! * [`cluster`]: [`Cluster`]: start, submit, wait, cancel one task, read states, stop.
//! * [`jobs`]: [`jobs::JobSpec`], [`jobs::JobId`], [`jobs::TaskState`], and sbatch's and
//!   squeue's answers parsed.
//! * [`listen`]: which addresses listen on a port (the daemons: loopback only).
//! * [`scripts`]: the Slurm scripts and the ggx stub that runs them without a renderer.
//! * [`selftest`]: `--selftest`, the stand-in array and the scenario with the stub.
//! * [`scenario`]: the render scenario: split, merge, cancel, resubmit, compare bit for bit.
//! * [`k8s`]: the Kubernetes manifests against the vendored JSON schemas (`--manifests`).
//!
//! The API for a new scenario:
//!
//! ```ignore
//! let cluster = Cluster::start()?; // installs, starts, waits for the idle node
//! let job = cluster.submit(&JobSpec::new(script).array("0-7").args(["--spp", "64"]).env("K", "V"))?;
//! cluster.wait_for_task(job, 3, |s| *s == TaskState::Running, timeout)?;
//! cluster.cancel_task(job, 3)?;
//! let states = cluster.wait(job, timeout)?; // BTreeMap<task, TaskState>
//! let again = cluster.submit(&JobSpec::new(script).array("3"))?;
//! cluster.require_completed(again, &cluster.wait(again, timeout)?, &[3])?;
//! ```
//! and the cluster stops when dropped.

pub mod cluster;
pub mod config;
pub mod daemon;
pub mod install;
pub mod jobs;
pub mod k8s;
pub mod listen;
pub mod scenario;
pub mod scripts;
pub mod selftest;

pub use cluster::Cluster;

use std::time::Instant;

/// The usage of `cargo xtask farm`.
const USAGE: &str = "usage: cargo xtask farm --selftest | --manifests | --scenario [--ggx PATH] [--scene PATH] [--spp N] [--tasks N] [--width W]";

/// Parses the arguments after `farm` and runs that mode.
pub fn run(args: &[String]) -> Result<(), String> {
    match args.first().map(String::as_str) {
        Some("--selftest") if args.len() == 1 => selftest::run(),
        Some("--manifests") if args.len() == 1 => {
            let count = timed("check scripts/k8s/*.yaml against the vendored schemas", k8s::check_all)?;
            eprintln!("{count} Kubernetes documents valid");
            let scratch = crate::render::output_dir("farm")?.join("k8s-pods");
            let report = timed("run the pods' shell with the ggx stub", || k8s::check_pod_scripts(&scratch))?;
            eprintln!("{report}");
            Ok(())
        }
        Some("--scenario") => {
            let options = scenario::Options::parse(&args[1..])?;
            let start = Instant::now();
            let cluster = timed("start the cluster", Cluster::start)?;
            let out = crate::render::output_dir("farm")?.join("scenario");
            scenario::run(&cluster, &scenario::Scenario::ggx(&options, &out))?;
            timed("stop the daemons", || {
                cluster.stop();
                Ok(())
            })?;
            eprintln!("\nfarm scenario passed in {:.1} s", start.elapsed().as_secs_f64());
            Ok(())
        }
        None => Err(format!("farm: which mode?\n{USAGE}")),
        Some(_) => Err(format!("farm: unknown arguments `{}`\n{USAGE}", args.join(" "))),
    }
}

/// Runs one step, printing what it is and how long it took.
pub fn timed<T>(what: &str, step: impl FnOnce() -> Result<T, String>) -> Result<T, String> {
    eprintln!("\n==> {what}");
    let start = Instant::now();
    let result = step();
    let verdict = if result.is_ok() { "" } else { " (failed)" };
    eprintln!("<== {what}: {:.1} s{verdict}", start.elapsed().as_secs_f64());
    result.map_err(|e| format!("{what}: {e}"))
}
