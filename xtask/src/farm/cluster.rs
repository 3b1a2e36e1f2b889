//! [`Cluster`]: a one-node Slurm cluster of this machine, started from nothing and stopped
//! for certain. `Cluster::start()` writes the configuration ([`super::config`]), starts munged,
//! slurmctld and slurmd in the foreground as children of this process, bound to 127.0.0.1,
//! and waits until the node is idle; dropping the cluster cancels every job and stops the
//! three daemons, also when a step failed or panicked.
//!
//! The client commands get `SLURM_CONF` (and none of the caller's `SLURM_*`, `SBATCH_*` and
//! `SQUEUE_*` variables, which would point them at another cluster or partition).

use super::config::{self, Layout, NODE, Settings};
use super::daemon::{self, Daemon};
use super::install;
use super::jobs::{JobId, JobSpec, JobStates, SQUEUE_FORMAT, TaskState, parse_job_id, parse_states, require_completed};
use std::cell::RefCell;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// How often job states are polled.
const POLL: Duration = Duration::from_millis(100);

/// How long one client command may take (Slurm's own timeouts are longer).
const CLIENT_TIMEOUT: Duration = Duration::from_secs(30);

/// How long the node may take to register and become idle.
const START_TIMEOUT: Duration = Duration::from_secs(30);

/// A running one-node cluster; see the module documentation.
pub struct Cluster {
    /// Where its files are.
    layout: Layout,
    /// Its user, CPUs and ports.
    settings: Settings,
    /// munged, slurmctld, slurmd, in start order (stopped in reverse).
    daemons: RefCell<Vec<Daemon>>,
}

/// The file that says which process uses a cluster directory.
const OWNER: &str = "xtask.pid";

/// Claims the cluster directory `root` for this process; fails while another live xtask
/// process holds it (two runs would stop each other's daemons).
fn claim(root: &Path) -> Result<(), String> {
    let owner = root.join(OWNER);
    let me = std::process::id();
    if let Some(pid) = std::fs::read_to_string(&owner).ok().and_then(|s| s.trim().parse::<u32>().ok())
        && pid != me
        && daemon::process_name(pid).is_some()
        && daemon::process_name(pid) == daemon::process_name(me)
    {
        return Err(format!("another `cargo xtask farm` (pid {pid}) is using {}", root.display()));
    }
    std::fs::create_dir_all(root).map_err(|e| format!("{}: {e}", root.display()))?;
    std::fs::write(&owner, format!("{me}\n")).map_err(|e| format!("{}: {e}", owner.display()))
}

/// Gives the cluster directory `root` up, if this process holds it.
fn release(root: &Path) {
    let owner = root.join(OWNER);
    if std::fs::read_to_string(&owner).is_ok_and(|s| s.trim() == std::process::id().to_string()) {
        let _ = std::fs::remove_file(owner);
    }
}

impl Cluster {
    /// Installs Slurm and munge where missing, then starts a cluster under `target/xtask/farm/`.
    pub fn start() -> Result<Cluster, String> {
        install::ensure_slurm()?;
        Cluster::start_in(&crate::render::output_dir("farm")?)
    }

    /// Starts a fresh cluster whose files are under `root` and waits until its node is idle.
    pub fn start_in(root: &Path) -> Result<Cluster, String> {
        claim(root)?;
        let layout = Layout::new(root);
        // Daemons an earlier run could not stop (it was killed) hold the ports and files.
        for daemon in ["slurmd", "slurmctld", "munged"] {
            daemon::stop_stale(&layout.pid_file(daemon), daemon);
        }
        layout.prepare()?;
        let (ctld_port, slurmd_port) = config::free_ports()?;
        let cpus = std::thread::available_parallelism().map_or(1, |n| n.get() as u32);
        let settings = Settings { user: config::current_user()?, cpus, ctld_port, slurmd_port };
        let conf = layout.conf();
        std::fs::write(&conf, config::slurm_conf(&layout, &settings))
            .map_err(|e| format!("{}: {e}", conf.display()))?;
        let key = config::munge_key(&layout)?;
        // From here on an error drops `cluster`, which stops whatever has started.
        let cluster = Cluster { layout, settings, daemons: RefCell::new(Vec::new()) };
        let l = &cluster.layout;
        let path = |p: PathBuf| p.display().to_string();
        cluster.spawn(
            "munged",
            &[
                "--foreground".into(),
                format!("--key-file={}", key.display()),
                format!("--socket={}", path(l.munge_socket())),
                format!("--pid-file={}", path(l.pid_file("munged"))),
                format!("--seed-file={}", path(l.run_dir().join("munged.seed"))),
            ],
        )?;
        let socket = l.munge_socket();
        cluster.wait_until("munged's socket", Duration::from_secs(10), || Ok(socket.exists()))?;
        cluster.spawn("slurmctld", &["-D".into(), "-f".into(), path(conf.clone())])?;
        cluster.spawn("slurmd", &["-D".into(), "-N".into(), NODE.into(), "-f".into(), path(conf)])?;
        cluster.wait_until("the node to be idle", START_TIMEOUT, || {
            // sinfo fails until slurmctld answers: not yet, rather than an error.
            Ok(cluster.run("sinfo", &["--noheader", "--nodes", NODE, "--format=%t"]).is_ok_and(|s| s.trim() == "idle"))
        })?;
        Ok(cluster)
    }

