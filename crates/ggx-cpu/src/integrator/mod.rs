//! The unidirectional path tracer: next-event estimation toward area lights and the
//! environment, multiple importance sampling (power heuristic) between light and BSDF
//! sampling, Russian roulette (Veach 1997; pbrt-v4's `PathIntegrator`).
//!
//! `trace` is generic over four `const bool`s, `AREA`, `ENV`, `PLASTIC` and `DIELECTRIC`: a
//! scene without area lights, without an environment, without plastics or without dielectrics
//! runs a copy of the kernel with that code compiled out.
//!
//! Dielectrics: a path transmitted into a dielectric's inside (the side its geometric normal
//! does not point to) travels through that dielectric's absorbing medium until it is
//! transmitted out again (Beer-Lambert `exp(-sigma t)` per segment). Media do not nest: a
//! path inside one glass that enters another takes the second's medium and leaves into
//! vacuum. Shadow rays stop at every surface, glass included (no caustics through glass by
//! next-event estimation: those paths are found by BSDF sampling). Russian roulette decides on
//! `beta` without the `1 / eta'^2` radiance scaling of the transmissions so far (pbrt-v4's
//! `etaScale`), so a path inside dense glass is not killed for a factor that leaving undoes.
//!
//! Every variant draws the same sample dimensions in the same order, so a specialized kernel
//! returns bit-identical radiance to the generic one.
//!
//! A camera packet's paths share two steps whose table reads miss the caches on a large
//! environment map: their first bounces are drawn ahead with the environment light samples
//! in one batch ([`draw_first_bounces`]), and the map is looked up for all the escaped paths
//! at once ([`add_escapes`]). Each batch's reads do not wait for one another, so their misses
//! overlap; each path gets the bits it would compute alone.

mod light_choice;
mod packet;
#[cfg(test)]
mod tests;

pub use light_choice::LightChoice;
pub use packet::{Escape, FirstBounce, Traced, add_escapes, draw_first_bounces, finish};

