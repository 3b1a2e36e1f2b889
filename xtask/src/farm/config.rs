//! The single-node cluster's files under one directory (`target/xtask/farm/`): slurm.conf,
//! the munge key, and the state, spool, log and pid directories.
//!
//! The configuration suits a container: no cgroups (proctrack/linuxproc, task/none), no
//! accounting, every daemon bound to 127.0.0.1 on ports that were free, the node's hardware
//! taken from its configuration (`SlurmdParameters=config_overrides`), and the current user
//! as SlurmUser and SlurmdUser (tested as root, which CI is; as another user, slurmd can run
//! only that user's jobs).

use std::io::Read;
use std::net::TcpListener;
use std::os::unix::fs::{MetadataExt, PermissionsExt};
use std::path::{Path, PathBuf};

/// The node's name (`slurmd -N`), resolved by every machine.
pub const NODE: &str = "localhost";

/// The system's munge key, used where this user owns it (munged refuses a key owned by another).
const SYSTEM_MUNGE_KEY: &str = "/etc/munge/munge.key";

/// Where the cluster's files go; every path is below [`Layout::root`].
#[derive(Clone, Debug)]
pub struct Layout {
    /// The directory of everything else.
    pub root: PathBuf,
}

impl Layout {
    /// The layout under `root` (nothing is created yet, see [`Layout::prepare`]).
    pub fn new(root: &Path) -> Layout {
        Layout { root: root.to_path_buf() }
    }

    /// The slurm.conf that the daemons and, through `SLURM_CONF`, the clients read.
    pub fn conf(&self) -> PathBuf {
        self.root.join("etc").join("slurm.conf")
    }

    /// munged's socket directory (its socket needs a directory everyone may traverse).
    pub fn munge_dir(&self) -> PathBuf {
        self.root.join("munge")
    }

    /// munged's socket.
    pub fn munge_socket(&self) -> PathBuf {
        self.munge_dir().join("munge.socket")
    }

    /// The generated munge key (in a directory only its owner may read).
    pub fn munge_key(&self) -> PathBuf {
        self.root.join("munge-key").join("munge.key")
    }

    /// slurmctld's state (emptied on every start: a fresh cluster).
    pub fn state_dir(&self) -> PathBuf {
        self.root.join("state")
    }

    /// slurmd's spool (emptied on every start).
    pub fn spool_dir(&self) -> PathBuf {
        self.root.join("spool")
    }

    /// The daemons' logs.
    pub fn log_dir(&self) -> PathBuf {
        self.root.join("log")
    }

    /// The daemons' pid files, read to stop daemons an earlier, killed run left behind.
    pub fn run_dir(&self) -> PathBuf {
        self.root.join("run")
    }

    /// The pid file of `daemon` (munged, slurmctld, slurmd).
    pub fn pid_file(&self, daemon: &str) -> PathBuf {
        self.run_dir().join(format!("{daemon}.pid"))
    }

    /// The output files of jobs submitted without their own `--output`.
    pub fn jobs_dir(&self) -> PathBuf {
        self.root.join("jobs")
    }

    /// Creates the directories with the permissions munged demands, emptying the state, spool,
    /// logs and job output of an earlier run.
    pub fn prepare(&self) -> Result<(), String> {
        let text = self.root.to_string_lossy();
        if text.chars().any(char::is_whitespace) || text.contains('#') {
            return Err(format!("{text}: slurm.conf cannot hold a path with spaces or `#`"));
        }
        for dir in [self.state_dir(), self.spool_dir(), self.log_dir(), self.jobs_dir()] {
            if dir.exists() {
                std::fs::remove_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
            }
        }
        let key_dir = self.munge_key().parent().map(Path::to_path_buf).unwrap_or_default();
        let dirs = [
            (self.root.join("etc"), 0o755),
            (self.munge_dir(), 0o755),
            (key_dir, 0o700),
            (self.state_dir(), 0o700),
            (self.spool_dir(), 0o755),
            (self.log_dir(), 0o755),
            (self.run_dir(), 0o755),
            (self.jobs_dir(), 0o755),
        ];
        for (dir, mode) in dirs {
            std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
            std::fs::set_permissions(&dir, std::fs::Permissions::from_mode(mode))
                .map_err(|e| format!("{}: {e}", dir.display()))?;
        }
        Ok(())
    }
}

