//! The render loop: passes over 16x16 tiles on a rayon pool, per pixel from the samples the
//! film holds to the pass's end.
//!
//! Determinism: sample `s` of pixel `i` always uses `SampleStream::new(kind, seed, i, s)` and
//! the film sums samples exactly ([`ggx_film::SampleSum`]), so the image depends only on the
//! scene, its seed and the samples held: never on the thread count, the tile order, the pass
//! schedule, how a sample range was split across runs or where a render was resumed. Camera
//! rays go in packets whose make-up follows the pass schedule, so a ray's hit must not depend
//! on its packet ([`crate::Accel::closest_packet`]: ties go to the lower triangle number). Only
//! a time budget, which ends the render after however many passes fit, depends on the clock.

use crate::PACKET_RAYS;
use crate::integrator::{Counters, FirstBounce, Traced, add_escapes, draw_first_bounces, finish, trace};
use crate::scene_data::SceneData;
use ggx_core::sequence::PixelSeeds;
use ggx_core::{SampleStream, SequenceKind};
use ggx_film::{Film, SampleSum, Window};
use ggx_render::{Job, KernelVariant, RenderError, pass_end};
use ggx_scene::SceneFeatures;
use glam::{Vec2, Vec3};
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant};

/// Tile edge in pixels.
const TILE: u32 = 16;

/// Per-pixel sampling set-up shared by all tiles of a render.
#[derive(Clone, Copy)]
pub struct Sampling {
    /// Sequence kind.
    pub kind: SequenceKind,
    /// 32-bit seed folded from the scene's 64-bit seed.
    pub seed: u32,
}

/// What a tile renders: pixel `i` of `rect` from sample `start + film[i].samples` up to `to`.
#[derive(Clone, Copy)]
pub struct TileWork<'a> {
    /// The tile `[x0, y0, x1, y1)`.
    pub rect: Window,
    /// The film so far (read only during a pass).
    pub film: &'a Film,
    /// The first sample of the render's range.
    pub start: u32,
    /// The end of this pass.
    pub to: u32,
}

