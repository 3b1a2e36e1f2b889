//! The distributed render of issue 12 on a real Slurm, written against ggx's command line
//! (`ggx render --samples A..B`, `ggx merge`, `--frame`) and run through the scripts of
//! `scripts/slurm/`:
//!
//! 1. [`single_render`]: one process renders all the samples: the reference.
//! 2. [`split_and_merge`]: `submit.sh` submits the array and the merge job (afterok); the
//!    merged image must equal the reference bit for bit.
//! 3. [`cancel_and_resubmit`]: the same, but one task is cancelled mid-run: it leaves no part
//!    or an interrupted one (ggx writes what it has on SIGTERM), Slurm cancels the merge job,
//!    `ggx merge` fails (without the part, naming the missing range); the task alone is
//!    resubmitted (`--array=K --resume`: it continues its interrupted part), and a merge job
//!    after it must again equal the reference bit for bit.
//! 4. [`frames`]: `frames-array.sbatch` renders one frame of an animation per task.
//!
//! `cargo xtask farm --scenario` runs it with the real ggx; the self-test runs it with the
//! ggx stub ([`super::scripts::GGX_STUB`]), which keeps the scripts and this file tested
//! without a renderer.

use super::cluster::{Cluster, output_within};
use super::jobs::{JobId, JobSpec, TaskState, require_completed, summary};
use super::scripts::slurm_script;
use super::timed;
use crate::render::workspace_root;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

/// How the merged image is compared with the single render.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Compare {
    /// Equal files (the stub's text films).
    Bytes,
    /// Equal size and equal bits of every channel of every pixel (EXR images of ggx).
    ExrPixels,
}

/// One run of the scenario.
#[derive(Clone, Debug)]
pub struct Scenario {
    /// The ggx binary (or the stub), as the jobs see it.
    pub ggx: PathBuf,
    /// The scene split across tasks.
    pub scene: PathBuf,
    /// Samples per pixel of the whole render.
    pub spp: u32,
    /// Array tasks.
    pub tasks: u32,
    /// Further `ggx render` options of every render (e.g. `--width 64`).
    pub render_args: Vec<String>,
    /// Variables that make the tasks of step 3 slow enough to be cancelled mid-run.
    pub slow_env: Vec<(String, String)>,
    /// The task cancelled in step 3.
    pub cancel_task: u32,
    /// How images are compared.
    pub compare: Compare,
    /// The animated scene and frame count of step 4 (none: no step 4).
    pub frames: Option<(PathBuf, u32)>,
    /// Where everything goes (emptied first).
    pub out: PathBuf,
    /// The longest wait for one job.
    pub timeout: Duration,
}

impl Scenario {
    /// The scenario with the ggx stub at `ggx`: small and quick (about 10 s on 2 CPUs).
    pub fn stub(ggx: &Path, out: &Path) -> Scenario {
        let scenes = workspace_root().join("scenes");
        Scenario {
            ggx: ggx.to_path_buf(),
            scene: scenes.join("cornell.toml"),
            spp: 16,
            tasks: 4,
            render_args: vec!["--width".into(), "32".into()],
            slow_env: vec![("GGX_STUB_SLEEP".into(), "2".into())],
            cancel_task: 1,
            compare: Compare::Bytes,
            frames: Some((scenes.join("turntable.toml"), 3)),
            out: out.to_path_buf(),
            timeout: Duration::from_secs(60),
        }
    }

    /// The scenario with the real ggx (see [`Options`] for the sizes).
    pub fn ggx(options: &Options, out: &Path) -> Scenario {
        let scenes = workspace_root().join("scenes");
        Scenario {
            ggx: options.ggx.clone(),
            scene: options.scene.clone(),
            spp: options.spp,
            tasks: options.tasks,
            render_args: vec!["--width".into(), options.width.to_string()],
            slow_env: Vec::new(),
            cancel_task: 1,
            compare: Compare::ExrPixels,
            frames: Some((scenes.join("turntable.toml"), 3)),
            out: out.to_path_buf(),
            timeout: Duration::from_secs(600),
        }
    }

