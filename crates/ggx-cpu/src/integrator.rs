//! The unidirectional path tracer: next-event estimation toward area lights and the
//! environment, multiple importance sampling (power heuristic) between light and BSDF
//! sampling, Russian roulette (Veach 1997; pbrt-v4's `PathIntegrator`).
//!
//! `trace` is generic over three `const bool`s, `AREA`, `ENV` and `PLASTIC`: a scene
//! without area lights, without an environment or without plastics runs a copy of the
//! kernel with that code compiled out. Every variant draws the same sample dimensions in
//! the same order, so a specialized kernel returns bit-identical radiance to the generic one.

use crate::offset::offset_ray_origin;
use crate::scene_data::SceneData;
use ggx_core::mis::power_heuristic;
use ggx_core::{Frame, SampleStream};
use ggx_render::Bsdf;
use ggx_scene::{LightStrategy, NO_INDEX};
use glam::{Vec2, Vec3};

/// Rays traced by one path, for the rays/s figure.
#[derive(Clone, Copy, Default)]
pub struct Counters {
    /// Closest-hit rays (camera and bounce rays).
    pub rays: u64,
    /// Shadow rays.
    pub shadow_rays: u64,
}

/// The random numbers of one bounce. Drawn after the path is known to continue, and only
/// those the scene can use (`draw` depends on per-scene values alone, never on the kernel
/// variant, so every variant consumes the same dimensions in the same order).
struct BounceSamples {
    bsdf: Vec2,
    lobe: f32,
    light: Vec2,
    select: f32,
    roulette: f32,
}

/// Which dimensions a bounce of this scene consumes.
#[derive(Clone, Copy)]
struct Draws {
    lobe: bool,
    light: bool,
    select: bool,
}

impl BounceSamples {
    #[inline(always)]
    fn draw(stream: &mut SampleStream, draws: Draws, roulette: bool) -> Self {
        let bsdf = stream.next_2d();
        let lobe = if draws.lobe { stream.next_1d() } else { 0.5 };
        let light = if draws.light { stream.next_2d() } else { Vec2::ZERO };
        let select = if draws.select { stream.next_1d() } else { 0.0 };
        let roulette = if roulette { stream.next_1d() } else { 0.5 };
        BounceSamples { bsdf, lobe, light, select, roulette }
    }
}

/// Uniform point on a triangle, Turk 1990 / pbrt: `b0 = 1 - sqrt(u0)`, `b1 = sqrt(u0) (1 - u1)`.
#[inline(always)]
fn sample_triangle(v: [Vec3; 3], u: Vec2) -> Vec3 {
    let su = u.x.max(0.0).sqrt();
    v[0] * (1.0 - su) + v[1] * (su * (1.0 - u.y)) + v[2] * (su * u.y)
}

/// Shading frame around `n` whose tangent `x` follows the latitude circles about world +y
/// (`x = normalize(y_world x n)`), so anisotropic roughness has a predictable direction;
/// within about 0.5 degrees of the poles it falls back to the Duff et al. 2017 basis.
#[inline(always)]
pub fn shading_frame(n: Vec3) -> Frame {
    let t = Vec3::Y.cross(n);
    let len2 = t.length_squared();
    if len2 < 1e-4 {
        return Frame::from_z(n);
    }
    let x = t / len2.sqrt();
    Frame { x, y: n.cross(x), z: n }
}

