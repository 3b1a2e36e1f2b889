// ggx path tracer, part 2: ggx-render's Bsdf (ggx-render/src/bsdf.rs) and textured materials (textured.rs), ggx-cpu's
// integrator (integrator.rs) and render loop (render.rs), one thread per pixel. Expects ggx_core.wgsl and scene.wgsl in
// front of it.

// Kernel variant, like ggx-cpu's const generics: features compiled out when the scene lacks them.
override AREA: bool = true;
override ENV: bool = true;
override PLASTIC: bool = true;
override DIELECTRIC: bool = true;
override TEXTURES: bool = true;

const MAT_DIFFUSE: u32 = 0u;
const MAT_CONDUCTOR: u32 = 1u;
const MAT_PLASTIC: u32 = 2u;
const MAT_BLACK: u32 = 3u;
const MAT_DIELECTRIC: u32 = 4u;
const MAT_THIN: u32 = 5u;
const MAT_METAL_ROUGH: u32 = 6u;
const MAT_CLEARCOAT: u32 = 7u;
// Word offsets of the fields of a MetalRoughRecord (scene_upload.rs) in `surface`.
const MR_BASE_COLOR: u32 = 0u;
const MR_METALLIC: u32 = 3u;
const MR_EMISSION: u32 = 4u;
const MR_ROUGHNESS: u32 = 7u;
const MR_SPECULAR_COLOR: u32 = 8u;
const MR_SPECULAR: u32 = 11u;
const MR_IOR: u32 = 12u;
const MR_NORMAL_SCALE: u32 = 13u;
const MR_ANISOTROPY: u32 = 14u;
const MR_BASE_COLOR_TEXTURE: u32 = 16u;
const MR_METALLIC_TEXTURE: u32 = 24u;
const MR_ROUGHNESS_TEXTURE: u32 = 32u;
const MR_NORMAL_TEXTURE: u32 = 40u;
const MR_EMISSION_TEXTURE: u32 = 48u;
const MR_ANISOTROPY_COS_SIN: u32 = 56u;
const MR_CLEARCOAT: u32 = 58u;
const MR_CLEARCOAT_ROUGHNESS: u32 = 59u;
const LIGHT_BSDF: u32 = 0u;
const LIGHT_MIS: u32 = 2u;
const SHADOW_SCALE: f32 = 1.0f - 1e-3f;
// TransportMode::Radiance.
const MODE_RADIANCE: u32 = 0u;

// Rec. 709 luminance: 0.2126 R + 0.7152 G + 0.0722 B, in glam's dot order.
fn luminance(c: vec3<f32>) -> f32 {
    return dot3(c, vec3(0.2126f, 0.7152f, 0.0722f));
}

// Coat probability of a plastic: F / (F + (1 - F) lum(albedo)) in [0.05, 0.95], 1 for a black base.
fn coat_probability(fo: f32, albedo: vec3<f32>) -> f32 {
    let base = (1.0 - fo) * luminance(albedo);
    if base <= 0.0 {
        return 1.0;
    }
    return min_num(max_num(fo / (fo + base), 0.05f), 0.95f);
}

// The conductor record as ggx-core's GgxConductorMs.
fn material_conductor_ms(m: Material) -> GgxConductorMs {
    return GgxConductorMs(m.conductor, m.extra, m.compensation);
}

// The dielectric record as ggx-core's GgxDielectricMs.
fn material_dielectric_ms(m: Material) -> GgxDielectricMs {
    return GgxDielectricMs(GgxDielectric(m.conductor.distribution, m.ior, 0u), m.compensation, array<u32, 3>(0u, 0u, 0u));
}

// The metal-rough record as ggx-core's GltfMetalRough (scene_upload.rs `MaterialRecord` table).
fn material_metal_rough(m: Material) -> GltfMetalRough {
    return GltfMetalRough(m.albedo, m.ior, m.extra, m.specular_weight, m.conductor.distribution, m.p_specular, 0u);
}

// The coated record as ggx-core's GltfClearcoat: the base as in material_metal_rough, the coat's alphas, weight and
// base albedo in conductor.fresnel.a (scene_upload.rs `MaterialRecord` table).
fn material_clearcoat(m: Material) -> GltfClearcoat {
    let a = m.conductor.fresnel.a;
    return GltfClearcoat(material_metal_rough(m), TrowbridgeReitz(a.x, a.y), a.z, a.w);
}