use crate::Hit;
use crate::offset::offset_ray_origin;
use crate::scene_data::SceneData;
use ggx_core::mis::power_heuristic;
use ggx_core::sequence::PixelSeeds;
use ggx_core::{Frame, SampleStream};
use ggx_render::{
    Bsdf, anisotropy_direction, metal_rough_bsdf, normal_map_at, perturb_normal, tangent_at, tangent_frame,
};
use ggx_scene::{Environment, NO_INDEX, PUNCTUAL_DIRECTIONAL};
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
#[derive(Clone, Copy)]
pub struct BounceSamples {
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

impl Draws {
    /// The dimensions a bounce of `scene` consumes with lights chosen as `lights` says.
    #[inline(always)]
    fn for_scene(scene: &SceneData, lights: &LightChoice) -> Self {
        Draws {
            lobe: scene.uses_lobe_sample,
            light: lights.use_nee && (lights.has_area || lights.env_light || lights.has_punctual),
            // Area lights need the dimension to pick an emitter even without another light type.
            select: lights.use_nee && (lights.has_area || lights.has_punctual),
        }
    }
}

/// Whether the bounce at `depth` draws a Russian roulette number (from `roulette_depth` on).
#[inline(always)]
fn draws_roulette(scene: &SceneData, depth: u32) -> bool {
    scene.roulette_depth > 0 && depth + 1 >= scene.roulette_depth
}

impl BounceSamples {
    #[inline(always)]
    fn draw(stream: &mut SampleStream, seeds: &mut PixelSeeds, draws: Draws, roulette: bool) -> Self {
        let bsdf = stream.next_2d_with(seeds);
        let lobe = if draws.lobe { stream.next_1d_with(seeds) } else { 0.5 };
        let light = if draws.light { stream.next_2d_with(seeds) } else { Vec2::ZERO };
        let select = if draws.select { stream.next_1d_with(seeds) } else { 0.0 };
        let roulette = if roulette { stream.next_1d_with(seeds) } else { 0.5 };
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

/// True when `wi` (shading frame) and `wi_world` lie on the same side of the geometric
/// normal `ng` (the frame's `+z` side is `ng`'s), and, for a material that does not
/// transmit, on the `+z` side.
#[inline(always)]
fn sides_agree(wi: Vec3, wi_world: Vec3, ng: Vec3, transmits: bool) -> bool {
    let side = wi_world.dot(ng);
    if transmits { side * wi.z > 0.0 } else { wi.z > 0.0 && side > 0.0 }
}

/// `f |wi.z|` and, with MIS, the BSDF's density of `wi` (`Bsdf::eval_pdf`, one half vector
/// for both); without MIS the density is not needed and is 0.
#[inline(always)]
fn bsdf_eval_pdf(bsdf: &Bsdf, wo: Vec3, wi: Vec3, use_mis: bool) -> (Vec3, f32) {
    if use_mis { bsdf.eval_pdf(wo, wi) } else { (bsdf.eval(wo, wi), 0.0) }
}

/// Beer-Lambert transmittance `exp(-sigma t)` of a segment of finite length `t`, 1 in the
/// channels that do not absorb.
#[inline(always)]
fn transmittance(sigma: Vec3, t: f32) -> Vec3 {
    let e = |s: f32| if s > 0.0 { (-s * t).exp() } else { 1.0 };
    Vec3::new(e(sigma.x), e(sigma.y), e(sigma.z))
}

/// Transmittance of an infinite segment (a ray that leaves an open absorbing mesh): 0 in
/// the channels that absorb, 1 in the others. Spelled out rather than `exp(-sigma inf)`, which
/// a GPU need not evaluate to 0.
#[inline(always)]
fn escape_transmittance(sigma: Vec3) -> Vec3 {
    let e = |s: f32| if s > 0.0 { 0.0 } else { 1.0 };
    Vec3::new(e(sigma.x), e(sigma.y), e(sigma.z))
}

/// The absorption of the segment leaving a vertex toward `wi` (`wi_z` in the shading frame):
/// a dielectric with an inside decides by the side (its own absorption inside, vacuum
/// outside); any other material leaves the ray in the medium `current` it was in.
#[inline(always)]
fn segment_medium(bsdf: &Bsdf, current: Vec3, wi_z: f32) -> Vec3 {
    if !bsdf.has_inside() {
        current
    } else if wi_z < 0.0 {
        bsdf.absorption()
    } else {
        Vec3::ZERO
    }
}

/// Radiance along the camera ray `(origin, dir)`, whose closest hit `camera_hit` is already
/// found (camera rays are traced in packets: [`crate::Accel::closest_packet`]), its random
/// numbers drawn from `stream` with the pixel's scramble seeds kept in `seeds`.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub fn trace<const AREA: bool, const ENV: bool, const PLASTIC: bool, const DIELECTRIC: bool, const TEX: bool>(
    scene: &SceneData,
    mut origin: Vec3,
    mut dir: Vec3,
    camera_hit: Option<Hit>,
    mut first: Option<FirstBounce>,
    stream: &mut SampleStream,
    seeds: &mut PixelSeeds,
    counters: &mut Counters,
) -> Traced {
    let lights = LightChoice::for_scene::<AREA, ENV>(scene);
    let LightChoice { use_nee, use_mis, has_env, env_light, p_area, p_punctual, p_env, .. } = lights;
    let draws = Draws::for_scene(scene, &lights);

    let mut radiance = Vec3::ZERO;
    let mut beta = Vec3::ONE;
    // MIS density of the BSDF sample that produced `dir` (`BsdfSample::mis_pdf`: +inf for a
    // delta lobe). The camera ray counts as a delta: emission it sees is always added.
    let mut prev_pdf = f32::INFINITY;
    let mut depth = 0u32;
    // Absorption coefficient of the medium the ray travels in (zero: vacuum).
    let mut sigma = Vec3::ZERO;
    // Product of eta'^2 over the transmissions so far: undoes their radiance scaling for
    // Russian roulette (pbrt-v4's `etaScale`).
    let mut eta_scale = 1.0f32;
    // The camera ray's hit, then each bounce's.
    let mut given = Some(camera_hit);
    loop {
        counters.rays += 1;
        let hit = match given.take() {
            Some(hit) => hit,
            None => scene.accel.closest(origin, dir, f32::INFINITY),
        };
        if DIELECTRIC && sigma != Vec3::ZERO {
            // A ray inside an open mesh that escapes has crossed an infinite medium.
            beta *= match hit {
                Some(h) => transmittance(sigma, h.t),
                None => escape_transmittance(sigma),
            };
        }
        let Some(hit) = hit else {
            if has_env && let Some(env) = &scene.environment {
                let escape = Escape { dir, beta, prev_pdf };
                if let Environment::Map(_) = env {
                    // A map's term is added with the packet's other escapes (`add_escapes`): its
                    // texel reads are cache misses worth overlapping.
                    return Traced { radiance, escape: Some(escape) };
                }
                let (le, pdf_env) = env.radiance_and_pdf(dir);
                radiance += escape.term(&lights, le, pdf_env);
            }
            break;
        };
        let Some(tri) = scene.triangles.get(hit.triangle as usize) else { break };
        let ng = scene.geometric_normals.get(hit.triangle as usize).copied().unwrap_or(Vec3::ZERO);
        let p = origin + dir * hit.t;
        let material = tri.material as usize;

        // Emission (front face only).
        if AREA && tri.emitter != NO_INDEX {
            let cos_l = -ng.dot(dir);
            if cos_l > 0.0 {
                let le = if TEX {
                    scene.emission_at(material, tri, hit.b1, hit.b2)
                } else {
                    scene.emission.get(material).copied().unwrap_or(Vec3::ZERO)
                };
                let w = lights.emission_weight(prev_pdf, || {
                    p_area * scene.lights.pdf_area(tri.emitter as usize) * hit.t * hit.t / cos_l
                });
                radiance += beta * le * w;
            }
        }
        let mut bsdf = scene.bsdfs.get(material).copied().unwrap_or(Bsdf::Black);
        // A textured material: its BSDF and normal at this point.
        let mut mapped_normal = None;
        let textured = if TEX { scene.textured.get(material).copied().flatten() } else { None };
        if let Some(m) = &textured {
            let uv = scene.uv_at(tri, hit.b1, hit.b2);
            bsdf = metal_rough_bsdf(m, &scene.textures, uv, scene.sampling);
            mapped_normal = normal_map_at(m, &scene.textures, uv);
        }
        if (!PLASTIC && matches!(bsdf, Bsdf::Plastic { .. })) || (!DIELECTRIC && bsdf.transmits()) {
            break;
        }
        if depth >= scene.max_depth || !bsdf.reflects() {
            break;
        }
        // The first bounce's numbers may be drawn already (`draw_first_bounces`): the same ones.
        let (s, mut env_sample) = match first.take() {
            Some(f) => (f.samples, f.env_sample),
            None => (BounceSamples::draw(stream, seeds, draws, draws_roulette(scene, depth)), None),
        };

        // Shading frame: on the side the ray arrives from for two-sided materials, around the
        // outward normal for a dielectric with an inside (`wo.z < 0` from inside).
        let inside = DIELECTRIC && bsdf.has_inside();
        let ng = if !inside && ng.dot(dir) > 0.0 { -ng } else { ng };
        let ns = match scene.shading_normals.get(tri.normals as usize) {
            Some(n) if tri.normals != NO_INDEX => {
                let mut n = n.interpolate(hit.b1, hit.b2);
                if let (Some(nt), Some(uvs)) = (mapped_normal, scene.uvs.get(tri.normals as usize)) {
                    let tangents = scene.tangents.get(tri.normals as usize);
                    n = perturb_normal(n, nt, tri.vertices(), uvs, tangents, hit.b1, hit.b2);
                }
                if n.dot(ng) < 0.0 { -n } else { n }
            }
            _ => ng,
        };
        let mut frame = shading_frame(ns);
        if let Some(m) = textured.filter(|m| m.anisotropy != 0.0)
            && let Some(uvs) = scene.uvs.get(tri.normals as usize)
        {
            // KHR_materials_anisotropy: alpha_x along the mesh's tangent turned by the rotation.
            let tangents = scene.tangents.get(tri.normals as usize);
            if let Some((t, w)) = tangent_at(ns, tri.vertices(), uvs, tangents, hit.b1, hit.b2)
                && let Some((t, b)) = tangent_frame(ns, t, w)
            {
                let x = anisotropy_direction(t, b, m.anisotropy_rotation);
                if x != Vec3::ZERO {
                    frame = Frame { x, y: ns.cross(x), z: ns };
                }
            }
        }
        let wo = frame.to_local(-dir);
        // The shading normal must agree with the geometric side the ray arrives from.
        if !(wo.z * -ng.dot(dir) > 0.0) {
            break;
        }
        let p_out = offset_ray_origin(p, if wo.z > 0.0 { ng } else { -ng });
        let transmits = DIELECTRIC && bsdf.transmits();

        // Next-event estimation.
        if use_nee && !bsdf.is_delta() {
            let (pick_area, pick_punctual) = lights.pick(s.select);
            if AREA && pick_punctual {
                // One punctual light, uniformly: a delta light, no MIS.
                let n = scene.punctual_lights.len();
                let u = ((s.select - p_area) / p_punctual).max(0.0);
                let i = ((u * n as f32) as usize).min(n - 1);
                if let Some(light) = scene.punctual_lights.get(i) {
                    let pmf = p_punctual / n as f32;
                    let (wi_world, dist) = if light.kind == PUNCTUAL_DIRECTIONAL {
                        (-Vec3::from(light.direction), f32::INFINITY)
                    } else {
                        let to = Vec3::from(light.position) - p;
                        let d = to.length();
                        (to / d, d)
                    };
                    let wi = frame.to_local(wi_world);
                    let li = light.incident(wi_world, dist);
                    if dist > 0.0
                        && wi_world.is_finite()
                        && li != Vec3::ZERO
                        && sides_agree(wi, wi_world, ng, transmits)
                    {
                        let f = bsdf.eval(wo, wi);
                        if f != Vec3::ZERO {
                            counters.shadow_rays += 1;
                            let origin = if transmits { offset_ray_origin(p, ng * wi.z.signum()) } else { p_out };
                            let tmax = if dist.is_finite() {
                                (Vec3::from(light.position) - origin).length() * (1.0 - 1e-3)
                            } else {
                                f32::INFINITY
                            };
                            let tr = if DIELECTRIC {
                                let sigma = segment_medium(&bsdf, sigma, wi.z);
                                if dist.is_finite() { transmittance(sigma, dist) } else { escape_transmittance(sigma) }
                            } else {
                                Vec3::ONE
                            };
                            if tr != Vec3::ZERO && scene.accel.unoccluded(origin, wi_world, tmax) {
                                radiance += beta * f * tr * li / pmf;
                            }
                        }
                    }
                }
            } else if AREA && pick_area {
                let u_emitter = if p_area < 1.0 { s.select / p_area } else { s.select };
                if let Some((e, _pmf, _)) = scene.lights.sample(u_emitter)
                    && let Some(emitter) = scene.lights.emitters.get(e)
                    && let Some(light_tri) = scene.triangles.get(emitter.triangle as usize)
                    && let Some(&light_ng) = scene.geometric_normals.get(emitter.triangle as usize)
                {
                    let pl = sample_triangle(light_tri.vertices(), s.light);
                    // The sampled point's barycentrics (`sample_triangle`'s weights of v1, v2).
                    let su = s.light.x.max(0.0).sqrt();
                    let (lb1, lb2) = (su * (1.0 - s.light.y), su * s.light.y);
                    // Offset toward the light's side of the surface.
                    let origin = if transmits { offset_ray_origin(p, ng * (pl - p).dot(ng).signum()) } else { p_out };
                    let to_light = pl - origin;
                    let dist2 = to_light.length_squared();
                    let dist = dist2.sqrt();
                    let wi_world = to_light / dist;
                    let cos_l = -light_ng.dot(wi_world);
                    let wi = frame.to_local(wi_world);
                    if cos_l > 0.0 && sides_agree(wi, wi_world, ng, transmits) && dist > 0.0 {
                        let pdf_light = p_area * scene.lights.pdf_area(e) * dist2 / cos_l;
                        let (f, pdf_bsdf) = bsdf_eval_pdf(&bsdf, wo, wi, use_mis);
                        if f != Vec3::ZERO && pdf_light > 0.0 && pdf_light.is_finite() {
                            counters.shadow_rays += 1;
                            if scene.accel.unoccluded(origin, wi_world, dist * (1.0 - 1e-3)) {
                                let lm = light_tri.material as usize;
                                let le = if TEX {
                                    scene.emission_at(lm, light_tri, lb1, lb2)
                                } else {
                                    scene.emission.get(lm).copied().unwrap_or(Vec3::ZERO)
                                };
                                let w = if use_mis { power_heuristic(1.0, pdf_light, 1.0, pdf_bsdf) } else { 1.0 };
                                let tr = if DIELECTRIC {
                                    transmittance(segment_medium(&bsdf, sigma, wi.z), dist)
                                } else {
                                    Vec3::ONE
                                };
                                radiance += beta * f * tr * le * (w / pdf_light);
                            }
                        }
                    }
                }
            } else if ENV
                && env_light
                && let Some(env) = &scene.environment
            {
                let (wi_world, pdf, le) = env_sample.take().unwrap_or_else(|| env.sample_with_radiance(s.light));
                let pdf_light = p_env * pdf;
                let wi = frame.to_local(wi_world);
                if sides_agree(wi, wi_world, ng, transmits) && pdf_light > 0.0 && pdf_light.is_finite() {
                    let (f, pdf_bsdf) = bsdf_eval_pdf(&bsdf, wo, wi, use_mis);
                    if f != Vec3::ZERO {
                        counters.shadow_rays += 1;
                        let origin = if transmits { offset_ray_origin(p, ng * wi.z.signum()) } else { p_out };
                        // Toward the environment through an absorbing medium: the absorbing
                        // channels receive nothing, the others all of it.
                        let tr = if DIELECTRIC {
                            escape_transmittance(segment_medium(&bsdf, sigma, wi.z))
                        } else {
                            Vec3::ONE
                        };
                        if tr != Vec3::ZERO && scene.accel.unoccluded(origin, wi_world, f32::INFINITY) {
                            let w = if use_mis { power_heuristic(1.0, pdf_light, 1.0, pdf_bsdf) } else { 1.0 };
                            radiance += beta * f * tr * le * (w / pdf_light);
                        }
                    }
                }
            }
        }

        // BSDF sampling.
        let Some(bs) = bsdf.sample(wo, s.lobe, s.bsdf) else { break };
        let wi_world = frame.to_world(bs.wi);
        if !sides_agree(bs.wi, wi_world, ng, transmits) {
            break; // the shading normal sent the ray to the other side
        }
        beta *= bs.weight;
        prev_pdf = bs.mis_pdf();
        if transmits {
            origin = offset_ray_origin(p, ng * bs.wi.z.signum());
            sigma = segment_medium(&bsdf, sigma, bs.wi.z);
            eta_scale *= bsdf.radiance_scale_inverse(wo, bs.wi);
        } else {
            origin = p_out;
        }
        dir = wi_world;
        depth += 1;

        // Russian roulette (pbrt-v4): continue with probability max(beta eta_scale) when it drops
        // below 1.
        if scene.roulette_depth > 0 && depth >= scene.roulette_depth {
            let m = (beta * eta_scale).max_element();
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
    Traced { radiance, escape: None }
}
