//! [`WgpuRenderer`]: the render loop of ggx-cpu on a wgpu adapter, through ggx-render's
//! interface. Same pass schedule
//! ([`ggx_render::pass_spp`]), same sample streams, same integrator; each pass is split
//! into dispatches of at most [`DISPATCH_PATHS`] paths so that no dispatch runs long, and the
//! per-pixel sums are read back after every pass and added to a [`Film`].

use crate::bvh_flat::STACK_SIZE;
use crate::context::{GpuContext, GpuError};
use crate::gpu_scene::GpuScene;
use crate::scene_upload::{Params, SceneTables};
use ggx_render::{
    KernelVariant, Progress, RenderControl, RenderOptions, RenderResult, new_film, pass_spp, time_budget,
};
use ggx_scene::{IntegratorSettings, Scene, SceneFeatures};
use glam::Vec3;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::time::Instant;

/// Most camera paths (pixels times samples) one dispatch traces.
pub const DISPATCH_PATHS: u64 = 1 << 18;
/// Camera paths of the first dispatch; later ones are sized from the measured rate.
const FIRST_DISPATCH_PATHS: u64 = 1 << 12;
/// Wall time one dispatch aims at: short enough that the cancel flag, checked between
/// dispatches, is honoured well within a second even on a software adapter.
const DISPATCH_SECONDS: f64 = 0.1;
/// Workgroup edge of `render` in `path_tracer.wgsl`.
const WORKGROUP: u32 = 8;

/// A scene uploaded to a GPU, ready to render.
pub struct WgpuRenderer<'a> {
    ctx: &'a GpuContext,
    gpu: GpuScene,
    params: Params,
    features: SceneFeatures,
    settings: IntegratorSettings,
    dispatch_paths: u64,
}

impl<'a> WgpuRenderer<'a> {
    /// Flattens the scene (BVH2, materials, lights, environment) and uploads it.
    pub fn new(scene: &Scene, ctx: &'a GpuContext) -> Result<WgpuRenderer<'a>, GpuError> {
        let tables = SceneTables::new(scene);
        if tables.bvh.depth > STACK_SIZE {
            return Err(GpuError::Wgpu(format!(
                "BVH depth {} exceeds the shader's traversal stack of {STACK_SIZE}",
                tables.bvh.depth
            )));
        }
        let gpu = GpuScene::new(ctx, &tables)?;
        Ok(WgpuRenderer {
            ctx,
            gpu,
            params: tables.params,
            features: scene.features,
            settings: scene.integrator,
            dispatch_paths: DISPATCH_PATHS,
        })
    }

    /// Caps the camera paths of one dispatch (default [`DISPATCH_PATHS`]; at least one row is
    /// dispatched). Below the cap, dispatches are sized to take about 0.1 s at the measured
    /// rate, so that cancelling is prompt on any adapter; the image is the same for any split.
    pub fn with_dispatch_paths(mut self, paths: u64) -> Self {
        self.dispatch_paths = paths.max(1);
        self
    }

    /// The kernel variant for the scene's features (everything when `specialize` is false).
    pub fn variant(&self, specialize: bool) -> KernelVariant {
        KernelVariant::for_scene(&self.features, specialize)
    }

    /// Renders the scene's `spp` samples per pixel (or until its time budget or `cancel`,
    /// checked between dispatches), in ggx-render's passes. `options.threads` is ignored;
    /// `elapsed` excludes the pipeline compilation.
    pub fn render(&self, options: &RenderOptions, control: &RenderControl) -> Result<RenderResult, GpuError> {
        let variant = self.variant(options.specialize);
        // Compiled (once per variant) before the clock starts, like ggx-cpu's BVH build.
        let pipeline = self.gpu.pipeline(self.ctx, variant)?;
        let start = Instant::now();
        let never = AtomicBool::new(false);
        let cancel = control.cancel.unwrap_or(&never);
        let (width, height) = (self.params.width, self.params.height);
        let spp = self.settings.spp.max(1);
        let budget = time_budget(&self.settings);
        let mut film = new_film(width, height)?;
        let (mut done, mut k, mut rays, mut interrupted) = (0u32, 0u32, 0u64, false);
        // Paths per dispatch, adapted to the adapter's speed (the image does not depend on it).
        let mut paths = FIRST_DISPATCH_PATHS.min(self.dispatch_paths);
        'passes: while done < spp {
            let mut n = pass_spp(k).min(spp - done);
            if let Some(budget) = budget
                && done > 0
            {
                let elapsed = start.elapsed().as_secs_f64();
                let fit = ((budget.as_secs_f64() - elapsed) / (elapsed / f64::from(done))).floor();
                if fit < 1.0 {
                    break;
                }
                n = n.min(fit as u32);
            }
            let row_paths = u64::from(width) * u64::from(n);
            let mut y0 = 0;
            while y0 < height {
                if cancel.load(Ordering::Relaxed) {
                    interrupted = true;
                    break 'passes;
                }
                let rows = (paths / row_paths).clamp(1, u64::from(height - y0)) as u32;
                let params = Params { y0, rows, s0: done, s1: done + n, ..self.params };
                let dispatch_start = Instant::now();
                self.dispatch(&pipeline, &params)?;
                let seconds = dispatch_start.elapsed().as_secs_f64().max(1e-6);
                let rate = (u64::from(rows) * row_paths) as f64 / seconds;
                paths = ((rate * DISPATCH_SECONDS) as u64).clamp(1, self.dispatch_paths);
                y0 += rows;
            }
            let (sums, pass_rays) = self.read_back()?;
            rays += pass_rays;
            film.add_pass(&sums, n).map_err(|e| GpuError::Wgpu(e.to_string()))?;
            done += n;
            k += 1;
            if let Some(p) = control.progress {
                p(Progress { spp_done: done, spp_target: spp, elapsed: start.elapsed() });
            }
            if cancel.load(Ordering::Relaxed) {
                interrupted = done < spp;
                break;
            }
        }
        Ok(RenderResult {
            camera_samples: u64::from(done) * u64::from(width) * u64::from(height),
            spp: done,
            film,
            elapsed: start.elapsed(),
            rays,
            interrupted,
            kernel: variant.name(),
        })
    }

