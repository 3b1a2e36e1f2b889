//! `--backend`: which renderer runs.

use anyhow::{Context, Result};
use ggx_wgpu::{GpuContext, GpuOptions};

use crate::args::Backend;

/// A renderer this build can run.
#[derive(Debug)]
pub enum Device {
    /// `ggx-cpu`.
    Cpu,
    /// `ggx-wgpu` on the adapter of the context.
    Wgpu(GpuContext),
}

/// Resolves `--backend`: `wgpu` fails when no adapter can be had; `auto` renders on the CPU,
/// with a message, when there is none or when the adapter is a software renderer (such as
/// Mesa's llvmpipe: the CPU backend is faster on the same cores). The adapter chosen (see
/// `ggx_wgpu::GpuOptions` for the `WGPU_*` variables) is printed.
pub fn select(backend: Backend) -> Result<Device> {
    match backend {
        Backend::Cpu => Ok(Device::Cpu),
        Backend::Wgpu => {
            let ctx = GpuContext::new(GpuOptions::default()).context("the wgpu backend has no GPU")?;
            eprintln!("wgpu adapter: {}", ctx.describe());
            Ok(Device::Wgpu(ctx))
        }
        Backend::Auto => match GpuContext::new(GpuOptions::default()) {
            Ok(ctx) if ctx.is_software() => {
                eprintln!("wgpu adapter {} is a software renderer: rendering on the CPU backend", ctx.describe());
                Ok(Device::Cpu)
            }
            Ok(ctx) => {
                eprintln!("wgpu adapter: {}", ctx.describe());
                Ok(Device::Wgpu(ctx))
            }
            Err(e) => {
                eprintln!("wgpu backend unavailable ({e}): rendering on the CPU");
                Ok(Device::Cpu)
            }
        },
    }
}
