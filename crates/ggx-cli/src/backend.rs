//! `--backend`: which renderer runs.

use anyhow::Result;

use crate::args::Backend;
use crate::exit::UsageError;

/// A renderer this build can run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Device {
    /// `ggx-cpu`.
    Cpu,
}

const WGPU_UNAVAILABLE: &str = "the wgpu backend is not available in this build";

/// Resolves `--backend` to a renderer of this build; asking for one it lacks is a usage
/// error (exit code 2).
pub fn select(backend: Backend) -> Result<Device> {
    match backend {
        Backend::Cpu => Ok(Device::Cpu),
        Backend::Wgpu => Err(UsageError(WGPU_UNAVAILABLE).into()),
        Backend::Auto => {
            eprintln!("wgpu backend unavailable, rendering on the CPU");
            Ok(Device::Cpu)
        }
    }
}