/// Radiance along the camera ray `(origin, dir)`.
#[inline(always)]
pub fn trace<const AREA: bool, const ENV: bool, const PLASTIC: bool>(
    scene: &SceneData,
    mut origin: Vec3,
    mut dir: Vec3,
    stream: &mut SampleStream,
    counters: &mut Counters,
) -> Vec3 {
    let strategy = scene.light_strategy;
    let use_nee = strategy != LightStrategy::Bsdf;
    let use_mis = strategy == LightStrategy::Mis;
    let has_area = AREA && !scene.lights.is_empty();
    let has_env = ENV && scene.environment.is_some();
    // Probability of choosing each light type in next-event estimation.
    let p_area = if has_area && has_env {
        0.5
    } else if has_area {
        1.0
    } else {
        0.0
    };
    let p_env = if has_env { 1.0 - p_area } else { 0.0 };
    let draws = Draws {
        lobe: scene.features.plastics,
        light: use_nee && (has_area || has_env),
        select: use_nee && has_area && has_env,
    };

    let mut radiance = Vec3::ZERO;
    let mut beta = Vec3::ONE;
    // MIS density of the BSDF sample that produced `dir` (`BsdfSample::mis_pdf`: +inf for a
    // delta lobe). The camera ray counts as a delta: emission it sees is always added.
    let mut prev_pdf = f32::INFINITY;
    let mut depth = 0u32;
    loop {
        counters.rays += 1;
        let Some(hit) = scene.accel.closest(origin, dir, f32::INFINITY) else {
            if has_env && let Some(env) = &scene.environment {
                let le = env.radiance(dir);
                let w = if !use_nee {
                    1.0
                } else if use_mis {
                    power_heuristic(1.0, prev_pdf, 1.0, p_env * env.pdf(dir))
                } else if prev_pdf == f32::INFINITY {
                    // NEE alone cannot find a delta direction: the BSDF sample counts in full.
                    1.0
                } else {
                    0.0
                };
                radiance += beta * le * w;
            }
            break;
        };
        let Some(tri) = scene.triangles.get(hit.triangle as usize) else { break };
        let ng = tri.geometric_normal();
        let p = origin + dir * hit.t;
        let material = tri.material as usize;

        // Emission (front face only).
        if AREA && tri.emitter != NO_INDEX {
            let cos_l = -ng.dot(dir);
            if cos_l > 0.0 {
                let le = scene.emission.get(material).copied().unwrap_or(Vec3::ZERO);
                let w = if !use_nee {
                    1.0
                } else if use_mis {
                    let pdf_area = scene.lights.pdf_area(tri.emitter as usize);
                    power_heuristic(1.0, prev_pdf, 1.0, p_area * pdf_area * hit.t * hit.t / cos_l)
                } else if prev_pdf == f32::INFINITY {
                    1.0
                } else {
                    0.0
                };
                radiance += beta * le * w;
            }
        }
        let bsdf = scene.bsdfs.get(material).copied().unwrap_or(Bsdf::Black);
        if !PLASTIC && matches!(bsdf, Bsdf::Plastic { .. }) {
            break;
        }
        if depth >= scene.max_depth || !bsdf.reflects() {
            break;
        }
        let roulette = scene.roulette_depth > 0 && depth + 1 >= scene.roulette_depth;
        let s = BounceSamples::draw(stream, draws, roulette);

        // Shading frame on the side the ray arrives from (two-sided materials).
        let ng = if ng.dot(dir) > 0.0 { -ng } else { ng };
        let ns = match scene.shading_normals.get(tri.normals as usize) {
            Some(n) if tri.normals != NO_INDEX => {
                let n = n.interpolate(hit.b1, hit.b2);
                if n.dot(ng) < 0.0 { -n } else { n }
            }
            _ => ng,
        };
        let frame = shading_frame(ns);
        let wo = frame.to_local(-dir);
        if wo.z <= 0.0 {
            break;
        }
        let p_out = offset_ray_origin(p, ng);

        // Next-event estimation.
        if use_nee && !bsdf.is_delta() {
            let pick_area = has_area && s.select < p_area;
            if AREA && pick_area {
                let u_emitter = if p_area < 1.0 { s.select / p_area } else { s.select };
                if let Some((e, _pmf, _)) = scene.lights.sample(u_emitter)
                    && let Some(emitter) = scene.lights.emitters.get(e)
                    && let Some(light_tri) = scene.triangles.get(emitter.triangle as usize)
                {
                    let pl = sample_triangle(light_tri.vertices(), s.light);
                    let to_light = pl - p_out;
                    let dist2 = to_light.length_squared();
                    let dist = dist2.sqrt();
                    let wi_world = to_light / dist;
                    let cos_l = -light_tri.geometric_normal().dot(wi_world);
                    let wi = frame.to_local(wi_world);
                    if cos_l > 0.0 && wi.z > 0.0 && wi_world.dot(ng) > 0.0 && dist > 0.0 {
                        let pdf_light = p_area * scene.lights.pdf_area(e) * dist2 / cos_l;
                        let f = bsdf.eval(wo, wi);
                        if f != Vec3::ZERO && pdf_light > 0.0 && pdf_light.is_finite() {
                            counters.shadow_rays += 1;
                            if scene.accel.unoccluded(p_out, wi_world, dist * (1.0 - 1e-3)) {
                                let le = scene.emission.get(light_tri.material as usize).copied().unwrap_or(Vec3::ZERO);
                                let w =
                                    if use_mis { power_heuristic(1.0, pdf_light, 1.0, bsdf.pdf(wo, wi)) } else { 1.0 };
                                radiance += beta * f * le * (w / pdf_light);
                            }
                        }
                    }
                }
            } else if ENV
                && has_env
                && let Some(env) = &scene.environment
            {
                let (wi_world, pdf) = env.sample(s.light);
                let pdf_light = p_env * pdf;
                let wi = frame.to_local(wi_world);
                if wi.z > 0.0 && wi_world.dot(ng) > 0.0 && pdf_light > 0.0 && pdf_light.is_finite() {
                    let f = bsdf.eval(wo, wi);
                    if f != Vec3::ZERO {
                        counters.shadow_rays += 1;
                        if scene.accel.unoccluded(p_out, wi_world, f32::INFINITY) {
                            let w = if use_mis { power_heuristic(1.0, pdf_light, 1.0, bsdf.pdf(wo, wi)) } else { 1.0 };
                            radiance += beta * f * env.radiance(wi_world) * (w / pdf_light);
                        }
                    }
                }
            }
        }

        // BSDF sampling.
        let Some(bs) = bsdf.sample(wo, s.lobe, s.bsdf) else { break };
        let wi_world = frame.to_world(bs.wi);
        if wi_world.dot(ng) <= 0.0 {
            break; // the shading normal sent the ray into the surface
        }
        beta *= bs.weight;
        prev_pdf = bs.mis_pdf();
        origin = p_out;
        dir = wi_world;
        depth += 1;

        // Russian roulette (pbrt-v4): continue with probability max(beta) when it drops below 1.
        if scene.roulette_depth > 0 && depth >= scene.roulette_depth {
            let m = beta.max_element();
            if m < 1.0 {
                let q = (1.0 - m).max(0.0);
                if s.roulette < q {
                    break;
                }
                beta /= 1.0 - q;
            }
        }
        if !beta.is_finite() || beta == Vec3::ZERO {
            break;
        }
    }
    if radiance.is_finite() { radiance } else { Vec3::ZERO }
}
