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

use crate::offset::offset_ray_origin;
use crate::scene_data::SceneData;
use crate::{Hit, PACKET_RAYS};
use ggx_core::mis::power_heuristic;
use ggx_core::sequence::PixelSeeds;
use ggx_core::{Frame, SampleStream};
use ggx_render::{
    Bsdf, anisotropy_direction, metal_rough_bsdf, normal_map_at, perturb_normal, tangent_at, tangent_frame,
};
use ggx_scene::{Environment, LightStrategy, NO_INDEX, PUNCTUAL_DIRECTIONAL};
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

/// How next-event estimation picks a light, and how emission that BSDF sampling finds is
/// weighted: the same for every path of a scene (and kernel variant).
#[derive(Clone, Copy)]
pub struct LightChoice {
    /// Next-event estimation is on.
    use_nee: bool,
    /// Light and BSDF samples are combined by the power heuristic.
    use_mis: bool,
    /// Area lights take part.
    has_area: bool,
    /// An environment is present.
    has_env: bool,
    /// The environment takes part in next-event estimation (not a constant or uniform one
    /// under MIS compensation: `Environment::for_integrator`).
    env_light: bool,
    /// Punctual lights take part.
    has_punctual: bool,
    /// Probabilities of picking area lights, punctual lights and the environment.
    p_area: f32,
    p_punctual: f32,
    p_env: f32,
}

impl LightChoice {
    /// The choice for `scene` in the kernel variant `AREA`, `ENV`: area lights, punctual
    /// lights and the environment share the selection equally.
    #[inline(always)]
    pub fn for_scene<const AREA: bool, const ENV: bool>(scene: &SceneData) -> Self {
        let strategy = scene.light_strategy;
        let has_area = AREA && !scene.lights.is_empty();
        let has_env = ENV && scene.environment.is_some();
        let env_light = has_env && scene.environment_is_light;
        let has_punctual = AREA && !scene.punctual_lights.is_empty();
        let classes = u32::from(has_area) + u32::from(env_light) + u32::from(has_punctual);
        let p_class = if classes > 0 { 1.0 / classes as f32 } else { 0.0 };
        let p_area = if has_area { p_class } else { 0.0 };
        let p_punctual = if has_punctual { p_class } else { 0.0 };
        let p_env = if env_light { 1.0 - p_area - p_punctual } else { 0.0 };
        LightChoice {
            use_nee: strategy != LightStrategy::Bsdf,
            use_mis: strategy == LightStrategy::Mis,
            has_area,
            has_env,
            env_light,
            has_punctual,
            p_area,
            p_punctual,
            p_env,
        }
    }

    /// Which light class next-event estimation picks with `select`: `(area, punctual)`, the
    /// environment when neither is picked and it takes part.
    #[inline(always)]
    fn pick(&self, select: f32) -> (bool, bool) {
        let pick_area = self.has_area && select < self.p_area;
        let pick_punctual = !pick_area && self.has_punctual && select < self.p_area + self.p_punctual;
        (pick_area, pick_punctual)
    }

    /// Whether next-event estimation samples the environment with `select` (the branch
    /// `trace` takes when neither an area nor a punctual light is picked).
    #[inline(always)]
    fn picks_environment(&self, select: f32) -> bool {
        let (pick_area, pick_punctual) = self.pick(select);
        self.use_nee && self.env_light && !pick_area && !pick_punctual
    }

    /// Weight of emission found by a BSDF sample of MIS density `prev_pdf` (+inf: a delta lobe
    /// or the camera ray), `pdf_light` its density under next-event estimation: 1 without
    /// next-event estimation, the power heuristic with MIS, and next-event estimation alone
    /// counts only what it cannot find (a delta direction).
    #[inline(always)]
    fn emission_weight(&self, prev_pdf: f32, pdf_light: impl FnOnce() -> f32) -> f32 {
        if !self.use_nee {
            1.0
        } else if self.use_mis {
            power_heuristic(1.0, prev_pdf, 1.0, pdf_light())
        } else if prev_pdf == f32::INFINITY {
            1.0
        } else {
            0.0
        }
    }
}

/// A camera path's first bounce drawn ahead, with the packet's other paths
/// ([`draw_first_bounces`]): its random numbers and, when next-event estimation picks the
/// environment, the environment light sample.
#[derive(Clone, Copy)]
pub struct FirstBounce {
    samples: BounceSamples,
    env_sample: Option<(Vec3, f32, Vec3)>,
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
    dir: Vec3,
    /// The path throughput.
    beta: Vec3,
    /// MIS density of the BSDF sample that produced `dir`.
    prev_pdf: f32,
}