// The record m shading as GltfMetalRough b (textured.rs `metal_rough_bsdf`: the same technique), under the coat of
// the MetalRoughRecord at word o for MAT_CLEARCOAT (Bsdf::metal_rough: gltf_clearcoat_new(b, weight, roughness^2)).
fn with_metal_rough(m_in: Material, b: GltfMetalRough, o: u32) -> Material {
    var m = m_in;
    m.albedo = b.base_color;
    m.ior = b.metallic;
    m.extra = b.f0;
    m.specular_weight = b.specular_weight;
    m.conductor.distribution = b.distribution;
    m.p_specular = b.p_specular;
    if m.kind == MAT_CLEARCOAT {
        let r = surface_f32(o + MR_CLEARCOAT_ROUGHNESS);
        let c = gltf_clearcoat_new(b, surface_f32(o + MR_CLEARCOAT), r * r);
        m.conductor.fresnel.a = vec4(c.coat.alpha_x, c.coat.alpha_y, c.weight, c.base_albedo);
    }
    return m;
}

// Bsdf::base_weight: plastic_base_weight with compensation, else (1 - F(mu_o)) (1 - F(mu_i)).
fn plastic_weight(m: Material, mu_o: f32, mu_i: f32) -> f32 {
    if m.compensation != 0u {
        return plastic_base_weight(mu_o, mu_i, m.conductor.distribution.alpha_x, m.ior);
    }
    return (1.0 - fresnel_dielectric(mu_o, m.ior)) * (1.0 - fresnel_dielectric(mu_i, m.ior));
}

// The transmittance tint where a dielectric sample crosses the surface, else 1.
fn transmission_tint(m: Material, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    return select(vec3(1.0), m.albedo, wo.z * wi.z < 0.0);
}

// Bsdf::eval: f(wo, wi) |wi.z|; plastic f = f_coat + w(wo, wi) albedo / pi; dielectric both sides, tinted transmission.
fn bsdf_eval(m: Material, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    if DIELECTRIC && m.kind == MAT_DIELECTRIC {
        return ggx_dielectric_ms_eval(material_dielectric_ms(m), wo, wi, MODE_RADIANCE) * transmission_tint(m, wo, wi);
    }
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return vec3(0.0);
    }
    if m.kind == MAT_DIFFUSE {
        return m.albedo * (wi.z * FRAC_1_PI);
    } else if m.kind == MAT_CONDUCTOR {
        return ggx_conductor_ms_eval(material_conductor_ms(m), wo, wi);
    } else if PLASTIC && m.kind == MAT_PLASTIC {
        let t = plastic_weight(m, wo.z, wi.z);
        return ggx_conductor_eval(m.conductor, wo, wi) + m.albedo * (t * wi.z * FRAC_1_PI);
    } else if m.kind == MAT_METAL_ROUGH {
        return gltf_metal_rough_eval(material_metal_rough(m), wo, wi);
    } else if m.kind == MAT_CLEARCOAT {
        return gltf_clearcoat_eval(material_clearcoat(m), wo, wi);
    }
    return vec3(0.0);
}

// Bsdf::pdf: solid-angle density of bsdf_sample; plastic p pdf_coat + (1 - p) pdf_cosine.
fn bsdf_pdf(m: Material, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    if DIELECTRIC && m.kind == MAT_DIELECTRIC {
        return ggx_dielectric_ms_pdf(material_dielectric_ms(m), wo, wi, m.sampling, MODE_RADIANCE);
    }
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return 0.0;
    }
    if m.kind == MAT_DIFFUSE {
        return pdf_cosine_hemisphere(wi);
    } else if m.kind == MAT_CONDUCTOR {
        return ggx_conductor_ms_pdf(material_conductor_ms(m), wo, wi, m.sampling);
    } else if PLASTIC && m.kind == MAT_PLASTIC {
        let p = coat_probability(fresnel_dielectric(wo.z, m.ior), m.albedo);
        return p * ggx_conductor_pdf(m.conductor, wo, wi, m.sampling) + (1.0 - p) * pdf_cosine_hemisphere(wi);
    } else if m.kind == MAT_METAL_ROUGH {
        return gltf_metal_rough_pdf(material_metal_rough(m), wo, wi, m.sampling);
    } else if m.kind == MAT_CLEARCOAT {
        return gltf_clearcoat_pdf(material_clearcoat(m), wo, wi, m.sampling);
    }
    return 0.0;
}