/// One tile of one pass: per-pixel sums of the new samples, or `None` if the render was
/// cancelled before the tile started.
type TileFn = fn(&SceneData, Sampling, TileWork<'_>, &AtomicBool, &AtomicU64) -> Option<Vec<SampleSum>>;

/// Up to [`PACKET_RAYS`] camera rays of a tile, in pixel and sample order (one pixel's samples
/// or, in passes of few samples, neighbouring pixels'), whose closest hits are found in one
/// walk ([`crate::Accel::closest_packet`]) before each path is traced on.
struct CameraPacket {
    /// The tile's pixel each ray is for.
    slots: [usize; PACKET_RAYS],
    /// Each ray's sample stream, past the pixel jitter.
    streams: [SampleStream; PACKET_RAYS],
    /// Each ray's origin and direction.
    rays: [(Vec3, Vec3); PACKET_RAYS],
    /// Rays held.
    count: usize,
    /// The paths' first bounces when drawn ahead (`draw_first_bounces`).
    firsts: [Option<FirstBounce>; PACKET_RAYS],
}

impl Default for CameraPacket {
    fn default() -> Self {
        let stream = SampleStream { kind: 0, seed: 0, sample_index: 0, dimension: 0 };
        CameraPacket {
            slots: [0; PACKET_RAYS],
            streams: [stream; PACKET_RAYS],
            rays: [(Vec3::ZERO, Vec3::ZERO); PACKET_RAYS],
            count: 0,
            firsts: [None; PACKET_RAYS],
        }
    }
}

impl CameraPacket {
    /// Adds the ray of tile pixel `slot`; true when the packet is full (the caller then traces
    /// it before the next push).
    #[inline(always)]
    fn push(&mut self, slot: usize, stream: SampleStream, ray: (Vec3, Vec3)) -> bool {
        debug_assert!(self.count < PACKET_RAYS, "a full packet was not traced");
        if let (Some(s), Some(st), Some(r)) =
            (self.slots.get_mut(self.count), self.streams.get_mut(self.count), self.rays.get_mut(self.count))
        {
            (*s, *st, *r) = (slot, stream, ray);
            self.count += 1;
        }
        self.count == PACKET_RAYS
    }

    /// Finds the held rays' closest hits together, traces each path on from its hit into
    /// its pixel's sum in `out` (its seeds in `seeds[slot % PACKET_RAYS]`), and empties the packet.
    #[inline(always)]
    fn trace<const AREA: bool, const ENV: bool, const PLASTIC: bool, const DIELECTRIC: bool, const TEX: bool>(
        &mut self,
        scene: &SceneData,
        seeds: &mut [PixelSeeds; PACKET_RAYS],
        out: &mut [SampleSum],
        counters: &mut Counters,
    ) {
        let count = core::mem::take(&mut self.count);
        let mut hits = [None; PACKET_RAYS];
        scene.accel.closest_packet(&self.rays[..count], &mut hits[..count]);
        let drawn = draw_first_bounces::<AREA, ENV>(
            scene,
            &hits[..count],
            &mut self.streams[..count],
            &self.slots[..count],
            seeds,
            &mut self.firsts,
        );
        let mut traced = [Traced::default(); PACKET_RAYS];
        let paths = self.slots.iter().zip(&self.rays).zip(self.streams.iter_mut()).zip(&hits).zip(&mut self.firsts);
        for (((((&slot, &(origin, dir)), stream), &hit), first), path) in paths.zip(&mut traced).take(count) {
            let seeds = &mut seeds[slot % PACKET_RAYS];
            let first = if drawn { first.take() } else { None };
            *path =
                trace::<AREA, ENV, PLASTIC, DIELECTRIC, TEX>(scene, origin, dir, hit, first, stream, seeds, counters);
        }
        add_escapes::<AREA, ENV>(scene, &mut traced);
        for (&slot, &path) in self.slots.iter().zip(&traced).take(count) {
            if let Some(sum) = out.get_mut(slot) {
                sum.add(finish(path));
            }
        }
    }
}

/// Renders one tile's pixels from the samples they hold to `work.to`, with the kernel compiled
/// for x86-64-v3 (AVX2, BMI, VEX encoding) when the CPU has it, else for the build's baseline
/// ([`TileKernel`]): the same bits either way.
fn render_tile<const AREA: bool, const ENV: bool, const PLASTIC: bool, const DIELECTRIC: bool, const TEX: bool>(
    scene: &SceneData,
    sampling: Sampling,
    work: TileWork<'_>,
    cancel: &AtomicBool,
    rays: &AtomicU64,
) -> Option<Vec<SampleSum>> {
    let kernel = TileKernel::<AREA, ENV, PLASTIC, DIELECTRIC, TEX> { scene, sampling, work, cancel, rays };
    #[cfg(target_arch = "x86_64")]
    if let Some(v3) = pulp::x86::V3::try_new() {
        return pulp::Simd::vectorize(v3, kernel);
    }
    kernel.run()
}

/// One tile's arguments, for `pulp`'s dispatch: [`TileKernel::run`] and everything it inlines
/// (the integrator, the camera packets, the BSDFs' sampling and evaluation, the Sobol' draws)
/// compiled into a function with x86-64-v3's target features, or for the baseline.
///
/// Bit-identical by construction: Rust never contracts a multiply and an add into a fused
/// multiply-add, target features or not, and crates that use FMA instructions do so behind
/// `cfg(target_feature = "fma")`, which a function's target features do not turn on (a whole
/// build for x86-64-v3 does: glam's `mul_add` then changes the bits; tested in
/// `v3_and_baseline_kernels_agree`). Measured on the Zen 5 AMD EPYC: SSE2 code spends its time
/// on register copies that VEX's three-operand forms do not need.
struct TileKernel<'a, const AREA: bool, const ENV: bool, const PLASTIC: bool, const DIELECTRIC: bool, const TEX: bool> {
    scene: &'a SceneData,
    sampling: Sampling,
    work: TileWork<'a>,
    cancel: &'a AtomicBool,
    rays: &'a AtomicU64,
}

