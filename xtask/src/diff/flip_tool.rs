//! FLIP through the `xtask-flip` binary (`xtask/flip`): NVIDIA's FLIP is C++, so it lives in a
//! binary of its own that is built, with a C++ compiler installed first where none is, only
//! when a diff needs it; xtask itself builds with the Rust toolchain alone.

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::{render, system};

/// The built `xtask-flip` binary.
pub struct FlipTool(PathBuf);

impl FlipTool {
    /// Installs a C++ compiler where none is ([`system::ensure_cxx`]) and builds `xtask-flip`
    /// with cargo (a no-op when it is up to date).
    pub fn build() -> Result<FlipTool, String> {
        system::ensure_cxx()?;
        let root = render::workspace_root();
        let status = Command::new(crate::cargo_program())
            .args(["build", "-q", "-p", "xtask-flip"])
            .current_dir(&root)
            .status()
            .map_err(|e| format!("cannot run cargo to build xtask-flip: {e}"))?;
        if !status.success() {
            return Err(format!("cargo build -p xtask-flip failed ({status})"));
        }
        Ok(FlipTool(root.join("target").join("debug").join("xtask-flip")))
    }

    /// Mean FLIP of `test` against `reference` (EXR files); the error map goes to `map`.
    pub fn measure(&self, test: &Path, reference: &Path, map: &Path) -> Result<f64, String> {
        let out = Command::new(&self.0)
            .args([test, reference, map])
            .output()
            .map_err(|e| format!("{}: {e}", self.0.display()))?;
        if !out.status.success() {
            return Err(format!("xtask-flip failed: {}", String::from_utf8_lossy(&out.stderr).trim()));
        }
        let text = String::from_utf8_lossy(&out.stdout);
        text.trim().parse().map_err(|_| format!("xtask-flip printed `{}`, not a number", text.trim()))
    }
}
