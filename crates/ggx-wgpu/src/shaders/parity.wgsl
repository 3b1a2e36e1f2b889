// parity.wgsl: runs one ggx_core.wgsl or energy.wgsl function (chosen by the pipeline constant
// FUNC) over a table of inputs and writes its outputs as raw bits, 16 words per case. Appended to
// ggx_core.wgsl and energy.wgsl, in that order. The Rust side (parity.rs) finds each function's id
// here by name: row `name` runs `case F_NAME`. Each row's pipeline compiles this file with only
// its own arm and `default` left in `switch FUNC` (parity.rs `row_source` cuts the others out by
// their lines: an arm opens with `        case F_NAME: {` and closes with `        }`, eight
// spaces in; comment lines between arms are dropped).

// One case. Floats arrive as bits, so NaN, infinities and signed zeros survive the upload.
struct ParityIn {
    a: vec4<f32>,
    b: vec4<f32>,
    c: vec4<f32>,
    n: vec4<u32>,
    m: vec4<u32>,
}

@group(0) @binding(0) var<storage, read> inputs: array<ParityIn>;
// One BRDF per case: the distribution, Fresnel and conductor functions read it from here, which
// also exercises the Rust/WGSL struct layout.
@group(0) @binding(1) var<storage, read> bsdfs: array<GgxConductor>;
@group(0) @binding(2) var<storage, read_write> outputs: array<u32>;
// One dielectric per case (zero for the other rows): the dielectric functions read it from here.
@group(0) @binding(3) var<storage, read> dielectrics: array<GgxDielectric>;
// ggx-core's energy-compensation tables concatenated as `scene_upload::energy_tables()` lists
// them (energy.wgsl's ENERGY_* offsets), the same f32 values ggx-core reads.
@group(0) @binding(4) var<storage, read> energy_values: array<f32>;

// energy.wgsl's table accessor.
fn energy_table(i: u32) -> f32 {
    return energy_values[i];
}

override FUNC: u32;

const OUT_WORDS: u32 = 16u;