impl<const AREA: bool, const ENV: bool, const PLASTIC: bool, const DIELECTRIC: bool, const TEX: bool> pulp::WithSimd
    for TileKernel<'_, AREA, ENV, PLASTIC, DIELECTRIC, TEX>
{
    type Output = Option<Vec<SampleSum>>;

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) -> Self::Output {
        self.run()
    }
}

impl<const AREA: bool, const ENV: bool, const PLASTIC: bool, const DIELECTRIC: bool, const TEX: bool>
    TileKernel<'_, AREA, ENV, PLASTIC, DIELECTRIC, TEX>
{
    /// The tile's render, compiled into its caller.
    #[inline(always)]
    fn run(self) -> Option<Vec<SampleSum>> {
        let TileKernel { scene, sampling, work, cancel, rays } = self;
        if cancel.load(Ordering::Relaxed) {
            return None;
        }
        let [x0, y0, x1, y1] = work.rect;
        let width = scene.camera.resolution[0];
        let mut out = vec![SampleSum::default(); ((x1 - x0) * (y1 - y0)) as usize];
        let mut counters = Counters::default();
        // Each pixel's samples share its scramble seeds, hashed once: the seeds of the pixels a
        // packet spans, in a ring (a pixel whose slot was taken gets hashed seeds: the same values).
        let mut seeds: [PixelSeeds; PACKET_RAYS] = core::array::from_fn(|_| PixelSeeds::new(0));
        let mut packet = CameraPacket::default();
        let pixels = (y0..y1).flat_map(|y| (x0..x1).map(move |x| (x, y)));
        for (slot, (x, y)) in pixels.enumerate() {
            let pixel = y * width + x;
            let held = work.film.pixels().get(pixel as usize).map_or(0, |p| p.samples);
            let (first, ring) = (work.start.saturating_add(held), slot % PACKET_RAYS);
            if first < work.to {
                seeds[ring].reset(SampleStream::new(sampling.kind, sampling.seed, pixel, 0).seed);
            }
            for s in first..work.to {
                let mut stream = SampleStream::new(sampling.kind, sampling.seed, pixel, s);
                let jitter = stream.next_2d_with(&mut seeds[ring]);
                let ray = scene.ray_generator.generate_ray(Vec2::new(x as f32, y as f32) + jitter);
                if packet.push(slot, stream, ray) {
                    packet.trace::<AREA, ENV, PLASTIC, DIELECTRIC, TEX>(scene, &mut seeds, &mut out, &mut counters);
                }
            }
        }
        packet.trace::<AREA, ENV, PLASTIC, DIELECTRIC, TEX>(scene, &mut seeds, &mut out, &mut counters);
        rays.fetch_add(counters.rays + counters.shadow_rays, Ordering::Relaxed);
        Some(out)
    }
}

/// Instantiates `render_tile` for a variant: `$v` is the variant, `$($bits),*` every
/// combination of its four flags (area, env, plastic, dielectric).
macro_rules! tile_fns {
    ($v:expr; $(($a:literal, $e:literal, $p:literal, $d:literal)),* $(,)?) => {
        match ($v.area, $v.env, $v.plastic, $v.dielectric) {
            $(($a, $e, $p, $d) => render_tile::<$a, $e, $p, $d, false> as TileFn,)*
        }
    };
}

