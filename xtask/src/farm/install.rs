//! Slurm and munge from Debian's packages, installed with apt-get where missing (the way
//! `cargo xtask ci` installs lavapipe, see [`crate::system::apt_install`]), without the
//! recommended plugins: 9 packages instead of 43 on Debian 12.

use crate::system::{apt_install, apt_install_without_recommends};
use std::path::{Path, PathBuf};

/// The programs the farm runs: the three daemons and the client commands.
pub const PROGRAMS: [&str; 8] = ["munged", "slurmctld", "slurmd", "sbatch", "squeue", "scancel", "sinfo", "scontrol"];

/// The Debian packages that hold [`PROGRAMS`] (slurm-wlm: slurmctld, slurmd, slurm-client).
const PACKAGES: [&str; 2] = ["slurm-wlm", "munge"];

/// Where Debian puts daemons, which are not on a user's `PATH`.
const SBIN: [&str; 4] = ["/usr/sbin", "/sbin", "/usr/local/sbin", "/usr/bin"];

/// The absolute path of `program`: searched on `PATH`, then in the sbin directories.
pub fn find_program(program: &str) -> Option<PathBuf> {
    let path = std::env::var_os("PATH").unwrap_or_default();
    std::env::split_paths(&path)
        .chain(SBIN.iter().map(PathBuf::from))
        .map(|dir| dir.join(program))
        .find(|candidate| is_executable(candidate))
}

/// True for a regular file with an execute bit.
fn is_executable(path: &Path) -> bool {
    use std::os::unix::fs::PermissionsExt;
    path.metadata().is_ok_and(|m| m.is_file() && m.permissions().mode() & 0o111 != 0)
}

/// The programs of `wanted` that are not installed.
pub fn missing(wanted: &[&str]) -> Vec<String> {
    wanted.iter().filter(|p| find_program(p).is_none()).map(|p| p.to_string()).collect()
}

/// Installs slurm-wlm and munge with apt-get when any of [`PROGRAMS`] is missing.
pub fn ensure_slurm() -> Result<(), String> {
    let absent = missing(&PROGRAMS);
    if absent.is_empty() {
        return Ok(());
    }
    eprintln!("==> Slurm is not installed ({} missing): installing {}", absent.join(", "), PACKAGES.join(" "));
    let manual = format!("install Slurm and munge by hand: apt-get install -y {}", PACKAGES.join(" "));
    // The daemons, the clients and the basic plugins; not the dozens of recommended plugins.
    apt_install_without_recommends(&PACKAGES, &manual)?;
    let absent = missing(&PROGRAMS);
    if absent.is_empty() { Ok(()) } else { Err(format!("still missing after apt-get: {}", absent.join(", "))) }
}

/// The path of shellcheck, installed with apt-get when missing (the self-test lints the scripts).
pub fn ensure_shellcheck() -> Result<PathBuf, String> {
    if let Some(path) = find_program("shellcheck") {
        return Ok(path);
    }
    eprintln!("==> shellcheck is not installed: installing it");
    apt_install(&["shellcheck"], "install it by hand: apt-get install -y shellcheck")?;
    find_program("shellcheck").ok_or_else(|| "shellcheck still missing after apt-get".to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn programs_are_found_on_path_or_in_sbin() {
        let sh = find_program("sh").expect("every machine has sh");
        assert!(sh.is_absolute() && sh.ends_with("sh"));
        assert!(find_program("no-such-program-of-xtask").is_none());
        assert_eq!(missing(&["sh", "no-such-program-of-xtask"]), ["no-such-program-of-xtask"]);
    }
}
