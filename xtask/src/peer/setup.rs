//! Everything `cargo xtask peer` needs besides Rust, installed on first use and checked
//! (quickly) on every run after: Debian's `libllvm19` for Dr.Jit's LLVM backend (apt-get,
//! [`crate::system::apt_install`]), a Python virtual environment under
//! `target/xtask/peer/venv` with the pinned Mitsuba 3 and Dr.Jit from PyPI, the driver script
//! written next to it, and the release `ggx`.
//!
//! Dr.Jit looks for `libLLVM.so` by itself and, on a machine where Mesa pulled in LLVM 15,
//! finds that one and aborts; the driver therefore always runs with `DRJIT_LIBLLVM_PATH`
//! naming LLVM 19 ([`find_llvm`]).

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::render;
use crate::system;

/// The packages the venv gets (`pip install`), the versions this comparison was verified with.
pub const REQUIREMENTS: [&str; 3] = ["mitsuba==3.9.1", "drjit==1.5.0", "numpy>=1.24,<3"];

/// The Debian package of LLVM 19's shared library.
const LLVM_PACKAGE: &str = "libllvm19";

/// Where distributions put `libLLVM.so.19.1` (or the `-19` name).
const LLVM_PATHS: [&str; 6] = [
    "/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1",
    "/usr/lib/x86_64-linux-gnu/libLLVM-19.so",
    "/usr/lib/aarch64-linux-gnu/libLLVM.so.19.1",
    "/usr/lib/aarch64-linux-gnu/libLLVM-19.so",
    "/usr/lib/llvm-19/lib/libLLVM.so.19.1",
    "/usr/lib64/libLLVM.so.19.1",
];

/// The driver script, written to `target/xtask/peer/mitsuba_driver.py`.
pub const DRIVER: &str = include_str!("mitsuba_driver.py");

/// What the run needs, ready.
#[derive(Clone, Debug)]
pub struct Setup {
    /// The venv's Python.
    pub python: PathBuf,
    /// The driver script.
    pub driver: PathBuf,
    /// LLVM 19 for Dr.Jit.
    pub llvm: PathBuf,
    /// The release `ggx`.
    pub ggx: PathBuf,
}

/// The first of `candidates` that exists.
pub fn find_llvm(candidates: &[&str]) -> Option<PathBuf> {
    candidates.iter().map(PathBuf::from).find(|p| p.is_file())
}

/// Installs or checks everything, in order: LLVM 19, the venv and its packages, the driver, the
/// release ggx (`cargo build --release -p ggx-cli`).
pub fn ensure(peer_dir: &Path) -> Result<Setup, String> {
    let llvm = match find_llvm(&LLVM_PATHS) {
        Some(p) => p,
        None => {
            eprintln!("\n==> no LLVM 19 found: installing {LLVM_PACKAGE} for Dr.Jit's LLVM backend");
            system::apt_install(&[LLVM_PACKAGE], &format!("install it by hand: `apt-get install -y {LLVM_PACKAGE}`"))?;
            find_llvm(&LLVM_PATHS)
                .ok_or_else(|| format!("{LLVM_PACKAGE} is installed but no libLLVM.so.19.1 was found"))?
        }
    };
    let python = ensure_venv(&peer_dir.join("venv"))?;
    let driver = peer_dir.join("mitsuba_driver.py");
    if std::fs::read_to_string(&driver).ok().as_deref() != Some(DRIVER) {
        crate::bench::files::write_atomic(&driver, DRIVER.as_bytes())?;
    }
    crate::cargo(&["build", "--release", "-p", "ggx-cli"])?;
    let ggx = render::workspace_root().join("target").join("release").join("ggx");
    if !ggx.is_file() {
        return Err(format!("{}: not built", ggx.display()));
    }
    Ok(Setup { python, driver, llvm, ggx })
}

/// Runs `program args`, failing with its output.
fn run(program: &Path, args: &[&str]) -> Result<String, String> {
    let line = format!("{} {}", program.display(), args.join(" "));
    let out = Command::new(program).args(args).output().map_err(|e| format!("{line}: {e}"))?;
    if out.status.success() {
        Ok(String::from_utf8_lossy(&out.stdout).into_owned())
    } else {
        Err(format!("`{line}` failed ({}): {}", out.status, String::from_utf8_lossy(&out.stderr).trim()))
    }
}

/// The venv at `dir` with [`REQUIREMENTS`] installed; creates it (`python3 -m venv`, with
/// apt-get's `python3-venv` where `ensurepip` is missing) and runs pip only when the marker
/// file written after a successful install is missing or names other requirements.
fn ensure_venv(dir: &Path) -> Result<PathBuf, String> {
    let python = dir.join("bin").join("python");
    let marker = dir.join(".ggx-peer-requirements");
    let wanted = REQUIREMENTS.join(" ");
    if python.is_file() && std::fs::read_to_string(&marker).ok().as_deref() == Some(wanted.as_str()) {
        return Ok(python);
    }
    if !python.is_file() {
        eprintln!("\n==> creating the Python venv {}", dir.display());
        let dir_s = dir.to_string_lossy().into_owned();
        if run(Path::new("python3"), &["-m", "venv", &dir_s]).is_err() {
            let _ = std::fs::remove_dir_all(dir);
            system::apt_install(&["python3-venv"], "install Python's venv module: `apt-get install -y python3-venv`")?;
            run(Path::new("python3"), &["-m", "venv", &dir_s])?;
        }
    }
    eprintln!("\n==> pip install {wanted} (the Mitsuba wheel is large; once)");
    let mut args = vec!["-m", "pip", "install", "--disable-pip-version-check", "-q"];
    args.extend(REQUIREMENTS);
    let status = Command::new(&python).args(&args).status().map_err(|e| format!("{}: {e}", python.display()))?;
    if !status.success() {
        return Err(format!("`{} {}` failed ({status})", python.display(), args.join(" ")));
    }
    crate::bench::files::write_atomic(&marker, wanted.as_bytes())?;
    Ok(python)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_the_first_existing_library() {
        let dir = std::env::temp_dir().join(format!("xtask-peer-llvm-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let lib = dir.join("libLLVM.so.19.1");
        let missing = dir.join("none.so");
        assert_eq!(find_llvm(&[missing.to_str().unwrap(), lib.to_str().unwrap()]), None);
        std::fs::write(&lib, b"").unwrap();
        assert_eq!(find_llvm(&[missing.to_str().unwrap(), lib.to_str().unwrap()]), Some(lib.clone()));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn requirements_are_pinned_and_the_driver_is_embedded() {
        assert!(REQUIREMENTS.iter().any(|r| r.starts_with("mitsuba==")));
        assert!(REQUIREMENTS.iter().any(|r| r.starts_with("drjit==")));
        assert!(DRIVER.contains("def render(") && DRIVER.contains("def microbench("));
    }
}