    /// Samples `[first, end)` of task `k`, as render-array.sbatch splits them.
    pub fn range(&self, k: u32) -> (u64, u64) {
        let (k, spp, n) = (u64::from(k), u64::from(self.spp), u64::from(self.tasks));
        (k * spp / n, (k + 1) * spp / n)
    }

    /// The command line of a render of the whole scene.
    fn render_command(&self, output: &Path) -> Command {
        let mut command = Command::new(&self.ggx);
        command.arg("render").arg(&self.scene).arg("--spp").arg(self.spp.to_string()).args(&self.render_args);
        command.arg("-o").arg(output);
        command
    }
}

/// Options of `cargo xtask farm --scenario`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Options {
    /// `--ggx PATH` (default: target/release/ggx, built first with cargo so that it is never
    /// stale).
    pub ggx: PathBuf,
    /// `--scene PATH` (default: scenes/cornell.toml).
    pub scene: PathBuf,
    /// `--spp N` (default 256): large enough that a task runs long enough to be cancelled.
    pub spp: u32,
    /// `--tasks N` (default 8).
    pub tasks: u32,
    /// `--width W` (default 128).
    pub width: u32,
}

impl Options {
    /// Parses the arguments after `--scenario`.
    pub fn parse(args: &[String]) -> Result<Options, String> {
        let root = workspace_root();
        let mut options = Options {
            ggx: PathBuf::new(),
            scene: root.join("scenes").join("cornell.toml"),
            spp: 256,
            tasks: 8,
            width: 128,
        };
        let mut args = args.iter();
        while let Some(arg) = args.next() {
            let mut value = || args.next().ok_or_else(|| format!("farm: {arg} needs a value"));
            let number = |v: &String| v.parse::<u32>().ok().filter(|&n| n > 0).ok_or(format!("farm: {arg} {v}?"));
            match arg.as_str() {
                "--ggx" => options.ggx = PathBuf::from(value()?),
                "--scene" => options.scene = PathBuf::from(value()?),
                "--spp" => options.spp = number(value()?)?,
                "--tasks" => options.tasks = number(value()?)?,
                "--width" => options.width = number(value()?)?,
                other => return Err(format!("farm: unknown argument `{other}`")),
            }
        }
        if options.ggx.as_os_str().is_empty() {
            eprintln!("==> cargo build --release -p ggx-cli (the ggx the scenario runs)");
            let status = Command::new(crate::cargo_program())
                .args(["build", "--release", "-p", "ggx-cli"])
                .current_dir(&root)
                .status()
                .map_err(|e| format!("farm: cannot run cargo: {e}"))?;
            if !status.success() {
                return Err(format!("farm: cargo build --release -p ggx-cli failed ({status})"));
            }
            options.ggx = root.join("target").join("release").join("ggx");
        }
        if options.tasks > options.spp {
            return Err(format!(
                "farm: {} tasks for {} samples: use at most {} tasks",
                options.tasks, options.spp, options.spp
            ));
        }
        if !options.ggx.is_file() {
            return Err(format!("farm: no ggx at {} (give --ggx PATH to a built ggx)", options.ggx.display()));
        }
        Ok(options)
    }
}

/// Runs the four steps; each prints its time.
pub fn run(cluster: &Cluster, s: &Scenario) -> Result<(), String> {
    if s.out.exists() {
        std::fs::remove_dir_all(&s.out).map_err(|e| format!("{}: {e}", s.out.display()))?;
    }
    std::fs::create_dir_all(&s.out).map_err(|e| format!("{}: {e}", s.out.display()))?;
    let reference = timed("single render (the reference)", || single_render(s))?;
    timed(&format!("array of {} tasks and merge job", s.tasks), || split_and_merge(cluster, s, &reference))?;
    timed("cancel a task mid-run, resubmit it, merge", || cancel_and_resubmit(cluster, s, &reference))?;
    if let Some((scene, count)) = &s.frames {
        timed(&format!("{count} frames, one task each"), || frames(cluster, s, scene, *count))?;
    }
    Ok(())
}