// Bsdf::sample: cosine lobe, compensated conductor, the plastic's one-sample mixture (weight = eval / mixture pdf),
// dielectric or thin sheet (tinted transmission).
fn bsdf_sample(m: Material, wo: vec3<f32>, u_lobe: f32, u: vec2<f32>) -> BsdfSample {
    var none: BsdfSample;
    if DIELECTRIC && m.kind == MAT_DIELECTRIC {
        var s = ggx_dielectric_ms_sample(material_dielectric_ms(m), wo, u, u_lobe, m.sampling, MODE_RADIANCE);
        s.weight *= transmission_tint(m, wo, s.wi);
        return s;
    }
    if DIELECTRIC && m.kind == MAT_THIN {
        var s = thin_dielectric_sample(m.ior, wo, u_lobe);
        s.weight *= transmission_tint(m, wo, s.wi);
        return s;
    }
    if wo.z <= 0.0 {
        return none;
    }
    if m.kind == MAT_DIFFUSE {
        let wi = sample_cosine_hemisphere(u);
        return BsdfSample(wi, m.albedo, pdf_cosine_hemisphere(wi), 0u, 1u);
    } else if m.kind == MAT_CONDUCTOR {
        return ggx_conductor_ms_sample(material_conductor_ms(m), wo, u, u_lobe, m.sampling);
    } else if PLASTIC && m.kind == MAT_PLASTIC {
        let p = coat_probability(fresnel_dielectric(wo.z, m.ior), m.albedo);
        var wi: vec3<f32>;
        if u_lobe < p {
            let s = ggx_conductor_sample(m.conductor, wo, u, m.sampling);
            if s.valid == 0u {
                return none;
            }
            if s.is_delta != 0u {
                return BsdfSample(s.wi, s.weight / p, p, s.is_delta, 1u);
            }
            wi = s.wi;
        } else {
            wi = sample_cosine_hemisphere(u);
        }
        let pdf = bsdf_pdf(m, wo, wi);
        if !(pdf > 0.0) {
            return none;
        }
        return BsdfSample(wi, bsdf_eval(m, wo, wi) / pdf, pdf, 0u, 1u);
    } else if m.kind == MAT_METAL_ROUGH {
        return gltf_metal_rough_sample(material_metal_rough(m), wo, u, u_lobe, m.sampling);
    } else if m.kind == MAT_CLEARCOAT {
        return gltf_clearcoat_sample(material_clearcoat(m), wo, u, u_lobe, m.sampling);
    }
    return none;
}

// Bsdf::is_delta: a mirror conductor, a smooth dielectric, a thin sheet (never a metal-rough material: its diffuse
// lobe stays).
fn bsdf_is_delta(m: Material) -> bool {
    if m.kind == MAT_CONDUCTOR {
        return ggx_conductor_is_delta(m.conductor);
    }
    if m.kind == MAT_DIELECTRIC {
        return is_effectively_smooth(m.conductor.distribution);
    }
    return m.kind == MAT_THIN;
}

// Bsdf::transmits: a dielectric or a thin sheet.
fn bsdf_transmits(m: Material) -> bool {
    return m.kind == MAT_DIELECTRIC || m.kind == MAT_THIN;
}

// textured.rs `metal_rough_at`: the BRDF of the MetalRoughRecord at word o at uv: each factor times its texture (base
// colour RGB, metallic and roughness their slot's channel), alpha = roughness^2; KHR_materials_anisotropy's
// alpha_x = mix(alpha, 1, strength^2) along the frame's tangent (the caller turns the frame).
fn metal_rough_at(o: u32, uv: vec2<f32>) -> GltfMetalRough {
    var base = surface_vec3(o + MR_BASE_COLOR);
    let base_tex = load_texture_ref(o + MR_BASE_COLOR_TEXTURE);
    if texture_ref_is_some(base_tex) {
        base *= texture_sample(base_tex, uv).xyz;
    }
    var metallic = surface_f32(o + MR_METALLIC);
    let metallic_tex = load_texture_ref(o + MR_METALLIC_TEXTURE);
    if texture_ref_is_some(metallic_tex) {
        metallic *= texture_sample_channel(metallic_tex, uv);
    }
    var roughness = surface_f32(o + MR_ROUGHNESS);
    let roughness_tex = load_texture_ref(o + MR_ROUGHNESS_TEXTURE);
    if texture_ref_is_some(roughness_tex) {
        roughness *= texture_sample_channel(roughness_tex, uv);
    }
    let alpha = roughness * roughness;
    let strength = surface_f32(o + MR_ANISOTROPY);
    let s2 = strength * strength;
    let alpha_t = alpha + (1.0 - alpha) * s2;
    let ior = surface_f32(o + MR_IOR);
    let specular_color = surface_vec3(o + MR_SPECULAR_COLOR);
    return gltf_metal_rough_new(base, metallic, alpha_t, alpha, ior, specular_color, surface_f32(o + MR_SPECULAR));
}

// textured.rs `normal_map_at`: normalize((2 rgb - 1) (scale, scale, 1)) of the record's normal map at uv; 0 (the
// Rust None) without a normal map or when the texel decodes to zero.
fn normal_map_at(o: u32, uv: vec2<f32>) -> vec3<f32> {
    let r = load_texture_ref(o + MR_NORMAL_TEXTURE);
    if !texture_ref_is_some(r) {
        return vec3(0.0);
    }
    let t = texture_sample(r, uv).xyz * 2.0 - vec3(1.0);
    let scale = surface_f32(o + MR_NORMAL_SCALE);
    return glam_normalize_or_zero(t * vec3(scale, scale, 1.0));
}