/// What varies between machines and runs.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Settings {
    /// The user the daemons run as and jobs run as (SlurmUser, SlurmdUser).
    pub user: String,
    /// The node's CPUs: how many one-CPU tasks run at once.
    pub cpus: u32,
    /// slurmctld's port on 127.0.0.1.
    pub ctld_port: u16,
    /// slurmd's port on 127.0.0.1.
    pub slurmd_port: u16,
}

/// The text of slurm.conf for one node, `localhost`, with `settings.cpus` CPUs.
pub fn slurm_conf(layout: &Layout, settings: &Settings) -> String {
    let p = |path: PathBuf| path.display().to_string();
    let Settings { user, cpus, ctld_port, slurmd_port } = settings;
    let lines = [
        "# Written by `cargo xtask farm` for a one-node test cluster; rewritten on every start.".to_string(),
        "ClusterName=ggxfarm".into(),
        format!("SlurmctldHost={NODE}(127.0.0.1)"),
        format!("SlurmctldPort={ctld_port}"),
        format!("SlurmdPort={slurmd_port}"),
        // Bind every daemon to the node's address (127.0.0.1) instead of all interfaces.
        "CommunicationParameters=NoCtldInAddrAny,NoInAddrAny".into(),
        format!("SlurmUser={user}"),
        format!("SlurmdUser={user}"),
        "AuthType=auth/munge".into(),
        "CredType=cred/munge".into(),
        format!("AuthInfo=socket={}", p(layout.munge_socket())),
        format!("StateSaveLocation={}", p(layout.state_dir())),
        format!("SlurmdSpoolDir={}", p(layout.spool_dir())),
        format!("SlurmctldPidFile={}", p(layout.pid_file("slurmctld"))),
        format!("SlurmdPidFile={}", p(layout.pid_file("slurmd"))),
        // No cgroups in a container: plain process tracking, no task binding, no accounting.
        "ProctrackType=proctrack/linuxproc".into(),
        "TaskPlugin=task/none".into(),
        "JobAcctGatherType=jobacct_gather/none".into(),
        "AccountingStorageType=accounting_storage/none".into(),
        "JobCompType=jobcomp/none".into(),
        "MpiDefault=none".into(),
        "SelectType=select/cons_tres".into(),
        "SelectTypeParameters=CR_CPU".into(),
        "SchedulerType=sched/backfill".into(),
        // Start batch jobs at once, not on the next 3 s tick (the default batch_sched_delay).
        "SchedulerParameters=batch_sched_delay=0".into(),
        "MailProg=/bin/true".into(),
        "ReturnToService=2".into(),
        // The node is what this file says, whatever slurmd detects (sockets, cores, memory).
        "SlurmdParameters=config_overrides".into(),
        // Cancelled tasks get SIGTERM, then SIGKILL 2 s later; finished jobs stay visible 5 min.
        "KillWait=2".into(),
        "MinJobAge=300".into(),
        "InactiveLimit=0".into(),
        format!("NodeName={NODE} NodeAddr=127.0.0.1 CPUs={cpus} State=UNKNOWN"),
        format!("PartitionName=farm Nodes={NODE} Default=YES MaxTime=INFINITE State=UP"),
    ];
    lines.join("\n") + "\n"
}

/// Two distinct TCP ports that are free on 127.0.0.1 now.
pub fn free_ports() -> Result<(u16, u16), String> {
    let bind = || TcpListener::bind(("127.0.0.1", 0)).map_err(|e| format!("no free port on 127.0.0.1: {e}"));
    // Both listeners live until both ports are read, so the two differ.
    let (a, b) = (bind()?, bind()?);
    let port = |l: &TcpListener| l.local_addr().map(|a| a.port()).map_err(|e| e.to_string());
    Ok((port(&a)?, port(&b)?))
}