    /// Starts one daemon of the cluster, its output in `log/NAME.log`.
    fn spawn(&self, name: &str, args: &[String]) -> Result<(), String> {
        let program = install::find_program(name).ok_or_else(|| format!("{name} is not installed"))?;
        let mut command = Command::new(program);
        command.args(args).env("SLURM_CONF", self.layout.conf());
        let daemon = Daemon::spawn(name, command, &self.layout.log_dir().join(format!("{name}.log")))?;
        self.daemons.borrow_mut().push(daemon);
        Ok(())
    }

    /// Fails, with the end of its log, when a daemon has exited.
    pub fn check_daemons(&self) -> Result<(), String> {
        self.daemons.borrow_mut().iter_mut().try_for_each(Daemon::check)
    }

    /// Polls `done` until it is true; fails after `timeout` or when a daemon exits.
    fn wait_until(
        &self,
        what: &str,
        timeout: Duration,
        mut done: impl FnMut() -> Result<bool, String>,
    ) -> Result<(), String> {
        let deadline = Instant::now() + timeout;
        loop {
            self.check_daemons()?;
            if done()? {
                return Ok(());
            }
            if Instant::now() > deadline {
                let logs = ["slurmctld", "slurmd"].map(|d| {
                    format!("{d}.log:\n{}", daemon::tail(&self.layout.log_dir().join(format!("{d}.log")), 10))
                });
                return Err(format!("timed out after {timeout:?} waiting for {what}\n{}", logs.join("\n")));
            }
            std::thread::sleep(POLL);
        }
    }

    /// The daemons' names and process ids.
    pub fn daemon_pids(&self) -> Vec<(String, u32)> {
        self.daemons.borrow().iter().map(|d| (d.name().to_string(), d.pid())).collect()
    }

    /// Where the cluster's files are.
    pub fn layout(&self) -> &Layout {
        &self.layout
    }

    /// The node's CPUs: how many one-CPU tasks run at once.
    pub fn cpus(&self) -> u32 {
        self.settings.cpus
    }

    /// slurmctld's and slurmd's ports on 127.0.0.1.
    pub fn ports(&self) -> (u16, u16) {
        (self.settings.ctld_port, self.settings.slurmd_port)
    }

    /// A command for a client program (`sbatch`, `squeue`, ...) or a script that calls them
    /// (a path), set up to talk to this cluster.
    pub fn command(&self, program: impl AsRef<Path>) -> Command {
        let program = program.as_ref();
        let resolved = match program.to_str() {
            Some(name) if !name.contains('/') => install::find_program(name).unwrap_or_else(|| program.to_path_buf()),
            _ => program.to_path_buf(),
        };
        let mut command = Command::new(resolved);
        for (key, _) in std::env::vars_os() {
            let key = key.to_string_lossy();
            if ["SLURM_", "SBATCH_", "SQUEUE_", "SALLOC_", "SRUN_"].iter().any(|p| key.starts_with(p)) {
                command.env_remove(key.as_ref());
            }
        }
        command.env("SLURM_CONF", self.layout.conf());
        command
    }