// SceneData::emission_at: the emitted radiance of material `mi` on `tri` at (b1, b2): with TEXTURES, a textured
// metal-rough material with an emission texture gives its factor times the texture (textured.rs `emission_at`).
fn emission_at(mi: u32, tri: Triangle, b1: f32, b2: f32) -> vec3<f32> {
    let m = materials[mi];
    if TEXTURES && m.surface != NO_INDEX {
        let r = load_texture_ref(m.surface + MR_EMISSION_TEXTURE);
        if texture_ref_is_some(r) {
            return surface_vec3(m.surface + MR_EMISSION) * texture_sample(r, uv_at(tri, b1, b2)).xyz;
        }
    }
    return m.emission;
}

// textured.rs `tangent_at`'s Option<(Vec3, f32)>: the tangent t, the bitangent's sign w, valid.
struct TangentAt {
    t: vec3<f32>,
    w: f32,
    valid: bool,
}

// textured.rs `tangent_frame`'s Option<(Vec3, Vec3)>: T, B, valid.
struct TangentFrame {
    t: vec3<f32>,
    b: vec3<f32>,
    valid: bool,
}

// textured.rs `tangent_at`: the tangent at (b1, b2) and the sign w (B = w (n x T)): the mesh's tangent (record k,
// interpolated) or dp/du with the sign that makes B follow -dp/dv; invalid when the coordinates are degenerate.
fn tangent_at(n: vec3<f32>, tri: Triangle, k: u32, b1: f32, b2: f32) -> TangentAt {
    if k < params.tangent_count {
        let o = params.tangents + 12u * k;
        let w0 = surface_f32(o + 3u);
        if w0 != 0.0 {
            let t = (1.0 - b1 - b2) * surface_vec3(o) + b1 * surface_vec3(o + 4u) + b2 * surface_vec3(o + 8u);
            return TangentAt(t, select(1.0, -1.0, w0 < 0.0), true);
        }
    }
    let dp1 = tri.v1 - tri.v0;
    let dp2 = tri.v2 - tri.v0;
    let o = params.uvs + 8u * k;
    let uv0 = vec2(surface_f32(o), surface_f32(o + 1u));
    let d1 = vec2(surface_f32(o + 2u), surface_f32(o + 3u)) - uv0;
    let d2 = vec2(surface_f32(o + 4u), surface_f32(o + 5u)) - uv0;
    let det = d1.x * d2.y - d2.x * d1.y;
    if !(abs(det) > 1e-20f) {
        return TangentAt(vec3(0.0), 1.0, false);
    }
    let dpdu = (dp1 * d2.y - dp2 * d1.y) / det;
    let dpdv = (dp2 * d1.x - dp1 * d2.x) / det;
    let w = select(1.0, -1.0, dot3(cross3(n, dpdu), -dpdv) < 0.0);
    return TangentAt(dpdu, w, true);
}

// textured.rs `tangent_frame`: T = t made orthogonal to the unit normal n, B = w (n x T); invalid when T vanishes.
fn tangent_frame(n: vec3<f32>, t: vec3<f32>, w: f32) -> TangentFrame {
    let tn = glam_normalize_or_zero(t - n * dot3(n, t));
    if all(tn == vec3(0.0)) || !is_finite3(tn) {
        return TangentFrame(vec3(0.0), vec3(0.0), false);
    }
    return TangentFrame(tn, cross3(n, tn) * w, true);
}

// textured.rs `perturb_normal`: n bent by the tangent-space normal nt, normalize(nt.x T + nt.y B + nt.z n) in the
// tangent_frame of tangent_at (record k); n unchanged without a tangent.
fn perturb_normal(n: vec3<f32>, nt: vec3<f32>, tri: Triangle, k: u32, b1: f32, b2: f32) -> vec3<f32> {
    let ta = tangent_at(n, tri, k, b1, b2);
    if !ta.valid {
        return n;
    }
    let tf = tangent_frame(n, ta.t, ta.w);
    if !tf.valid {
        return n;
    }
    let bent = glam_normalize_or_zero(tf.t * nt.x + tf.b * nt.y + n * nt.z);
    if all(bent == vec3(0.0)) || !is_finite3(bent) {
        return n;
    }
    return bent;
}

// textured.rs `anisotropy_direction`: T turned by the rotation toward B, normalize(cos r T + sin r B), with (cos r,
// sin r) the record's, from the CPU's sin_cos.
fn anisotropy_direction(t: vec3<f32>, b: vec3<f32>, cos_sin: vec2<f32>) -> vec3<f32> {
    return glam_normalize_or_zero(t * cos_sin.x + b * cos_sin.y);
}