/// Renders every sample in one process, outside Slurm; returns the image.
pub fn single_render(s: &Scenario) -> Result<PathBuf, String> {
    let image = s.out.join("single.exr");
    run_ok(&mut s.render_command(&image), s.timeout)?;
    Ok(image)
}

/// The ids `submit.sh` printed.
#[derive(Clone, Copy, Debug)]
pub struct Submitted {
    /// The render array.
    pub array: JobId,
    /// The merge job that waits for it.
    pub merge: JobId,
}

/// Runs `scripts/slurm/submit.sh` for the scenario into `dir`, with `env` added.
pub fn submit(cluster: &Cluster, s: &Scenario, dir: &Path, env: &[(String, String)]) -> Result<Submitted, String> {
    let mut command = cluster.command(slurm_script("submit.sh"));
    command.arg("--ggx").arg(&s.ggx).arg("--spp").arg(s.spp.to_string()).arg("--tasks").arg(s.tasks.to_string());
    command.arg("--out").arg(dir).arg(&s.scene).arg("--").args(&s.render_args);
    command.envs(env.iter().map(|(k, v)| (k, v)));
    let out = run_ok(&mut command, Duration::from_secs(60))?;
    let id = |key: &str| {
        out.lines()
            .find_map(|l| l.strip_prefix(key))
            .and_then(|v| v.trim().parse().ok())
            .map(JobId)
            .ok_or_else(|| format!("submit.sh printed no {key}: {out}"))
    };
    Ok(Submitted { array: id("ARRAY_JOB_ID=")?, merge: id("MERGE_JOB_ID=")? })
}

/// Step 2: the array and its merge job through submit.sh; the merged image equals the reference.
pub fn split_and_merge(cluster: &Cluster, s: &Scenario, reference: &Path) -> Result<(), String> {
    let dir = s.out.join("split");
    let ids = submit(cluster, s, &dir, &[])?;
    let all: Vec<u32> = (0..s.tasks).collect();
    let states = cluster.wait(ids.array, s.timeout)?;
    require_completed(ids.array, &states, &all, |k| dir.join(format!("logs/render-{}_{k}.out", ids.array)))?;
    let merge = cluster.wait(ids.merge, s.timeout)?;
    require_completed(ids.merge, &merge, &[0], |_| dir.join(format!("logs/merge-{}.out", ids.merge)))?;
    same_image(s.compare, &dir.join("merged.exr"), reference)?;
    eprintln!("array {}: {}; merge {}: identical to the single render", ids.array, summary(&states), ids.merge);
    Ok(())
}