const F_SAFE_SQRT: u32 = 0u;
const F_FINITE_OR_ZERO: u32 = 1u;
const F_SANITIZE_U: u32 = 2u;
const F_SANITIZE_U2: u32 = 3u;
const F_NORMALIZE_OR_ZERO: u32 = 4u;
const F_SINCOS_2PI: u32 = 5u;
const F_CLAMP_ALPHA: u32 = 6u;
const F_ROUGHNESS_TO_ALPHA: u32 = 7u;
const F_ALPHA_TO_ROUGHNESS: u32 = 8u;
const F_TROWBRIDGE_REITZ_NEW: u32 = 9u;
const F_D: u32 = 10u;
const F_LAMBDA: u32 = 11u;
const F_G1: u32 = 12u;
const F_G2: u32 = 13u;
const F_G2_SEPARABLE: u32 = 14u;
const F_D_VISIBLE: u32 = 15u;
const F_SAMPLE_WM_NDF: u32 = 16u;
const F_PDF_WM_NDF: u32 = 17u;
const F_SAMPLE_WM_VNDF: u32 = 18u;
const F_SAMPLE_WM_SPHERICAL_CAPS: u32 = 19u;
const F_BOUNDED_K: u32 = 20u;
const F_SAMPLE_WM_BOUNDED: u32 = 21u;
const F_PDF_WI_BOUNDED: u32 = 22u;
const F_SAMPLE_COSINE_HEMISPHERE: u32 = 23u;
const F_PDF_COSINE_HEMISPHERE: u32 = 24u;
const F_SAMPLE_UNIFORM_HEMISPHERE: u32 = 25u;
const F_PDF_UNIFORM_HEMISPHERE: u32 = 26u;
const F_FRESNEL_SCHLICK: u32 = 27u;
const F_FRESNEL_DIELECTRIC: u32 = 28u;
const F_FRESNEL_COMPLEX: u32 = 29u;
const F_FRESNEL_PARAMS_EVAL: u32 = 30u;
const F_GGX_CONDUCTOR_EVAL: u32 = 31u;
const F_GGX_CONDUCTOR_PDF: u32 = 32u;
const F_GGX_CONDUCTOR_SAMPLE: u32 = 33u;
const F_BALANCE_HEURISTIC: u32 = 34u;
const F_POWER_HEURISTIC: u32 = 35u;
const F_FRAME_FROM_Z: u32 = 36u;
const F_FRAME_TO_LOCAL: u32 = 37u;
const F_FRAME_TO_WORLD: u32 = 38u;
const F_REFLECT: u32 = 39u;
const F_HASH_U32: u32 = 40u;
const F_HASH_COMBINE: u32 = 41u;
const F_U32_TO_UNIT_F32: u32 = 42u;
const F_COUNTER_RNG_NEW: u32 = 43u;
const F_COUNTER_RNG_GET_U32: u32 = 44u;
const F_COUNTER_RNG_NEXT_U32: u32 = 45u;
const F_COUNTER_RNG_NEXT_F32: u32 = 46u;
const F_COUNTER_RNG_NEXT_VEC2: u32 = 47u;
const F_COUNTER_RNG_ADVANCE: u32 = 48u;
const F_SOBOL: u32 = 49u;
const F_OWEN_SCRAMBLE: u32 = 50u;
const F_SOBOL_OWEN_U32: u32 = 51u;
const F_SOBOL_OWEN: u32 = 52u;
const F_SAMPLE_STREAM_NEW: u32 = 53u;
const F_SAMPLE_STREAM_GET_U32: u32 = 54u;
const F_SAMPLE_STREAM_NEXT_1D: u32 = 55u;
const F_SAMPLE_STREAM_NEXT_2D: u32 = 56u;
const F_GGX_CONDUCTOR_LAYOUT: u32 = 57u;
// Not a ggx-core function: how the adapter treats NaN, infinities, subnormals and a * b + c.
const F_PROBE: u32 = 58u;
const F_SHUFFLE_INDEX_REVERSED: u32 = 59u;
const F_SOBOL_OWEN_SHUFFLED: u32 = 60u;
const F_CLAMP_ETA: u32 = 61u;
const F_REFRACT: u32 = 62u;
const F_GGX_DIELECTRIC_EVAL: u32 = 63u;
const F_GGX_DIELECTRIC_PDF: u32 = 64u;
const F_GGX_DIELECTRIC_SAMPLE: u32 = 65u;
const F_GGX_DIELECTRIC_LAYOUT: u32 = 66u;
const F_BSDF_SAMPLE_MIS_PDF: u32 = 67u;
// energy.wgsl.
const F_ENERGY_ALBEDO: u32 = 68u;
const F_ENERGY_AVERAGE_ALBEDO: u32 = 69u;
const F_MULTIPLE_SCATTERING_FRESNEL: u32 = 70u;
const F_EFFECTIVE_ALPHA: u32 = 71u;
const F_ALPHA_COORDINATE: u32 = 72u;
const F_MU_COORDINATE: u32 = 73u;
const F_GGX_CONDUCTOR_MS_IS_COMPENSATED: u32 = 74u;
const F_GGX_CONDUCTOR_MS_FRESNEL: u32 = 75u;
const F_GGX_CONDUCTOR_MS_EVAL_MS: u32 = 76u;
const F_GGX_CONDUCTOR_MS_EVAL: u32 = 77u;
const F_GGX_CONDUCTOR_MS_PROBABILITY: u32 = 78u;
const F_GGX_CONDUCTOR_MS_PDF: u32 = 79u;
const F_GGX_CONDUCTOR_MS_SAMPLE: u32 = 80u;
const F_ETA_COORDINATE: u32 = 81u;
const F_COAT_ALBEDO: u32 = 82u;
const F_COAT_AVERAGE_ALBEDO: u32 = 83u;
const F_PLASTIC_BASE_WEIGHT: u32 = 84u;
const F_GGX_DIELECTRIC_MS_IS_COMPENSATED: u32 = 85u;
const F_GGX_DIELECTRIC_MS_COMPENSATION_SCALE: u32 = 86u;
const F_GGX_DIELECTRIC_MS_EVAL: u32 = 87u;
const F_GGX_DIELECTRIC_MS_PDF: u32 = 88u;
const F_GGX_DIELECTRIC_MS_SAMPLE: u32 = 89u;
const F_THIN_DIELECTRIC_REFLECTANCE: u32 = 90u;
const F_THIN_DIELECTRIC_SAMPLE: u32 = 91u;
// metal_rough.rs.
const F_CLAMP_IOR: u32 = 92u;
const F_DIELECTRIC_F0: u32 = 93u;
const F_GLTF_METAL_ROUGH_NEW: u32 = 94u;
const F_GLTF_METAL_ROUGH_CORE: u32 = 95u;
const F_GLTF_METAL_ROUGH_IS_DELTA: u32 = 96u;
const F_GLTF_METAL_ROUGH_SPECULAR: u32 = 97u;
const F_GLTF_METAL_ROUGH_SPECULAR_PROBABILITY: u32 = 98u;
const F_GLTF_METAL_ROUGH_SPECULAR_FRESNEL: u32 = 99u;
const F_GLTF_METAL_ROUGH_DIFFUSE_WEIGHT: u32 = 100u;
const F_GLTF_METAL_ROUGH_EVAL: u32 = 101u;
const F_GLTF_METAL_ROUGH_PDF: u32 = 102u;
const F_GLTF_METAL_ROUGH_SAMPLE: u32 = 103u;
// clearcoat.rs.
const F_CLEARCOAT_FRESNEL: u32 = 104u;
const F_METAL_ROUGH_ALBEDO_ESTIMATE: u32 = 105u;
const F_GLTF_CLEARCOAT_NEW: u32 = 106u;
const F_GLTF_CLEARCOAT_COAT_WEIGHT: u32 = 107u;
const F_GLTF_CLEARCOAT_COAT_IS_DELTA: u32 = 108u;
const F_GLTF_CLEARCOAT_COAT_LOBE: u32 = 109u;
const F_GLTF_CLEARCOAT_COAT_MIX: u32 = 110u;
const F_GLTF_CLEARCOAT_COAT_PROBABILITY: u32 = 111u;
const F_GLTF_CLEARCOAT_EVAL: u32 = 112u;
const F_GLTF_CLEARCOAT_PDF: u32 = 113u;
const F_GLTF_CLEARCOAT_SAMPLE: u32 = 114u;
const F_GLTF_CLEARCOAT_BASE_MIX: u32 = 115u;

