//! [`WgpuRenderer`]: the render loop of ggx-cpu on a wgpu adapter, through ggx-render's
//! interface. Same pass schedule
//! ([`ggx_render::pass_end`]), same sample streams, same integrator; each pass is split
//! into dispatches of at most [`DISPATCH_PATHS`] paths so that no dispatch runs long, and the
//! per-pixel sums are read back after every pass and added to a [`Film`]. A render of a sample
//! range or a pixel window dispatches the window's rows only (the columns outside it are
//! traced and dropped); a cancelled pass keeps its finished rows.

use crate::bvh_flat::STACK_SIZE;
use crate::context::{GpuContext, GpuError};
use crate::gpu_scene::GpuScene;
use crate::scene_upload::{Params, SceneTables};
use ggx_film::{Film, Window};
use ggx_render::{
    Job, KernelVariant, Progress, RenderControl, RenderError, RenderOptions, RenderResult, new_film, pass_end,
    time_budget,
};
use ggx_scene::{IntegratorSettings, Scene, SceneFeatures};
use glam::Vec3;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::time::Instant;

/// `(y, samples)` for each row of `window`: the count its pixels hold, which must be the
/// same across the row.
fn row_counts(film: &Film, [x0, y0, x1, y1]: Window) -> Result<Vec<(u32, u32)>, GpuError> {
    let width = film.width() as usize;
    (y0..y1)
        .map(|y| {
            let row = &film.pixels()[y as usize * width + x0 as usize..y as usize * width + x1 as usize];
            let n = row.first().map_or(0, |p| p.samples);
            if row.iter().any(|p| p.samples != n) {
                return Err(GpuError::Render(RenderError::Job(format!(
                    "row {y} of the film to continue holds different sample counts: the GPU continues only films \
                     whose window rows are uniform, as its own are (this one was cut mid-pass or merged from uneven parts)"
                ))));
            }
            Ok((y, n))
        })
        .collect()
}

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

    /// Renders the scene's `spp` samples per pixel, or `options.samples` of `options.window`
    /// (until its time budget or `cancel`, checked between dispatches), in ggx-render's passes.
    /// `options.threads` is ignored; `elapsed` excludes the pipeline compilation.
    pub fn render(&self, options: &RenderOptions, control: &RenderControl) -> Result<RenderResult, GpuError> {
        self.render_film(options, control, new_film(self.params.width, self.params.height)?)
    }

    /// [`WgpuRenderer::render`] continuing `film` (pixel `i` holds samples
    /// `[start, start + film[i].samples)` of the range). Every pixel of a window row must hold
    /// the same count (a GPU pass covers whole rows): films this backend wrote always do.
    pub fn render_film(
        &self,
        options: &RenderOptions,
        control: &RenderControl,
        mut film: Film,
    ) -> Result<RenderResult, GpuError> {
        let variant = self.variant(options.specialize);
        let (width, height) = (self.params.width, self.params.height);
        let job = Job::new(options, self.settings.spp, [width, height])?;
        let held = job.check_film(&film, [width, height])?;
        let mut rows = row_counts(&film, job.window)?;
        // Compiled (once per variant) before the clock starts, like ggx-cpu's BVH build.
        let pipeline = self.gpu.pipeline(self.ctx, variant)?;
        let start = Instant::now();
        let never = AtomicBool::new(false);
        let cancel = control.cancel.unwrap_or(&never);
        let budget = time_budget(&self.settings);
        let [wx0, _, wx1, _] = job.window;
        let (mut traced, mut rays, mut interrupted) = (0u64, 0u64, false);
        // Paths per dispatch, adapted to the adapter's speed (the image does not depend on it).
        let mut paths = FIRST_DISPATCH_PATHS.min(self.dispatch_paths);
        let report = |traced: u64, pass_end: bool, film_spp: u32| {
            if let Some(p) = control.progress {
                p(Progress {
                    spp_done: film_spp,
                    spp_target: job.spp(),
                    samples_done: held + traced,
                    samples_target: u64::from(job.spp()) * job.pixels(),
                    pass_end,
                    elapsed: start.elapsed(),
                });
            }
        };
        'passes: loop {
            let lowest = rows.iter().map(|r| r.1).min().unwrap_or(u32::MAX).saturating_add(job.samples[0]);
            if lowest >= job.samples[1] {
                break;
            }
            let mut to = pass_end(lowest).min(job.samples[1]);
            if let Some(budget) = budget
                && traced > 0
            {
                let elapsed = start.elapsed().as_secs_f64();
                let per_spp = elapsed / (traced as f64 / job.pixels() as f64);
                let fit = ((budget.as_secs_f64() - elapsed) / per_spp).floor();
                if fit < 1.0 {
                    break;
                }
                to = to.min(lowest.saturating_add(fit as u32));
            }
            // Bands of window rows that hold the lowest count, each one dispatch or more.
            let mut finished: Vec<(u32, u32)> = Vec::new();
            let n = to - lowest;
            let row_paths = u64::from(width) * u64::from(n);
            let mut i = 0;
            while i < rows.len() {
                if rows[i].1.saturating_add(job.samples[0]) != lowest {
                    i += 1;
                    continue;
                }
                if cancel.load(Ordering::Relaxed) {
                    interrupted = true;
                    break;
                }
                let band = rows[i..].iter().take_while(|r| r.1 == rows[i].1).count() as u64;
                let count = (paths / row_paths).clamp(1, band) as u32;
                let y0 = rows[i].0;
                let params = Params { y0, rows: count, s0: lowest, s1: to, ..self.params };
                let dispatch_start = Instant::now();
                self.dispatch(&pipeline, &params)?;
                let seconds = dispatch_start.elapsed().as_secs_f64().max(1e-6);
                let rate = (u64::from(count) * row_paths) as f64 / seconds;
                paths = ((rate * DISPATCH_SECONDS) as u64).clamp(1, self.dispatch_paths);
                finished.push((y0, y0 + count));
                traced += u64::from(count) * u64::from(wx1 - wx0) * u64::from(n);
                report(traced, false, rows.iter().map(|r| r.1).min().unwrap_or(0));
                i += count as usize;
            }
            if !finished.is_empty() {
                let (sums, pass_rays) = self.read_back()?;
                rays += pass_rays;
                for &(y0, y1) in &finished {
                    let window: Window = [wx0, y0, wx1, y1];
                    film.add_pass_window(&sums, n, window)
                        .map_err(|e| GpuError::Render(RenderError::Job(e.to_string())))?;
                    for row in rows.iter_mut().filter(|r| (y0..y1).contains(&r.0)) {
                        row.1 += n;
                    }
                }
            }
            if interrupted {
                break 'passes;
            }
            report(traced, true, rows.iter().map(|r| r.1).min().unwrap_or(0));
            if let Some(f) = control.pass_film {
                f(&film);
            }
            if cancel.load(Ordering::Relaxed) {
                interrupted = rows.iter().any(|r| r.1.saturating_add(job.samples[0]) < job.samples[1]);
                break;
            }
        }
        Ok(RenderResult {
            camera_samples: traced,
            spp: rows.iter().map(|r| r.1).min().unwrap_or(0),
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