/// The name of the user running this process (`id -un`).
pub fn current_user() -> Result<String, String> {
    let out = std::process::Command::new("id").arg("-un").output().map_err(|e| format!("id -un: {e}"))?;
    let name = String::from_utf8_lossy(&out.stdout).trim().to_string();
    if out.status.success() && !name.is_empty() { Ok(name) } else { Err("id -un: no user name".into()) }
}

/// The id of the user running this process (`id -u`).
fn current_uid() -> Option<u32> {
    let out = std::process::Command::new("id").arg("-u").output().ok()?;
    String::from_utf8_lossy(&out.stdout).trim().parse().ok()
}

/// The munge key munged gets: the system's where this user owns it, else one of 1024 random
/// bytes under the layout (made once, mode 0600).
pub fn munge_key(layout: &Layout) -> Result<PathBuf, String> {
    let system = Path::new(SYSTEM_MUNGE_KEY);
    if let (Ok(meta), Some(uid)) = (system.metadata(), current_uid())
        && meta.uid() == uid
    {
        return Ok(system.to_path_buf());
    }
    let key = layout.munge_key();
    if key.metadata().is_ok_and(|m| m.len() >= 32) {
        return Ok(key);
    }
    let mut bytes = vec![0u8; 1024];
    std::fs::File::open("/dev/urandom")
        .and_then(|mut f| f.read_exact(&mut bytes))
        .map_err(|e| format!("/dev/urandom: {e}"))?;
    std::fs::write(&key, &bytes).map_err(|e| format!("{}: {e}", key.display()))?;
    std::fs::set_permissions(&key, std::fs::Permissions::from_mode(0o600))
        .map_err(|e| format!("{}: {e}", key.display()))?;
    Ok(key)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_config_names_one_node_bound_to_loopback_without_cgroups() {
        let layout = Layout::new(Path::new("/w/target/xtask/farm"));
        let settings = Settings { user: "root".into(), cpus: 2, ctld_port: 40001, slurmd_port: 40002 };
        let conf = slurm_conf(&layout, &settings);
        for line in [
            "SlurmctldHost=localhost(127.0.0.1)",
            "SlurmctldPort=40001",
            "SlurmdPort=40002",
            "CommunicationParameters=NoCtldInAddrAny,NoInAddrAny",
            "SlurmUser=root",
            "AuthInfo=socket=/w/target/xtask/farm/munge/munge.socket",
            "StateSaveLocation=/w/target/xtask/farm/state",
            "ProctrackType=proctrack/linuxproc",
            "TaskPlugin=task/none",
            "JobAcctGatherType=jobacct_gather/none",
            "SelectType=select/cons_tres",
            "SelectTypeParameters=CR_CPU",
            "NodeName=localhost NodeAddr=127.0.0.1 CPUs=2 State=UNKNOWN",
        ] {
            assert!(conf.lines().any(|l| l == line), "missing `{line}` in\n{conf}");
        }
        assert!(!conf.contains("cgroup"), "no cgroup plugin in a container");
    }

    #[test]
    fn free_ports_differ() {
        let (a, b) = free_ports().unwrap();
        assert!(a != b && a > 0 && b > 0);
    }

    #[test]
    fn prepare_makes_the_directories_munged_accepts_and_a_private_key() {
        let root = std::env::temp_dir().join(format!("xtask-farm-layout-{}", std::process::id()));
        let layout = Layout::new(&root);
        layout.prepare().unwrap();
        std::fs::write(layout.state_dir().join("job_state"), "old").unwrap();
        layout.prepare().unwrap();
        assert!(!layout.state_dir().join("job_state").exists(), "every start is a fresh cluster");
        let mode = |p: PathBuf| p.metadata().unwrap().permissions().mode() & 0o777;
        assert_eq!(mode(layout.munge_dir()), 0o755);
        let key = munge_key(&layout).unwrap();
        if key == layout.munge_key() {
            assert_eq!(mode(key.clone()), 0o600);
            assert_eq!(key.metadata().unwrap().len(), 1024);
            assert_eq!(munge_key(&layout).unwrap(), key, "made once");
        }
        assert!(Layout::new(Path::new("/a b")).prepare().is_err(), "no spaces in slurm.conf paths");
        std::fs::remove_dir_all(&root).unwrap();
    }
}