/// The kernel variant for a scene ([`KernelVariant::for_scene`]): only the features it uses,
/// or everything when `specialize` is false.
pub fn select_kernel(features: &SceneFeatures, specialize: bool) -> (TileFn, &'static str) {
    let v = KernelVariant::for_scene(features, specialize);
    if v.textures {
        // Only the generic kernel carries textures (`KernelVariant::for_scene`).
        return (render_tile::<true, true, true, true, true> as TileFn, KernelVariant::ALL.name());
    }
    let f = tile_fns!(v;
        (false, false, false, false), (true, false, false, false), (false, true, false, false), (true, true, false, false),
        (false, false, true, false), (true, false, true, false), (false, true, true, false), (true, true, true, false),
        (false, false, false, true), (true, false, false, true), (false, true, false, true), (true, true, false, true),
        (false, false, true, true), (true, false, true, true), (false, true, true, true), (true, true, true, true),
    );
    (f, v.name())
}

/// What one call of [`run`] produced.
pub struct Outcome {
    /// The accumulated image.
    pub film: Film,
    /// Whether the cancel flag stopped the render early.
    pub interrupted: bool,
    /// Camera samples traced.
    pub camera_samples: u64,
    /// Rays traced (closest-hit and shadow).
    pub rays: u64,
    /// Wall time.
    pub elapsed: Duration,
}

/// How a render reports: `progress(film_samples, pass_end, elapsed)` as tiles finish (from
/// worker threads) and `pass_film(film)` after each pass.
pub struct Reporting<'a> {
    /// Camera samples the film holds inside the window, whether a pass just ended, the time.
    pub progress: &'a (dyn Fn(u64, bool, Duration) + Sync),
    /// The film after each pass.
    pub pass_film: &'a dyn Fn(&Film),
}

/// Renders `job` into `film` (which may hold samples already: a resumed render), in passes
/// that end at [`pass_end`] boundaries, stopping early on `cancel` (the finished tiles of the
/// pass in flight are kept) or when the time budget would be exceeded.
#[allow(clippy::too_many_arguments)]
pub fn run(
    scene: &SceneData,
    tile_fn: TileFn,
    sampling: Sampling,
    job: Job,
    mut film: Film,
    budget: Option<Duration>,
    pool: &rayon::ThreadPool,
    cancel: &AtomicBool,
    report: &Reporting<'_>,
) -> Result<Outcome, RenderError> {
    let start = Instant::now();
    let [wx0, wy0, wx1, wy1] = job.window;
    let tiles: Vec<Window> = (wy0..wy1)
        .step_by(TILE as usize)
        .flat_map(|y| (wx0..wx1).step_by(TILE as usize).map(move |x| [x, y, (x + TILE).min(wx1), (y + TILE).min(wy1)]))
        .collect();
    let held = job.check_film(&film, scene.camera.resolution)?;
    let (rays, traced) = (AtomicU64::new(0), AtomicU64::new(0));
    let mut interrupted = false;
    loop {
        let lowest = lowest_held(&film, job.window).saturating_add(job.samples[0]);
        if lowest >= job.samples[1] {
            break;
        }
        let mut to = pass_end(lowest).min(job.samples[1]);
        if let Some(budget) = budget {
            let (elapsed, done) = (start.elapsed(), traced.load(Ordering::Relaxed));
            if done > 0 {
                // Fit the next pass into the remaining time at the measured rate.
                let per_spp = elapsed.as_secs_f64() / (done as f64 / job.pixels() as f64);
                let fit = ((budget.as_secs_f64() - elapsed.as_secs_f64()) / per_spp).floor();
                if fit < 1.0 {
                    break;
                }
                to = to.min(lowest.saturating_add(fit as u32));
            }
        }
        let results: Vec<Option<Vec<SampleSum>>> = pool.install(|| {
            tiles
                .par_iter()
                .map(|&rect| {
                    let sums = tile_fn(
                        scene,
                        sampling,
                        TileWork { rect, film: &film, start: job.samples[0], to },
                        cancel,
                        &rays,
                    )?;
                    let n: u64 = sums.iter().map(|s| u64::from(s.samples)).sum();
                    let total = traced.fetch_add(n, Ordering::Relaxed) + n;
                    (report.progress)(held + total, false, start.elapsed());
                    Some(sums)
                })
                .collect()
        });
        for (rect, sums) in tiles.iter().zip(&results) {
            if let Some(sums) = sums {
                // Sizes match by construction and counts stay within the range.
                film.add_window(*rect, sums).map_err(|e| RenderError::Job(e.to_string()))?;
            }
        }
        if results.iter().any(Option::is_none) {
            interrupted = true;
            break;
        }
        (report.progress)(held + traced.load(Ordering::Relaxed), true, start.elapsed());
        (report.pass_film)(&film);
        if cancel.load(Ordering::Relaxed) {
            interrupted = lowest_held(&film, job.window).saturating_add(job.samples[0]) < job.samples[1];
            break;
        }
    }
    Ok(Outcome {
        film,
        interrupted,
        camera_samples: traced.load(Ordering::Relaxed),
        rays: rays.load(Ordering::Relaxed),
        elapsed: start.elapsed(),
    })
}