    /// One dispatch over rows `[y0, y0 + rows)`, waited for.
    fn dispatch(&self, pipeline: &wgpu::ComputePipeline, params: &Params) -> Result<(), GpuError> {
        let device = self.ctx.device();
        let queue = self.ctx.queue();
        crate::parity::checked(device, || {
            queue.write_buffer(&self.gpu.params, 0, bytemuck::bytes_of(params));
            let mut encoder =
                device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("ggx pass") });
            {
                let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some("ggx pass"),
                    timestamp_writes: None,
                });
                pass.set_pipeline(pipeline);
                pass.set_bind_group(0, &self.gpu.bind_group, &[]);
                pass.dispatch_workgroups(params.width.div_ceil(WORKGROUP), params.rows.div_ceil(WORKGROUP), 1);
            }
            queue.submit([encoder.finish()]);
        })?;
        device.poll(wgpu::PollType::wait_indefinitely())?;
        Ok(())
    }

    /// Copies the per-pixel sums back: radiance per pixel and the pass's ray count.
    fn read_back(&self) -> Result<(Vec<Vec3>, u64), GpuError> {
        let device = self.ctx.device();
        crate::parity::checked(device, || {
            let mut encoder =
                device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("ggx copy") });
            encoder.copy_buffer_to_buffer(&self.gpu.output, 0, &self.gpu.readback, 0, self.gpu.output_size);
            self.ctx.queue().submit([encoder.finish()]);
        })?;
        let slice = self.gpu.readback.slice(..);
        let (tx, rx) = mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |result| {
            let _ = tx.send(result);
        });
        device.poll(wgpu::PollType::wait_indefinitely())?;
        rx.recv().map_err(|e| GpuError::Wgpu(e.to_string()))??;
        let view = slice.get_mapped_range().map_err(|e| GpuError::Wgpu(e.to_string()))?;
        let words: &[[f32; 4]] = bytemuck::cast_slice(&view);
        let sums = words.iter().map(|w| Vec3::new(w[0], w[1], w[2])).collect();
        let rays = words.iter().map(|w| u64::from(w[3].to_bits())).sum();
        drop(view);
        self.gpu.readback.unmap();
        Ok((sums, rays))
    }
}