// f32::signum: 1 for +0 and positives, -1 for -0 and negatives.
fn signum(x: f32) -> f32 {
    return copysign(1.0, x);
}

// Bsdf::radiance_scale_inverse: eta'^2 for a transmission through a dielectric with an inside, else 1.
fn radiance_scale_inverse(m: Material, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    if m.kind == MAT_DIELECTRIC && wo.z * wi.z < 0.0 {
        let eta = clamp_eta(m.ior);
        return select(1.0 / (eta * eta), eta * eta, wo.z > 0.0);
    }
    return 1.0;
}

// integrator.rs `sides_agree`: wi and wi_world on the same side of ng; +z only for materials that do not transmit.
fn sides_agree(wi: vec3<f32>, wi_world: vec3<f32>, ng: vec3<f32>, transmits: bool) -> bool {
    let side = dot3(wi_world, ng);
    if transmits {
        return side * wi.z > 0.0;
    }
    return wi.z > 0.0 && side > 0.0;
}

// integrator.rs `transmittance`: exp(-sigma t) per channel for a finite t, 1 where sigma <= 0.
fn medium_transmittance(sigma: vec3<f32>, t: f32) -> vec3<f32> {
    return vec3(
        select(1.0, exp(-sigma.x * t), sigma.x > 0.0),
        select(1.0, exp(-sigma.y * t), sigma.y > 0.0),
        select(1.0, exp(-sigma.z * t), sigma.z > 0.0),
    );
}

// integrator.rs `escape_transmittance`: 0 in the channels that absorb, 1 in the others (not exp(-sigma inf)).
fn escape_transmittance(sigma: vec3<f32>) -> vec3<f32> {
    return select(vec3(1.0), vec3(0.0), sigma > vec3(0.0));
}

// integrator.rs `segment_medium`: a dielectric's absorption inside (wi.z < 0), vacuum outside; others keep `current`.
fn segment_medium(m: Material, current: vec3<f32>, wi_z: f32) -> vec3<f32> {
    if m.kind != MAT_DIELECTRIC {
        return current;
    }
    return select(vec3(0.0), m.extra, wi_z < 0.0);
}

// Shading frame with x = normalize(y_world x n) along latitude circles; Duff et al. 2017 within ~0.5 degrees of the poles.
fn shading_frame(n: vec3<f32>) -> Frame {
    let t = cross3(vec3(0.0, 1.0, 0.0), n);
    let len2 = dot3(t, t);
    if len2 < 1e-4f {
        return frame_from_z(n);
    }
    let x = t / sqrt(len2);
    return Frame(x, cross3(n, x), n);
}

// Wachter & Binder 2019: move p by 256 n ulps per coordinate, or by n / 65536 within 1/32 of the origin.
fn offset_coord(p: f32, n: f32) -> f32 {
    let of_i = i32(256.0 * n);
    let moved = bitcast<f32>(bitcast<i32>(p) + select(of_i, -of_i, p < 0.0));
    return select(moved, p + (1.0f / 65536.0f) * n, abs(p) < 1.0f / 32.0f);
}

// offset_ray_origin: offset_coord on each axis.
fn offset_ray_origin(p: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    return vec3(offset_coord(p.x, n.x), offset_coord(p.y, n.y), offset_coord(p.z, n.z));
}

struct BounceSamples {
    bsdf: vec2<f32>,
    lobe: f32,
    light: vec2<f32>,
    pick: f32,
    roulette: f32,
}

// BounceSamples::draw: bsdf 2D, then lobe, light 2D, light pick and roulette only where the scene uses them.
fn draw_bounce(stream: ptr<function, SampleStream>, lobe: bool, light: bool, pick: bool, roulette: bool) -> BounceSamples {
    var s = BounceSamples(sample_stream_next_2d(stream), 0.5, vec2(0.0), 0.0, 0.5);
    if lobe {
        s.lobe = sample_stream_next_1d(stream);
    }
    if light {
        s.light = sample_stream_next_2d(stream);
    }
    if pick {
        s.pick = sample_stream_next_1d(stream);
    }
    if roulette {
        s.roulette = sample_stream_next_1d(stream);
    }
    return s;
}