/// The fewest samples a pixel of `window` holds.
pub fn lowest_held(film: &Film, [x0, y0, x1, y1]: Window) -> u32 {
    let width = film.width() as usize;
    (y0..y1)
        .flat_map(|y| film.pixels()[y as usize * width + x0 as usize..y as usize * width + x1 as usize].iter())
        .map(|p| p.samples)
        .min()
        .unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::AccelKind;
    use std::path::Path;

    /// Every tile of `scene` rendered by `kernel` (dispatched or baseline), pixel sums in order.
    fn tiles(data: &SceneData, film: &Film, spp: u32, dispatched: bool) -> Vec<SampleSum> {
        let [w, h] = data.camera.resolution;
        let (cancel, rays) = (AtomicBool::new(false), AtomicU64::new(0));
        let sampling = Sampling { kind: SequenceKind::Sobol, seed: 7 };
        let mut all = Vec::new();
        for y0 in (0..h).step_by(TILE as usize) {
            for x0 in (0..w).step_by(TILE as usize) {
                let work = TileWork { rect: [x0, y0, (x0 + TILE).min(w), (y0 + TILE).min(h)], film, start: 0, to: spp };
                let sums = if dispatched {
                    render_tile::<true, true, true, true, false>(data, sampling, work, &cancel, &rays)
                } else {
                    TileKernel::<true, true, true, true, false> {
                        scene: data,
                        sampling,
                        work,
                        cancel: &cancel,
                        rays: &rays,
                    }
                    .run()
                };
                all.extend(sums.unwrap());
            }
        }
        all
    }

    #[test]
    fn v3_and_baseline_kernels_agree() {
        #[cfg(target_arch = "x86_64")]
        assert!(
            pulp::x86::V3::try_new().is_some() || std::env::var_os("CI").is_none(),
            "CI runs on x86-64-v3 machines: without AVX2 this test compares the baseline with itself"
        );
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
        // Area light + plastic, an environment map + compensated conductors, glass.
        for name in ["cornell.toml", "peer/bunny.toml", "glass.toml", "peer/anisotropic.toml"] {
            let mut scene = ggx_scene::load_scene(&root.join(name)).unwrap();
            scene.camera.resolution = [40, 24];
            let data = SceneData::new(&scene, AccelKind::Wide);
            let film = ggx_render::new_film(40, 24).unwrap();
            let (a, b) = (tiles(&data, &film, 8, true), tiles(&data, &film, 8, false));
            assert_eq!(a.len(), 40 * 24);
            assert!(a.iter().any(|s| s.rgb != [0; 3]), "{name}: a black image proves nothing");
            assert_eq!(a, b, "{name}: x86-64-v3 kernel vs baseline");
        }
    }
}
