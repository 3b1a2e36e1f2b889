//! The render loop: passes of whole samples per pixel over 16x16 tiles on a rayon pool.
//!
//! Determinism: sample `s` of pixel `i` always uses `SampleStream::new(kind, seed, i, s)`,
//! each pixel's samples are summed in index order inside one tile, and the pass schedule
//! (1, 1, 2, 4, 8, 16, 16, ... samples) does not depend on timing. The image therefore
//! depends only on the scene and its seed, never on the thread count or tile order. Only a
//! time budget, which ends the render after however many passes fit, depends on the clock.

use crate::integrator::{Counters, trace};
use crate::scene_data::SceneData;
use ggx_core::{SampleStream, SequenceKind};
use ggx_film::Film;
use ggx_render::{KernelVariant, RenderError, new_film, pass_spp};
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

/// One tile of one pass: per-pixel radiance sums, or `None` if the render was cancelled.
type TileFn = fn(&SceneData, Sampling, [u32; 4], (u32, u32), &AtomicBool, &AtomicU64) -> Option<Vec<Vec3>>;

/// Renders samples `[s0, s1)` of every pixel of the tile `[x0, y0, x1, y1)`.
fn render_tile<const AREA: bool, const ENV: bool, const PLASTIC: bool, const DIELECTRIC: bool>(
    scene: &SceneData,
    sampling: Sampling,
    [x0, y0, x1, y1]: [u32; 4],
    (s0, s1): (u32, u32),
    cancel: &AtomicBool,
    rays: &AtomicU64,
) -> Option<Vec<Vec3>> {
    if cancel.load(Ordering::Relaxed) {
        return None;
    }
    let width = scene.camera.resolution[0];
    let mut out = Vec::with_capacity(((x1 - x0) * (y1 - y0)) as usize);
    let mut counters = Counters::default();
    for y in y0..y1 {
        for x in x0..x1 {
            let pixel = y * width + x;
            let mut sum = Vec3::ZERO;
            for s in s0..s1 {
                let mut stream = SampleStream::new(sampling.kind, sampling.seed, pixel, s);
                let jitter = stream.next_2d();
                let (origin, dir) = scene.camera.generate_ray(Vec2::new(x as f32, y as f32) + jitter);
                sum += trace::<AREA, ENV, PLASTIC, DIELECTRIC>(scene, origin, dir, &mut stream, &mut counters);
            }
            out.push(sum);
        }
    }
    rays.fetch_add(counters.rays + counters.shadow_rays, Ordering::Relaxed);
    Some(out)
}

/// Instantiates `render_tile` for a variant: `$v` is the variant, `$($bits),*` every
/// combination of its four flags (area, env, plastic, dielectric).
macro_rules! tile_fns {
    ($v:expr; $(($a:literal, $e:literal, $p:literal, $d:literal)),* $(,)?) => {
        match ($v.area, $v.env, $v.plastic, $v.dielectric) {
            $(($a, $e, $p, $d) => render_tile::<$a, $e, $p, $d> as TileFn,)*
        }
    };
}

/// The kernel variant for a scene ([`KernelVariant::for_scene`]): only the features it uses,
/// or everything when `specialize` is false.
pub fn select_kernel(features: &SceneFeatures, specialize: bool) -> (TileFn, &'static str) {
    let v = KernelVariant::for_scene(features, specialize);
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
    /// Rays traced (closest-hit and shadow).
    pub rays: u64,
    /// Wall time.
    pub elapsed: Duration,
}

/// Renders up to `spp` samples per pixel, in passes, stopping early on `cancel` or when the
/// time budget would be exceeded. `progress(spp_done, elapsed)` runs after each pass.
#[allow(clippy::too_many_arguments)]
pub fn run(
    scene: &SceneData,
    tile_fn: TileFn,
    sampling: Sampling,
    spp: u32,
    budget: Option<Duration>,
    pool: &rayon::ThreadPool,
    cancel: &AtomicBool,
    progress: &dyn Fn(u32, Duration),
) -> Result<Outcome, RenderError> {
    let start = Instant::now();
    let [width, height] = scene.camera.resolution;
    let mut film = new_film(width, height)?;
    let tiles: Vec<[u32; 4]> = (0..height.div_ceil(TILE))
        .flat_map(|ty| {
            (0..width.div_ceil(TILE))
                .map(move |tx| [tx * TILE, ty * TILE, ((tx + 1) * TILE).min(width), ((ty + 1) * TILE).min(height)])
        })
        .collect();
    let rays = AtomicU64::new(0);
    // The film's length is the pixel count, and it was allocated: so can the pass be.
    let mut pass_buffer = Vec::new();
    pass_buffer.try_reserve_exact(film.len()).map_err(|_| RenderError::Film {
        width,
        height,
        source: ggx_film::FilmError::TooLarge { width, height },
    })?;
    pass_buffer.resize(film.len(), Vec3::ZERO);
    let (mut done, mut k, mut interrupted) = (0u32, 0u32, false);
    while done < spp {
        let mut n = pass_spp(k).min(spp - done);
        if let Some(budget) = budget {
            let elapsed = start.elapsed();
            if done > 0 {
                // Fit the next pass into the remaining time at the measured rate.
                let per_spp = elapsed.as_secs_f64() / done as f64;
                let left = budget.as_secs_f64() - elapsed.as_secs_f64();
                let fit = (left / per_spp).floor();
                if fit < 1.0 {
                    break;
                }
                n = n.min(fit as u32);
            }
        }
        let results: Vec<Option<Vec<Vec3>>> = pool.install(|| {
            tiles.par_iter().map(|&t| tile_fn(scene, sampling, t, (done, done + n), cancel, &rays)).collect()
        });
        if results.iter().any(Option::is_none) {
            interrupted = true;
            break;
        }
        for (tile, sums) in tiles.iter().zip(results.into_iter().flatten()) {
            let [x0, y0, x1, _] = *tile;
            let w = (x1 - x0) as usize;
            for (row, chunk) in sums.chunks(w).enumerate() {
                let start = ((y0 as usize + row) * width as usize) + x0 as usize;
                pass_buffer[start..start + w].copy_from_slice(chunk);
            }
        }
        // Lengths match by construction; an error here would be a bug in the tiling.
        if film.add_pass(&pass_buffer, n).is_err() {
            break;
        }
        done += n;
        k += 1;
        progress(done, start.elapsed());
        if cancel.load(Ordering::Relaxed) {
            interrupted = done < spp;
            break;
        }
    }
    Ok(Outcome { film, interrupted, rays: rays.load(Ordering::Relaxed), elapsed: start.elapsed() })
}