    /// Runs a client program and returns its standard output; fails with its standard error.
    pub fn run(&self, program: &str, args: &[&str]) -> Result<String, String> {
        let mut command = self.command(program);
        command.args(args);
        let out = output_within(&mut command, CLIENT_TIMEOUT)?;
        if out.status.success() {
            Ok(String::from_utf8_lossy(&out.stdout).into_owned())
        } else {
            Err(format!(
                "`{program} {}` failed ({}): {}",
                args.join(" "),
                out.status,
                String::from_utf8_lossy(&out.stderr).trim()
            ))
        }
    }

    /// Submits a job (sbatch) and returns its id.
    pub fn submit(&self, spec: &JobSpec) -> Result<JobId, String> {
        let mut command = self.command("sbatch");
        command.args(spec.sbatch_args(&self.layout.jobs_dir())).envs(spec.env.iter().map(|(k, v)| (k, v)));
        let out = output_within(&mut command, CLIENT_TIMEOUT)?;
        if !out.status.success() {
            return Err(format!("sbatch {}: {}", spec.script.display(), String::from_utf8_lossy(&out.stderr).trim()));
        }
        parse_job_id(&String::from_utf8_lossy(&out.stdout))
    }

    /// The state of every task of `job` that Slurm still knows (finished jobs stay 5 minutes).
    pub fn states(&self, job: JobId) -> Result<JobStates, String> {
        let id = job.to_string();
        let format = format!("--format={SQUEUE_FORMAT}");
        match self.run("squeue", &["--noheader", "--array", "--states=all", "--jobs", &id, &format]) {
            Ok(text) => parse_states(job, &text),
            // A job Slurm has forgotten has no tasks left.
            Err(e) if e.contains("Invalid job id") => Ok(JobStates::new()),
            Err(e) => Err(e),
        }
    }

    /// Waits until every task of `job` has ended and returns their states.
    pub fn wait(&self, job: JobId, timeout: Duration) -> Result<JobStates, String> {
        let mut states = JobStates::new();
        self.wait_until(&format!("job {job} to end"), timeout, || {
            states = self.states(job)?;
            Ok(states.values().all(TaskState::is_final))
        })?;
        Ok(states)
    }

    /// Waits until task `task` of `job` is in a state `want` accepts and returns it; fails
    /// early when the task ends in another state.
    pub fn wait_for_task(
        &self,
        job: JobId,
        task: u32,
        want: impl Fn(&TaskState) -> bool,
        timeout: Duration,
    ) -> Result<TaskState, String> {
        let mut state = None;
        self.wait_until(&format!("task {job}_{task}"), timeout, || {
            state = self.states(job)?.remove(&task);
            match &state {
                Some(s) if want(s) => Ok(true),
                Some(s) if s.is_final() => Err(format!("task {job}_{task} ended {s} before it was wanted")),
                _ => Ok(false),
            }
        })?;
        Ok(state.expect("set when done"))
    }

    /// Cancels one task of an array (`scancel JOB_K`) and waits until it has ended.
    pub fn cancel_task(&self, job: JobId, task: u32) -> Result<(), String> {
        self.run("scancel", &[&format!("{job}_{task}")])?;
        self.wait_until(&format!("task {job}_{task} to be cancelled"), Duration::from_secs(30), || {
            // A task cancelled before it started leaves no record.
            Ok(self.states(job)?.get(&task).is_none_or(TaskState::is_final))
        })
    }

    /// The output file of a task submitted without its own `--output` (`None`: no array).
    pub fn job_output(&self, job: JobId, task: Option<u32>) -> PathBuf {
        let name = task.map_or_else(|| format!("{job}.out"), |k| format!("{job}_{k}.out"));
        self.layout.jobs_dir().join(name)
    }

    /// Fails unless exactly the tasks `tasks` of `job` are in `states`, all COMPLETED, showing
    /// the end of each other task's output (jobs submitted without their own `--output`).
    pub fn require_completed(&self, job: JobId, states: &JobStates, tasks: &[u32]) -> Result<(), String> {
        require_completed(job, states, tasks, |k| self.job_output(job, Some(k)))
    }

    /// Cancels every job and stops the daemons (what dropping the cluster does).
    pub fn stop(mut self) {
        self.shutdown();
    }

