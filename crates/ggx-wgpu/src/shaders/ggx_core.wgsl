// ggx_core.wgsl: the WGSL twin of the `ggx-core` crate, one function per Rust function.
//
// Naming: free functions keep their Rust names; methods of `TrowbridgeReitz` keep their bare
// names (`d`, `lambda`, `g1`, ...) and take the distribution first; methods of the other types
// are prefixed with the type in snake_case (`ggx_conductor_eval`, `counter_rng_next_u32`).
// `Option<BsdfSample>` becomes `BsdfSample` with a `valid` flag, `Sampling` and `SequenceKind`
// are their `u32` discriminants.
//
// NaN: WGSL's `max`, `min` and `clamp` are undefined for NaN operands (SPIR-V FMax/FMin), so
// every Rust `f32::max` / `f32::min` is spelled `max_num` / `min_num` (IEEE 754 maxNum/minNum:
// a NaN operand is ignored). NaN and infinity are detected from the bit pattern, never by
// comparisons that a compiler might fold. The arithmetic itself is assumed to follow IEEE 754
// (inf and NaN propagate, division by zero gives inf), which the parity harness checks on the
// adapter it runs on.
//
// Layout: `TrowbridgeReitz` (8 bytes), `FresnelParams` (48), `GgxConductor` (64), `GgxDielectric`
// (16), `GltfMetalRough` (48), `CounterRng` (8) and `SampleStream` (16) match the Rust
// `#[repr(C)]` structs byte for byte. `Frame`, `BsdfSample`, `Refracted` and `Half` are values only (the Rust `Frame` packs
// three 12-byte `Vec3`s). `TransportMode` is its `u32` discriminant.

// ---------------------------------------------------------------------------------------------
// Constants
// ---------------------------------------------------------------------------------------------

const PI: f32 = 3.14159265358979323846264338327950288f;
const TAU: f32 = 6.28318530717958647692528676655900577f;
const FRAC_1_PI: f32 = 0.318309886183790671537767526745028724f;
// The largest f32 below one, 1 - 2^-24 (0x3f7fffff).
const ONE_MINUS_EPSILON: f32 = 0.99999994f;

const ALPHA_MIN: f32 = 1e-4f;
const ALPHA_MAX: f32 = 1.0f;
const DELTA_ALPHA: f32 = 1e-3f;

// `ggx_core::Sampling` discriminants.
const SAMPLING_NDF: u32 = 0u;
const SAMPLING_VNDF: u32 = 1u;
const SAMPLING_SPHERICAL_CAPS: u32 = 2u;
const SAMPLING_BOUNDED: u32 = 3u;
const SAMPLING_COSINE: u32 = 4u;
const SAMPLING_UNIFORM: u32 = 5u;

// `ggx_core::fresnel::kind` values.
const FRESNEL_KIND_ONE: u32 = 0u;
const FRESNEL_KIND_SCHLICK: u32 = 1u;
const FRESNEL_KIND_CONDUCTOR: u32 = 2u;
const FRESNEL_KIND_DIELECTRIC: u32 = 3u;

// `ggx_core::SequenceKind` discriminants.
const SEQUENCE_INDEPENDENT: u32 = 0u;
const SEQUENCE_SOBOL: u32 = 1u;

const SOBOL_DIMENSIONS: u32 = 4u;

// ---------------------------------------------------------------------------------------------
// Types
// ---------------------------------------------------------------------------------------------

struct TrowbridgeReitz {
    alpha_x: f32,
    alpha_y: f32,
}

struct FresnelParams {
    kind: u32,
    eta: f32,
    pad: vec2<u32>,
    a: vec4<f32>,
    b: vec4<f32>,
}

struct GgxConductor {
    distribution: TrowbridgeReitz,
    pad: vec2<u32>,
    fresnel: FresnelParams,
}

struct BsdfSample {
    wi: vec3<f32>,
    weight: vec3<f32>,
    pdf: f32,
    is_delta: u32,
    // 1 where the Rust `sample` returns `Some`, 0 (and every other field zero) for `None`.
    valid: u32,
}

struct Frame {
    x: vec3<f32>,
    y: vec3<f32>,
    z: vec3<f32>,
}

struct Complex {
    re: f32,
    im: f32,
}

struct CounterRng {
    key: u32,
    counter: u32,
}

struct SampleStream {
    kind: u32,
    seed: u32,
    sample_index: u32,
    dimension: u32,
}

// ---------------------------------------------------------------------------------------------
// IEEE helpers (what Rust's f32 methods and glam's Vec3 do)
// ---------------------------------------------------------------------------------------------

// f32::is_nan: exponent all ones and a non-zero mantissa (bit test, immune to fast-math).
fn is_nan(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7fffffffu) > 0x7f800000u;
}

// f32::is_finite: exponent not all ones.
fn is_finite(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7f800000u) != 0x7f800000u;
}

// Vec3::is_finite: every component finite.
fn is_finite3(v: vec3<f32>) -> bool {
    return is_finite(v.x) && is_finite(v.y) && is_finite(v.z);
}

// v if every component is finite, else 0 (frame.rs `finite_or_zero3`).
fn finite_or_zero3(v: vec3<f32>) -> vec3<f32> {
    return select(vec3(0.0), v, is_finite3(v));
}

// f32::INFINITY, built at run time (a constant infinity is a WGSL shader-creation error).
fn inf_f32() -> f32 {
    var bits = 0x7f800000u;
    return bitcast<f32>(bits);
}

// f32::max = IEEE maxNum: the larger operand, a NaN operand ignored.
fn max_num(a: f32, b: f32) -> f32 {
    return select(b, a, a > b || is_nan(b));
}

// f32::min = IEEE minNum: the smaller operand, a NaN operand ignored.
fn min_num(a: f32, b: f32) -> f32 {
    return select(b, a, a < b || is_nan(b));
}

// f32::copysign: magnitude of x, sign bit of s.
fn copysign(x: f32, s: f32) -> f32 {
    return bitcast<f32>((bitcast<u32>(x) & 0x7fffffffu) | (bitcast<u32>(s) & 0x80000000u));
}