var<private> out_base: u32;

fn put_u(k: u32, x: u32) {
    outputs[out_base + k] = x;
}

fn put_b(k: u32, x: bool) {
    put_u(k, select(0u, 1u, x));
}

fn put_f(k: u32, x: f32) {
    put_u(k, bitcast<u32>(x));
}

fn put_v2(k: u32, v: vec2<f32>) {
    put_f(k, v.x);
    put_f(k + 1u, v.y);
}

fn put_v3(k: u32, v: vec3<f32>) {
    put_f(k, v.x);
    put_f(k + 1u, v.y);
    put_f(k + 2u, v.z);
}

// A sample's words: valid, delta, wi, weight, pdf.
fn put_sample(s: BsdfSample) {
    put_u(0u, s.valid);
    put_u(1u, s.is_delta);
    put_v3(2u, s.wi);
    put_v3(5u, s.weight);
    put_f(8u, s.pdf);
}

// The compensated conductor of a case: the case's conductor, F_avg in c.xyz, compensation in m.x.
fn conductor_ms(p: ParityIn, bsdf: GgxConductor) -> GgxConductorMs {
    return GgxConductorMs(bsdf, p.c.xyz, p.m.x);
}

// The compensated dielectric of a case: the case's dielectric, compensation in m.x.
fn dielectric_ms(p: ParityIn, dielectric: GgxDielectric) -> GgxDielectricMs {
    return GgxDielectricMs(dielectric, p.m.x, array<u32, 3>(0u, 0u, 0u));
}

// The glTF material of a case, packed into the case's conductor (parity/cases.rs
// `pack_metal_rough`): distribution as is, base_color and metallic in fresnel.a, f0 and
// specular_weight in fresnel.b, p_specular in fresnel.eta, pad in fresnel.kind.
fn metal_rough(bsdf: GgxConductor) -> GltfMetalRough {
    let f = bsdf.fresnel;
    return GltfMetalRough(f.a.xyz, f.a.w, f.b.xyz, f.b.w, bsdf.distribution, f.eta, f.kind);
}

// A GltfMetalRough's words: base_color, metallic, f0, specular_weight, alphas, p_specular, pad.
fn put_metal_rough(b: GltfMetalRough) {
    put_v3(0u, b.base_color);
    put_f(3u, b.metallic);
    put_v3(4u, b.f0);
    put_f(7u, b.specular_weight);
    put_f(8u, b.distribution.alpha_x);
    put_f(9u, b.distribution.alpha_y);
    put_f(10u, b.p_specular);
    put_u(11u, b.pad);
}

// The clearcoat of a case, packed into the case's conductor (parity/cases.rs `pack_clearcoat`): the
// base as `metal_rough` unpacks it, the coat's alphas (bits) in pad, weight and base_albedo (bits)
// in fresnel.pad.
fn clearcoat(bsdf: GgxConductor) -> GltfClearcoat {
    let coat = TrowbridgeReitz(bitcast<f32>(bsdf.pad.x), bitcast<f32>(bsdf.pad.y));
    let f = bsdf.fresnel;
    return GltfClearcoat(metal_rough(bsdf), coat, bitcast<f32>(f.pad.x), bitcast<f32>(f.pad.y));
}

// A GltfClearcoat's words: the base's (put_metal_rough), the coat's alphas, weight, base_albedo.
fn put_clearcoat(b: GltfClearcoat) {
    put_metal_rough(b.base);
    put_f(12u, b.coat.alpha_x);
    put_f(13u, b.coat.alpha_y);
    put_f(14u, b.weight);
    put_f(15u, b.base_albedo);
}