    /// Cancels every job, waits for them to end, then stops slurmd, slurmctld and munged.
    fn shutdown(&mut self) {
        if self.daemons.borrow().is_empty() {
            return;
        }
        if self.check_daemons().is_ok() {
            // No job step may outlive slurmd: cancel everything first.
            let _ = self.run("scancel", &["--user", &self.settings.user]);
            let deadline = Instant::now() + Duration::from_secs(15);
            while Instant::now() < deadline {
                match self
                    .run("squeue", &["--noheader", "--states=PENDING,RUNNING,COMPLETING,CONFIGURING", "--format=%i"])
                {
                    Ok(text) if text.trim().is_empty() => break,
                    Ok(_) => std::thread::sleep(POLL),
                    Err(_) => break,
                }
            }
        }
        let mut daemons = self.daemons.borrow_mut();
        while let Some(mut daemon) = daemons.pop() {
            daemon.stop();
        }
        release(&self.layout.root);
    }
}

impl Drop for Cluster {
    fn drop(&mut self) {
        self.shutdown();
    }
}

/// Runs `command` to its end with its output captured, killing it after `timeout`.
pub fn output_within(command: &mut Command, timeout: Duration) -> Result<Output, String> {
    let mut child = command
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| format!("{command:?}: {e}"))?;
    // Readers on their own threads, so a chatty command never blocks on a full pipe.
    let read = |pipe: Option<Box<dyn std::io::Read + Send>>| {
        std::thread::spawn(move || {
            let mut bytes = Vec::new();
            if let Some(mut pipe) = pipe {
                let _ = pipe.read_to_end(&mut bytes);
            }
            bytes
        })
    };
    let stdout = read(child.stdout.take().map(|p| Box::new(p) as Box<dyn std::io::Read + Send>));
    let stderr = read(child.stderr.take().map(|p| Box::new(p) as Box<dyn std::io::Read + Send>));
    let deadline = Instant::now() + timeout;
    let status = loop {
        if let Some(status) = child.try_wait().map_err(|e| format!("{command:?}: {e}"))? {
            break status;
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            return Err(format!("{command:?} did not finish within {timeout:?}"));
        }
        std::thread::sleep(Duration::from_millis(10));
    };
    let stdout = stdout.join().unwrap_or_default();
    let stderr = stderr.join().unwrap_or_default();
    Ok(Output { status, stdout, stderr })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Stays alive for XTASK_FARM_SLEEP_MS when set: the other owner of the test below.
    #[test]
    fn sleeps_when_asked() {
        if let Some(ms) = std::env::var("XTASK_FARM_SLEEP_MS").ok().and_then(|v| v.parse().ok()) {
            std::thread::sleep(Duration::from_millis(ms));
        }
    }

    #[test]
    fn a_cluster_directory_has_one_owner_at_a_time() {
        let root = std::env::temp_dir().join(format!("xtask-farm-claim-{}", std::process::id()));
        claim(&root).unwrap();
        claim(&root).unwrap();
        // Another live process of this program holds it.
        let mut other = Command::new(std::env::current_exe().unwrap())
            .args(["--exact", "farm::cluster::tests::sleeps_when_asked", "--quiet"])
            .env("XTASK_FARM_SLEEP_MS", "20000")
            .stdout(Stdio::null())
            .spawn()
            .unwrap();
        std::fs::write(root.join(OWNER), format!("{}\n", other.id())).unwrap();
        let held = claim(&root);
        other.kill().unwrap();
        other.wait().unwrap();
        assert!(held.unwrap_err().contains("another `cargo xtask farm`"));
        // Once it has exited, its claim is stale.
        claim(&root).unwrap();
        release(&root);
        assert!(!root.join(OWNER).exists());
        std::fs::remove_dir_all(&root).unwrap();
    }

    #[test]
    fn a_command_is_cut_off_at_its_timeout() {
        let mut quick = Command::new("sh");
        quick.arg("-c").arg("echo out; echo err >&2");
        let out = output_within(&mut quick, Duration::from_secs(10)).unwrap();
        assert_eq!((out.stdout.as_slice(), out.stderr.as_slice()), (&b"out\n"[..], &b"err\n"[..]));
        let mut slow = Command::new("sleep");
        slow.arg("30");
        let start = Instant::now();
        assert!(output_within(&mut slow, Duration::from_millis(200)).is_err());
        assert!(start.elapsed() < Duration::from_secs(10));
    }
}