// integrator.rs `trace`: radiance along a camera ray (NEE toward area, punctual and environment lights + power-heuristic
// MIS, Russian roulette); rays counts traced rays.
fn trace(origin_in: vec3<f32>, dir_in: vec3<f32>, stream: ptr<function, SampleStream>, rays: ptr<function, u32>) -> vec3<f32> {
    let use_nee = params.light_strategy != LIGHT_BSDF;
    let use_mis = params.light_strategy == LIGHT_MIS;
    let has_area = AREA && params.emitter_count > 0u;
    let has_env = ENV && params.env_kind != ENV_NONE;
    // The environment takes part in next-event estimation (Environment::for_integrator).
    let env_light = has_env && params.env_light != 0u;
    let has_punctual = AREA && params.punctual_count > 0u;
    // Area lights, punctual lights and the environment share the light selection equally.
    let classes = select(0u, 1u, has_area) + select(0u, 1u, env_light) + select(0u, 1u, has_punctual);
    let p_class = select(0.0, 1.0 / f32(classes), classes > 0u);
    let p_area = select(0.0, p_class, has_area);
    let p_punctual = select(0.0, p_class, has_punctual);
    let p_env = select(0.0, 1.0 - p_area - p_punctual, env_light);
    let draw_light = use_nee && (has_area || env_light || has_punctual);
    // Area lights need the pick to choose an emitter even without another light type.
    let draw_pick = use_nee && (has_area || has_punctual);

    var origin = origin_in;
    var dir = dir_in;
    var radiance = vec3(0.0);
    var beta = vec3(1.0);
    // BsdfSample::mis_pdf of the sample that produced dir; the camera ray counts as a delta.
    var prev_pdf = inf_f32();
    var depth = 0u;
    // Absorption coefficient of the medium the ray travels in (zero: vacuum).
    var sigma = vec3(0.0);
    // Product of eta'^2 over the transmissions so far, for Russian roulette (pbrt-v4's etaScale).
    var eta_scale = 1.0f;
    loop {
        *rays += 1u;
        var ray = make_ray(origin, dir, inf_f32());
        let prim = traverse(&ray, false);
        if DIELECTRIC && any(sigma != vec3(0.0)) {
            if prim == NO_INDEX {
                // Escaping an open mesh from inside: an infinite medium.
                beta *= escape_transmittance(sigma);
            } else {
                beta *= medium_transmittance(sigma, ray.tmax);
            }
        }
        if prim == NO_INDEX {
            if has_env {
                let le = env_radiance(dir);
                var w = 0.0f;
                if !use_nee {
                    w = 1.0;
                } else if use_mis {
                    w = power_heuristic(1.0, prev_pdf, 1.0, p_env * env_pdf(dir));
                } else if prev_pdf == inf_f32() {
                    w = 1.0;
                }
                radiance += beta * le * w;
            }
            break;
        }
        let t_hit = ray.tmax;
        let tri = triangles[prim];
        var ng = geometric_normal(tri);
        let p = origin + dir * t_hit;
        var m = materials[tri.material];
        // The hit's barycentrics (ggx-cpu's Hit::b1, b2), where something reads them.
        var b = vec2(0.0);
        if TEXTURES || tri.normals != NO_INDEX {
            b = barycentrics(tri, origin, dir);
        }

        if AREA && tri.emitter != NO_INDEX {
            let cos_l = -dot3(ng, dir);
            if cos_l > 0.0 {
                var w = 0.0f;
                if !use_nee {
                    w = 1.0;
                } else if use_mis {
                    w = power_heuristic(1.0, prev_pdf, 1.0, p_area * pdf_area(tri.emitter) * t_hit * t_hit / cos_l);
                } else if prev_pdf == inf_f32() {
                    w = 1.0;
                }
                var le = m.emission;
                if TEXTURES {
                    le = emission_at(tri.material, tri, b.x, b.y);
                }
                radiance += beta * le * w;
            }
        }
        // A textured material (only textured metal-rough records, coated or not, have a surface): its BSDF and normal
        // at this point.
        var mapped_normal = vec3(0.0);
        if TEXTURES && m.surface != NO_INDEX {
            let uv = uv_at(tri, b.x, b.y);
            m = with_metal_rough(m, metal_rough_at(m.surface, uv), m.surface);
            mapped_normal = normal_map_at(m.surface, uv);
        }
        if (!PLASTIC && m.kind == MAT_PLASTIC) || (!DIELECTRIC && bsdf_transmits(m)) {
            break;
        }
        if depth >= params.max_depth || m.kind == MAT_BLACK {
            break;
        }
        let roulette = params.roulette_depth > 0u && depth + 1u >= params.roulette_depth;
        let s = draw_bounce(stream, params.draw_lobe != 0u, draw_light, draw_pick, roulette);

        // Frame toward the arriving ray for two-sided materials, around the outward normal for a dielectric.
        let inside = DIELECTRIC && m.kind == MAT_DIELECTRIC;
        if !inside && dot3(ng, dir) > 0.0 {
            ng = -ng;
        }
        var ns = ng;
        if tri.normals != NO_INDEX && tri.normals < arrayLength(&shading_normals) {
            var n = interpolate_normal(shading_normals[tri.normals], b.x, b.y);
            if TEXTURES && any(mapped_normal != vec3(0.0)) && tri.normals < params.uv_count {
                n = perturb_normal(n, mapped_normal, tri, tri.normals, b.x, b.y);
            }
            ns = select(n, -n, dot3(n, ng) < 0.0);
        }
        var frame = shading_frame(ns);
        if TEXTURES && m.surface != NO_INDEX && tri.normals < params.uv_count
            && surface_f32(m.surface + MR_ANISOTROPY) != 0.0 {
            // KHR_materials_anisotropy: alpha_x along the mesh's tangent turned by the rotation.
            let ta = tangent_at(ns, tri, tri.normals, b.x, b.y);
            if ta.valid {
                let tf = tangent_frame(ns, ta.t, ta.w);
                if tf.valid {
                    let x = anisotropy_direction(tf.t, tf.b, surface_vec2(m.surface + MR_ANISOTROPY_COS_SIN));
                    if any(x != vec3(0.0)) {
                        frame = Frame(x, cross3(ns, x), ns);
                    }
                }
            }
        }
        let wo = frame_to_local(frame, -dir);
        if !(wo.z * -dot3(ng, dir) > 0.0) {
            break;
        }
        let p_out = offset_ray_origin(p, select(-ng, ng, wo.z > 0.0));
        let transmits = DIELECTRIC && bsdf_transmits(m);

        if use_nee && !bsdf_is_delta(m) {
            let pick_area = has_area && s.pick < p_area;
            let pick_punctual = !pick_area && has_punctual && s.pick < p_area + p_punctual;
            if AREA && pick_punctual {
                // One punctual light, uniformly: a delta light, no MIS.
                let n = params.punctual_count;
                let u = max_num((s.pick - p_area) / p_punctual, 0.0);
                let light = load_punctual(min(u32(u * f32(n)), n - 1u));
                let pmf = p_punctual / f32(n);
                var wi_world = -light.direction;
                var dist = inf_f32();
                if light.kind != PUNCTUAL_DIRECTIONAL {
                    let to = light.position - p;
                    dist = sqrt(dot3(to, to));
                    wi_world = to / dist;
                }
                let wi = frame_to_local(frame, wi_world);
                let li = punctual_incident(light, wi_world, dist);
                let lit = any(li != vec3(0.0));
                if dist > 0.0 && is_finite3(wi_world) && lit && sides_agree(wi, wi_world, ng, transmits) {
                    let f = bsdf_eval(m, wo, wi);
                    if any(f != vec3(0.0)) {
                        *rays += 1u;
                        var shadow_origin = p_out;
                        if transmits {
                            shadow_origin = offset_ray_origin(p, ng * signum(wi.z));
                        }
                        var tmax = inf_f32();
                        if is_finite(dist) {
                            let to = light.position - shadow_origin;
                            tmax = sqrt(dot3(to, to)) * SHADOW_SCALE;
                        }
                        var tr = vec3(1.0);
                        if DIELECTRIC {
                            let medium = segment_medium(m, sigma, wi.z);
                            if is_finite(dist) {
                                tr = medium_transmittance(medium, dist);
                            } else {
                                tr = escape_transmittance(medium);
                            }
                        }
                        if any(tr != vec3(0.0)) && unoccluded(shadow_origin, wi_world, tmax) {
                            radiance += beta * f * tr * li / pmf;
                        }
                    }
                }
            } else if AREA && pick_area {
                let u_emitter = select(s.pick, s.pick / p_area, p_area < 1.0);
                let e = sample_emitter(u_emitter);
                let light_tri = triangles[load_emitter(e).triangle];
                let pl = sample_triangle(light_tri, s.light);
                // The sampled point's barycentrics (sample_triangle's weights of v1, v2).
                let su = sqrt(max_num(s.light.x, 0.0));
                let lb = vec2(su * (1.0 - s.light.y), su * s.light.y);
                var shadow_origin = p_out;
                if transmits {
                    shadow_origin = offset_ray_origin(p, ng * signum(dot3(pl - p, ng)));
                }
                let to_light = pl - shadow_origin;
                let dist2 = dot3(to_light, to_light);
                let dist = sqrt(dist2);
                let wi_world = to_light / dist;
                let cos_l = -dot3(geometric_normal(light_tri), wi_world);
                let wi = frame_to_local(frame, wi_world);
                if cos_l > 0.0 && sides_agree(wi, wi_world, ng, transmits) && dist > 0.0 {
                    let pdf_light = p_area * pdf_area(e) * dist2 / cos_l;
                    let f = bsdf_eval(m, wo, wi);
                    if any(f != vec3(0.0)) && pdf_light > 0.0 && is_finite(pdf_light) {
                        *rays += 1u;
                        if unoccluded(shadow_origin, wi_world, dist * SHADOW_SCALE) {
                            var le = materials[light_tri.material].emission;
                            if TEXTURES {
                                le = emission_at(light_tri.material, light_tri, lb.x, lb.y);
                            }
                            var w = 1.0f;
                            if use_mis {
                                w = power_heuristic(1.0, pdf_light, 1.0, bsdf_pdf(m, wo, wi));
                            }
                            var tr = vec3(1.0);
                            if DIELECTRIC {
                                tr = medium_transmittance(segment_medium(m, sigma, wi.z), dist);
                            }
                            radiance += beta * f * tr * le * (w / pdf_light);
                        }
                    }
                }
            } else if ENV && env_light {
                let sample = env_sample(s.light);
                let wi_world = sample.wi;
                let pdf_light = p_env * sample.pdf;
                let wi = frame_to_local(frame, wi_world);
                if sides_agree(wi, wi_world, ng, transmits) && pdf_light > 0.0 && is_finite(pdf_light) {
                    let f = bsdf_eval(m, wo, wi);
                    if any(f != vec3(0.0)) {
                        *rays += 1u;
                        var shadow_origin = p_out;
                        if transmits {
                            shadow_origin = offset_ray_origin(p, ng * signum(wi.z));
                        }
                        var tr = vec3(1.0);
                        if DIELECTRIC {
                            tr = escape_transmittance(segment_medium(m, sigma, wi.z));
                        }
                        if any(tr != vec3(0.0)) && unoccluded(shadow_origin, wi_world, inf_f32()) {
                            var w = 1.0f;
                            if use_mis {
                                w = power_heuristic(1.0, pdf_light, 1.0, bsdf_pdf(m, wo, wi));
                            }
                            radiance += beta * f * tr * sample.radiance * (w / pdf_light);
                        }
                    }
                }
            }
        }

        let bs = bsdf_sample(m, wo, s.lobe, s.bsdf);
        if bs.valid == 0u {
            break;
        }
        let wi_world = frame_to_world(frame, bs.wi);
        if !sides_agree(bs.wi, wi_world, ng, transmits) {
            break;
        }
        beta *= bs.weight;
        prev_pdf = bsdf_sample_mis_pdf(bs);
        if transmits {
            origin = offset_ray_origin(p, ng * signum(bs.wi.z));
            sigma = segment_medium(m, sigma, bs.wi.z);
            eta_scale *= radiance_scale_inverse(m, wo, bs.wi);
        } else {
            origin = p_out;
        }
        dir = wi_world;
        depth += 1u;

        if params.roulette_depth > 0u && depth >= params.roulette_depth {
            let rr = beta * eta_scale;
            let mx = max_num(rr.x, max_num(rr.y, rr.z));
            if mx < 1.0 {
                let q = max_num(1.0 - mx, 0.0);
                if s.roulette < q {
                    break;
                }
                beta /= 1.0 - q;
            }
        }
        if !is_finite3(beta) || all(beta == vec3(0.0)) {
            break;
        }
    }
    return select(vec3(0.0), radiance, is_finite3(radiance));
}

