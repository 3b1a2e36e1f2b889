//! What a camera packet's paths do together: their first bounces drawn ahead with the
//! environment light samples in one batch, and the environment looked up for all their
//! escapes at once, so that the map tables' cache misses overlap.

use super::{BounceSamples, Draws, LightChoice, draws_roulette};
use crate::scene_data::SceneData;
use crate::{Hit, PACKET_RAYS};
use ggx_core::SampleStream;
use ggx_core::sequence::PixelSeeds;
use glam::{Vec2, Vec3};

/// A camera path's first bounce drawn ahead, with the packet's other paths
/// ([`draw_first_bounces`]): its random numbers and, when next-event estimation picks the
/// environment, the environment light sample.
#[derive(Clone, Copy)]
pub struct FirstBounce {
    pub(super) samples: BounceSamples,
    pub(super) env_sample: Option<(Vec3, f32, Vec3)>,
}

/// In a scene whose next-event estimation samples the environment, draws the first bounce
/// of each of a packet's paths whose camera ray hit a surface that is not a delta BSDF
/// (`hits`; `streams` past the pixel jitter; tile pixel `slots[k]`'s seeds in
/// `seeds[slots[k] % PACKET_RAYS]`): the same numbers each path would draw there itself. Then
/// samples the environment for all the paths that pick it, in one batch
/// ([`ggx_scene::Environment::sample_with_radiance_batch`]), so that the table reads' cache
/// misses overlap. Fills `firsts` (`None` for a path not drawn ahead) and returns true, or
/// returns false, leaving `firsts` as it is, when nothing is drawn ahead for this scene.
#[inline(always)]
pub fn draw_first_bounces<const AREA: bool, const ENV: bool>(
    scene: &SceneData,
    hits: &[Option<Hit>],
    streams: &mut [SampleStream],
    slots: &[usize],
    seeds: &mut [PixelSeeds; PACKET_RAYS],
    firsts: &mut [Option<FirstBounce>; PACKET_RAYS],
) -> bool {
    let lights = LightChoice::for_scene::<AREA, ENV>(scene);
    // Drawn ahead only for the environment's light samples.
    if scene.max_depth == 0 || !(lights.use_nee && lights.env_light) {
        return false;
    }
    let (draws, roulette) = (Draws::for_scene(scene, &lights), draws_roulette(scene, 0));
    let mut us = [Vec2::ZERO; PACKET_RAYS];
    let mut which = [0usize; PACKET_RAYS];
    let mut n = 0;
    for (k, (((first, hit), stream), &slot)) in firsts.iter_mut().zip(hits).zip(streams).zip(slots).enumerate() {
        *first = None;
        let Some(hit) = hit else { continue };
        // Judged by the material's untextured BSDF: a textured path that turns out to be a
        // mirror only leaves the numbers drawn for it unused (its stream is its own).
        let material = scene.triangles.get(hit.triangle as usize).map(|t| t.material as usize);
        if material.and_then(|m| scene.bsdfs.get(m)).is_none_or(|b| b.is_delta()) {
            continue;
        }
        let samples = BounceSamples::draw(stream, &mut seeds[slot % PACKET_RAYS], draws, roulette);
        if lights.picks_environment(samples.select) {
            (us[n], which[n]) = (samples.light, k);
            n += 1;
        }
        *first = Some(FirstBounce { samples, env_sample: None });
    }
    if n > 0
        && let Some(env) = scene.environment.as_ref().filter(|_| ENV)
    {
        let mut found = [(Vec3::ZERO, 0.0f32, Vec3::ZERO); PACKET_RAYS];
        env.sample_with_radiance_batch(&us[..n], &mut found[..n]);
        for (&k, &sample) in which.iter().zip(&found).take(n) {
            if let Some(first) = &mut firsts[k] {
                first.env_sample = Some(sample);
            }
        }
    }
    true
}

/// A path that left the scene toward an environment map: what its last term, `beta Le w`,
/// needs. The camera packet looks the environment up for all its escaped paths at once
/// ([`add_escapes`]), so that the map reads' cache misses overlap.
#[derive(Clone, Copy)]
pub struct Escape {
    /// The escaping direction.
    pub(super) dir: Vec3,
    /// The path throughput.
    pub(super) beta: Vec3,
    /// MIS density of the BSDF sample that produced `dir`.
    pub(super) prev_pdf: f32,
}

impl Escape {
    /// The term `beta Le w` for the environment's radiance `le` and density `pdf_env` along
    /// `dir` (`w`: [`LightChoice::emission_weight`]).
    #[inline(always)]
    pub(super) fn term(&self, lights: &LightChoice, le: Vec3, pdf_env: f32) -> Vec3 {
        self.beta * le * lights.emission_weight(self.prev_pdf, || lights.p_env * pdf_env)
    }
}

/// A traced path: the radiance gathered so far and, if it escaped to the environment, the
/// term still to add ([`add_escapes`]); then [`finish`].
#[derive(Clone, Copy, Default)]
pub struct Traced {
    /// Radiance gathered before the escape.
    pub radiance: Vec3,
    /// The escape term, added by [`add_escapes`].
    pub escape: Option<Escape>,
}

/// Adds each escaped path's environment term `beta Le w` to its radiance, the environment
/// looked up for all of `paths` in one batch ([`ggx_scene::Environment::radiance_and_pdf_batch`]):
/// the same bits as adding it where the path escaped.
#[inline(always)]
pub fn add_escapes<const AREA: bool, const ENV: bool>(scene: &SceneData, paths: &mut [Traced; PACKET_RAYS]) {
    let Some(env) = scene.environment.as_ref().filter(|_| ENV) else { return };
    let mut dirs = [Vec3::ZERO; PACKET_RAYS];
    let mut which = [0usize; PACKET_RAYS];
    let mut n = 0;
    for (k, path) in paths.iter().enumerate() {
        if let Some(e) = path.escape {
            (dirs[n], which[n]) = (e.dir, k);
            n += 1;
        }
    }
    if n == 0 {
        return;
    }
    let mut found = [(Vec3::ZERO, 0.0f32); PACKET_RAYS];
    env.radiance_and_pdf_batch(&dirs[..n], &mut found[..n]);
    let lights = LightChoice::for_scene::<AREA, ENV>(scene);
    for (&k, &(le, pdf_env)) in which.iter().zip(&found).take(n) {
        let path = &mut paths[k];
        if let Some(e) = path.escape.take() {
            path.radiance += e.term(&lights, le, pdf_env);
        }
    }
}

/// The sample a traced path adds to its pixel: its radiance, or zero when not finite.
#[inline(always)]
pub fn finish(path: Traced) -> Vec3 {
    if path.radiance.is_finite() { path.radiance } else { Vec3::ZERO }
}