impl Escape {
    /// The term `beta Le w` for the environment's radiance `le` and density `pdf_env` along
    /// `dir` (`w`: [`LightChoice::emission_weight`]).
    #[inline(always)]
    fn term(&self, lights: &LightChoice, le: Vec3, pdf_env: f32) -> Vec3 {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::AccelKind;
    use ggx_core::SequenceKind;
    use std::path::Path;

    /// A plastic floor, rough and smooth (delta) conductors, an area light and a procedural sky
    /// that next-event estimation samples; roulette from the first bounce on.
    const SCENE: &str = r#"
[camera]
position = [0, 1.2, 4]
look_at = [0, 0.4, 0]
fov_y = 45.0
resolution = [24, 16]

[integrator]
max_depth = 4
russian_roulette = 1

[environment]
type = "procedural"
preset = "sky"
resolution = [64, 32]
rotation = 30

[materials.floor]
type = "plastic"
roughness = 0.5
ior = 1.5
albedo = [0.45, 0.45, 0.42]

[materials.gold]
type = "conductor"
roughness = 0.3
preset = "gold"

[materials.mirror]
type = "conductor"
roughness = 0.0
preset = "silver"

[materials.lamp]
type = "emissive"
radiance = [4, 4, 4]

[[shapes]]
type = "rectangle"
material = "floor"
transform = { rotate = [-90, 0, 0], scale = 8 }

[[shapes]]
type = "sphere"
material = "gold"
center = [-0.6, 0.5, 0]
radius = 0.5

[[shapes]]
type = "sphere"
material = "mirror"
center = [0.6, 0.5, 0]
radius = 0.5

[[shapes]]
type = "rectangle"
material = "lamp"
transform = { translate = [0, 3, 1], rotate = [90, 0, 0], scale = 0.5 }
"#;

    /// A path whose first bounce was drawn ahead with its packet's (`draw_first_bounces`)
    /// returns the bits of the same path drawing it itself, over every pixel and 16 samples,
    /// and the environment's light samples were drawn ahead for some of them.
    #[test]
    fn first_bounces_drawn_ahead_are_the_bounces_drawn_in_the_path() {
        let scene = ggx_scene::parse_scene(SCENE, "test.toml", Path::new(".")).unwrap_or_else(|e| panic!("{e}"));
        let data = SceneData::new(&scene, AccelKind::default());
        assert!(data.environment_is_light && !data.lights.is_empty());
        let [w, h] = data.camera.resolution;
        let mut counters = Counters::default();
        let (mut ahead, mut env_ahead) = (0, 0);
        for pixel in 0..w * h {
            let mut seeds = core::array::from_fn(|_| PixelSeeds::new(0));
            let seed = SampleStream::new(SequenceKind::Sobol, 5, pixel, 0).seed;
            seeds[0] = PixelSeeds::new(seed);
            let mut streams = [SampleStream { kind: 0, seed: 0, sample_index: 0, dimension: 0 }; PACKET_RAYS];
            let mut rays = [(Vec3::ZERO, Vec3::ZERO); PACKET_RAYS];
            for (s, (stream, ray)) in streams.iter_mut().zip(&mut rays).enumerate() {
                *stream = SampleStream::new(SequenceKind::Sobol, 5, pixel, s as u32);
                let jitter = stream.next_2d_with(&mut seeds[0]);
                let xy = Vec2::new((pixel % w) as f32, (pixel / w) as f32) + jitter;
                *ray = data.ray_generator.generate_ray(xy);
            }
            let hits = rays.map(|(o, d)| data.accel.closest(o, d, f32::INFINITY));
            let in_path = streams;
            let mut firsts = [None; PACKET_RAYS];
            let slots = [0; PACKET_RAYS];
            assert!(draw_first_bounces::<true, true>(&data, &hits, &mut streams, &slots, &mut seeds, &mut firsts));
            ahead += firsts.iter().flatten().count();
            env_ahead += firsts.iter().flatten().filter(|f| f.env_sample.is_some()).count();
            for k in 0..PACKET_RAYS {
                let (o, d) = rays[k];
                let mut stream = in_path[k];
                let want = trace::<true, true, true, true, false>(
                    &data,
                    o,
                    d,
                    hits[k],
                    None,
                    &mut stream,
                    &mut seeds[0],
                    &mut counters,
                );
                let got = trace::<true, true, true, true, false>(
                    &data,
                    o,
                    d,
                    hits[k],
                    firsts[k],
                    &mut streams[k],
                    &mut seeds[0],
                    &mut counters,
                );
                let bits = |t: &Traced| {
                    (t.radiance.to_array().map(f32::to_bits), t.escape.map(|e| (e.dir, e.beta, e.prev_pdf.to_bits())))
                };
                assert_eq!(bits(&got), bits(&want), "pixel {pixel} sample {k}");
                assert_eq!(stream, streams[k], "pixel {pixel} sample {k}: the dimensions consumed");
            }
        }
        // Paths that hit the delta mirror or nothing are not drawn ahead; the others are, and
        // those that pick the environment (half of them) carry its light sample.
        let paths = (w * h) as usize * PACKET_RAYS;
        assert!(ahead > paths / 2 && ahead < paths, "{ahead} of {paths} drawn ahead");
        assert!(env_ahead > ahead / 3 && env_ahead < ahead, "{env_ahead} environment samples of {ahead}");
    }
}
