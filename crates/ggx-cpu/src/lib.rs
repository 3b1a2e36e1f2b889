//! # ggx-cpu
//!
//! The CPU path tracer of the ggx workspace: an obvhs BVH ([`AccelKind`]), next-event
//! estimation toward area lights and the environment with power-heuristic MIS, Russian
//! roulette, on all cores through rayon.
//!
//! * **Deterministic**: the image depends only on the scene and its seed (see [`render`]
//!   module docs): bit-identical for any thread count.
//! * **Specialized**: [`Renderer::render`] runs a kernel compiled without the features the
//!   scene lacks (area lights, environment, plastics), chosen from
//!   [`ggx_scene::SceneFeatures`]; [`RenderOptions::specialize`] = false runs the generic one.
//!
//! ```no_run
//! let scene = ggx_scene::load_scene(std::path::Path::new("scenes/cornell.toml")).unwrap();
//! let renderer = ggx_cpu::Renderer::new(&scene, ggx_cpu::AccelKind::default());
//! let result = renderer.render(&ggx_cpu::RenderOptions::default(), &ggx_cpu::RenderControl::default()).unwrap();
//! println!("{} spp in {:?}", result.spp, result.elapsed);
//! ```
#![deny(missing_docs)]

mod accel;
mod integrator;
mod offset;
mod ray_triangle;
pub mod render;
mod scene_data;
mod wide_bvh;

pub use accel::{Accel, AccelKind, Hit, PACKET_RAYS};
pub use ggx_render::{
    Bsdf, Job, Progress, RenderControl, RenderError, RenderOptions, RenderResult, pass_end, sampling_for, stream_seed,
};
pub use scene_data::SceneData;

use ggx_core::SequenceKind;
use ggx_scene::{IntegratorSettings, SamplerKind, Scene};
use std::sync::atomic::AtomicBool;
use std::time::Duration;

/// A scene prepared for rendering: BVH built, materials and lights precomputed.
pub struct Renderer {
    data: SceneData,
    settings: IntegratorSettings,
}

impl Renderer {
    /// Builds the BVH and precomputes everything the kernels need.
    pub fn new(scene: &Scene, accel: AccelKind) -> Renderer {
        Renderer { data: SceneData::new(scene, accel), settings: scene.integrator }
    }

    /// Time spent building the BVH.
    pub fn build_time(&self) -> Duration {
        self.data.accel.build_time()
    }

    /// The precomputed scene.
    pub fn data(&self) -> &SceneData {
        &self.data
    }

    /// Renders the scene's `spp` samples per pixel, or `options.samples` of `options.window`
    /// (until the time budget or `cancel`); fails only when the image buffers cannot be
    /// allocated or the range or window do not fit the scene.
    pub fn render(&self, options: &RenderOptions, control: &RenderControl) -> Result<RenderResult, RenderError> {
        let [w, h] = self.data.camera.resolution;
        self.render_film(options, control, ggx_render::new_film(w, h)?)
    }

    /// [`Renderer::render`] continuing `film`: pixel `i` already holds samples
    /// `[start, start + film[i].samples)` of the range, and gets the rest. The result is the
    /// same, bit for bit, as a render that was never stopped.
    pub fn render_film(
        &self,
        options: &RenderOptions,
        control: &RenderControl,
        film: ggx_film::Film,
    ) -> Result<RenderResult, RenderError> {
        let never = AtomicBool::new(false);
        let cancel = control.cancel.unwrap_or(&never);
        let (tile_fn, kernel) = render::select_kernel(&self.data.features, options.specialize);
        let sampling = render::Sampling {
            kind: match self.settings.sampler {
                SamplerKind::Independent => SequenceKind::Independent,
                SamplerKind::Sobol => SequenceKind::Sobol,
            },
            seed: stream_seed(self.settings.seed),
        };
        let job = Job::new(options, self.settings.spp, self.data.camera.resolution)?;
        let budget = ggx_render::time_budget(&self.settings);
        let pool = rayon::ThreadPoolBuilder::new().num_threads(options.threads).build();
        let pool = match pool {
            Ok(p) => p,
            // Thread creation failed (resource limits): fall back to a single worker.
            Err(_) => match rayon::ThreadPoolBuilder::new().num_threads(1).use_current_thread().build() {
                Ok(p) => p,
                Err(_) => return Ok(Self::empty_result(film, kernel)),
            },
        };
        let (pixels, hook) = (job.pixels(), control.progress);
        let progress = |samples_done: u64, pass_end: bool, elapsed: Duration| {
            if let Some(p) = hook {
                p(Progress {
                    spp_done: u32::try_from(samples_done / pixels.max(1)).unwrap_or(u32::MAX),
                    spp_target: job.spp(),
                    samples_done,
                    samples_target: u64::from(job.spp()) * pixels,
                    pass_end,
                    elapsed,
                });
            }
        };
        let pass_film = |film: &ggx_film::Film| {
            if let Some(f) = control.pass_film {
                f(film);
            }
        };
        let report = render::Reporting { progress: &progress, pass_film: &pass_film };
        let outcome = render::run(&self.data, tile_fn, sampling, job, film, budget, &pool, cancel, &report)?;
        Ok(RenderResult {
            camera_samples: outcome.camera_samples,
            spp: render::lowest_held(&outcome.film, job.window),
            film: outcome.film,
            elapsed: outcome.elapsed,
            rays: outcome.rays,
            interrupted: outcome.interrupted,
            kernel,
        })
    }

    /// The result of a render that could not start: `film` as it was, marked interrupted.
    fn empty_result(film: ggx_film::Film, kernel: &'static str) -> RenderResult {
        let spp = film.spp();
        RenderResult { film, spp, elapsed: Duration::ZERO, camera_samples: 0, rays: 0, interrupted: true, kernel }
    }
}
