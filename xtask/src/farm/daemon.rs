//! A daemon run in the foreground as a child of this process, its output in a log file, so
//! stopping it is certain: [`Daemon::stop`] (also on drop) terminates it and reaps it.

use std::fs::File;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// How long a daemon gets to exit after SIGTERM before it is killed.
const STOP_GRACE: Duration = Duration::from_secs(5);

/// A running daemon; dropping it stops it.
#[derive(Debug)]
pub struct Daemon {
    /// Its name in messages, also its `/proc/PID/comm`.
    name: String,
    /// The process.
    child: Child,
    /// Where its stdout and stderr go.
    log: PathBuf,
    /// Set once stopped, so stopping twice is harmless.
    stopped: bool,
}

impl Daemon {
    /// Starts `command` (which must stay in the foreground) with its output appended to `log`.
    pub fn spawn(name: &str, mut command: Command, log: &Path) -> Result<Daemon, String> {
        let file =
            File::options().create(true).append(true).open(log).map_err(|e| format!("{}: {e}", log.display()))?;
        let err = file.try_clone().map_err(|e| format!("{}: {e}", log.display()))?;
        let child = command
            .stdin(Stdio::null())
            .stdout(file)
            .stderr(err)
            .spawn()
            .map_err(|e| format!("starting {name} ({command:?}): {e}"))?;
        Ok(Daemon { name: name.to_string(), child, log: log.to_path_buf(), stopped: false })
    }

    /// The daemon's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The daemon's process id.
    pub fn pid(&self) -> u32 {
        self.child.id()
    }

    /// Fails, with the end of its log, when the daemon has exited.
    pub fn check(&mut self) -> Result<(), String> {
        match self.child.try_wait() {
            Ok(None) => Ok(()),
            Ok(Some(status)) => {
                self.stopped = true;
                Err(format!("{} exited ({status}); {}:\n{}", self.name, self.log.display(), tail(&self.log, 15)))
            }
            Err(e) => Err(format!("{}: {e}", self.name)),
        }
    }

    /// SIGTERM, up to [`STOP_GRACE`] to exit, then SIGKILL; always reaps the process.
    pub fn stop(&mut self) {
        if self.stopped {
            return;
        }
        self.stopped = true;
        if matches!(self.child.try_wait(), Ok(Some(_))) {
            return;
        }
        terminate(self.child.id());
        let deadline = Instant::now() + STOP_GRACE;
        while Instant::now() < deadline {
            if matches!(self.child.try_wait(), Ok(Some(_))) {
                return;
            }
            std::thread::sleep(Duration::from_millis(50));
        }
        eprintln!("farm: {} (pid {}) ignored SIGTERM for {STOP_GRACE:?}: killing it", self.name, self.child.id());
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

impl Drop for Daemon {
    fn drop(&mut self) {
        self.stop();
    }
}

/// Sends SIGTERM to one process by its id (through sh's built-in kill: std has no signals).
fn terminate(pid: u32) {
    let _ = Command::new("sh").arg("-c").arg(format!("kill -TERM {pid}")).stderr(Stdio::null()).status();
}

/// The process name of `pid` (`/proc/PID/comm`), if it runs.
pub fn process_name(pid: u32) -> Option<String> {
    std::fs::read_to_string(format!("/proc/{pid}/comm")).ok().map(|s| s.trim_end().to_string())
}

/// Stops a daemon that an earlier run left behind (killed before it could stop it): the one
/// whose id `pid_file` holds, only if its process name is still `name`.
pub fn stop_stale(pid_file: &Path, name: &str) {
    let Some(pid) = std::fs::read_to_string(pid_file).ok().and_then(|s| s.trim().parse::<u32>().ok()) else {
        return;
    };
    if process_name(pid).as_deref() != Some(name) {
        return;
    }
    eprintln!("farm: stopping {name} (pid {pid}) left running by an earlier run ({})", pid_file.display());
    terminate(pid);
    let deadline = Instant::now() + STOP_GRACE;
    while process_name(pid).as_deref() == Some(name) && Instant::now() < deadline {
        std::thread::sleep(Duration::from_millis(50));
    }
    if process_name(pid).as_deref() == Some(name) {
        let _ = Command::new("sh").arg("-c").arg(format!("kill -KILL {pid}")).status();
    }
}

/// The last `lines` lines of a file (empty when unreadable), for error messages.
pub fn tail(path: &Path, lines: usize) -> String {
    let text = std::fs::read_to_string(path).unwrap_or_default();
    let all: Vec<&str> = text.lines().collect();
    all[all.len().saturating_sub(lines)..].join("\n")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_daemon_is_stopped_and_reaped_on_drop() {
        let dir = std::env::temp_dir().join(format!("xtask-daemon-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let log = dir.join("sleep.log");
        let mut command = Command::new("sh");
        command.arg("-c").arg("echo started; exec sleep 60");
        let mut daemon = Daemon::spawn("sleep", command, &log).unwrap();
        let pid = daemon.pid();
        daemon.check().unwrap();
        // Under load the shell may not have written its line yet: wait for it (not a timing
        // assertion: the deadline only bounds a hang).
        let deadline = Instant::now() + Duration::from_secs(30);
        while tail(&log, 5).is_empty() && Instant::now() < deadline {
            std::thread::sleep(Duration::from_millis(10));
        }
        drop(daemon);
        assert!(process_name(pid).is_none(), "the process is gone, not a zombie");
        assert_eq!(tail(&log, 5), "started");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn an_exited_daemon_fails_its_check_with_its_log() {
        let dir = std::env::temp_dir().join(format!("xtask-daemon-exit-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let log = dir.join("false.log");
        let mut command = Command::new("sh");
        command.arg("-c").arg("echo 'fatal: no config'; exit 3");
        let mut daemon = Daemon::spawn("broken", command, &log).unwrap();
        let deadline = Instant::now() + Duration::from_secs(10);
        let error = loop {
            match daemon.check() {
                Err(e) => break e,
                Ok(()) if Instant::now() < deadline => std::thread::sleep(Duration::from_millis(20)),
                Ok(()) => panic!("sh did not exit"),
            }
        };
        assert!(error.contains("broken exited") && error.contains("fatal: no config"), "{error}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_stale_pid_file_of_another_program_is_left_alone() {
        let dir = std::env::temp_dir().join(format!("xtask-daemon-stale-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let pid_file = dir.join("slurmctld.pid");
        // This test process is not slurmctld: nothing is signalled.
        std::fs::write(&pid_file, format!("{}\n", std::process::id())).unwrap();
        stop_stale(&pid_file, "slurmctld");
        std::fs::write(&pid_file, "not a pid").unwrap();
        stop_stale(&pid_file, "slurmctld");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