// Camera::generate_ray direction: normalize(forward + x tan aspect right + y tan up), x = 2 px / w - 1, y = 1 - 2 py / h.
fn camera_dir(px: vec2<f32>) -> vec3<f32> {
    let x = (2.0 * px.x / params.width_f - 1.0) * params.tan_half_fov * params.aspect;
    let y = (1.0 - 2.0 * px.y / params.height_f) * params.tan_half_fov;
    let d = params.cam_forward + x * params.cam_right + y * params.cam_up;
    return d * (1.0 / sqrt(dot3(d, d)));
}

// render.rs `render_tile` for one pixel: sum of samples [s0, s1), each on SampleStream(kind, seed, pixel, s); w = rays (bits).
@compute @workgroup_size(8, 8)
fn render(@builtin(global_invocation_id) gid: vec3<u32>) {
    if gid.x >= params.width || gid.y >= params.rows {
        return;
    }
    let y = params.y0 + gid.y;
    let pixel = y * params.width + gid.x;
    var sum = vec3(0.0);
    var rays = 0u;
    for (var s = params.s0; s < params.s1; s++) {
        var stream = sample_stream_new(params.sequence, params.seed, pixel, s);
        let jitter = sample_stream_next_2d(&stream);
        let px = vec2(f32(gid.x), f32(y)) + jitter;
        sum += trace(params.cam_position, camera_dir(px), &stream, &rays);
    }
    output[pixel] = vec4(sum, bitcast<f32>(rays));
}