// Behaviour of builtins and arithmetic on special values; inputs come from the buffer so that
// nothing is folded at compile time: a = (NaN, 1, 0, -1), b = (subnormal 2^-133, 1e-20, 1 + 2^-12,
// -(1 + 2^-11)).
fn probe(p: ParityIn) {
    let nan = p.a.x;
    let one = p.a.y;
    let zero = p.a.z;
    put_b(0u, nan != nan);
    put_b(1u, !(nan > zero));
    put_f(2u, max(nan, zero));
    put_f(3u, min(nan, one));
    put_f(4u, clamp(nan, zero, one));
    put_f(5u, one / zero);
    put_f(6u, zero / zero);
    put_f(7u, p.b.x * one);
    put_f(8u, p.b.y * p.b.y);
    put_f(9u, p.b.z * p.b.z + p.b.w);
    put_f(10u, sqrt(p.a.w));
    put_b(11u, is_nan(nan));
}

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&inputs) {
        return;
    }
    out_base = i * OUT_WORDS;
    let p = inputs[i];
    let bsdf = bsdfs[i];
    let dist = bsdf.distribution;
    let dielectric = dielectrics[i];
    switch FUNC {
        case F_SAFE_SQRT: {
            put_f(0u, safe_sqrt(p.a.x));
        }
        case F_FINITE_OR_ZERO: {
            put_f(0u, finite_or_zero(p.a.x));
        }
        case F_SANITIZE_U: {
            put_f(0u, sanitize_u(p.a.x));
        }
        case F_SANITIZE_U2: {
            put_v2(0u, sanitize_u2(p.a.xy));
        }
        case F_NORMALIZE_OR_ZERO: {
            put_v3(0u, normalize_or_zero(p.a.xyz));
        }
        case F_SINCOS_2PI: {
            put_v2(0u, sincos_2pi(p.a.x));
        }
        case F_CLAMP_ALPHA: {
            put_f(0u, clamp_alpha(p.a.x));
        }
        case F_ROUGHNESS_TO_ALPHA: {
            put_f(0u, roughness_to_alpha(p.a.x));
        }
        case F_ALPHA_TO_ROUGHNESS: {
            put_f(0u, alpha_to_roughness(p.a.x));
        }
        case F_TROWBRIDGE_REITZ_NEW: {
            let t = trowbridge_reitz_new(p.a.x, p.a.y);
            put_f(0u, t.alpha_x);
            put_f(1u, t.alpha_y);
            put_b(2u, is_isotropic(t));
            put_b(3u, is_effectively_smooth(t));
        }
        case F_D: {
            put_f(0u, d(dist, p.a.xyz));
        }
        case F_LAMBDA: {
            put_f(0u, lambda(dist, p.a.xyz));
        }
        case F_G1: {
            put_f(0u, g1(dist, p.a.xyz));
        }
        case F_G2: {
            put_f(0u, g2(dist, p.a.xyz, p.b.xyz));
        }
        case F_G2_SEPARABLE: {
            put_f(0u, g2_separable(dist, p.a.xyz, p.b.xyz));
        }
        case F_D_VISIBLE: {
            put_f(0u, d_visible(dist, p.a.xyz, p.b.xyz));
        }
        case F_SAMPLE_WM_NDF: {
            put_v3(0u, sample_wm_ndf(dist, p.c.xy));
        }
        case F_PDF_WM_NDF: {
            put_f(0u, pdf_wm_ndf(dist, p.a.xyz));
        }
        case F_SAMPLE_WM_VNDF: {
            put_v3(0u, sample_wm_vndf(dist, p.a.xyz, p.c.xy));
        }
        case F_SAMPLE_WM_SPHERICAL_CAPS: {
            put_v3(0u, sample_wm_spherical_caps(dist, p.a.xyz, p.c.xy));
        }
        case F_BOUNDED_K: {
            put_f(0u, bounded_k(dist, p.a.xyz));
        }
        case F_SAMPLE_WM_BOUNDED: {
            put_v3(0u, sample_wm_bounded(dist, p.a.xyz, p.c.xy));
        }
        case F_PDF_WI_BOUNDED: {
            put_f(0u, pdf_wi_bounded(dist, p.a.xyz, p.b.xyz));
        }
        case F_SAMPLE_COSINE_HEMISPHERE: {
            put_v3(0u, sample_cosine_hemisphere(p.c.xy));
        }
        case F_PDF_COSINE_HEMISPHERE: {
            put_f(0u, pdf_cosine_hemisphere(p.a.xyz));
        }
        case F_SAMPLE_UNIFORM_HEMISPHERE: {
            put_v3(0u, sample_uniform_hemisphere(p.c.xy));
        }
        case F_PDF_UNIFORM_HEMISPHERE: {
            put_f(0u, pdf_uniform_hemisphere(p.a.xyz));
        }
        case F_FRESNEL_SCHLICK: {
            put_v3(0u, fresnel_schlick(p.c.x, p.a.xyz, p.b.xyz));
        }
        case F_FRESNEL_DIELECTRIC: {
            put_f(0u, fresnel_dielectric(p.c.x, p.c.y));
        }
        case F_FRESNEL_COMPLEX: {
            put_f(0u, fresnel_complex(p.c.x, p.c.y, p.c.z));
        }
        case F_FRESNEL_PARAMS_EVAL: {
            put_v3(0u, fresnel_params_eval(bsdf.fresnel, p.c.x));
        }
        case F_GGX_CONDUCTOR_EVAL: {
            put_v3(0u, ggx_conductor_eval(bsdf, p.a.xyz, p.b.xyz));
        }
        case F_GGX_CONDUCTOR_PDF: {
            put_f(0u, ggx_conductor_pdf(bsdf, p.a.xyz, p.b.xyz, p.n.x));
        }
        case F_GGX_CONDUCTOR_SAMPLE: {
            put_sample(ggx_conductor_sample(bsdf, p.a.xyz, p.c.xy, p.n.x));
        }
        case F_BALANCE_HEURISTIC: {
            put_f(0u, balance_heuristic(p.c.x, p.c.y, p.c.z, p.c.w));
        }
        case F_POWER_HEURISTIC: {
            put_f(0u, power_heuristic(p.c.x, p.c.y, p.c.z, p.c.w));
        }
        case F_FRAME_FROM_Z: {
            let f = frame_from_z(p.a.xyz);
            put_v3(0u, f.x);
            put_v3(3u, f.y);
            put_v3(6u, f.z);
        }
        case F_FRAME_TO_LOCAL: {
            let f = Frame(p.a.xyz, p.b.xyz, p.c.xyz);
            put_v3(0u, frame_to_local(f, vec3(p.a.w, p.b.w, p.c.w)));
        }
        case F_FRAME_TO_WORLD: {
            let f = Frame(p.a.xyz, p.b.xyz, p.c.xyz);
            put_v3(0u, frame_to_world(f, vec3(p.a.w, p.b.w, p.c.w)));
        }
        case F_REFLECT: {
            put_v3(0u, reflect(p.a.xyz, p.b.xyz));
        }
        case F_HASH_U32: {
            put_u(0u, hash_u32(p.n.x));
        }
        case F_HASH_COMBINE: {
            put_u(0u, hash_combine(p.n.x, p.n.y));
        }
        case F_U32_TO_UNIT_F32: {
            put_f(0u, u32_to_unit_f32(p.n.x));
        }
        case F_COUNTER_RNG_NEW: {
            let r = counter_rng_new(p.n.x, p.n.y);
            put_u(0u, r.key);
            put_u(1u, r.counter);
        }
        case F_COUNTER_RNG_GET_U32: {
            put_u(0u, counter_rng_get_u32(CounterRng(p.n.x, p.n.y), p.n.z));
        }
        case F_COUNTER_RNG_NEXT_U32: {
            var r = CounterRng(p.n.x, p.n.y);
            put_u(0u, counter_rng_next_u32(&r));
            put_u(1u, counter_rng_next_u32(&r));
            put_u(2u, r.counter);
        }
        case F_COUNTER_RNG_NEXT_F32: {
            var r = CounterRng(p.n.x, p.n.y);
            put_f(0u, counter_rng_next_f32(&r));
            put_u(1u, r.counter);
        }
        case F_COUNTER_RNG_NEXT_VEC2: {
            var r = CounterRng(p.n.x, p.n.y);
            put_v2(0u, counter_rng_next_vec2(&r));
            put_u(2u, r.counter);
        }
        case F_COUNTER_RNG_ADVANCE: {
            var r = CounterRng(p.n.x, p.n.y);
            counter_rng_advance(&r, p.n.z);
            put_u(0u, r.counter);
            put_u(1u, counter_rng_next_u32(&r));
        }
        case F_SOBOL: {
            put_u(0u, sobol(p.n.x, p.n.y));
        }
        case F_OWEN_SCRAMBLE: {
            put_u(0u, owen_scramble(p.n.x, p.n.y));
        }
        case F_SHUFFLE_INDEX_REVERSED: {
            put_u(0u, shuffle_index_reversed(p.n.x, p.n.y));
        }
        case F_SOBOL_OWEN_SHUFFLED: {
            put_u(0u, sobol_owen_shuffled(p.n.x, p.n.y, p.n.z));
        }
        case F_SOBOL_OWEN_U32: {
            put_u(0u, sobol_owen_u32(p.n.x, p.n.y, p.n.z));
        }
        case F_SOBOL_OWEN: {
            put_f(0u, sobol_owen(p.n.x, p.n.y, p.n.z));
        }
        case F_SAMPLE_STREAM_NEW: {
            let s = sample_stream_new(p.n.x, p.n.y, p.n.z, p.n.w);
            put_u(0u, s.kind);
            put_u(1u, s.seed);
            put_u(2u, s.sample_index);
            put_u(3u, s.dimension);
        }
        case F_SAMPLE_STREAM_GET_U32: {
            put_u(0u, sample_stream_get_u32(SampleStream(p.n.x, p.n.y, p.n.z, p.n.w), p.m.x));
        }
        case F_SAMPLE_STREAM_NEXT_1D: {
            var s = SampleStream(p.n.x, p.n.y, p.n.z, p.n.w);
            put_f(0u, sample_stream_next_1d(&s));
            put_f(1u, sample_stream_next_1d(&s));
            put_u(2u, s.dimension);
        }
        case F_SAMPLE_STREAM_NEXT_2D: {
            var s = SampleStream(p.n.x, p.n.y, p.n.z, p.n.w);
            put_v2(0u, sample_stream_next_2d(&s));
            put_v2(2u, sample_stream_next_2d(&s));
            put_u(4u, s.dimension);
        }
        case F_GGX_CONDUCTOR_LAYOUT: {
            put_f(0u, bsdf.distribution.alpha_x);
            put_f(1u, bsdf.distribution.alpha_y);
            put_u(2u, bsdf.pad.x);
            put_u(3u, bsdf.pad.y);
            put_u(4u, bsdf.fresnel.kind);
            put_f(5u, bsdf.fresnel.eta);
            put_u(6u, bsdf.fresnel.pad.x);
            put_u(7u, bsdf.fresnel.pad.y);
            put_f(8u, bsdf.fresnel.a.x);
            put_f(9u, bsdf.fresnel.a.y);
            put_f(10u, bsdf.fresnel.a.z);
            put_f(11u, bsdf.fresnel.a.w);
            put_f(12u, bsdf.fresnel.b.x);
            put_f(13u, bsdf.fresnel.b.y);
            put_f(14u, bsdf.fresnel.b.z);
            put_f(15u, bsdf.fresnel.b.w);
        }
        case F_CLAMP_ETA: {
            put_f(0u, clamp_eta(p.a.x));
        }
        case F_REFRACT: {
            let r = refract(p.a.xyz, p.b.xyz, p.c.x);
            put_u(0u, r.valid);
            put_v3(1u, r.wt);
        }
        case F_GGX_DIELECTRIC_EVAL: {
            put_v3(0u, ggx_dielectric_eval(dielectric, p.a.xyz, p.b.xyz, p.n.y));
        }
        case F_GGX_DIELECTRIC_PDF: {
            put_f(0u, ggx_dielectric_pdf(dielectric, p.a.xyz, p.b.xyz, p.n.x, p.n.y));
        }
        case F_GGX_DIELECTRIC_SAMPLE: {
            put_sample(ggx_dielectric_sample(dielectric, p.a.xyz, p.c.xy, p.c.z, p.n.x, p.n.y));
        }
        case F_GGX_DIELECTRIC_LAYOUT: {
            put_f(0u, dielectric.distribution.alpha_x);
            put_f(1u, dielectric.distribution.alpha_y);
            put_f(2u, dielectric.eta);
            put_u(3u, dielectric.pad);
        }
        case F_BSDF_SAMPLE_MIS_PDF: {
            put_f(0u, bsdf_sample_mis_pdf(BsdfSample(vec3(0.0), vec3(0.0), p.a.x, p.n.x, 1u)));
        }
        // energy.wgsl. Scalars in a (energy_albedo: mu, alpha; coat_albedo: mu, alpha, eta;
        // plastic_base_weight: mu_o, mu_i, alpha, eta); the conductor MS rows read wo in a, wi in
        // b (the sampler: u in b.xy, u_lobe in b.z), F_avg in c.xyz, sampling in n.x and
        // compensation in m.x; the dielectric MS rows read wo, wi in a, b, u and u_lobe in c.xyz,
        // sampling and mode in n.x, n.y and compensation in m.x; the thin sheet reads cos in c.x
        // (the reflectance) or wo in a and u_lobe in c.z (the sampler), and eta in c.y.
        case F_ENERGY_ALBEDO: {
            put_f(0u, energy_albedo(p.a.x, p.a.y));
        }
        case F_ENERGY_AVERAGE_ALBEDO: {
            put_f(0u, energy_average_albedo(p.a.x));
        }
        case F_MULTIPLE_SCATTERING_FRESNEL: {
            put_v3(0u, multiple_scattering_fresnel(p.a.xyz, p.b.x));
        }
        case F_EFFECTIVE_ALPHA: {
            put_f(0u, effective_alpha(dist));
        }
        case F_ALPHA_COORDINATE: {
            put_f(0u, alpha_coordinate(p.a.x));
        }
        case F_MU_COORDINATE: {
            put_f(0u, mu_coordinate(p.a.x));
        }
        case F_GGX_CONDUCTOR_MS_IS_COMPENSATED: {
            put_b(0u, ggx_conductor_ms_is_compensated(conductor_ms(p, bsdf)));
        }
        case F_GGX_CONDUCTOR_MS_FRESNEL: {
            put_v3(0u, ggx_conductor_ms_fresnel(conductor_ms(p, bsdf)));
        }
        case F_GGX_CONDUCTOR_MS_EVAL_MS: {
            put_v3(0u, ggx_conductor_ms_eval_ms(conductor_ms(p, bsdf), p.a.xyz, p.b.xyz));
        }
        case F_GGX_CONDUCTOR_MS_EVAL: {
            put_v3(0u, ggx_conductor_ms_eval(conductor_ms(p, bsdf), p.a.xyz, p.b.xyz));
        }
        case F_GGX_CONDUCTOR_MS_PROBABILITY: {
            put_f(0u, ggx_conductor_ms_probability(conductor_ms(p, bsdf), p.a.xyz));
        }
        case F_GGX_CONDUCTOR_MS_PDF: {
            put_f(0u, ggx_conductor_ms_pdf(conductor_ms(p, bsdf), p.a.xyz, p.b.xyz, p.n.x));
        }
        case F_GGX_CONDUCTOR_MS_SAMPLE: {
            put_sample(ggx_conductor_ms_sample(conductor_ms(p, bsdf), p.a.xyz, p.b.xy, p.b.z, p.n.x));
        }
        case F_ETA_COORDINATE: {
            put_f(0u, eta_coordinate(p.a.x));
        }
        case F_COAT_ALBEDO: {
            put_f(0u, coat_albedo(p.a.x, p.a.y, p.a.z));
        }
        case F_COAT_AVERAGE_ALBEDO: {
            put_f(0u, coat_average_albedo(p.a.x, p.a.y));
        }
        case F_PLASTIC_BASE_WEIGHT: {
            put_f(0u, plastic_base_weight(p.a.x, p.a.y, p.a.z, p.a.w));
        }
        case F_GGX_DIELECTRIC_MS_IS_COMPENSATED: {
            put_b(0u, ggx_dielectric_ms_is_compensated(dielectric_ms(p, dielectric)));
        }
        case F_GGX_DIELECTRIC_MS_COMPENSATION_SCALE: {
            put_f(0u, ggx_dielectric_ms_compensation_scale(dielectric_ms(p, dielectric), p.a.xyz));
        }
        case F_GGX_DIELECTRIC_MS_EVAL: {
            put_v3(0u, ggx_dielectric_ms_eval(dielectric_ms(p, dielectric), p.a.xyz, p.b.xyz, p.n.y));
        }
        case F_GGX_DIELECTRIC_MS_PDF: {
            put_f(0u, ggx_dielectric_ms_pdf(dielectric_ms(p, dielectric), p.a.xyz, p.b.xyz, p.n.x, p.n.y));
        }
        case F_GGX_DIELECTRIC_MS_SAMPLE: {
            let b = dielectric_ms(p, dielectric);
            put_sample(ggx_dielectric_ms_sample(b, p.a.xyz, p.c.xy, p.c.z, p.n.x, p.n.y));
        }
        case F_THIN_DIELECTRIC_REFLECTANCE: {
            put_f(0u, thin_dielectric_reflectance(p.c.y, p.c.x));
        }
        case F_THIN_DIELECTRIC_SAMPLE: {
            put_sample(thin_dielectric_sample(p.c.y, p.a.xyz, p.c.z));
        }
        // metal_rough.rs. clamp_ior reads ior in a.x; dielectric_f0 ior in a.x and the specular
        // colour in b.xyz; gltf_metal_rough_new the base colour in a.xyz, metallic in a.w, the
        // alphas in b.xy, ior in b.z, the specular weight in b.w and the specular colour in
        // c.xyz (gltf_metal_rough_core: base colour, metallic, alpha in b.x). The method rows
        // read the material from the case's conductor (`metal_rough`), wo in a, wi in b, cos in
        // c.x, u and u_lobe in c.xyz, sampling in n.x.
        case F_CLAMP_IOR: {
            put_f(0u, clamp_ior(p.a.x));
        }
        case F_DIELECTRIC_F0: {
            put_v3(0u, dielectric_f0(p.a.x, p.b.xyz));
        }
        case F_GLTF_METAL_ROUGH_NEW: {
            put_metal_rough(gltf_metal_rough_new(p.a.xyz, p.a.w, p.b.x, p.b.y, p.b.z, p.c.xyz, p.b.w));
        }
        case F_GLTF_METAL_ROUGH_CORE: {
            put_metal_rough(gltf_metal_rough_core(p.a.xyz, p.a.w, p.b.x));
        }
        case F_GLTF_METAL_ROUGH_IS_DELTA: {
            put_b(0u, gltf_metal_rough_is_delta(metal_rough(bsdf)));
        }
        case F_GLTF_METAL_ROUGH_SPECULAR: {
            let k = gltf_metal_rough_specular(metal_rough(bsdf));
            put_f(0u, k.distribution.alpha_x);
            put_f(1u, k.distribution.alpha_y);
            put_u(2u, k.pad.x);
            put_u(3u, k.pad.y);
            put_u(4u, k.fresnel.kind);
            put_f(5u, k.fresnel.eta);
            put_u(6u, k.fresnel.pad.x);
            put_u(7u, k.fresnel.pad.y);
            put_f(8u, k.fresnel.a.x);
            put_f(9u, k.fresnel.a.y);
            put_f(10u, k.fresnel.a.z);
            put_f(11u, k.fresnel.a.w);
            put_f(12u, k.fresnel.b.x);
            put_f(13u, k.fresnel.b.y);
            put_f(14u, k.fresnel.b.z);
            put_f(15u, k.fresnel.b.w);
        }
        case F_GLTF_METAL_ROUGH_SPECULAR_PROBABILITY: {
            put_f(0u, gltf_metal_rough_specular_probability(metal_rough(bsdf)));
        }
        case F_GLTF_METAL_ROUGH_SPECULAR_FRESNEL: {
            put_v3(0u, gltf_metal_rough_specular_fresnel(metal_rough(bsdf), p.c.x));
        }
        case F_GLTF_METAL_ROUGH_DIFFUSE_WEIGHT: {
            put_f(0u, gltf_metal_rough_diffuse_weight(metal_rough(bsdf), p.c.x));
        }
        case F_GLTF_METAL_ROUGH_EVAL: {
            put_v3(0u, gltf_metal_rough_eval(metal_rough(bsdf), p.a.xyz, p.b.xyz));
        }
        case F_GLTF_METAL_ROUGH_PDF: {
            put_f(0u, gltf_metal_rough_pdf(metal_rough(bsdf), p.a.xyz, p.b.xyz, p.n.x));
        }
        case F_GLTF_METAL_ROUGH_SAMPLE: {
            put_sample(gltf_metal_rough_sample(metal_rough(bsdf), p.a.xyz, p.c.xy, p.c.z, p.n.x));
        }
        // clearcoat.rs. clearcoat_fresnel reads cos in a.x; metal_rough_albedo_estimate the base
        // from the case's conductor (`metal_rough`); gltf_clearcoat_new the base likewise, the
        // weight in a.x and the coat alpha in a.y. The method rows read the clearcoat from the
        // case's conductor (`clearcoat`), wo in a, wi in b, cos in c.x, u and u_lobe in c.xyz,
        // sampling in n.x.
        case F_CLEARCOAT_FRESNEL: {
            put_f(0u, clearcoat_fresnel(p.a.x));
        }
        case F_METAL_ROUGH_ALBEDO_ESTIMATE: {
            put_f(0u, metal_rough_albedo_estimate(metal_rough(bsdf)));
        }
        case F_GLTF_CLEARCOAT_NEW: {
            put_clearcoat(gltf_clearcoat_new(metal_rough(bsdf), p.a.x, p.a.y));
        }
        case F_GLTF_CLEARCOAT_COAT_WEIGHT: {
            put_f(0u, gltf_clearcoat_coat_weight(clearcoat(bsdf)));
        }
        case F_GLTF_CLEARCOAT_COAT_IS_DELTA: {
            put_b(0u, gltf_clearcoat_coat_is_delta(clearcoat(bsdf)));
        }
        case F_GLTF_CLEARCOAT_COAT_LOBE: {
            let k = gltf_clearcoat_coat_lobe(clearcoat(bsdf));
            put_f(0u, k.distribution.alpha_x);
            put_f(1u, k.distribution.alpha_y);
            put_u(2u, k.pad.x);
            put_u(3u, k.pad.y);
            put_u(4u, k.fresnel.kind);
            put_f(5u, k.fresnel.eta);
            put_u(6u, k.fresnel.pad.x);
            put_u(7u, k.fresnel.pad.y);
            put_f(8u, k.fresnel.a.x);
            put_f(9u, k.fresnel.a.y);
            put_f(10u, k.fresnel.a.z);
            put_f(11u, k.fresnel.a.w);
            put_f(12u, k.fresnel.b.x);
            put_f(13u, k.fresnel.b.y);
            put_f(14u, k.fresnel.b.z);
            put_f(15u, k.fresnel.b.w);
        }
        case F_GLTF_CLEARCOAT_COAT_MIX: {
            put_f(0u, gltf_clearcoat_coat_mix(clearcoat(bsdf), p.c.x));
        }
        case F_GLTF_CLEARCOAT_BASE_MIX: {
            put_f(0u, gltf_clearcoat_base_mix(clearcoat(bsdf), p.c.x));
        }
        case F_GLTF_CLEARCOAT_COAT_PROBABILITY: {
            put_f(0u, gltf_clearcoat_coat_probability(clearcoat(bsdf), p.c.x));
        }
        case F_GLTF_CLEARCOAT_EVAL: {
            put_v3(0u, gltf_clearcoat_eval(clearcoat(bsdf), p.a.xyz, p.b.xyz));
        }
        case F_GLTF_CLEARCOAT_PDF: {
            put_f(0u, gltf_clearcoat_pdf(clearcoat(bsdf), p.a.xyz, p.b.xyz, p.n.x));
        }
        case F_GLTF_CLEARCOAT_SAMPLE: {
            put_sample(gltf_clearcoat_sample(clearcoat(bsdf), p.a.xyz, p.c.xy, p.c.z, p.n.x));
        }
        case F_PROBE: {
            probe(p);
        }
        default: {
            put_u(0u, 0xdeadbeefu);
        }
    }
}