/// Step 3: cancel one task mid-run, see the gap refused, resubmit the task alone, merge.
pub fn cancel_and_resubmit(cluster: &Cluster, s: &Scenario, reference: &Path) -> Result<(), String> {
    let dir = s.out.join("cancelled");
    let k = s.cancel_task;
    let ids = submit(cluster, s, &dir, &s.slow_env)?;
    cluster.wait_for_task(ids.array, k, |st| *st == TaskState::Running, s.timeout)?;
    // Into the render proper, past ggx's start-up.
    std::thread::sleep(Duration::from_millis(300));
    cluster.cancel_task(ids.array, k)?;
    let states = cluster.wait(ids.array, s.timeout)?;
    if states.get(&k) != Some(&TaskState::Cancelled) {
        return Err(format!(
            "task {}_{k} was not cancelled mid-run ({}): make the tasks slower",
            ids.array,
            summary(&states)
        ));
    }
    let others: Vec<u32> = (0..s.tasks).filter(|&t| t != k).collect();
    let mut rest = states.clone();
    rest.remove(&k);
    require_completed(ids.array, &rest, &others, |t| dir.join(format!("logs/render-{}_{t}.out", ids.array)))?;
    let merge = cluster.wait(ids.merge, s.timeout)?;
    if merge.get(&0) != Some(&TaskState::Cancelled) {
        return Err(format!(
            "merge job {} should be cancelled (dependency never satisfied): {}",
            ids.merge,
            summary(&merge)
        ));
    }
    // The cancelled task left no part, or the interrupted one ggx writes on SIGTERM: never a
    // complete one. Without it, ggx merge names the missing range; with it, merge still fails.
    let part = |t: u32| dir.join(format!("part-{t:04}.exr"));
    let (first, end) = s.range(k);
    let message =
        merge_fails(s, &dir, &others.iter().map(|&t| part(t)).collect::<Vec<_>>(), &format!("{first}..{end}"))?;
    let left = if part(k).exists() {
        let all: Vec<PathBuf> = (0..s.tasks).map(part).collect();
        merge_fails(s, &dir, &all, "")?;
        "an interrupted part"
    } else {
        "no part"
    };
    eprintln!("array {}: {}; merge job {} cancelled; task {k} left {left}", ids.array, summary(&states), ids.merge);
    eprintln!("ggx merge without it: {}", message.lines().take(3).collect::<Vec<_>>().join(" / "));
    // The task alone, told the total (its array of one does not tell it), continuing its
    // interrupted part where there is one.
    let render = JobSpec::new(slurm_script("render-array.sbatch"))
        .array(k.to_string())
        .args(["--resume".to_string(), "--ggx".into(), s.ggx.display().to_string(), "--spp".into(), s.spp.to_string()])
        .args(["--tasks".to_string(), s.tasks.to_string(), "--out".into(), dir.display().to_string()])
        .args([s.scene.display().to_string(), "--".into()])
        .args(s.render_args.iter().cloned())
        .output(dir.join("logs").join("resubmit-%A_%a.out"));
    let again = cluster.submit(&render)?;
    let states = cluster.wait(again, s.timeout)?;
    require_completed(again, &states, &[k], |t| dir.join(format!("logs/resubmit-{again}_{t}.out")))?;
    let merge = JobSpec::new(slurm_script("merge.sbatch"))
        .after_ok(again)
        .args(["--ggx".to_string(), s.ggx.display().to_string(), "--out".into(), dir.display().to_string()])
        .output(dir.join("logs").join("merge-%j.out"));
    let merge = cluster.submit(&merge)?;
    let merged = cluster.wait(merge, s.timeout)?;
    require_completed(merge, &merged, &[0], |_| dir.join(format!("logs/merge-{merge}.out")))?;
    same_image(s.compare, &dir.join("merged.exr"), reference)?;
    eprintln!(
        "resubmitted task {again}_{k} ({left} before): COMPLETED; merge job {merge}: identical to the single render"
    );
    Ok(())
}

/// Step 4: `frames-array.sbatch` renders frames 0..count of `scene`, one task each, with
/// as many samples as one task of the array.
pub fn frames(cluster: &Cluster, s: &Scenario, scene: &Path, count: u32) -> Result<(), String> {
    let dir = s.out.join("frames");
    let spec = JobSpec::new(slurm_script("frames-array.sbatch"))
        .array(format!("0-{}", count - 1))
        .args(["--ggx".to_string(), s.ggx.display().to_string(), "--out".into(), dir.display().to_string()])
        .args(["--spp".to_string(), (s.spp / s.tasks).max(1).to_string(), scene.display().to_string(), "--".into()])
        .args(s.render_args.iter().cloned());
    let job = cluster.submit(&spec)?;
    let states = cluster.wait(job, s.timeout)?;
    cluster.require_completed(job, &states, &(0..count).collect::<Vec<_>>())?;
    let missing: Vec<String> = (0..count)
        .map(|f| dir.join(format!("frame-{f:04}.png")))
        .filter(|p| !p.is_file())
        .map(|p| p.display().to_string())
        .collect();
    if !missing.is_empty() {
        return Err(format!("frames missing: {}", missing.join(", ")));
    }
    eprintln!("array {job}: {}; {count} frames in {}", summary(&states), dir.display());
    Ok(())
}