// Vec3::dot = (x x') + (y y') + (z z'), in glam's order.
fn dot3(a: vec3<f32>, b: vec3<f32>) -> f32 {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

// Vec3::cross = (y z' - y' z, z x' - z' x, x y' - x' y), in glam's order.
fn cross3(a: vec3<f32>, b: vec3<f32>) -> vec3<f32> {
    return vec3(a.y * b.z - b.y * a.z, a.z * b.x - b.z * a.x, a.x * b.y - b.x * a.y);
}

// ---------------------------------------------------------------------------------------------
// math.rs
// ---------------------------------------------------------------------------------------------

// sqrt(max(x, 0)), NaN -> 0.
fn safe_sqrt(x: f32) -> f32 {
    return sqrt(max_num(x, 0.0));
}

// x if finite, else 0.
fn finite_or_zero(x: f32) -> f32 {
    return select(0.0, x, is_finite(x));
}

// clamp(u, 0, 1 - 2^-24), NaN -> 0.
fn sanitize_u(u: f32) -> f32 {
    return min_num(max_num(u, 0.0), ONE_MINUS_EPSILON);
}

// sanitize_u on both components.
fn sanitize_u2(u: vec2<f32>) -> vec2<f32> {
    return vec2(sanitize_u(u.x), sanitize_u(u.y));
}

// v / |v|; v unchanged when |len2 - 1| <= 2e-6 (idempotent); 0 for zero, tiny or non-finite v.
fn normalize_or_zero(v: vec3<f32>) -> vec3<f32> {
    let len2 = dot3(v, v);
    if abs(len2 - 1.0) <= 2e-6f {
        return v;
    } else if len2 > 1e-30f && is_finite(len2) {
        return v * (1.0 / sqrt(len2));
    }
    return vec3(0.0);
}

// |u| - trunc(|u|) in [0, 1), exact; 0 for |u| >= 2^23 (integers), infinities and NaN (bit test).
fn fract_abs(u: f32) -> f32 {
    let a = abs(u);
    return select(0.0, a - trunc(a), (bitcast<u32>(u) & 0x7fffffffu) < 0x4b000000u);
}

// (sin 2 pi u, cos 2 pi u) for any u: exact reduction to sign(u) fract_abs(u) (sine odd, cosine
// even), nearest quarter turn, Taylor polynomials of degree 9 and 8 on [-pi/4, pi/4]; NaN, inf -> (+-0, 1).
// The Rust twin reduces by float floors and compares (so its batch loops vectorize); math.rs's
// sincos_by_float_floor_is_the_integer_cast_formulation proves it equal to this one bit for bit.
fn sincos_2pi(u: f32) -> vec2<f32> {
    let v = fract_abs(u);
    let q = i32(v * 4.0 + 0.5);
    let r = v - f32(q) * 0.25;
    let x = r * TAU;
    let x2 = x * x;
    let s = x * (1.0 + x2 * (-1.0f / 6.0f + x2 * (1.0f / 120.0f + x2 * (-1.0f / 5040.0f + x2 * (1.0f / 362880.0f)))));
    let c = 1.0 + x2 * (-0.5f + x2 * (1.0f / 24.0f + x2 * (-1.0f / 720.0f + x2 * (1.0f / 40320.0f))));
    let quadrant = q & 3;
    let ab = select(vec2(s, c), vec2(c, s), (quadrant & 1) != 0);
    let sin = select(ab.x, -ab.x, (quadrant & 2) != 0);
    let cos = select(ab.y, -ab.y, ((quadrant + 1) & 2) != 0);
    return vec2(select(sin, -sin, (bitcast<u32>(u) & 0x80000000u) != 0u), cos);
}

// ---------------------------------------------------------------------------------------------
// alpha.rs
// ---------------------------------------------------------------------------------------------

// clamp(alpha, ALPHA_MIN, ALPHA_MAX), NaN -> ALPHA_MIN.
fn clamp_alpha(alpha: f32) -> f32 {
    return min_num(max_num(alpha, ALPHA_MIN), ALPHA_MAX);
}

// alpha = clamp(roughness, 0, 1)^2, Burley 2012.
fn roughness_to_alpha(roughness: f32) -> f32 {
    let r = min_num(max_num(roughness, 0.0), 1.0);
    return r * r;
}

// roughness = sqrt(clamp(alpha, 0, 1)).
fn alpha_to_roughness(alpha: f32) -> f32 {
    return safe_sqrt(min_num(max_num(alpha, 0.0), 1.0));
}

// ---------------------------------------------------------------------------------------------
// distribution/formulas.rs: TrowbridgeReitz
// ---------------------------------------------------------------------------------------------

// TrowbridgeReitz::new: both alphas clamped to [ALPHA_MIN, ALPHA_MAX].
fn trowbridge_reitz_new(alpha_x: f32, alpha_y: f32) -> TrowbridgeReitz {
    return TrowbridgeReitz(clamp_alpha(alpha_x), clamp_alpha(alpha_y));
}

// (clamp_alpha(alpha_x), clamp_alpha(alpha_y)): the alphas every formula reads, so raw field
// values behave as trowbridge_reitz_new made them (the identity for constructor-made values).
fn alphas(dist: TrowbridgeReitz) -> vec2<f32> {
    return vec2(clamp_alpha(dist.alpha_x), clamp_alpha(dist.alpha_y));
}

// alphas().x == alphas().y enables the isotropic fast paths.
fn is_isotropic(dist: TrowbridgeReitz) -> bool {
    let a = alphas(dist);
    return a.x == a.y;
}

// Mirror lobe: max(alpha_x, alpha_y) < DELTA_ALPHA on alphas() (pbrt-v4, Bevy).
fn is_effectively_smooth(dist: TrowbridgeReitz) -> bool {
    let a = alphas(dist);
    return max_num(a.x, a.y) < DELTA_ALPHA;
}

// ax^2 x^2 + ay^2 y^2.
fn alpha2_xy(dist: TrowbridgeReitz, w: vec3<f32>) -> f32 {
    let a = alphas(dist);
    if is_isotropic(dist) {
        return a.x * a.x * (w.x * w.x + w.y * w.y);
    }
    let x = a.x * w.x;
    let y = a.y * w.y;
    return x * x + y * y;
}

// |(ax x, ay y, z)|, never below |z|.
fn stretched_len(dist: TrowbridgeReitz, w: vec3<f32>) -> f32 {
    return max_num(sqrt(w.z * w.z + alpha2_xy(dist, w)), abs(w.z));
}

// D(wm) = 1 / (pi ax ay (x^2/ax^2 + y^2/ay^2 + z^2)^2), 0 for z <= 0; Walter et al. 2007 eq. 33.
fn d(dist: TrowbridgeReitz, wm: vec3<f32>) -> f32 {
    if !(wm.z > 0.0) {
        return 0.0;
    }
    let a = alphas(dist);
    var t: f32;
    if is_isotropic(dist) {
        t = (wm.x * wm.x + wm.y * wm.y) / (a.x * a.x) + wm.z * wm.z;
    } else {
        let x = wm.x / a.x;
        let y = wm.y / a.y;
        t = x * x + y * y + wm.z * wm.z;
    }
    return finite_or_zero(1.0 / (PI * a.x * a.y * t * t));
}

// Lambda(w) = q / (2 (1 + sqrt(1 + q))), q = (ax^2 x^2 + ay^2 y^2) / z^2; +inf at z = 0; Heitz 2014 eq. 86.
fn lambda(dist: TrowbridgeReitz, w: vec3<f32>) -> f32 {
    let q = alpha2_xy(dist, w) / (w.z * w.z);
    if is_nan(q) {
        return 0.0;
    }
    let inf = inf_f32();
    if q == inf {
        return inf;
    }
    return q / (2.0 * (1.0 + sqrt(1.0 + q)));
}

// G1(w) = 2 |z| / (|z| + |(ax x, ay y, z)|), Smith masking.
fn g1(dist: TrowbridgeReitz, w: vec3<f32>) -> f32 {
    let z = abs(w.z);
    return min_num(finite_or_zero(2.0 * z / (z + stretched_len(dist, w))), 1.0);
}

// G2 = 2 |zo| |zi| / (|zi| so + |zo| si), height-correlated; Heitz 2014 eq. 99.
fn g2(dist: TrowbridgeReitz, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    let zo = abs(wo.z);
    let zi = abs(wi.z);
    let den = zi * stretched_len(dist, wo) + zo * stretched_len(dist, wi);
    return min_num(finite_or_zero(2.0 * zo * zi / den), 1.0);
}

// G2 = G1(wo) G1(wi), separable (Mitsuba 3).
fn g2_separable(dist: TrowbridgeReitz, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    return g1(dist, wo) * g1(dist, wi);
}

// D_w(wm) = 2 D(wm) max(0, w.wm) / (w.z + s(w)), 0 for w.z <= 0; Heitz 2014 eq. 2.
fn d_visible(dist: TrowbridgeReitz, w: vec3<f32>, wm: vec3<f32>) -> f32 {
    if !(w.z > 0.0) {
        return 0.0;
    }
    let cos = max_num(dot3(w, wm), 0.0);
    return finite_or_zero(2.0 * d(dist, wm) * cos / (w.z + stretched_len(dist, w)));
}

// ---------------------------------------------------------------------------------------------
// distribution/samplers.rs (sample_ndf.rs, sample_vndf.rs, sample_spherical_caps.rs, sample_bounded.rs)
// ---------------------------------------------------------------------------------------------

// wm = normalize(ax sqrt(u0) cos phi, ay sqrt(u0) sin phi, sqrt(1 - u0)), phi = 2 pi u1; Walter et al. 2007 eq. 35-36.
fn sample_wm_ndf(dist: TrowbridgeReitz, u_in: vec2<f32>) -> vec3<f32> {
    let u = sanitize_u2(u_in);
    let r = safe_sqrt(u.x);
    let sc = sincos_2pi(u.y);
    let a = alphas(dist);
    return normalize_or_zero(vec3(a.x * r * sc.y, a.y * r * sc.x, safe_sqrt(1.0 - u.x)));
}

// p(wm) = D(wm) max(0, wm.z), 0 when not finite.
fn pdf_wm_ndf(dist: TrowbridgeReitz, wm: vec3<f32>) -> f32 {
    return finite_or_zero(d(dist, wm) * max_num(wm.z, 0.0));
}

// Stretch wo, warp a disk sample onto the projected hemisphere, unstretch; Heitz 2018 listing 1.
// q = sqrt(1 - p1^2) = sqrt((1 - u0) + (r sin phi)^2), (q - r sin phi)(q + r sin phi) = 1 - u0,
// lift^2 = 1 - p1^2 - p2^2 = (q - r sin phi)(|vh.xy|^2 q / 2 + s^2 (q + r sin phi))
// (1 - vh.z = |vh.xy|^2 / (1 + vh.z)): no cancellation.
fn sample_wm_vndf(dist: TrowbridgeReitz, wo: vec3<f32>, u_in: vec2<f32>) -> vec3<f32> {
    if !(wo.z > 0.0) {
        return vec3(0.0);
    }
    let u = sanitize_u2(u_in);
    let a = alphas(dist);
    let vh = normalize_or_zero(vec3(a.x * wo.x, a.y * wo.y, wo.z));
    // Basis around vh, Heitz 2018's rule: t1 = (-vh.y, vh.x, 0) / |vh.xy|, X only when vh is
    // exactly the normal (no pbrt-v4 `vh.z >= 0.99999` shortcut).
    let lensq = vh.x * vh.x + vh.y * vh.y;
    var t1 = vec3(1.0, 0.0, 0.0);
    if lensq > 0.0 {
        let inv_len = 1.0 / sqrt(lensq);
        t1 = vec3(-vh.y * inv_len, vh.x * inv_len, 0.0);
    }
    let t2 = cross3(vh, t1);
    let r = safe_sqrt(u.x);
    let sc = sincos_2pi(u.y);
    let p1 = r * sc.y;
    let rs = r * sc.x;
    let rim = 1.0 - u.x;
    let q = safe_sqrt(rim + rs * rs);
    let far = q + abs(rs);
    let near = rim / far;
    var q_minus = far;
    var q_plus = near;
    if rs >= 0.0 {
        q_minus = near;
        q_plus = far;
    }
    let s = 0.5 * (1.0 + vh.z);
    let p2 = (1.0 - s) * q + s * rs;
    let lift = safe_sqrt(q_minus * (0.5 * lensq * q + s * s * q_plus));
    let nh = p1 * t1 + p2 * t2 + lift * vh;
    return normalize_or_zero(vec3(a.x * nh.x, a.y * nh.y, max_num(nh.z, 0.0)));
}

// vh plus a uniform point on the cap z in [-lower, 1], lower = k vh.z, unstretched; Dupuy &
// Benyoub 2023. t = (1 - u1)(1 + lower), z = t - lower, without cancellation: 1 - z^2 =
// u1 ((1 - lower^2) + (1 + lower) t), 1 - lower^2 = |vh.xy|^2 + vh.z^2 (1 - k)(1 + k),
// h.z = z + vh.z = t + (1 - k) vh.z (exactly t for caps, k = 1).
fn sample_cap(dist: TrowbridgeReitz, vh: vec3<f32>, k: f32, one_minus_k: f32, u_in: vec2<f32>) -> vec3<f32> {
    let u = sanitize_u2(u_in);
    let a = alphas(dist);
    let sc = sincos_2pi(u.x);
    let lower = k * vh.z;
    let one_minus_lower2 = (vh.x * vh.x + vh.y * vh.y) + vh.z * vh.z * (one_minus_k * (1.0 + k));
    let t = (1.0 - u.y) * (1.0 + lower);
    let sin_theta = safe_sqrt(u.y * (one_minus_lower2 + (1.0 + lower) * t));
    let h = vec3(sin_theta * sc.y + vh.x, sin_theta * sc.x + vh.y, t + one_minus_k * vh.z);
    return normalize_or_zero(vec3(a.x * h.x, a.y * h.y, max_num(h.z, 0.0)));
}

// Visible normals from the spherical cap z in [-vh.z, 1]; Dupuy & Benyoub 2023 listing 3.
fn sample_wm_spherical_caps(dist: TrowbridgeReitz, wo: vec3<f32>, u: vec2<f32>) -> vec3<f32> {
    if !(wo.z > 0.0) {
        return vec3(0.0);
    }
    let a = alphas(dist);
    let vh = normalize_or_zero(vec3(a.x * wo.x, a.y * wo.y, wo.z));
    return sample_cap(dist, vh, 1.0, 0.0, u);
}

// k = (1 - a^2) s^2 / (s^2 + a^2 wo.z^2), a = min(ax, ay), s = 1 + |wo.xy|; Eto & Tokuyoshi 2023 eq. 5.
fn bounded_k(dist: TrowbridgeReitz, wo: vec3<f32>) -> f32 {
    return bounded_k_and_complement(dist, wo).x;
}

// (k, 1 - k), 1 - k = a^2 (s^2 + wo.z^2) / (s^2 + a^2 wo.z^2) without cancellation; (0, 1) where k is not finite.
fn bounded_k_and_complement(dist: TrowbridgeReitz, wo: vec3<f32>) -> vec2<f32> {
    let alpha = alphas(dist);
    let a = min_num(alpha.x, alpha.y);
    let a2 = a * a;
    let s = 1.0 + sqrt(wo.x * wo.x + wo.y * wo.y);
    let s2 = s * s;
    let z2 = wo.z * wo.z;
    let den = s2 + a2 * z2;
    let k = (1.0 - a2) * s2 / den;
    if !is_finite(k) {
        return vec2(0.0, 1.0);
    }
    return vec2(k, a2 * (s2 + z2) / den);
}

// Spherical cap with lower bound -k vh.z; Eto & Tokuyoshi 2023 listing 1.
fn sample_wm_bounded(dist: TrowbridgeReitz, wo: vec3<f32>, u: vec2<f32>) -> vec3<f32> {
    if !(wo.z > 0.0) {
        return vec3(0.0);
    }
    let a = alphas(dist);
    let vh = normalize_or_zero(vec3(a.x * wo.x, a.y * wo.y, wo.z));
    let k = bounded_k_and_complement(dist, wo);
    return sample_cap(dist, vh, k.x, k.y, u);
}

// p(wi) = D(wm) / (2 (k wo.z + |(ax wo.x, ay wo.y, wo.z)|)), 0 for wo.z <= 0; Eto & Tokuyoshi 2023 eq. 8.
fn pdf_wi_bounded(dist: TrowbridgeReitz, wo: vec3<f32>, wm: vec3<f32>) -> f32 {
    if !(wo.z > 0.0) {
        return 0.0;
    }
    return finite_or_zero(d(dist, wm) / (2.0 * (bounded_k(dist, wo) * wo.z + stretched_len(dist, wo))));
}

// ---------------------------------------------------------------------------------------------
// warp.rs
// ---------------------------------------------------------------------------------------------

// (sqrt(u0) cos 2 pi u1, sqrt(u0) sin 2 pi u1, sqrt(1 - u0)), Malley's method.
fn sample_cosine_hemisphere(u_in: vec2<f32>) -> vec3<f32> {
    let u = sanitize_u2(u_in);
    let r = safe_sqrt(u.x);
    let sc = sincos_2pi(u.y);
    return vec3(r * sc.y, r * sc.x, safe_sqrt(1.0 - u.x));
}

// p(w) = max(0, w.z) / pi.
fn pdf_cosine_hemisphere(w: vec3<f32>) -> f32 {
    return select(0.0, w.z * FRAC_1_PI, w.z > 0.0);
}

// z = 1 - u0, phi = 2 pi u1.
fn sample_uniform_hemisphere(u_in: vec2<f32>) -> vec3<f32> {
    let u = sanitize_u2(u_in);
    let z = 1.0 - u.x;
    let r = safe_sqrt(1.0 - z * z);
    let sc = sincos_2pi(u.y);
    return vec3(r * sc.y, r * sc.x, z);
}

// p(w) = 1 / (2 pi) for w.z > 0.
fn pdf_uniform_hemisphere(w: vec3<f32>) -> f32 {
    return select(0.0, 0.5f / PI, w.z > 0.0);
}

// ---------------------------------------------------------------------------------------------
// fresnel/complex.rs
// ---------------------------------------------------------------------------------------------

// a + b.
fn complex_add(a: Complex, b: Complex) -> Complex {
    return Complex(a.re + b.re, a.im + b.im);
}

// a - b.
fn complex_sub(a: Complex, b: Complex) -> Complex {
    return Complex(a.re - b.re, a.im - b.im);
}

// a b = (ar br - ai bi) + i (ar bi + ai br).
fn complex_mul(a: Complex, b: Complex) -> Complex {
    return Complex(a.re * b.re - a.im * b.im, a.re * b.im + a.im * b.re);
}

// a / b = a conj(b) / |b|^2.
fn complex_div(a: Complex, b: Complex) -> Complex {
    let scale = 1.0 / (b.re * b.re + b.im * b.im);
    return Complex((a.re * b.re + a.im * b.im) * scale, (a.im * b.re - a.re * b.im) * scale);
}

// |z|^2.
fn complex_norm(z: Complex) -> f32 {
    return z.re * z.re + z.im * z.im;
}

// Principal root: t1 = sqrt((|z| + |re|) / 2), t2 = im / (2 t1); Press et al. 5.4.
fn complex_sqrt(z: Complex) -> Complex {
    let n = sqrt(complex_norm(z));
    if n == 0.0 {
        return Complex(0.0, 0.0);
    }
    let t1 = sqrt(0.5 * (n + abs(z.re)));
    let t2 = 0.5 * z.im / t1;
    if z.re >= 0.0 {
        return Complex(t1, t2);
    }
    return Complex(abs(t2), copysign(t1, z.im));
}

// ---------------------------------------------------------------------------------------------
// fresnel/formulas.rs, fresnel/mod.rs
// ---------------------------------------------------------------------------------------------

// F = f0 + (f90 - f0) (1 - cos)^5, cos clamped to [0, 1], each component 0 when not finite;
// Schlick 1994, Burley 2012.
fn fresnel_schlick(cos_theta: f32, f0: vec3<f32>, f90: vec3<f32>) -> vec3<f32> {
    let m = 1.0 - min_num(max_num(cos_theta, 0.0), 1.0);
    let m2 = m * m;
    let f = f0 + (f90 - f0) * (m2 * m2 * m);
    return vec3(finite_or_zero(f.x), finite_or_zero(f.y), finite_or_zero(f.z));
}

// F = (r_par^2 + r_perp^2) / 2, inside flips eta, TIR -> 1; pbrt-v4 FrDielectric.
fn fresnel_dielectric(cos_theta_i: f32, eta_in: f32) -> f32 {
    if !(eta_in > 0.0) || !is_finite(eta_in) {
        return 1.0;
    }
    var cos_i = min_num(max_num(cos_theta_i, -1.0), 1.0);
    var eta = eta_in;
    if cos_i < 0.0 {
        eta = 1.0 / eta;
        cos_i = -cos_i;
    }
    let sin2_i = 1.0 - cos_i * cos_i;
    let sin2_t = sin2_i / (eta * eta);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = safe_sqrt(1.0 - sin2_t);
    let r_par = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    let f = 0.5 * (r_par * r_par + r_perp * r_perp);
    return select(f, 1.0, is_nan(f));
}

// F = (|r_par|^2 + |r_perp|^2) / 2 for complex eta + i k, cos clamped to [0, 1]; pbrt-v4 FrComplex.
fn fresnel_complex(cos_theta_i: f32, eta_re: f32, k: f32) -> f32 {
    let cos_i = min_num(max_num(cos_theta_i, 0.0), 1.0);
    let eta = Complex(eta_re, k);
    let sin2_i = 1.0 - cos_i * cos_i;
    let sin2_t = complex_div(Complex(sin2_i, 0.0), complex_mul(eta, eta));
    let cos_t = complex_sqrt(complex_sub(Complex(1.0, 0.0), sin2_t));
    let ci = Complex(cos_i, 0.0);
    let r_par = complex_div(complex_sub(complex_mul(eta, ci), cos_t), complex_add(complex_mul(eta, ci), cos_t));
    let r_perp = complex_div(complex_sub(ci, complex_mul(eta, cos_t)), complex_add(ci, complex_mul(eta, cos_t)));
    let f = 0.5 * (complex_norm(r_par) + complex_norm(r_perp));
    // 1 unless f <= 1 (NaN, inf and the huge noise of an unphysical eta near -1 + 0i).
    return select(1.0, f, is_finite(f) && f <= 1.0);
}

// clamp(x, 0, 1), NaN -> 0 (fresnel/mod.rs `unit`).
fn fresnel_unit(x: f32) -> f32 {
    return min_num(max_num(x, 0.0), 1.0);
}

// FresnelParams::eval: the model selected by `kind` (unknown -> One), clamped to [0, 1].
fn fresnel_params_eval(params: FresnelParams, cos_theta: f32) -> vec3<f32> {
    var f = vec3(1.0);
    switch params.kind {
        case FRESNEL_KIND_SCHLICK: {
            f = fresnel_schlick(cos_theta, params.a.xyz, params.b.xyz);
        }
        case FRESNEL_KIND_CONDUCTOR: {
            f = vec3(
                fresnel_complex(cos_theta, params.a.x, params.b.x),
                fresnel_complex(cos_theta, params.a.y, params.b.y),
                fresnel_complex(cos_theta, params.a.z, params.b.z),
            );
        }
        case FRESNEL_KIND_DIELECTRIC: {
            f = vec3(fresnel_dielectric(cos_theta, params.eta));
        }
        default: {}
    }
    return vec3(fresnel_unit(f.x), fresnel_unit(f.y), fresnel_unit(f.z));
}

// ---------------------------------------------------------------------------------------------
// conductor/ (mod.rs, formulas.rs): GgxConductor
// ---------------------------------------------------------------------------------------------

// BsdfSample::mis_pdf: +inf for a delta lobe (it wins every MIS weight), else the pdf with
// NaN, negative and infinite values as 0.
fn bsdf_sample_mis_pdf(s: BsdfSample) -> f32 {
    if s.is_delta != 0u {
        return inf_f32();
    }
    return max_num(finite_or_zero(s.pdf), 0.0);
}

// 2 (|wi.z| s(wo) + |wo.z| s(wi)) = 4 zo zi / G2.
fn g2_denominator(dist: TrowbridgeReitz, wo: vec3<f32>, wi: vec3<f32>, so: f32) -> f32 {
    return 2.0 * (wi.z * so + wo.z * stretched_len(dist, wi));
}

// Mirror lobe: both alphas below DELTA_ALPHA.
fn ggx_conductor_is_delta(bsdf: GgxConductor) -> bool {
    return is_effectively_smooth(bsdf.distribution);
}

// f |wi.z| = F(wo.wm) D(wm) |wi.z| / (2 (|wi.z| so + |wo.z| si)); Cook-Torrance, Heitz 2014.
fn ggx_conductor_eval(bsdf: GgxConductor, wo_in: vec3<f32>, wi_in: vec3<f32>) -> vec3<f32> {
    let wo = normalize_or_zero(wo_in);
    let wi = normalize_or_zero(wi_in);
    if !(wo.z > 0.0 && wi.z > 0.0) || ggx_conductor_is_delta(bsdf) {
        return vec3(0.0);
    }
    let wm = normalize_or_zero(wo + wi);
    let cos_om = dot3(wo, wm);
    // wo.wm = |wo + wi| / 2 >= 0 exactly; rounding can flip it where wo ~ -wi at grazing angles.
    if !(cos_om > 0.0) {
        return vec3(0.0);
    }
    let dist = bsdf.distribution;
    let so = stretched_len(dist, wo);
    let f = d(dist, wm) * wi.z / g2_denominator(dist, wo, wi, so);
    return fresnel_params_eval(bsdf.fresnel, cos_om) * finite_or_zero(f);
}

// Solid-angle density of `ggx_conductor_sample` for the technique (unknown -> VNDF).
fn ggx_conductor_pdf(bsdf: GgxConductor, wo_in: vec3<f32>, wi_in: vec3<f32>, sampling: u32) -> f32 {
    let wo = normalize_or_zero(wo_in);
    let wi = normalize_or_zero(wi_in);
    if !(wo.z > 0.0 && wi.z > 0.0) || ggx_conductor_is_delta(bsdf) {
        return 0.0;
    }
    let dist = bsdf.distribution;
    let wm = normalize_or_zero(wo + wi);
    let cos_om = dot3(wo, wm);
    // A back-facing half vector (rounding where wo ~ -wi) is never sampled; eval is 0 there too.
    if !(cos_om > 0.0) && sampling != SAMPLING_COSINE && sampling != SAMPLING_UNIFORM {
        return 0.0;
    }
    var pdf: f32;
    switch sampling {
        case SAMPLING_NDF: {
            pdf = pdf_wm_ndf(dist, wm) / (4.0 * cos_om);
        }
        case SAMPLING_BOUNDED: {
            pdf = pdf_wi_bounded(dist, wo, wm);
        }
        case SAMPLING_COSINE: {
            pdf = pdf_cosine_hemisphere(wi);
        }
        case SAMPLING_UNIFORM: {
            pdf = pdf_uniform_hemisphere(wi);
        }
        default: {
            pdf = d(dist, wm) / (2.0 * (wo.z + stretched_len(dist, wo)));
        }
    }
    return finite_or_zero(pdf);
}

// Draws wi for wo; weights in closed form (VNDF F G2 / G1, bounded F zi (k zo + so) / (zi so + zo si), NDF F G2 |wo.wm| / (zo wm.z)).
fn ggx_conductor_sample(bsdf: GgxConductor, wo_in: vec3<f32>, u_in: vec2<f32>, sampling: u32) -> BsdfSample {
    var none: BsdfSample;
    let wo = normalize_or_zero(wo_in);
    if !(wo.z > 0.0) {
        return none;
    }
    let u = sanitize_u2(u_in);
    if ggx_conductor_is_delta(bsdf) {
        let weight = fresnel_params_eval(bsdf.fresnel, wo.z);
        return BsdfSample(vec3(-wo.x, -wo.y, wo.z), weight, 1.0, 1u, 1u);
    }
    let dist = bsdf.distribution;
    var wi: vec3<f32>;
    var pdf: f32;
    var weight: vec3<f32>;
    if sampling == SAMPLING_COSINE || sampling == SAMPLING_UNIFORM {
        if sampling == SAMPLING_COSINE {
            wi = sample_cosine_hemisphere(u);
        } else {
            wi = sample_uniform_hemisphere(u);
        }
        pdf = ggx_conductor_pdf(bsdf, wo, wi, sampling);
        weight = ggx_conductor_eval(bsdf, wo, wi) / pdf;
    } else {
        var wm: vec3<f32>;
        switch sampling {
            case SAMPLING_NDF: {
                wm = sample_wm_ndf(dist, u);
            }
            case SAMPLING_SPHERICAL_CAPS: {
                wm = sample_wm_spherical_caps(dist, wo, u);
            }
            case SAMPLING_BOUNDED: {
                wm = sample_wm_bounded(dist, wo, u);
            }
            default: {
                wm = sample_wm_vndf(dist, wo, u);
            }
        }
        if !(dot3(wo, wm) > 0.0) {
            return none;
        }
        wi = normalize_or_zero(reflect(wo, wm));
        if !(wi.z > 0.0) {
            return none;
        }
        // Weight and pdf from the half vector of the returned pair (see conductor/mod.rs).
        let wh = normalize_or_zero(wo + wi);
        let cos_om = dot3(wo, wh);
        let so = stretched_len(dist, wo);
        let denom = g2_denominator(dist, wo, wi, so);
        var scale: f32;
        switch sampling {
            case SAMPLING_NDF: {
                pdf = pdf_wm_ndf(dist, wh) / (4.0 * cos_om);
                scale = 4.0 * wi.z * cos_om / (wh.z * denom);
            }
            case SAMPLING_BOUNDED: {
                let c = bounded_k(dist, wo) * wo.z + so;
                pdf = d(dist, wh) / (2.0 * c);
                scale = min_num(2.0 * wi.z * c / denom, 1.0);
            }
            default: {
                pdf = d(dist, wh) / (2.0 * (wo.z + so));
                scale = min_num(2.0 * wi.z * (wo.z + so) / denom, 1.0);
            }
        }
        weight = fresnel_params_eval(bsdf.fresnel, cos_om) * scale;
    }
    if !(pdf > 0.0 && is_finite(pdf) && is_finite3(weight)) {
        return none;
    }
    return BsdfSample(wi, weight, pdf, 0u, 1u);
}

// ---------------------------------------------------------------------------------------------
// dielectric.rs: GgxDielectric
// ---------------------------------------------------------------------------------------------

// Smallest and largest relative index of refraction used in any formula.
const ETA_MIN: f32 = 1e-2f;
const ETA_MAX: f32 = 1e2f;

// `ggx_core::TransportMode` discriminants (TransportMode::from_u32: 1 is importance, anything
// else radiance).
const TRANSPORT_RADIANCE: u32 = 0u;
const TRANSPORT_IMPORTANCE: u32 = 1u;

struct GgxDielectric {
    distribution: TrowbridgeReitz,
    eta: f32,
    pad: u32,
}

// `Option<Vec3>` of `refract`: `valid` 1 for `Some`, 0 (and `wt` zero) for `None`.
struct Refracted {
    wt: vec3<f32>,
    valid: u32,
}

// `Option<Half>` of `ggx_dielectric_half`: the generalized half vector and what is derived
// from it; `valid` false (every other field zero) for `None`.
struct Half {
    wm: vec3<f32>,
    reflect: bool,
    etap: f32,
    cos_om: f32,
    p_lobe: f32,
    jacobian: f32,
    valid: bool,
}

// clamp(eta, ETA_MIN, ETA_MAX); NaN, zero and negative -> 1 (an index-matched interface).
fn clamp_eta(eta: f32) -> f32 {
    if is_nan(eta) || !(eta > 0.0) {
        return 1.0;
    }
    return min_num(max_num(eta, ETA_MIN), ETA_MAX);
}

// wt = -w / eta' + (cos_i / eta' - cos_t) n', n' = -n and eta' = 1 / eta when w.n < 0; None under
// total internal reflection (sin2_t = (1 - cos_i^2) / eta'^2 not below 1) or for a non-finite
// result; pbrt-v4 Refract.
fn refract(w: vec3<f32>, n_in: vec3<f32>, eta_in: f32) -> Refracted {
    var none: Refracted;
    var eta = clamp_eta(eta_in);
    var n = n_in;
    var cos_i = min_num(max_num(dot3(w, n), -1.0), 1.0);
    if cos_i < 0.0 {
        eta = 1.0 / eta;
        cos_i = -cos_i;
        n = -n;
    }
    // The same test as `fresnel_dielectric`'s total internal reflection, so F < 1 <=> valid.
    let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    if !(sin2_t < 1.0) {
        return none;
    }
    let cos_t = safe_sqrt(1.0 - sin2_t);
    let wt = -w / eta + (cos_i / eta - cos_t) * n;
    if is_finite3(wt) {
        return Refracted(wt, 1u);
    }
    return none;
}

// dwm/dwi = eta'^2 |wi.wm| / (wo.wm + eta' wi.wm)^2; Walter et al. 2007 eq. 17.
fn jacobian_transmission(etap: f32, cos_om: f32, cos_im: f32) -> f32 {
    let s = cos_om + etap * cos_im;
    return etap * etap * abs(cos_im) / (s * s);
}

// dwm/dwi = 1 / (4 |wo.wm|); Walter et al. 2007 eq. 14.
fn jacobian_reflection(cos_om: f32) -> f32 {
    return 1.0 / (4.0 * abs(cos_om));
}

// 1 / eta'^2 for transmitted radiance, 1 for importance and for reflection; Veach 1997 eq. 5.16.
fn transport_scale(reflect: bool, etap: f32, mode: u32) -> f32 {
    if reflect || mode == TRANSPORT_IMPORTANCE {
        return 1.0;
    }
    return 1.0 / (etap * etap);
}

// sign(wo.z) wo: the side whose visible normals the samplers draw.
fn visible_side(wo: vec3<f32>) -> vec3<f32> {
    return select(wo, -wo, wo.z < 0.0);
}

// GgxDielectric::eta: clamp_eta of the field.
fn ggx_dielectric_eta(bsdf: GgxDielectric) -> f32 {
    return clamp_eta(bsdf.eta);
}

// Smooth interface: both alphas below DELTA_ALPHA.
fn ggx_dielectric_is_delta(bsdf: GgxDielectric) -> bool {
    return is_effectively_smooth(bsdf.distribution);
}

// wm = normalize(wo + eta' wi) turned to +z (eta' = 1 for reflection, eta or 1 / eta by the side
// of wo); None for a horizontal or zero direction, a zero wm or unless wo.wm has the sign of wo.z
// and wi.wm that of wi.z; P(lobe) = F(wo.wm) or 1 - F (pbrt-v3 #254); Walter et al. 2007 eq. 13/16.
fn ggx_dielectric_half(bsdf: GgxDielectric, wo: vec3<f32>, wi: vec3<f32>) -> Half {
    var none: Half;
    let side = wo.z * wi.z;
    if side == 0.0 || is_nan(side) {
        return none;
    }
    let reflect = side > 0.0;
    let eta = ggx_dielectric_eta(bsdf);
    var etap = 1.0;
    if !reflect {
        if wo.z > 0.0 {
            etap = eta;
        } else {
            etap = 1.0 / eta;
        }
    }
    var wm = normalize_or_zero(wo + etap * wi);
    // Rust `!(wm.z != 0.0)`; WGSL `!=` is ordered (false for NaN), so test equality instead.
    if wm.z == 0.0 {
        return none;
    }
    if wm.z < 0.0 {
        wm = -wm;
    }
    let cos_om = dot3(wo, wm);
    let cos_im = dot3(wi, wm);
    if !(cos_om * wo.z > 0.0 && cos_im * wi.z > 0.0) {
        return none;
    }
    let f = fresnel_dielectric(cos_om, eta);
    var p_lobe: f32;
    var jacobian: f32;
    if reflect {
        p_lobe = f;
        jacobian = jacobian_reflection(cos_om);
    } else {
        p_lobe = 1.0 - f;
        jacobian = jacobian_transmission(etap, cos_om, cos_im);
    }
    return Half(wm, reflect, etap, cos_om, p_lobe, jacobian, true);
}

// p(wi) = P(lobe) p(wm) dwm/dwi, p(wm) = D(wm) wm.z (NDF) or D_wo'(wm), wo' = sign(wo.z) wo
// (VNDF, spherical caps, bounded and unknown techniques); 0 for cosine and uniform.
fn ggx_dielectric_pdf_half(bsdf: GgxDielectric, wo: vec3<f32>, h: Half, sampling: u32) -> f32 {
    let dist = bsdf.distribution;
    var p_wm: f32;
    switch sampling {
        case SAMPLING_NDF: {
            p_wm = pdf_wm_ndf(dist, h.wm);
        }
        case SAMPLING_COSINE, SAMPLING_UNIFORM: {
            p_wm = 0.0;
        }
        default: {
            p_wm = d_visible(dist, visible_side(wo), h.wm);
        }
    }
    return finite_or_zero(h.p_lobe * p_wm * h.jacobian);
}

// f |wi.z| = F D G2 / (4 |wo.z|) (reflection) or (1 - F) D G2 |wo.wm| dwm/dwi / |wo.z| (transmission,
// / eta'^2 for radiance), as P(lobe) (D G2) |wo.wm / wo.z| dwm/dwi scale; Walter et al. 2007 eq. 20-21.
fn ggx_dielectric_eval(bsdf: GgxDielectric, wo_in: vec3<f32>, wi_in: vec3<f32>, mode: u32) -> vec3<f32> {
    let wo = normalize_or_zero(wo_in);
    let wi = normalize_or_zero(wi_in);
    if ggx_dielectric_is_delta(bsdf) {
        return vec3(0.0);
    }
    let h = ggx_dielectric_half(bsdf, wo, wi);
    if !h.valid {
        return vec3(0.0);
    }
    let dist = bsdf.distribution;
    let dg = d(dist, h.wm) * g2(dist, wo, wi);
    let f = h.p_lobe * dg * abs(h.cos_om / wo.z) * h.jacobian * transport_scale(h.reflect, h.etap, mode);
    return vec3(finite_or_zero(f));
}

// Solid-angle density of `ggx_dielectric_sample`: P(lobe) p(wm) dwm/dwi (`mode` does not change it);
// 0 for a smooth interface and degenerate input.
fn ggx_dielectric_pdf(bsdf: GgxDielectric, wo_in: vec3<f32>, wi_in: vec3<f32>, sampling: u32, mode: u32) -> f32 {
    let wo = normalize_or_zero(wo_in);
    let wi = normalize_or_zero(wi_in);
    if ggx_dielectric_is_delta(bsdf) {
        return 0.0;
    }
    let h = ggx_dielectric_half(bsdf, wo, wi);
    if !h.valid {
        return 0.0;
    }
    return ggx_dielectric_pdf_half(bsdf, wo, h, sampling);
}

// wm from u (visible normals of sign(wo.z) wo, NDF; bounded -> spherical caps), reflect when
// u_lobe < F(wo.wm) else refract; weight G2 / G1(wo) (visible) or G2 |wo.wm| / (|wo.z| wm.z) (NDF),
// / eta'^2 for transmitted radiance. Smooth: mirror (pdf F, weight 1) or refraction (pdf 1 - F,
// weight 1 / eta'^2 or 1). Cosine and uniform refused.
fn ggx_dielectric_sample(
    bsdf: GgxDielectric,
    wo_in: vec3<f32>,
    u: vec2<f32>,
    u_lobe_in: f32,
    sampling: u32,
    mode: u32,
) -> BsdfSample {
    var none: BsdfSample;
    let wo = normalize_or_zero(wo_in);
    // Rust `!(wo.z != 0.0)`: equality, since WGSL `!=` is ordered.
    if wo.z == 0.0 || sampling == SAMPLING_COSINE || sampling == SAMPLING_UNIFORM {
        return none;
    }
    let eta = ggx_dielectric_eta(bsdf);
    let u_lobe = sanitize_u(u_lobe_in);
    if ggx_dielectric_is_delta(bsdf) {
        let f = fresnel_dielectric(wo.z, eta);
        if u_lobe < f {
            return BsdfSample(vec3(-wo.x, -wo.y, wo.z), vec3(1.0), f, 1u, 1u);
        }
        let r = refract(wo, vec3(0.0, 0.0, 1.0), eta);
        if r.valid == 0u {
            return none;
        }
        let wi = normalize_or_zero(r.wt);
        var etap = eta;
        if !(wo.z > 0.0) {
            etap = 1.0 / eta;
        }
        let pdf = 1.0 - f;
        let weight = transport_scale(false, etap, mode);
        if !(wi.z * wo.z < 0.0 && pdf > 0.0 && is_finite(weight)) {
            return none;
        }
        return BsdfSample(wi, vec3(weight), pdf, 1u, 1u);
    }
    let dist = bsdf.distribution;
    let wv = visible_side(wo);
    var wm: vec3<f32>;
    switch sampling {
        case SAMPLING_NDF: {
            wm = sample_wm_ndf(dist, u);
        }
        case SAMPLING_SPHERICAL_CAPS, SAMPLING_BOUNDED: {
            wm = sample_wm_spherical_caps(dist, wv, u);
        }
        default: {
            wm = sample_wm_vndf(dist, wv, u);
        }
    }
    let cos_om = dot3(wo, wm);
    if !(cos_om * wo.z > 0.0) {
        return none;
    }
    let reflected = u_lobe < fresnel_dielectric(cos_om, eta);
    var wi: vec3<f32>;
    if reflected {
        wi = reflect(wo, wm);
    } else {
        let r = refract(wo, wm, eta);
        if r.valid == 0u {
            return none;
        }
        wi = r.wt;
    }
    wi = normalize_or_zero(wi);
    // Weight and pdf from the half vector of the returned pair (see dielectric.rs).
    let h = ggx_dielectric_half(bsdf, wo, wi);
    if !h.valid || h.reflect != reflected {
        return none;
    }
    let pdf = ggx_dielectric_pdf_half(bsdf, wo, h, sampling);
    let g2_wo_wi = g2(dist, wo, wi);
    var ratio: f32;
    if sampling == SAMPLING_NDF {
        ratio = g2_wo_wi * abs(h.cos_om / wo.z) / h.wm.z;
    } else {
        // G2 / G1(wo) <= 1.
        ratio = min_num(g2_wo_wi / g1(dist, wo), 1.0);
    }
    let weight = ratio * transport_scale(h.reflect, h.etap, mode);
    if !(pdf > 0.0 && is_finite(pdf) && is_finite(weight)) {
        return none;
    }
    return BsdfSample(wi, vec3(weight), pdf, 0u, 1u);
}

// ---------------------------------------------------------------------------------------------
// metal_rough.rs: GltfMetalRough
// ---------------------------------------------------------------------------------------------

// KHR_materials_ior's default index of refraction (f0 = 0.04).
const DEFAULT_IOR: f32 = 1.5f;
// 2 integral (1 - mu)^5 mu dmu = 1 / 21, Schlick's cosine-weighted grazing average.
const SCHLICK_GRAZING_AVERAGE: f32 = 0.04761904761904762f;
// Smallest probability gltf_metal_rough_new gives a lobe that is present.
const P_LOBE_MIN: f32 = 0.1f;

// The glTF 2.0 metallic-roughness BRDF, 48 bytes: `base_color` and `f0` are vec3 with the next
// f32 in their fourth lane, as the Rust `[f32; 3]` fields are.
struct GltfMetalRough {
    base_color: vec3<f32>,
    metallic: f32,
    f0: vec3<f32>,
    specular_weight: f32,
    distribution: TrowbridgeReitz,
    p_specular: f32,
    pad: u32,
}

// x if finite, else default (metal_rough.rs `finite_or`).
fn metal_rough_finite_or(x: f32, default_value: f32) -> f32 {
    return select(default_value, x, is_finite(x));
}

// Each component clamped to [0, 1], NaN -> 0 (metal_rough.rs `unit3`).
fn metal_rough_unit3(v: vec3<f32>) -> vec3<f32> {
    return vec3(fresnel_unit(v.x), fresnel_unit(v.y), fresnel_unit(v.z));
}

// (x + y + z) / 3 (metal_rough.rs `mean`).
fn metal_rough_mean(v: vec3<f32>) -> f32 {
    return (v.x + v.y + v.z) * (1.0 / 3.0);
}

// Vec3::max_element: max(x, max(y, z)).
fn max_element3(v: vec3<f32>) -> f32 {
    return max_num(v.x, max_num(v.y, v.z));
}

// NaN, inf -> DEFAULT_IOR; 0 kept (KHR_materials_ior: f0 = 1); else clamp(ior, 1, ETA_MAX).
fn clamp_ior(ior_in: f32) -> f32 {
    let ior = metal_rough_finite_or(ior_in, DEFAULT_IOR);
    if ior == 0.0 {
        return 0.0;
    }
    return min_num(max_num(ior, 1.0), ETA_MAX);
}

// f0 = min(((ior - 1) / (ior + 1))^2 specular_color, 1), colour finite or 1, at least 0; KHR_materials_specular.
fn dielectric_f0(ior_in: f32, specular_color: vec3<f32>) -> vec3<f32> {
    let ior = clamp_ior(ior_in);
    let r = (ior - 1.0) / (ior + 1.0);
    let r0 = r * r;
    return vec3(
        min_num(r0 * max_num(metal_rough_finite_or(specular_color.x, 1.0), 0.0), 1.0),
        min_num(r0 * max_num(metal_rough_finite_or(specular_color.y, 1.0), 0.0), 1.0),
        min_num(r0 * max_num(metal_rough_finite_or(specular_color.z, 1.0), 0.0), 1.0),
    );
}

// f0 + (1 - f0) / 21, Schlick's hemispherical average (GltfMetalRough::new's `f_avg`).
fn metal_rough_f_avg(f0: f32) -> f32 {
    return f0 + (1.0 - f0) * SCHLICK_GRAZING_AVERAGE;
}

// Sanitized fields (NaN, inf -> 1 then [0, 1]; alphas clamped; f0 = dielectric_f0) and
// p_specular = a_s / (a_s + a_d) in [0.1, 0.9], 0 without a specular lobe, 1 without a diffuse one.
fn gltf_metal_rough_new(
    base_color: vec3<f32>,
    metallic_in: f32,
    alpha_x: f32,
    alpha_y: f32,
    ior: f32,
    specular_color: vec3<f32>,
    specular_weight_in: f32,
) -> GltfMetalRough {
    let base = vec3(
        fresnel_unit(metal_rough_finite_or(base_color.x, 1.0)),
        fresnel_unit(metal_rough_finite_or(base_color.y, 1.0)),
        fresnel_unit(metal_rough_finite_or(base_color.z, 1.0)),
    );
    let metallic = fresnel_unit(metal_rough_finite_or(metallic_in, 1.0));
    let specular_weight = fresnel_unit(metal_rough_finite_or(specular_weight_in, 1.0));
    let f0 = dielectric_f0(ior, specular_color);
    let f_avg_d = metal_rough_f_avg(max_element3(f0));
    let f_avg_base = vec3(metal_rough_f_avg(base.x), metal_rough_f_avg(base.y), metal_rough_f_avg(base.z));
    let a_s = metallic * metal_rough_mean(f_avg_base) + (1.0 - metallic) * specular_weight * f_avg_d;
    let a_d = (1.0 - metallic) * max_num(1.0 - specular_weight * f_avg_d, 0.0) * metal_rough_mean(base);
    var p_specular: f32;
    if !(a_s > 0.0) {
        p_specular = 0.0;
    } else if !(a_d > 0.0) {
        p_specular = 1.0;
    } else {
        p_specular = min_num(max_num(a_s / (a_s + a_d), P_LOBE_MIN), 1.0 - P_LOBE_MIN);
    }
    return GltfMetalRough(base, metallic, f0, specular_weight, trowbridge_reitz_new(alpha_x, alpha_y), p_specular, 0u);
}

// glTF's core material: ior 1.5, specular colour 1, specular weight 1, isotropic alpha.
fn gltf_metal_rough_core(base_color: vec3<f32>, metallic: f32, alpha: f32) -> GltfMetalRough {
    return gltf_metal_rough_new(base_color, metallic, alpha, alpha, DEFAULT_IOR, vec3(1.0), 1.0);
}

// Mirror specular lobe: both alphas below DELTA_ALPHA.
fn gltf_metal_rough_is_delta(b: GltfMetalRough) -> bool {
    return is_effectively_smooth(b.distribution);
}

// The specular lobe: GgxConductor of the distribution with F = 1.
fn gltf_metal_rough_specular(b: GltfMetalRough) -> GgxConductor {
    let one = FresnelParams(FRESNEL_KIND_ONE, 1.0, vec2(0u), vec4(0.0), vec4(0.0));
    return GgxConductor(b.distribution, vec2(0u), one);
}

// clamp(p_specular, 0, 1), NaN -> 0.
fn gltf_metal_rough_specular_probability(b: GltfMetalRough) -> f32 {
    return fresnel_unit(b.p_specular);
}

// (specular lobe weight, diffuse lobe weight) at cos = |wo.h|: xyz (1 - m) sw fr_d + m F_m,
// w (1 - m) max(1 - sw max(fr_d), 0); glTF 2.0 Appendix B fresnel_mix, conductor_fresnel, mix.
fn gltf_metal_rough_weights(b: GltfMetalRough, cos_theta: f32) -> vec4<f32> {
    let metallic = fresnel_unit(b.metallic);
    let specular_weight = fresnel_unit(b.specular_weight);
    let fr_d = fresnel_schlick(cos_theta, metal_rough_unit3(b.f0), vec3(1.0));
    let fr_m = fresnel_schlick(cos_theta, metal_rough_unit3(b.base_color), vec3(1.0));
    let specular = fr_d * ((1.0 - metallic) * specular_weight) + fr_m * metallic;
    let diffuse = (1.0 - metallic) * max_num(1.0 - specular_weight * max_element3(fr_d), 0.0);
    return vec4(specular, diffuse);
}

// (1 - m) sw (f0 + (1 - f0) (1 - cos)^5) + m (base + (1 - base) (1 - cos)^5); glTF 2.0 Appendix B.
fn gltf_metal_rough_specular_fresnel(b: GltfMetalRough, cos_theta: f32) -> vec3<f32> {
    return gltf_metal_rough_weights(b, cos_theta).xyz;
}

// (1 - m) (1 - sw max(f0 + (1 - f0) (1 - cos)^5)), at least 0; glTF 2.0 Appendix B fresnel_mix.
fn gltf_metal_rough_diffuse_weight(b: GltfMetalRough, cos_theta: f32) -> f32 {
    return gltf_metal_rough_weights(b, cos_theta).w;
}

// f |wi.z| = specular_fresnel(|wo.h|) D G2 / (4 wo.z) + diffuse_weight(|wo.h|) base wi.z / pi; glTF 2.0 Appendix B.
fn gltf_metal_rough_eval(b: GltfMetalRough, wo_in: vec3<f32>, wi_in: vec3<f32>) -> vec3<f32> {
    let wo = normalize_or_zero(wo_in);
    let wi = normalize_or_zero(wi_in);
    if !(wo.z > 0.0 && wi.z > 0.0) {
        return vec3(0.0);
    }
    // |wo.h|; rounding can make it 0 or negative where wo ~ -wi (fresnel_schlick clamps).
    let cos_h = dot3(wo, normalize_or_zero(wo + wi));
    let w = gltf_metal_rough_weights(b, cos_h);
    let s = ggx_conductor_eval(gltf_metal_rough_specular(b), wo, wi).x;
    return w.xyz * s + metal_rough_unit3(b.base_color) * (w.w * wi.z * FRAC_1_PI);
}

// p_s pdf_s(wi) + (1 - p_s) wi.z / pi, pdf_s = ggx_conductor_pdf of the specular lobe.
fn gltf_metal_rough_pdf(b: GltfMetalRough, wo_in: vec3<f32>, wi_in: vec3<f32>, sampling: u32) -> f32 {
    let wo = normalize_or_zero(wo_in);
    let wi = normalize_or_zero(wi_in);
    if !(wo.z > 0.0 && wi.z > 0.0) {
        return 0.0;
    }
    let p = gltf_metal_rough_specular_probability(b);
    let pdf_s = ggx_conductor_pdf(gltf_metal_rough_specular(b), wo, wi, sampling);
    return p * pdf_s + (1.0 - p) * pdf_cosine_hemisphere(wi);
}

// The specular lobe (ggx_conductor_sample) when u_lobe < p_s, else the cosine hemisphere; weight =
// eval / pdf of the mixture. A mirror lobe: delta sample, pdf p_s, weight specular_fresnel(wo.z) / p_s.
fn gltf_metal_rough_sample(b: GltfMetalRough, wo_in: vec3<f32>, u: vec2<f32>, u_lobe: f32, sampling: u32) -> BsdfSample {
    var none: BsdfSample;
    let wo = normalize_or_zero(wo_in);
    if !(wo.z > 0.0) {
        return none;
    }
    let p = gltf_metal_rough_specular_probability(b);
    var wi: vec3<f32>;
    if sanitize_u(u_lobe) < p {
        let s = ggx_conductor_sample(gltf_metal_rough_specular(b), wo, u, sampling);
        if s.valid == 0u {
            return none;
        }
        if s.is_delta != 0u {
            let weight = gltf_metal_rough_specular_fresnel(b, wo.z) / p;
            if !is_finite3(weight) {
                return none;
            }
            return BsdfSample(s.wi, weight, p, 1u, 1u);
        }
        wi = s.wi;
    } else {
        wi = sample_cosine_hemisphere(u);
    }
    let pdf = gltf_metal_rough_pdf(b, wo, wi, sampling);
    let weight = gltf_metal_rough_eval(b, wo, wi) / pdf;
    if !(pdf > 0.0 && is_finite(pdf) && is_finite3(weight)) {
        return none;
    }
    return BsdfSample(wi, weight, pdf, 0u, 1u);
}

// ---------------------------------------------------------------------------------------------
// mis.rs
// ---------------------------------------------------------------------------------------------

// max(pdf, 0), NaN -> 0.
fn mis_sanitize(pdf: f32) -> f32 {
    return max_num(pdf, 0.0);
}

// Weight of the smaller of two densities from r = small / large: r / (1 + r) or r^2 / (1 + r^2).
fn mis_small_over_large(r: f32, power: bool) -> f32 {
    if power {
        let r2 = r * r;
        return r2 / (1.0 + r2);
    }
    return r / (1.0 + r);
}

// Weight of f against g: infinite densities win (two share 0.5), ratios formed before squaring.
fn mis_heuristic(f: f32, g: f32, power: bool) -> f32 {
    let inf = inf_f32();
    if f == inf {
        return select(1.0, 0.5, g == inf);
    }
    if g == inf || f <= 0.0 {
        return 0.0;
    }
    if f >= g {
        return 1.0 - mis_small_over_large(g / f, power);
    }
    return mis_small_over_large(f / g, power);
}

// w = nf pf / (nf pf + ng pg); Veach 1997 eq. 9.10. Each product is sanitized again, so 0 inf
// (an unused technique with a delta density) counts as 0, not NaN.
fn balance_heuristic(nf: f32, f_pdf: f32, ng: f32, g_pdf: f32) -> f32 {
    let f = mis_sanitize(mis_sanitize(nf) * mis_sanitize(f_pdf));
    let g = mis_sanitize(mis_sanitize(ng) * mis_sanitize(g_pdf));
    return mis_heuristic(f, g, false);
}

// w = (nf pf)^2 / ((nf pf)^2 + (ng pg)^2); Veach 1997 eq. 9.13. Products sanitized as above.
fn power_heuristic(nf: f32, f_pdf: f32, ng: f32, g_pdf: f32) -> f32 {
    let f = mis_sanitize(mis_sanitize(nf) * mis_sanitize(f_pdf));
    let g = mis_sanitize(mis_sanitize(ng) * mis_sanitize(g_pdf));
    return mis_heuristic(f, g, true);
}

// ---------------------------------------------------------------------------------------------
// frame.rs
// ---------------------------------------------------------------------------------------------

// s = sign(n.z), a = -1 / (s + n.z), b = n.x n.y a; Duff et al. 2017 (JCGT 6(1)). Degenerate n -> +z.
fn frame_from_z(n_in: vec3<f32>) -> Frame {
    var n = normalize_or_zero(n_in);
    if all(n == vec3(0.0)) {
        n = vec3(0.0, 0.0, 1.0);
    }
    let sign = copysign(1.0, n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    return Frame(vec3(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x), vec3(b, sign + n.y * n.y * a, -n.y), n);
}

// (v.x, v.y, v.z) in the frame's coordinates; 0 when a component is not finite.
fn frame_to_local(frame: Frame, v: vec3<f32>) -> vec3<f32> {
    return finite_or_zero3(vec3(dot3(v, frame.x), dot3(v, frame.y), dot3(v, frame.z)));
}

// x v.x + y v.y + z v.z; 0 when a component is not finite.
fn frame_to_world(frame: Frame, v: vec3<f32>) -> vec3<f32> {
    return finite_or_zero3(frame.x * v.x + frame.y * v.y + frame.z * v.z);
}

// 2 (wo.n) n - wo, 0 when a component is not finite (shadows WGSL's builtin `reflect`, which
// mirrors an incident vector instead).
fn reflect(wo: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    return finite_or_zero3(2.0 * dot3(wo, n) * n - wo);
}

// ---------------------------------------------------------------------------------------------
// sequence/hash.rs
// ---------------------------------------------------------------------------------------------

// x ^= x >> 16; x *= 0x7feb352d; x ^= x >> 15; x *= 0x846ca68b; x ^= x >> 16 (Wellons 2018, lowbias32).
fn hash_u32(x_in: u32) -> u32 {
    var x = x_in;
    x ^= x >> 16u;
    x *= 0x7feb352du;
    x ^= x >> 15u;
    x *= 0x846ca68bu;
    x ^= x >> 16u;
    return x;
}

// h(a ^ h(a ^ b ^ 0x9e3779b9)), h = lowbias32 (Wellons 2018; Boost golden-ratio offset).
fn hash_combine(a: u32, b: u32) -> u32 {
    return hash_u32(a ^ hash_u32(a ^ b ^ 0x9e3779b9u));
}

// u = floor(x / 2^8) 2^-24: exact 24-bit fixed point, never 1.
fn u32_to_unit_f32(x: u32) -> f32 {
    return f32(x >> 8u) * (1.0 / 16777216.0);
}

// ---------------------------------------------------------------------------------------------
// sequence/counter.rs: CounterRng
// ---------------------------------------------------------------------------------------------

// key = hash_combine(seed, stream), counter 0 (Salmon et al. 2011).
fn counter_rng_new(seed: u32, stream: u32) -> CounterRng {
    return CounterRng(hash_combine(seed, stream), 0u);
}

// x_n = hash_combine(key, n).
fn counter_rng_get_u32(rng: CounterRng, counter: u32) -> u32 {
    return hash_combine(rng.key, counter);
}

// x = hash_combine(key, counter); counter += 1 mod 2^32.
fn counter_rng_next_u32(rng: ptr<function, CounterRng>) -> u32 {
    let x = counter_rng_get_u32(*rng, (*rng).counter);
    (*rng).counter += 1u;
    return x;
}

// u = u32_to_unit_f32(next_u32).
fn counter_rng_next_f32(rng: ptr<function, CounterRng>) -> f32 {
    return u32_to_unit_f32(counter_rng_next_u32(rng));
}

// (next_f32, next_f32), x drawn before y.
fn counter_rng_next_vec2(rng: ptr<function, CounterRng>) -> vec2<f32> {
    let x = counter_rng_next_f32(rng);
    let y = counter_rng_next_f32(rng);
    return vec2(x, y);
}

// counter += delta mod 2^32.
fn counter_rng_advance(rng: ptr<function, CounterRng>, delta: u32) {
    (*rng).counter += delta;
}

// ---------------------------------------------------------------------------------------------
// sequence/sobol.rs
// ---------------------------------------------------------------------------------------------

// Direction words of Sobol' dimensions 0..4 (van der Corput, then Joe & Kuo new-joe-kuo-6.21201),
// copied from ggx_core::sequence::SOBOL_DIRECTIONS (a test checks this text).
const SOBOL_DIRECTIONS: array<array<u32, 32>, 4> = array<array<u32, 32>, 4>(
    array<u32, 32>(
        0x80000000u, 0x40000000u, 0x20000000u, 0x10000000u, 0x08000000u, 0x04000000u, 0x02000000u, 0x01000000u,
        0x00800000u, 0x00400000u, 0x00200000u, 0x00100000u, 0x00080000u, 0x00040000u, 0x00020000u, 0x00010000u,
        0x00008000u, 0x00004000u, 0x00002000u, 0x00001000u, 0x00000800u, 0x00000400u, 0x00000200u, 0x00000100u,
        0x00000080u, 0x00000040u, 0x00000020u, 0x00000010u, 0x00000008u, 0x00000004u, 0x00000002u, 0x00000001u,
    ),
    array<u32, 32>(
        0x80000000u, 0xc0000000u, 0xa0000000u, 0xf0000000u, 0x88000000u, 0xcc000000u, 0xaa000000u, 0xff000000u,
        0x80800000u, 0xc0c00000u, 0xa0a00000u, 0xf0f00000u, 0x88880000u, 0xcccc0000u, 0xaaaa0000u, 0xffff0000u,
        0x80008000u, 0xc000c000u, 0xa000a000u, 0xf000f000u, 0x88008800u, 0xcc00cc00u, 0xaa00aa00u, 0xff00ff00u,
        0x80808080u, 0xc0c0c0c0u, 0xa0a0a0a0u, 0xf0f0f0f0u, 0x88888888u, 0xccccccccu, 0xaaaaaaaau, 0xffffffffu,
    ),
    array<u32, 32>(
        0x80000000u, 0xc0000000u, 0x60000000u, 0x90000000u, 0xe8000000u, 0x5c000000u, 0x8e000000u, 0xc5000000u,
        0x68800000u, 0x9cc00000u, 0xee600000u, 0x55900000u, 0x80680000u, 0xc09c0000u, 0x60ee0000u, 0x90550000u,
        0xe8808000u, 0x5cc0c000u, 0x8e606000u, 0xc5909000u, 0x6868e800u, 0x9c9c5c00u, 0xeeee8e00u, 0x5555c500u,
        0x8000e880u, 0xc0005cc0u, 0x60008e60u, 0x9000c590u, 0xe8006868u, 0x5c009c9cu, 0x8e00eeeeu, 0xc5005555u,
    ),
    array<u32, 32>(
        0x80000000u, 0xc0000000u, 0x20000000u, 0x50000000u, 0xf8000000u, 0x74000000u, 0xa2000000u, 0x93000000u,
        0xd8800000u, 0x25400000u, 0x59e00000u, 0xe6d00000u, 0x78080000u, 0xb40c0000u, 0x82020000u, 0xc3050000u,
        0x208f8000u, 0x51474000u, 0xfbea2000u, 0x75d93000u, 0xa0858800u, 0x914e5400u, 0xdbe79e00u, 0x25db6d00u,
        0x58800080u, 0xe54000c0u, 0x79e00020u, 0xb6d00050u, 0x800800f8u, 0xc00c0074u, 0x200200a2u, 0x50050093u,
    ),
);

// XOR of table[j] over the set bits j of bits.
fn xor_set_bits(dim: u32, bits_in: u32) -> u32 {
    var x = 0u;
    var bits = bits_in;
    while bits != 0u {
        x ^= SOBOL_DIRECTIONS[dim & 3u][countTrailingZeros(bits)];
        bits &= bits - 1u;
    }
    return x;
}

// x = XOR of v_k over the set bits k of index (Sobol' 1967; Joe & Kuo 2008), dim taken mod 4.
fn sobol(index: u32, dim: u32) -> u32 {
    return xor_set_bits(dim, index);
}

// v += seed, then v ^= v * c for four even constants, on bit-reversed values (Laine & Karras 2011; Burley 2020).
fn laine_karras(v: u32, seed: u32) -> u32 {
    var x = v + seed;
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return x;
}

// reverse(LK(reverse(x), seed)): nested uniform (Owen) scramble (Burley 2020).
fn owen_scramble(x: u32, seed: u32) -> u32 {
    return reverseBits(laine_karras(reverseBits(x), seed));
}

// reverse(owen_scramble(index, group_seed)): the shuffled index, kept bit-reversed.
fn shuffle_index_reversed(index: u32, group_seed: u32) -> u32 {
    return laine_karras(reverseBits(index), group_seed);
}

// reverse(LK(reverse(sobol(reverse(r), dim)), h(group_seed, dim % 4))) (Burley 2020). ggx-core XORs
// a pre-reversed table instead (x86 has no bit reversal); GPUs reverse in one instruction.
fn sobol_owen_shuffled(reversed: u32, group_seed: u32, dim: u32) -> u32 {
    let point = reverseBits(sobol(reverseBits(reversed), dim));
    return reverseBits(laine_karras(point, hash_combine(group_seed, dim & 3u)));
}

// g = h(seed, dim / 4); x = owen(sobol(owen(index, g), dim % 4), h(g, dim % 4)) (Burley 2020).
fn sobol_owen_u32(index: u32, dim: u32, seed: u32) -> u32 {
    let group_seed = hash_combine(seed, dim >> 2u);
    return sobol_owen_shuffled(shuffle_index_reversed(index, group_seed), group_seed, dim);
}

// u = u32_to_unit_f32(sobol_owen_u32(index, dim, seed)).
fn sobol_owen(index: u32, dim: u32, seed: u32) -> f32 {
    return u32_to_unit_f32(sobol_owen_u32(index, dim, seed));
}

// ---------------------------------------------------------------------------------------------
// sequence/stream.rs: SampleStream
// ---------------------------------------------------------------------------------------------

// seed = hash_combine(scene seed, pixel), dimension 0 (Burley 2020).
fn sample_stream_new(kind: u32, seed: u32, pixel: u32, sample_index: u32) -> SampleStream {
    return SampleStream(kind, hash_combine(seed, pixel), sample_index, 0u);
}

// Independent: h(h(seed, sample), dim); Sobol: sobol_owen_u32(sample, dim, seed).
fn sample_stream_get_u32(stream: SampleStream, dim: u32) -> u32 {
    if stream.kind == SEQUENCE_SOBOL {
        return sobol_owen_u32(stream.sample_index, dim, stream.seed);
    }
    return hash_combine(hash_combine(stream.seed, stream.sample_index), dim);
}

// u = u32_to_unit_f32(get_u32(dimension)); dimension += 1.
fn sample_stream_next_1d(stream: ptr<function, SampleStream>) -> f32 {
    let u = u32_to_unit_f32(sample_stream_get_u32(*stream, (*stream).dimension));
    (*stream).dimension += 1u;
    return u;
}

// d = 4 ceil(dimension / 4); (get(d), get(d + 1)), a Sobol' index shuffled once; dimension = d + 2 (Burley 2020 padding; pbrt-v4).
fn sample_stream_next_2d(stream: ptr<function, SampleStream>) -> vec2<f32> {
    let d = ((*stream).dimension + 3u) & ~3u;
    (*stream).dimension = d + 2u;
    var xy: vec2<u32>;
    if (*stream).kind == SEQUENCE_SOBOL {
        let group_seed = hash_combine((*stream).seed, d >> 2u);
        let reversed = shuffle_index_reversed((*stream).sample_index, group_seed);
        xy = vec2(sobol_owen_shuffled(reversed, group_seed, d), sobol_owen_shuffled(reversed, group_seed, d + 1u));
    } else {
        xy = vec2(sample_stream_get_u32(*stream, d), sample_stream_get_u32(*stream, d + 1u));
    }
    return vec2(u32_to_unit_f32(xy.x), u32_to_unit_f32(xy.y));
}

// ---------------------------------------------------------------------------------------------
// clearcoat.rs: GltfClearcoat
// ---------------------------------------------------------------------------------------------

// The coat's normal-incidence reflectance ((1 - ior) / (1 + ior))^2 at KHR_materials_clearcoat's ior 1.5.
const CLEARCOAT_F0: f32 = 0.04f;
// Smallest and largest probability with which gltf_clearcoat_sample draws a present coat lobe.
const P_COAT_MIN: f32 = 0.05f;
const P_COAT_MAX: f32 = 0.95f;

// KHR_materials_clearcoat over the metallic-roughness BRDF, 64 bytes like the Rust struct: base 0,
// coat 48, weight 56, base_albedo 60.
struct GltfClearcoat {
    base: GltfMetalRough,
    coat: TrowbridgeReitz,
    weight: f32,
    base_albedo: f32,
}

// fr(mu) = 0.04 + 0.96 (1 - |mu|)^5, at most 1, NaN -> 1; KHR_materials_clearcoat fresnel_coat.
fn clearcoat_fresnel(cos_theta: f32) -> f32 {
    return min_num(fresnel_schlick(abs(cos_theta), vec3(CLEARCOAT_F0), vec3(1.0)).x, 1.0);
}

// m mean(F_avg(base)) + (1 - m) (sw F_avg(max f0) + max(1 - sw F_avg(max f0), 0) mean(base)), in [0, 1];
// GltfMetalRough::new's a_s + a_d with F_avg(f0) = f0 + (1 - f0) / 21.
fn metal_rough_albedo_estimate(base: GltfMetalRough) -> f32 {
    let c = metal_rough_unit3(base.base_color);
    let mean_base = (c.x + c.y + c.z) * (1.0 / 3.0);
    let mean_f_avg = (metal_rough_f_avg(c.x) + metal_rough_f_avg(c.y) + metal_rough_f_avg(c.z)) * (1.0 / 3.0);
    let metallic = fresnel_unit(base.metallic);
    let specular_weight = fresnel_unit(base.specular_weight);
    let f0 = metal_rough_unit3(base.f0);
    let f_avg_d = specular_weight * metal_rough_f_avg(max_num(max_num(f0.x, f0.y), f0.z));
    let dielectric = f_avg_d + max_num(1.0 - f_avg_d, 0.0) * mean_base;
    return fresnel_unit(metallic * mean_f_avg + (1.0 - metallic) * dielectric);
}

// weight NaN, inf -> 0 then [0, 1]; coat = trowbridge_reitz_new(alpha, alpha); base_albedo = metal_rough_albedo_estimate(base).
fn gltf_clearcoat_new(base: GltfMetalRough, weight_in: f32, coat_alpha: f32) -> GltfClearcoat {
    let weight = select(0.0, fresnel_unit(weight_in), is_finite(weight_in));
    return GltfClearcoat(base, trowbridge_reitz_new(coat_alpha, coat_alpha), weight, metal_rough_albedo_estimate(base));
}

// clamp(weight, 0, 1), NaN -> 0 (clearcoatFactor as every function reads it).
fn gltf_clearcoat_coat_weight(b: GltfClearcoat) -> f32 {
    return fresnel_unit(b.weight);
}

// Mirror coat: both coat alphas below DELTA_ALPHA.
fn gltf_clearcoat_coat_is_delta(b: GltfClearcoat) -> bool {
    return is_effectively_smooth(b.coat);
}

// The coat lobe D G2 / (4 |wo.z| |wi.z|): GgxConductor of the coat with F = 1 (clearcoat_brdf).
fn gltf_clearcoat_coat_lobe(b: GltfClearcoat) -> GgxConductor {
    let one = FresnelParams(FRESNEL_KIND_ONE, 1.0, vec2(0u), vec4(0.0), vec4(0.0));
    return GgxConductor(b.coat, vec2(0u), one);
}

// c = weight fr(cos), fresnel_coat's mix factor at cos = wo.z; KHR_materials_clearcoat.
fn gltf_clearcoat_coat_mix(b: GltfClearcoat, cos_theta: f32) -> f32 {
    return gltf_clearcoat_coat_weight(b) * clearcoat_fresnel(cos_theta);
}

// 1 - c = (1 - weight) + weight (1 - f0) (1 - (1 - |cos|)^5), 1 - (1 - x)^5 = x (5 - 10 x + 10 x^2 - 5 x^3 + x^4)
// below x = 1/2 (no cancellation at grazing views); fresnel_coat's base share.
fn gltf_clearcoat_base_mix(b: GltfClearcoat, cos_theta: f32) -> f32 {
    let w = gltf_clearcoat_coat_weight(b);
    let x = min_num(max_num(abs(cos_theta), 0.0), 1.0);
    var grazing: f32;
    if x < 0.5 {
        grazing = x * (5.0 + x * (-10.0 + x * (10.0 + x * (-5.0 + x))));
    } else {
        let m = 1.0 - x;
        let m2 = m * m;
        grazing = 1.0 - m2 * m2 * m;
    }
    return min_num((1.0 - w) + w * (1.0 - CLEARCOAT_F0) * grazing, 1.0);
}

// p_c = clamp(c / (c + (1 - c) a_b), 0.05, 0.95) (NaN -> 0.05), 1 - c = base_mix, a_b = clamp(base_albedo, 0, 1); 0 without a coat.
fn gltf_clearcoat_coat_probability(b: GltfClearcoat, cos_theta: f32) -> f32 {
    if !(gltf_clearcoat_coat_weight(b) > 0.0) {
        return 0.0;
    }
    let c = gltf_clearcoat_coat_mix(b, cos_theta);
    let p = c / (c + gltf_clearcoat_base_mix(b, cos_theta) * fresnel_unit(b.base_albedo));
    return min_num(max_num(p, P_COAT_MIN), P_COAT_MAX);
}

// f |wi.z| = (1 - c) base + c coat_lobe, c = weight fr(wo.z), 1 - c = base_mix; KHR_materials_clearcoat fresnel_coat. Weight 0: the base.
fn gltf_clearcoat_eval(b: GltfClearcoat, wo_in: vec3<f32>, wi_in: vec3<f32>) -> vec3<f32> {
    if !(gltf_clearcoat_coat_weight(b) > 0.0) {
        return gltf_metal_rough_eval(b.base, wo_in, wi_in);
    }
    let wo = normalize_or_zero(wo_in);
    let wi = normalize_or_zero(wi_in);
    if !(wo.z > 0.0 && wi.z > 0.0) {
        return vec3(0.0);
    }
    let base = gltf_metal_rough_eval(b.base, wo, wi) * gltf_clearcoat_base_mix(b, wo.z);
    return base + ggx_conductor_eval(gltf_clearcoat_coat_lobe(b), wo, wi) * gltf_clearcoat_coat_mix(b, wo.z);
}

// p_c pdf_coat + (1 - p_c) pdf_base, p_c = gltf_clearcoat_coat_probability(wo.z). Weight 0: the base.
fn gltf_clearcoat_pdf(b: GltfClearcoat, wo_in: vec3<f32>, wi_in: vec3<f32>, sampling: u32) -> f32 {
    if !(gltf_clearcoat_coat_weight(b) > 0.0) {
        return gltf_metal_rough_pdf(b.base, wo_in, wi_in, sampling);
    }
    let wo = normalize_or_zero(wo_in);
    let wi = normalize_or_zero(wi_in);
    if !(wo.z > 0.0 && wi.z > 0.0) {
        return 0.0;
    }
    let p = gltf_clearcoat_coat_probability(b, wo.z);
    let pdf_coat = ggx_conductor_pdf(gltf_clearcoat_coat_lobe(b), wo, wi, sampling);
    return p * pdf_coat + (1.0 - p) * gltf_metal_rough_pdf(b.base, wo, wi, sampling);
}

// The coat lobe when u_lobe < p_c, else gltf_metal_rough_sample with u_lobe' = (u_lobe - p_c) / (1 - p_c); weight =
// eval / pdf. Deltas: a mirror coat (c / p_c, pdf p_c), a mirror base ((1 - c) F_s / pdf, pdf (1 - p_c) p_s).
fn gltf_clearcoat_sample(b: GltfClearcoat, wo_in: vec3<f32>, u: vec2<f32>, u_lobe_in: f32, sampling: u32) -> BsdfSample {
    if !(gltf_clearcoat_coat_weight(b) > 0.0) {
        return gltf_metal_rough_sample(b.base, wo_in, u, u_lobe_in, sampling);
    }
    var none: BsdfSample;
    let wo = normalize_or_zero(wo_in);
    if !(wo.z > 0.0) {
        return none;
    }
    let p = gltf_clearcoat_coat_probability(b, wo.z);
    let u_lobe = sanitize_u(u_lobe_in);
    var wi: vec3<f32>;
    if u_lobe < p {
        let s = ggx_conductor_sample(gltf_clearcoat_coat_lobe(b), wo, u, sampling);
        if s.valid == 0u {
            return none;
        }
        if s.is_delta != 0u {
            return BsdfSample(s.wi, vec3(gltf_clearcoat_coat_mix(b, wo.z) / p), p, 1u, 1u);
        }
        wi = s.wi;
    } else {
        // Uniform on [0, 1) again (gltf_metal_rough_sample's sanitize_u catches a quotient rounded to 1).
        let s = gltf_metal_rough_sample(b.base, wo, u, (u_lobe - p) / (1.0 - p), sampling);
        if s.valid == 0u {
            return none;
        }
        if s.is_delta != 0u {
            let pdf = (1.0 - p) * s.pdf;
            let weight = gltf_metal_rough_specular_fresnel(b.base, wo.z) * gltf_clearcoat_base_mix(b, wo.z) / pdf;
            if !(pdf > 0.0 && is_finite3(weight)) {
                return none;
            }
            return BsdfSample(s.wi, weight, pdf, 1u, 1u);
        }
        wi = s.wi;
    }
    let pdf = gltf_clearcoat_pdf(b, wo, wi, sampling);
    let weight = gltf_clearcoat_eval(b, wo, wi) / pdf;
    if !(pdf > 0.0 && is_finite(pdf) && is_finite3(weight)) {
        return none;
    }
    return BsdfSample(wi, weight, pdf, 0u, 1u);
}
