//! `cargo xtask farm --selftest`: proves the Slurm plumbing on this machine. It installs
//! Slurm, munge and shellcheck where missing, lints the scripts, starts the cluster, checks
//! that its daemons listen on 127.0.0.1 only, then runs
//!
//! * the stand-in array: 8 tasks that each sleep 2 s and then write a file; one is cancelled
//!   mid-run, its file is missing, it is resubmitted alone, and all 8 files are there;
//! * the render scenario ([`super::scenario`]) with the ggx stub, through the real scripts;
//!
//! and stops the daemons, checking that they are gone.

use super::cluster::Cluster;
use super::jobs::{JobSpec, TaskState, summary};
use super::scenario::{self, Scenario};
use super::{install, listen, scripts, timed};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Tasks of the stand-in array.
const STAND_IN_TASKS: u32 = 8;

/// The stand-in task cancelled mid-run (on 2 CPUs it starts in the second wave).
const STAND_IN_CANCELLED: u32 = 3;

/// The stand-in job: sleep 2 s, then write the task's file atomically, so a task cancelled
/// mid-run leaves no file.
const STAND_IN: &str = r#"#!/usr/bin/env bash
set -euo pipefail
sleep 2
out="$STAND_IN_OUT/task-$(printf %02d "$SLURM_ARRAY_TASK_ID").txt"
echo "task $SLURM_ARRAY_TASK_ID of array $SLURM_ARRAY_JOB_ID" >"$out.tmp"
mv "$out.tmp" "$out"
"#;

/// Runs the self-test (see the module documentation).
pub fn run() -> Result<(), String> {
    let start = Instant::now();
    timed("install Slurm and munge where missing", install::ensure_slurm)?;
    let shellcheck = timed("install shellcheck where missing", install::ensure_shellcheck)?;
    timed("shellcheck the farm's scripts", || {
        scripts::shellcheck(&shellcheck).map(|n| eprintln!("{n} scripts clean"))
    })?;
    let root = crate::render::output_dir("farm")?;
    let cluster = timed("start munged, slurmctld and slurmd", || Cluster::start_in(&root))?;
    let (ctld, slurmd) = cluster.ports();
    listen::require_loopback_only(&[("slurmctld", ctld), ("slurmd", slurmd)])?;
    eprintln!(
        "cluster: 1 node, {} CPUs; slurmctld on 127.0.0.1:{ctld}, slurmd on 127.0.0.1:{slurmd} (loopback only); {}",
        cluster.cpus(),
        cluster.layout().conf().display()
    );
    timed("stand-in array: cancel a task mid-run, resubmit it", || stand_in(&cluster))?;
    let stub = scripts::install_stub(&root.join("bin"))?;
    let scenario = Scenario::stub(&stub, &root.join("scenario-stub"));
    timed("render scenario with the ggx stub", || scenario::run(&cluster, &scenario))?;
    let pids = cluster.daemon_pids();
    timed("stop the daemons", || {
        cluster.stop();
        let alive: Vec<String> = pids
            .iter()
            .filter(|(_, pid)| Path::new(&format!("/proc/{pid}")).exists())
            .map(|(n, p)| format!("{n} ({p})"))
            .collect();
        if alive.is_empty() { Ok(()) } else { Err(format!("still running: {}", alive.join(", "))) }
    })?;
    eprintln!("\nfarm self-test passed in {:.1} s", start.elapsed().as_secs_f64());
    Ok(())
}

/// The stand-in array: submit 8 tasks, cancel one mid-run, check the files, resubmit it.
fn stand_in(cluster: &Cluster) -> Result<(), String> {
    let dir = cluster.layout().root.join("stand-in");
    if dir.exists() {
        std::fs::remove_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    let out = dir.join("out");
    std::fs::create_dir_all(&out).map_err(|e| format!("{}: {e}", out.display()))?;
    let script = dir.join("stand-in.sh");
    std::fs::write(&script, STAND_IN).map_err(|e| format!("{}: {e}", script.display()))?;
    let spec = |array: String| {
        JobSpec::new(&script).array(array).name("stand-in").env("STAND_IN_OUT", out.display().to_string())
    };
    let timeout = Duration::from_secs(60);
    let k = STAND_IN_CANCELLED;
    let job = cluster.submit(&spec(format!("0-{}", STAND_IN_TASKS - 1)))?;
    cluster.wait_for_task(job, k, |s| *s == TaskState::Running, timeout)?;
    cluster.cancel_task(job, k)?;
    let states = cluster.wait(job, timeout)?;
    eprintln!("array {job}: {}", summary(&states));
    if states.get(&k) != Some(&TaskState::Cancelled) {
        return Err(format!("task {job}_{k} should be CANCELLED"));
    }
    let others: Vec<u32> = (0..STAND_IN_TASKS).filter(|&t| t != k).collect();
    let mut rest = states.clone();
    rest.remove(&k);
    cluster.require_completed(job, &rest, &others)?;
    let present = files(&out)?;
    eprintln!("files: {}", present.join(" "));
    if present != others.iter().map(|t| format!("task-{t:02}.txt")).collect::<Vec<_>>() {
        return Err(format!("expected the files of every task but {k}"));
    }
    let again = cluster.submit(&spec(k.to_string()))?;
    let states = cluster.wait(again, timeout)?;
    cluster.require_completed(again, &states, &[k])?;
    let present = files(&out)?;
    eprintln!("resubmitted {again}_{k}: {}; files: {}", summary(&states), present.join(" "));
    if present.len() != STAND_IN_TASKS as usize {
        return Err(format!("expected {STAND_IN_TASKS} files after the resubmission"));
    }
    Ok(())
}

/// The names of the files in `dir`, sorted (temporary files excluded).
fn files(dir: &Path) -> Result<Vec<String>, String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .map_err(|e| format!("{}: {e}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "txt"))
        .filter_map(|p: PathBuf| p.file_name().map(|n| n.to_string_lossy().into_owned()))
        .collect();
    names.sort();
    Ok(names)
}