/// Fails unless the two images are equal as `compare` says.
pub fn same_image(compare: Compare, image: &Path, reference: &Path) -> Result<(), String> {
    match compare {
        Compare::Bytes => {
            let read = |p: &Path| std::fs::read(p).map_err(|e| format!("{}: {e}", p.display()));
            if read(image)? == read(reference)? {
                Ok(())
            } else {
                Err(format!("{} differs from {}", image.display(), reference.display()))
            }
        }
        Compare::ExrPixels => {
            let read = |p: &Path| ggx_film::read_exr(p).map_err(|e| format!("{}: {e}", p.display()));
            let ((w, h, a), (rw, rh, b)) = (read(image)?, read(reference)?);
            if (w, h) != (rw, rh) {
                return Err(format!("{} is {w}x{h}, {} is {rw}x{rh}", image.display(), reference.display()));
            }
            let bits = |v: &ggx_film::Vec3| v.to_array().map(f32::to_bits);
            let differ: Vec<usize> = (0..a.len()).filter(|&i| bits(&a[i]) != bits(&b[i])).collect();
            match differ.first() {
                None => Ok(()),
                Some(&i) => Err(format!(
                    "{} differs from {} in {} pixels, first ({}, {}): {:?} against {:?}",
                    image.display(),
                    reference.display(),
                    differ.len(),
                    i % w as usize,
                    i / w as usize,
                    a[i],
                    b[i]
                )),
            }
        }
    }
}

/// Runs `ggx merge` of `parts` into `dir/incomplete.exr`: it must fail, write nothing, and say
/// `expected` on stderr; returns what it said.
fn merge_fails(s: &Scenario, dir: &Path, parts: &[PathBuf], expected: &str) -> Result<String, String> {
    let incomplete = dir.join("incomplete.exr");
    let mut command = Command::new(&s.ggx);
    command.arg("merge").args(parts).arg("-o").arg(&incomplete);
    let out = output_within(&mut command, s.timeout)?;
    let stderr = String::from_utf8_lossy(&out.stderr).trim().to_string();
    if out.status.success() || incomplete.exists() || !stderr.contains(expected) {
        return Err(format!(
            "ggx merge of {} parts should fail naming `{expected}`: {}: {stderr}",
            parts.len(),
            out.status
        ));
    }
    Ok(stderr)
}

/// Runs a command to its end; fails with its stderr unless it succeeds; returns its stdout.
fn run_ok(command: &mut Command, timeout: Duration) -> Result<String, String> {
    let out = output_within(command, timeout)?;
    if out.status.success() {
        Ok(String::from_utf8_lossy(&out.stdout).into_owned())
    } else {
        Err(format!("{command:?} failed ({}): {}", out.status, String::from_utf8_lossy(&out.stderr).trim()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_match_the_script_split() {
        let s = Scenario::stub(Path::new("/bin/ggx"), Path::new("/tmp/x"));
        let ranges: Vec<(u64, u64)> = (0..s.tasks).map(|k| s.range(k)).collect();
        assert_eq!(ranges, [(0, 4), (4, 8), (8, 12), (12, 16)]);
    }

    #[test]
    fn scenario_options_are_checked() {
        let args = |a: &[&str]| a.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        let sh = crate::farm::install::find_program("sh").unwrap();
        let sh = sh.to_str().unwrap();
        let options = Options::parse(&args(&["--ggx", sh, "--spp", "16", "--tasks", "4", "--width", "8"])).unwrap();
        assert_eq!((options.spp, options.tasks, options.width), (16, 4, 8));
        assert!(Options::parse(&args(&["--ggx", sh, "--spp", "4", "--tasks", "5"])).unwrap_err().contains("at most 4"));
        assert!(Options::parse(&args(&["--ggx", "/no/ggx"])).unwrap_err().contains("no ggx"));
        assert!(Options::parse(&args(&["--ggx", sh, "--spp", "0"])).is_err());
        assert!(Options::parse(&args(&["--bogus"])).is_err());
    }
}
