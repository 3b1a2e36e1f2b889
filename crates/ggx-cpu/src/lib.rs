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
//! let result = renderer.render(&ggx_cpu::RenderOptions::default(), &ggx_cpu::RenderControl::default());
//! println!("{} spp in {:?}", result.spp, result.elapsed);
//! ```
#![deny(missing_docs)]

mod accel;
mod bsdf;
mod integrator;
mod offset;
pub mod render;
mod scene_data;

pub use accel::{Accel, AccelKind, Hit};
pub use bsdf::{Bsdf, sampling_for};
pub use scene_data::SceneData;

use ggx_core::SequenceKind;
use ggx_film::Film;
use ggx_scene::{IntegratorSettings, SamplerKind, Scene};
use std::sync::atomic::AtomicBool;
use std::time::Duration;

/// How to run a render (the scene file decides what to render).
#[derive(Clone, Copy, Debug)]
pub struct RenderOptions {
    /// Worker threads; 0 = one per core.
    pub threads: usize,
    /// Run the kernel specialized to the scene's features (default) or the generic one.
    pub specialize: bool,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions { threads: 0, specialize: true }
    }
}

/// Progress reported after each pass.
#[derive(Clone, Copy, Debug)]
pub struct Progress {
    /// Samples per pixel accumulated so far.
    pub spp_done: u32,
    /// Samples per pixel requested.
    pub spp_target: u32,
    /// Time since the render started.
    pub elapsed: Duration,
}

/// Optional hooks into a running render.
#[derive(Clone, Copy, Default)]
pub struct RenderControl<'a> {
    /// Set it to stop after the current pass; the image keeps every completed pass.
    pub cancel: Option<&'a AtomicBool>,
    /// Called after every pass.
    pub progress: Option<&'a (dyn Fn(Progress) + Sync)>,
}

/// A finished (or interrupted) render.
pub struct RenderResult {
    /// Accumulated radiance.
    pub film: Film,
    /// Samples per pixel in `film`.
    pub spp: u32,
    /// Wall time of the render (BVH build excluded).
    pub elapsed: Duration,
    /// Camera samples traced (`spp * pixels`).
    pub camera_samples: u64,
    /// Rays traced (closest-hit and shadow rays).
    pub rays: u64,
    /// True when the cancel flag stopped the render before its target.
    pub interrupted: bool,
    /// The kernel variant that ran (e.g. `"area+env"`).
    pub kernel: &'static str,
}

/// A scene prepared for rendering: BVH built, materials and lights precomputed.
pub struct Renderer {
    data: SceneData,
    settings: IntegratorSettings,
}

/// Folds the scene's 64-bit seed into the 32-bit seed of the sample streams.
pub fn stream_seed(seed: u64) -> u32 {
    (seed ^ (seed >> 32)) as u32
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

    /// Renders the scene's `spp` samples per pixel (or until its time budget or `cancel`).
    pub fn render(&self, options: &RenderOptions, control: &RenderControl) -> RenderResult {
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
        let spp = self.settings.spp.max(1);
        let budget = self.settings.time_budget.filter(|t| *t > 0.0 && t.is_finite()).map(Duration::from_secs_f32);
        let pool = rayon::ThreadPoolBuilder::new().num_threads(options.threads).build();
        let pool = match pool {
            Ok(p) => p,
            // Thread creation failed (resource limits): fall back to a single worker.
            Err(_) => match rayon::ThreadPoolBuilder::new().num_threads(1).use_current_thread().build() {
                Ok(p) => p,
                Err(_) => return self.empty_result(kernel),
            },
        };
        let report = |done: u32, elapsed: Duration| {
            if let Some(p) = control.progress {
                p(Progress { spp_done: done, spp_target: spp, elapsed });
            }
        };
        let outcome = render::run(&self.data, tile_fn, sampling, spp, budget, &pool, cancel, &report);
        let [w, h] = self.data.camera.resolution;
        let done = outcome.film.spp();
        RenderResult {
            camera_samples: done as u64 * w as u64 * h as u64,
            spp: done,
            film: outcome.film,
            elapsed: outcome.elapsed,
            rays: outcome.rays,
            interrupted: outcome.interrupted,
            kernel,
        }
    }

    fn empty_result(&self, kernel: &'static str) -> RenderResult {
        let [w, h] = self.data.camera.resolution;
        RenderResult {
            film: Film::new(w, h),
            spp: 0,
            elapsed: Duration::ZERO,
            camera_samples: 0,
            rays: 0,
            interrupted: true,
            kernel,
        }
    }
}
