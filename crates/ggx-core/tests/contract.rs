//! The "any f32 in, no NaN out" contract, one property test per public function and method.
//!
//! Inputs mix special values (NaN, infinities, signed zeros, subnormals, `f32::MAX`,
//! `1 - ulp`, `2^23`, negative values) with ordinary ones and arbitrary bit patterns; the `Pod`
//! structs (`TrowbridgeReitz`, `GgxConductor`, `FresnelParams`, `Frame`, `CounterRng`,
//! `SampleStream`) are also built field by field from arbitrary bits, bypassing the
//! constructors. Each test asserts what the function's documentation promises: finite outputs,
//! unit (or zero) directions, non-negative densities, values in `[0, 1]`, and, for everything
//! that reads alphas, the same bits as the distribution the constructor would have made from
//! the raw fields. The exceptions the crate documents (`math::sqrt` is IEEE, `safe_sqrt(+inf)`,
//! `pdf_cosine_hemisphere` at `w.z = +inf` and `lambda` where `q` overflows are `+inf`) are
//! asserted exactly.

use ggx_core::batch::{self, Vec3Slices, Vec3SlicesMut};
use ggx_core::conductor::formulas::reflection;
use ggx_core::distribution::formulas::{self, Widths};
use ggx_core::distribution::samplers;
use ggx_core::energy::{
    albedo, alpha_coordinate, average_albedo, column_mu, effective_alpha, mu_coordinate, multiple_scattering_fresnel,
    row_alpha,
};
use ggx_core::energy_dielectric::{
    DIELECTRIC_ALBEDO_MIN, ETA_TABLE_MAX, coat_albedo, coat_albedo_table, coat_average_albedo,
    coat_average_albedo_table, dielectric_albedo, dielectric_albedo_inside_table, dielectric_albedo_outside_table,
    eta_coordinate, plastic_base_weight, slice_eta,
};
use ggx_core::fresnel::{FresnelParams, fresnel_complex, fresnel_dielectric, fresnel_schlick, kind};
use ggx_core::lanes::Vec3Lanes;
use ggx_core::math::{self, ONE_MINUS_EPSILON};
use ggx_core::mis::{balance_heuristic, power_heuristic};
use ggx_core::sequence::{
    self as seq, CounterRng, SOBOL_DIMENSIONS, SOBOL_DIRECTIONS, SampleStream, SequenceKind, hash_combine,
};
use ggx_core::{
    ALPHA_MAX, ALPHA_MIN, BsdfSample, Bxdf, BxdfFlags, DELTA_ALPHA, ETA_MAX, ETA_MIN, Frame, Fresnel, GgxConductor,
    GgxConductorMs, GgxDielectric, GgxDielectricMs, Sampling, ThinDielectric, TransportMode, TrowbridgeReitz, Vec2,
    Vec3, alpha, alpha_to_roughness, clamp_eta, reflect, refract, roughness_to_alpha, warp,
};
use proptest::prelude::*;
use proptest::test_runner::RngSeed;

// ---------------------------------------------------------------------------------------------
// Strategies
// ---------------------------------------------------------------------------------------------

const SPECIALS: [f32; 30] = [
    f32::NAN,
    -f32::NAN,
    f32::INFINITY,
    f32::NEG_INFINITY,
    0.0,
    -0.0,
    1e-45,
    -1e-45,
    1e-40,
    f32::MIN_POSITIVE,
    1e-30,
    1e-7,
    0.25,
    0.5,
    ONE_MINUS_EPSILON,
    -ONE_MINUS_EPSILON,
    1.0,
    -1.0,
    1.000_000_1,
    2.0,
    -0.3,
    8_388_607.5,
    8_388_608.0,
    -8_388_608.0,
    1e30,
    -1e30,
    f32::MAX,
    f32::MIN,
    1e-4,
    1e-3,
];

/// Any f32: special values, ordinary and negative values, the unit interval, arbitrary bits.
fn any_f32() -> impl Strategy<Value = f32> {
    prop_oneof![
        3 => prop::sample::select(SPECIALS.to_vec()),
        2 => -2.0f32..2.0,
        1 => 0.0f32..1.0,
        1 => -1e7f32..1e7,
        2 => any::<u32>().prop_map(f32::from_bits),
    ]
}

/// A raw `Pod` float field: anything `any_f32` gives, plus valid alphas from 1e-7 to 1.
fn field() -> impl Strategy<Value = f32> {
    prop_oneof![3 => any_f32(), 1 => (-7.0f32..=0.0).prop_map(|e| 10f32.powf(e))]
}

fn vec2() -> impl Strategy<Value = Vec2> {
    (any_f32(), any_f32()).prop_map(|(x, y)| Vec2::new(x, y))
}

/// A direction: raw components, a unit vector on the hemisphere, or a grazing one.
fn dir() -> impl Strategy<Value = Vec3> {
    prop_oneof![
        2 => (any_f32(), any_f32(), any_f32()).prop_map(|(x, y, z)| Vec3::new(x, y, z)),
        2 => (0.0f32..1.0, 0.0f32..1.0).prop_map(|(a, b)| warp::sample_uniform_hemisphere(Vec2::new(a, b))),
        1 => (-7.0f32..0.0, 0.0f32..6.3).prop_map(|(e, phi)| {
            let z = 10f32.powf(e);
            let r = (1.0 - z * z).sqrt();
            Vec3::new(r * phi.cos(), r * phi.sin(), z)
        }),
    ]
}

/// A distribution whose fields bypass the constructor.
fn raw_dist() -> impl Strategy<Value = TrowbridgeReitz> {
    (field(), field(), any::<bool>())
        .prop_map(|(x, y, iso)| TrowbridgeReitz { alpha_x: x, alpha_y: if iso { x } else { y } })
}

/// `FresnelParams` with any kind (known ones over-represented) and raw parameters.
fn raw_fresnel() -> impl Strategy<Value = FresnelParams> {
    let kinds = prop_oneof![3 => 0u32..4, 1 => any::<u32>()];
    let v4 = || (field(), field(), field(), field()).prop_map(|(a, b, c, d)| [a, b, c, d]);
    (kinds, field(), any::<[u32; 2]>(), v4(), v4()).prop_map(|(kind, eta, pad, a, b)| FresnelParams {
        kind,
        eta,
        pad,
        a,
        b,
    })
}

/// A conductor whose every field bypasses the constructor; sometimes all 64 bytes arbitrary.
fn raw_brdf() -> impl Strategy<Value = GgxConductor> {
    prop_oneof![
        4 => (raw_dist(), any::<[u32; 2]>(), raw_fresnel())
            .prop_map(|(distribution, pad, fresnel)| GgxConductor { distribution, pad, fresnel }),
        1 => any::<[u32; 16]>().prop_map(bytemuck::cast::<[u32; 16], GgxConductor>),
    ]
}

/// A dielectric whose every field bypasses the constructor; sometimes all 16 bytes arbitrary.
fn raw_dielectric() -> impl Strategy<Value = GgxDielectric> {
    prop_oneof![
        4 => (raw_dist(), prop_oneof![3 => field(), 1 => Just(1.5f32), 1 => 0.3f32..3.0], any::<u32>())
            .prop_map(|(distribution, eta, pad)| GgxDielectric { distribution, eta, pad }),
        1 => any::<[u32; 4]>().prop_map(bytemuck::cast::<[u32; 4], GgxDielectric>),
    ]
}

/// A compensated conductor whose every field bypasses the constructor (raw `f_avg`, any
/// `compensation`); sometimes built by `new`, sometimes all 80 bytes arbitrary.
fn raw_ms() -> impl Strategy<Value = GgxConductorMs> {
    let comp = prop_oneof![2 => Just(1u32), 1 => Just(0u32), 1 => any::<u32>()];
    prop_oneof![
        4 => (raw_brdf(), (field(), field(), field()), comp)
            .prop_map(|(conductor, (r, g, b), compensation)| GgxConductorMs { conductor, f_avg: [r, g, b], compensation }),
        2 => raw_brdf().prop_map(GgxConductorMs::new),
        1 => any::<[u32; 20]>().prop_map(bytemuck::cast::<[u32; 20], GgxConductorMs>),
    ]
}

fn constructed_ms(m: GgxConductorMs) -> GgxConductorMs {
    GgxConductorMs { conductor: constructed_brdf(m.conductor), ..m }
}

fn constructed_dielectric(b: GgxDielectric) -> GgxDielectric {
    GgxDielectric::new(b.distribution.alpha_x, b.distribution.alpha_y, b.eta)
}

/// A compensated dielectric whose every field bypasses the constructor (any `compensation` and
/// `pad`); sometimes built by `new`, sometimes all 32 bytes arbitrary.
fn raw_dielectric_ms() -> impl Strategy<Value = GgxDielectricMs> {
    let comp = prop_oneof![2 => Just(1u32), 1 => Just(0u32), 1 => any::<u32>()];
    prop_oneof![
        4 => (raw_dielectric(), comp, any::<[u32; 3]>())
            .prop_map(|(dielectric, compensation, pad)| GgxDielectricMs { dielectric, compensation, pad }),
        2 => raw_dielectric().prop_map(GgxDielectricMs::new),
        1 => any::<[u32; 8]>().prop_map(bytemuck::cast::<[u32; 8], GgxDielectricMs>),
    ]
}

fn constructed_dielectric_ms(m: GgxDielectricMs) -> GgxDielectricMs {
    GgxDielectricMs { dielectric: constructed_dielectric(m.dielectric), ..m }
}

fn mode() -> impl Strategy<Value = TransportMode> {
    prop_oneof![Just(TransportMode::Radiance), Just(TransportMode::Importance)]
}

fn flags() -> impl Strategy<Value = BxdfFlags> {
    prop_oneof![0u32..16, any::<u32>()].prop_map(BxdfFlags)
}

fn sample_key(r: Option<BsdfSample>) -> Option<([u32; 3], [u32; 3], u32, bool)> {
    r.map(|b| (b.wi.to_array().map(f32::to_bits), b.weight.to_array().map(f32::to_bits), b.pdf.to_bits(), b.is_delta))
}

fn raw_frame() -> impl Strategy<Value = Frame> {
    prop_oneof![
        1 => dir().prop_map(Frame::from_z),
        1 => proptest::array::uniform9(any_f32()).prop_map(bytemuck::cast::<[f32; 9], Frame>),
    ]
}

fn fresnel_enum() -> impl Strategy<Value = Fresnel> {
    let v = || (any_f32(), any_f32(), any_f32()).prop_map(|(a, b, c)| Vec3::new(a, b, c));
    prop_oneof![
        Just(Fresnel::One),
        v().prop_map(|f0| Fresnel::Schlick { f0 }),
        (v(), v()).prop_map(|(f0, f90)| Fresnel::SchlickF90 { f0, f90 }),
        (v(), v()).prop_map(|(eta, k)| Fresnel::Conductor { eta, k }),
        any_f32().prop_map(|eta| Fresnel::Dielectric { eta }),
    ]
}

fn sampling() -> impl Strategy<Value = Sampling> {
    prop::sample::select(Sampling::ALL.to_vec())
}

// ---------------------------------------------------------------------------------------------
// Predicates
// ---------------------------------------------------------------------------------------------

/// Finite and not negative.
fn ok(x: f32) -> bool {
    x.is_finite() && x >= 0.0
}

fn ok3(v: Vec3) -> bool {
    ok(v.x) && ok(v.y) && ok(v.z)
}

fn unit_interval(x: f32) -> bool {
    (0.0..=1.0).contains(&x)
}

/// In `[0, 1)`.
fn unit_open(x: f32) -> bool {
    (0.0..1.0).contains(&x)
}

/// `x` clamped to `[0, 1]`, NaN -> 0 (the clamp the energy functions document).
fn clamp01(x: f32) -> f32 {
    x.max(0.0).min(1.0)
}

/// Zero, or unit length within 1e-5 with `z >= 0` (a microfacet normal).
fn normal_or_zero(m: Vec3) -> bool {
    m == Vec3::ZERO || (m.is_finite() && (m.length() - 1.0).abs() < 1e-5 && m.z >= 0.0)
}

fn same(a: f32, b: f32) -> bool {
    a.to_bits() == b.to_bits()
}

fn same3(a: Vec3, b: Vec3) -> bool {
    same(a.x, b.x) && same(a.y, b.y) && same(a.z, b.z)
}

/// The distribution the constructor makes from the raw fields: every method must agree with it.
fn constructed(t: TrowbridgeReitz) -> TrowbridgeReitz {
    TrowbridgeReitz::new(t.alpha_x, t.alpha_y)
}

fn constructed_brdf(b: GgxConductor) -> GgxConductor {
    GgxConductor { distribution: constructed(b.distribution), ..b }
}

fn config() -> ProptestConfig {
    // `cargo xtask fuzz` raises the budget through GGX_FUZZ_CASES.
    let cases = std::env::var("GGX_FUZZ_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(4000);
    ProptestConfig { cases, rng_seed: RngSeed::Fixed(0x636f_6e74), failure_persistence: None, ..Default::default() }
}

// ---------------------------------------------------------------------------------------------
// math
// ---------------------------------------------------------------------------------------------

proptest! {
    #![proptest_config(config())]

    /// IEEE: finite for finite `x >= 0`, `+inf` for `+inf`, NaN for `x < 0` and NaN.
    #[test]
    fn math_sqrt(x in any_f32()) {
        let r = math::sqrt(x);
        if x >= 0.0 && x.is_finite() {
            prop_assert!(ok(r), "{x} -> {r}");
        } else if x == f32::INFINITY {
            prop_assert_eq!(r, f32::INFINITY);
        } else {
            prop_assert!(r.is_nan(), "{x} -> {r}");
        }
    }

    /// Never NaN; finite and `>= 0` except `safe_sqrt(+inf) = +inf`.
    #[test]
    fn math_safe_sqrt(x in any_f32()) {
        let r = math::safe_sqrt(x);
        prop_assert!(ok(r) || (x == f32::INFINITY && r == f32::INFINITY), "{x} -> {r}");
    }

    #[test]
    fn math_finite_or_zero(x in any_f32()) {
        let r = math::finite_or_zero(x);
        prop_assert!(r.is_finite() && (r == x || (!x.is_finite() && r == 0.0)), "{x} -> {r}");
    }

    #[test]
    fn math_sanitize_u(x in any_f32()) {
        let r = math::sanitize_u(x);
        prop_assert!(unit_open(r), "{x} -> {r}");
        prop_assert!(!unit_open(x) || r == x, "{x} -> {r}");
    }

    #[test]
    fn math_sanitize_u2(u in vec2()) {
        let r = math::sanitize_u2(u);
        prop_assert!(unit_open(r.x) && unit_open(r.y), "{u:?} -> {r:?}");
    }

    /// Zero or unit length, and idempotent.
    #[test]
    fn math_normalize_or_zero(v in dir(), scale in any_f32()) {
        for v in [v, v * scale] {
            let n = math::normalize_or_zero(v);
            prop_assert!(n == Vec3::ZERO || (n.is_finite() && (n.length() - 1.0).abs() < 1e-5), "{v:?} -> {n:?}");
            prop_assert_eq!(math::normalize_or_zero(n), n);
        }
    }

    /// Finite, in [-1, 1], within 2e-7 of f64 at `u mod 1` for every finite u (|u| >= 2^23 is
    /// an integer: exactly (0, 1)); NaN and infinities give (+-0, 1).
    #[test]
    fn math_sincos_2pi(u in any_f32()) {
        let (s, c) = math::sincos_2pi(u);
        prop_assert!(s.is_finite() && c.is_finite() && s.abs() <= 1.0 && c.abs() <= 1.0, "{u} -> {s} {c}");
        if u.is_finite() {
            let a = std::f64::consts::TAU * f64::from(u).rem_euclid(1.0);
            let err = (f64::from(s) - a.sin()).abs().max((f64::from(c) - a.cos()).abs());
            prop_assert!(err < 2e-7, "{u} -> {s} {c}, error {err}");
        } else {
            prop_assert!(s == 0.0 && c == 1.0, "{u} -> {s} {c}");
        }
    }
}

// ---------------------------------------------------------------------------------------------
// alpha
// ---------------------------------------------------------------------------------------------

proptest! {
    #![proptest_config(config())]

    #[test]
    fn alpha_clamp_alpha(x in field()) {
        let a = alpha::clamp_alpha(x);
        prop_assert!((ALPHA_MIN..=ALPHA_MAX).contains(&a), "{x} -> {a}");
        prop_assert!(!(ALPHA_MIN..=ALPHA_MAX).contains(&x) || a == x);
    }

    #[test]
    fn alpha_roughness_to_alpha(x in field()) {
        let a = roughness_to_alpha(x);
        prop_assert!(unit_interval(a), "{x} -> {a}");
    }

    #[test]
    fn alpha_alpha_to_roughness(x in field()) {
        let r = alpha_to_roughness(x);
        prop_assert!(unit_interval(r), "{x} -> {r}");
    }
}

// ---------------------------------------------------------------------------------------------
// TrowbridgeReitz: raw fields behave as the constructor's clamp of them
// ---------------------------------------------------------------------------------------------

proptest! {
    #![proptest_config(config())]

    #[test]
    fn trowbridge_reitz_new(x in field(), y in field()) {
        let t = TrowbridgeReitz::new(x, y);
        prop_assert!((ALPHA_MIN..=ALPHA_MAX).contains(&t.alpha_x) && (ALPHA_MIN..=ALPHA_MAX).contains(&t.alpha_y));
        prop_assert_eq!(t.alphas(), (t.alpha_x, t.alpha_y));
    }

    #[test]
    fn trowbridge_reitz_isotropic(x in field()) {
        let t = TrowbridgeReitz::isotropic(x);
        prop_assert!(t.is_isotropic() && (ALPHA_MIN..=ALPHA_MAX).contains(&t.alpha_x));
        prop_assert_eq!(t, TrowbridgeReitz::new(x, x));
    }

    #[test]
    fn trowbridge_reitz_alphas(t in raw_dist()) {
        let (ax, ay) = t.alphas();
        prop_assert!((ALPHA_MIN..=ALPHA_MAX).contains(&ax) && (ALPHA_MIN..=ALPHA_MAX).contains(&ay), "{t:?}");
        prop_assert_eq!((ax, ay), constructed(t).alphas());
    }

    #[test]
    fn trowbridge_reitz_is_isotropic(t in raw_dist()) {
        prop_assert_eq!(t.is_isotropic(), constructed(t).is_isotropic(), "{:?}", t);
    }

    #[test]
    fn trowbridge_reitz_is_effectively_smooth(t in raw_dist()) {
        let smooth = t.is_effectively_smooth();
        prop_assert_eq!(smooth, constructed(t).is_effectively_smooth(), "{:?}", t);
        let (ax, ay) = t.alphas();
        prop_assert_eq!(smooth, ax.max(ay) < DELTA_ALPHA);
    }

    #[test]
    fn trowbridge_reitz_d(t in raw_dist(), wm in dir()) {
        let d = t.d(wm);
        prop_assert!(ok(d), "{t:?} {wm:?} -> {d}");
        prop_assert!(same(d, constructed(t).d(wm)), "{t:?} {wm:?} -> {d}");
    }

    /// Never NaN, never negative; `+inf` only where `q = (ax^2 x^2 + ay^2 y^2) / z^2` overflows:
    /// `w.z^2` is 0 (or underflows) under a non-zero tangential part, or the tangential part
    /// (or `x^2 + y^2` on the isotropic path) itself overflows (non-unit `w`).
    #[test]
    fn trowbridge_reitz_lambda(t in raw_dist(), w in dir()) {
        let l = t.lambda(w);
        prop_assert!(!l.is_nan() && l >= 0.0, "{t:?} {w:?} -> {l}");
        prop_assert!(same(l, constructed(t).lambda(w)));
        if l.is_infinite() {
            let (ax, ay) = t.alphas();
            let (x, y, z) = (f64::from(ax * w.x), f64::from(ay * w.y), f64::from(w.z));
            let (tangential, raw) = (x * x + y * y, f64::from(w.x).powi(2) + f64::from(w.y).powi(2));
            let overflow = tangential.max(raw) > 3.0e38 || tangential / (z * z) > 1e37 || (w.z * w.z == 0.0 && tangential > 0.0);
            prop_assert!(l == f32::INFINITY && overflow, "{t:?} {w:?} -> {l}");
        }
    }

    #[test]
    fn trowbridge_reitz_g1(t in raw_dist(), w in dir()) {
        let g = t.g1(w);
        prop_assert!(ok(g) && g <= 1.0, "{t:?} {w:?} -> {g}");
        prop_assert!(same(g, constructed(t).g1(w)));
    }

    #[test]
    fn trowbridge_reitz_g2(t in raw_dist(), wo in dir(), wi in dir()) {
        let g = t.g2(wo, wi);
        prop_assert!(ok(g) && g <= 1.0, "{t:?} -> {g}");
        prop_assert!(same(g, constructed(t).g2(wo, wi)));
    }

    #[test]
    fn trowbridge_reitz_g2_separable(t in raw_dist(), wo in dir(), wi in dir()) {
        let g = t.g2_separable(wo, wi);
        prop_assert!(ok(g) && g <= 1.0, "{t:?} -> {g}");
        prop_assert!(same(g, constructed(t).g2_separable(wo, wi)));
    }

    #[test]
    fn trowbridge_reitz_d_visible(t in raw_dist(), w in dir(), wm in dir()) {
        let d = t.d_visible(w, wm);
        prop_assert!(ok(d), "{t:?} {w:?} {wm:?} -> {d}");
        prop_assert!(same(d, constructed(t).d_visible(w, wm)));
    }

    /// The generic formulas take any widths (fields of any bits, either grouping): finite, and
    /// Lambda never NaN; with the widths `TrowbridgeReitz::widths` makes, non-negative and the
    /// methods' own bits.
    #[test]
    fn distribution_formulas(t in raw_dist(), x in any_f32(), y in any_f32(), isotropic in any::<bool>(), w in dir(), v in dir()) {
        let (w3, v3) = (w, v);
        let (w, v) = (Vec3Lanes::from(w), Vec3Lanes::from(v));
        let a = Widths { x, y, isotropic };
        for f in [formulas::d(a, w), formulas::g1(a, w), formulas::g2(a, w, v), formulas::d_visible(a, w, v)] {
            prop_assert!(f.is_finite(), "{a:?} {w:?} {v:?} -> {f}");
        }
        prop_assert!(!formulas::lambda(a, w).is_nan(), "{a:?} {w:?}");
        let a = t.widths();
        let pairs = [
            (formulas::d(a, w), t.d(w3)),
            (formulas::g1(a, w), t.g1(w3)),
            (formulas::g2(a, w, v), t.g2(w3, v3)),
            (formulas::d_visible(a, w, v), t.d_visible(w3, v3)),
        ];
        for (f, method) in pairs {
            prop_assert!(ok(f) && same(f, method), "{a:?} {w:?} {v:?} -> {f} vs {method}");
        }
        let l = formulas::lambda(a, w);
        prop_assert!(l >= 0.0 && same(l, t.lambda(w3)), "{a:?} {w:?} -> {l}");
    }

    /// The generic samplers and densities take any widths (fields of any bits, either grouping)
    /// and any numbers, in `f32` and `f64`: a normal on the upper hemisphere, unit to within
    /// `normalize_or_zero`'s idempotence window, or zero; finite densities.
    #[test]
    fn sampler_formulas(x in any_f32(), y in any_f32(), isotropic in any::<bool>(), wo in dir(), wm in dir(), u in vec2()) {
        let a = Widths { x, y, isotropic };
        let (o, m) = (Vec3Lanes::from(wo), Vec3Lanes::from(wm));
        let samples = [
            samplers::sample_wm_ndf(a, u.x, u.y),
            samplers::sample_wm_vndf(a, o, u.x, u.y),
            samplers::sample_wm_spherical_caps(a, o, u.x, u.y),
            samplers::sample_wm_bounded(a, o, u.x, u.y),
        ];
        for s in samples {
            prop_assert!(normal_or_zero(s.into()), "{a:?} {wo:?} {u:?} -> {s:?}");
        }
        for p in [samplers::pdf_wm_ndf(a, m), samplers::pdf_wi_bounded(a, o, m), samplers::bounded_k(a, o)] {
            prop_assert!(p.is_finite(), "{a:?} {wo:?} {wm:?} -> {p}");
        }
        let a = Widths { x: f64::from(x), y: f64::from(y), isotropic };
        let (o, m, u0, u1) = (Vec3Lanes::<f64>::from(wo), Vec3Lanes::<f64>::from(wm), f64::from(u.x), f64::from(u.y));
        for s in [samplers::sample_wm_ndf(a, u0, u1), samplers::sample_wm_vndf(a, o, u0, u1), samplers::sample_wm_bounded(a, o, u0, u1)] {
            let len = s.dot(s).sqrt();
            prop_assert!(len == 0.0 || ((len - 1.0).abs() <= 2e-6 && s.z >= 0.0), "{a:?} {wo:?} {u:?} -> {s:?}");
        }
        prop_assert!(samplers::pdf_wi_bounded(a, o, m).is_finite() && samplers::pdf_wm_ndf(a, m).is_finite());
    }

    /// The conductor's generic microfacet factor: finite for any widths and directions; with a
    /// conductor's own widths and `F = 1`, `eval`'s bits (0 for a delta lobe, which `eval` adds).
    #[test]
    fn conductor_formulas_reflection(t in raw_dist(), x in any_f32(), y in any_f32(), isotropic in any::<bool>(), wo in dir(), wi in dir()) {
        let (o, i) = (Vec3Lanes::from(wo), Vec3Lanes::from(wi));
        let (f, cos) = reflection(Widths { x, y, isotropic }, o, i);
        prop_assert!(f.is_finite(), "{f} {cos}");
        let brdf = GgxConductor { distribution: t, pad: [0; 2], fresnel: Fresnel::One.into() };
        let (f, _) = reflection(t.widths(), o, i);
        let expect = if brdf.is_delta() { 0.0 } else { f };
        prop_assert!(ok(f) && same(expect, brdf.eval(wo, wi).x), "{t:?} {wo:?} {wi:?} -> {f}");
    }

    #[test]
    fn trowbridge_reitz_sample_wm_ndf(t in raw_dist(), u in vec2()) {
        let m = t.sample_wm_ndf(u);
        prop_assert!(normal_or_zero(m), "{t:?} {u:?} -> {m:?}");
        prop_assert!(same3(m, constructed(t).sample_wm_ndf(u)), "{t:?} {u:?} -> {m:?}");
    }

    #[test]
    fn trowbridge_reitz_pdf_wm_ndf(t in raw_dist(), wm in dir()) {
        let p = t.pdf_wm_ndf(wm);
        prop_assert!(ok(p), "{t:?} {wm:?} -> {p}");
        prop_assert!(same(p, constructed(t).pdf_wm_ndf(wm)));
    }

    #[test]
    fn trowbridge_reitz_sample_wm_vndf(t in raw_dist(), wo in dir(), u in vec2()) {
        let m = t.sample_wm_vndf(wo, u);
        prop_assert!(normal_or_zero(m), "{t:?} {wo:?} {u:?} -> {m:?}");
        prop_assert!(same3(m, constructed(t).sample_wm_vndf(wo, u)), "{t:?} {wo:?} {u:?} -> {m:?}");
    }

    #[test]
    fn trowbridge_reitz_sample_wm_spherical_caps(t in raw_dist(), wo in dir(), u in vec2()) {
        let m = t.sample_wm_spherical_caps(wo, u);
        prop_assert!(normal_or_zero(m), "{t:?} {wo:?} {u:?} -> {m:?}");
        prop_assert!(same3(m, constructed(t).sample_wm_spherical_caps(wo, u)), "{t:?} {wo:?} {u:?} -> {m:?}");
    }

    /// `k` in [0, 1] (alpha <= 1).
    #[test]
    fn trowbridge_reitz_bounded_k(t in raw_dist(), wo in dir()) {
        let k = t.bounded_k(wo);
        prop_assert!(unit_interval(k), "{t:?} {wo:?} -> {k}");
        prop_assert!(same(k, constructed(t).bounded_k(wo)));
    }

    #[test]
    fn trowbridge_reitz_sample_wm_bounded(t in raw_dist(), wo in dir(), u in vec2()) {
        let m = t.sample_wm_bounded(wo, u);
        prop_assert!(normal_or_zero(m), "{t:?} {wo:?} {u:?} -> {m:?}");
        prop_assert!(same3(m, constructed(t).sample_wm_bounded(wo, u)), "{t:?} {wo:?} {u:?} -> {m:?}");
    }

    #[test]
    fn trowbridge_reitz_pdf_wi_bounded(t in raw_dist(), wo in dir(), wm in dir()) {
        let p = t.pdf_wi_bounded(wo, wm);
        prop_assert!(ok(p), "{t:?} {wo:?} {wm:?} -> {p}");
        prop_assert!(same(p, constructed(t).pdf_wi_bounded(wo, wm)));
    }
}

// ---------------------------------------------------------------------------------------------
// warp
// ---------------------------------------------------------------------------------------------

proptest! {
    #![proptest_config(config())]

    #[test]
    fn warp_sample_cosine_hemisphere(u in vec2()) {
        let w = warp::sample_cosine_hemisphere(u);
        prop_assert!(w.is_finite() && (w.length() - 1.0).abs() < 1e-5 && w.z > 0.0, "{u:?} -> {w:?}");
        prop_assert!(warp::pdf_cosine_hemisphere(w) > 0.0);
    }

    /// Finite and `>= 0`, except `+inf` at `w.z = +inf`.
    #[test]
    fn warp_pdf_cosine_hemisphere(w in dir()) {
        let p = warp::pdf_cosine_hemisphere(w);
        prop_assert!(ok(p) || (w.z == f32::INFINITY && p == f32::INFINITY), "{w:?} -> {p}");
    }

    #[test]
    fn warp_sample_uniform_hemisphere(u in vec2()) {
        let w = warp::sample_uniform_hemisphere(u);
        prop_assert!(w.is_finite() && (w.length() - 1.0).abs() < 1e-5 && w.z > 0.0, "{u:?} -> {w:?}");
        prop_assert!(warp::pdf_uniform_hemisphere(w) > 0.0);
    }

    #[test]
    fn warp_pdf_uniform_hemisphere(w in dir()) {
        let p = warp::pdf_uniform_hemisphere(w);
        prop_assert!(p == 0.0 || p == 0.5 / std::f32::consts::PI, "{w:?} -> {p}");
    }
}

// ---------------------------------------------------------------------------------------------
// fresnel
// ---------------------------------------------------------------------------------------------

proptest! {
    #![proptest_config(config())]

    /// Finite for any input; in [0, 1] when `f0` and `f90` are.
    #[test]
    fn fresnel_fresnel_schlick(c in any_f32(), f0 in dir(), f90 in dir()) {
        let f = fresnel_schlick(c, f0, f90);
        prop_assert!(f.is_finite(), "{c} {f0:?} {f90:?} -> {f:?}");
        let inside = |v: Vec3| v.cmpge(Vec3::ZERO).all() && v.cmple(Vec3::ONE).all();
        prop_assert!(!(inside(f0) && inside(f90)) || inside(f), "{c} {f0:?} {f90:?} -> {f:?}");
    }

    /// In [0, 1] for any cosine and any `eta`.
    #[test]
    fn fresnel_fresnel_dielectric(c in any_f32(), eta in field()) {
        let f = fresnel_dielectric(c, eta);
        prop_assert!(unit_interval(f), "{c} {eta} -> {f}");
    }

    /// In [0, 1] for any input.
    #[test]
    fn fresnel_fresnel_complex(c in any_f32(), eta in field(), k in field()) {
        let f = fresnel_complex(c, eta, k);
        prop_assert!(unit_interval(f), "{c} {eta} {k} -> {f}");
    }

    #[test]
    fn fresnel_params_eval(p in raw_fresnel(), c in any_f32()) {
        let f = p.eval(c);
        prop_assert!(ok3(f) && f.max_element() <= 1.0, "{p:?} {c} -> {f:?}");
        if p.kind > kind::DIELECTRIC {
            prop_assert_eq!(f, Vec3::ONE);
        }
    }

    #[test]
    fn fresnel_params_to_fresnel(p in raw_fresnel(), c in any_f32()) {
        let e = p.to_fresnel();
        let f = e.eval(c);
        prop_assert!(ok3(f) && f.max_element() <= 1.0, "{p:?} {c} -> {f:?}");
        prop_assert!(same3(f, p.eval(c)), "{p:?} {c}: {f:?} vs {:?}", p.eval(c));
    }

    #[test]
    fn fresnel_params_from_fresnel(e in fresnel_enum(), c in any_f32()) {
        let p = FresnelParams::from(e);
        prop_assert!(p.kind <= kind::DIELECTRIC);
        prop_assert!(same3(p.eval(c), e.eval(c)));
    }

    #[test]
    fn fresnel_eval(e in fresnel_enum(), c in any_f32()) {
        let f = e.eval(c);
        prop_assert!(ok3(f) && f.max_element() <= 1.0, "{e:?} {c} -> {f:?}");
    }
}

// ---------------------------------------------------------------------------------------------
// GgxConductor
// ---------------------------------------------------------------------------------------------

proptest! {
    #![proptest_config(config())]

    #[test]
    fn ggx_conductor_new(x in field(), y in field(), f in fresnel_enum()) {
        let b = GgxConductor::new(x, y, f);
        prop_assert_eq!(b.distribution, TrowbridgeReitz::new(x, y));
        prop_assert_eq!(b.pad, [0, 0]);
        let expected = FresnelParams::from(f);
        prop_assert_eq!(bytemuck::bytes_of(&b.fresnel), bytemuck::bytes_of(&expected));
    }

    #[test]
    fn ggx_conductor_isotropic(x in field(), f in fresnel_enum()) {
        let b = GgxConductor::isotropic(x, f);
        prop_assert!(b.distribution.is_isotropic());
        prop_assert_eq!(b.distribution, TrowbridgeReitz::isotropic(x));
    }

    #[test]
    fn ggx_conductor_fresnel(b in raw_brdf(), c in any_f32()) {
        let f = b.fresnel().eval(c);
        prop_assert!(ok3(f) && f.max_element() <= 1.0, "{b:?} {c} -> {f:?}");
    }

    #[test]
    fn ggx_conductor_is_delta(b in raw_brdf()) {
        prop_assert_eq!(b.is_delta(), constructed_brdf(b).is_delta(), "{:?}", b);
    }

    #[test]
    fn ggx_conductor_eval(b in raw_brdf(), wo in dir(), wi in dir()) {
        let f = b.eval(wo, wi);
        prop_assert!(ok3(f), "{b:?} {wo:?} {wi:?} -> {f:?}");
        prop_assert!(same3(f, constructed_brdf(b).eval(wo, wi)), "{b:?} {wo:?} {wi:?} -> {f:?}");
    }

    #[test]
    fn ggx_conductor_pdf(b in raw_brdf(), wo in dir(), wi in dir(), s in sampling()) {
        let p = b.pdf(wo, wi, s);
        prop_assert!(ok(p), "{b:?} {wo:?} {wi:?} {s:?} -> {p}");
        prop_assert!(same(p, constructed_brdf(b).pdf(wo, wi, s)), "{b:?} {wo:?} {wi:?} {s:?} -> {p}");
    }

    /// `Some`: unit `wi` above the horizon, weight finite and `>= 0`, pdf finite and `> 0`.
    #[test]
    fn ggx_conductor_sample(b in raw_brdf(), wo in dir(), u in vec2(), s in sampling()) {
        let r = b.sample(wo, u, s);
        if let Some(bs) = r {
            prop_assert!((bs.wi.length() - 1.0).abs() < 1e-5 && bs.wi.z > 0.0, "{b:?} {s:?} wi {:?}", bs.wi);
            prop_assert!(ok3(bs.weight), "{b:?} {s:?} weight {:?}", bs.weight);
            prop_assert!(bs.pdf > 0.0 && bs.pdf.is_finite(), "{b:?} {s:?} pdf {}", bs.pdf);
        }
        let c = constructed_brdf(b).sample(wo, u, s);
        let key = |r: Option<ggx_core::BsdfSample>| {
            r.map(|b| (b.wi.to_array().map(f32::to_bits), b.weight.to_array().map(f32::to_bits), b.pdf.to_bits(), b.is_delta))
        };
        prop_assert_eq!(key(r), key(c), "{:?} {:?} {:?} {:?}", b, wo, u, s);
    }
}

// ---------------------------------------------------------------------------------------------
// GgxDielectric, refract, the Bxdf trait, BsdfSample
// ---------------------------------------------------------------------------------------------

proptest! {
    #![proptest_config(config())]

    #[test]
    fn dielectric_clamp_eta(x in field()) {
        let e = clamp_eta(x);
        prop_assert!((ETA_MIN..=ETA_MAX).contains(&e), "{x} -> {e}");
        if x > 0.0 && x.is_finite() && (ETA_MIN..=ETA_MAX).contains(&x) {
            prop_assert_eq!(e, x);
        }
    }

    /// `Some`: finite; on the other side of `n` from `w`; unit for unit inputs, within 1e-5 plus
    /// the inputs' rounding amplified by `1 / eta'^2` (the tangential part's conditioning:
    /// 9.5e-5 off at `eta' = ETA_MIN` for inputs unit to 1e-8, 4.2e-5 even in f64).
    #[test]
    fn dielectric_refract(w in dir(), n in dir(), eta in field()) {
        if let Some(t) = refract(w, n, eta) {
            prop_assert!(t.is_finite(), "{w:?} {n:?} {eta} -> {t:?}");
            let unit = |v: Vec3| (v.length() - 1.0).abs() < 1e-5;
            if unit(w) && unit(n) {
                let e = if w.dot(n) < 0.0 { 1.0 / clamp_eta(eta) } else { clamp_eta(eta) };
                let bound = 1e-5 + 2e-7 / (e * e);
                prop_assert!((t.length() - 1.0).abs() < bound && t.dot(n) * w.dot(n) <= 1e-6, "{w:?} {n:?} {eta} -> {t:?}");
            }
        }
    }

    #[test]
    fn ggx_dielectric_new(x in field(), y in field(), eta in field()) {
        let b = GgxDielectric::new(x, y, eta);
        prop_assert_eq!(b.distribution, TrowbridgeReitz::new(x, y));
        prop_assert_eq!((b.eta, b.pad), (clamp_eta(eta), 0));
    }

    #[test]
    fn ggx_dielectric_isotropic(x in field(), eta in field()) {
        let b = GgxDielectric::isotropic(x, eta);
        prop_assert_eq!(b, GgxDielectric::new(x, x, eta));
    }

    #[test]
    fn ggx_dielectric_eta(b in raw_dielectric()) {
        prop_assert!((ETA_MIN..=ETA_MAX).contains(&b.eta()));
        prop_assert!(same(b.eta(), constructed_dielectric(b).eta()));
    }

    #[test]
    fn ggx_dielectric_is_delta(b in raw_dielectric()) {
        prop_assert_eq!(b.is_delta(), constructed_dielectric(b).is_delta());
        prop_assert_eq!(Bxdf::flags(&b).is_delta(), b.is_delta());
        prop_assert!(Bxdf::flags(&b).is_transmissive());
    }

    #[test]
    fn ggx_dielectric_eval(b in raw_dielectric(), wo in dir(), wi in dir(), m in mode()) {
        let f = b.eval(wo, wi, m);
        prop_assert!(ok3(f), "{b:?} {wo:?} {wi:?} -> {f:?}");
        prop_assert!(same3(f, constructed_dielectric(b).eval(wo, wi, m)));
        prop_assert!(same3(f, Bxdf::eval(&b, wo, wi, m)));
    }

    #[test]
    fn ggx_dielectric_pdf(b in raw_dielectric(), wo in dir(), wi in dir(), s in sampling(), m in mode()) {
        let p = b.pdf(wo, wi, s, m);
        prop_assert!(ok(p), "{b:?} {wo:?} {wi:?} {s:?} -> {p}");
        prop_assert!(same(p, constructed_dielectric(b).pdf(wo, wi, s, m)));
        prop_assert!(same(p, Bxdf::pdf(&b, wo, wi, s, m)));
    }

    /// `eval_pdf` is `eval` and `pdf` bit for bit, inherent and through the trait.
    #[test]
    fn ggx_dielectric_eval_pdf(b in raw_dielectric(), wo in dir(), wi in dir(), s in sampling(), m in mode()) {
        let (f, p) = b.eval_pdf(wo, wi, s, m);
        prop_assert!(same3(f, b.eval(wo, wi, m)) && same(p, b.pdf(wo, wi, s, m)), "{b:?} {wo:?} {wi:?} {s:?}");
        let (tf, tp) = Bxdf::eval_pdf(&b, wo, wi, s, m);
        prop_assert!(same3(tf, f) && same(tp, p));
    }

    /// `Some`: unit `wi` off the horizon, weight finite and `>= 0`, pdf finite and in `(0, ...)`
    /// (`<= 1` for a delta sample).
    #[test]
    fn ggx_dielectric_sample(b in raw_dielectric(), wo in dir(), u in vec2(), ul in any_f32(), s in sampling(), m in mode()) {
        let r = b.sample(wo, u, ul, s, m);
        if let Some(bs) = r {
            prop_assert!((bs.wi.length() - 1.0).abs() < 1e-5 && bs.wi.z != 0.0, "{b:?} {s:?} wi {:?}", bs.wi);
            prop_assert!(ok3(bs.weight), "{b:?} {s:?} weight {:?}", bs.weight);
            prop_assert!(bs.pdf > 0.0 && bs.pdf.is_finite(), "{b:?} {s:?} pdf {}", bs.pdf);
            prop_assert!(!bs.is_delta || bs.pdf <= 1.0);
        }
        prop_assert_eq!(sample_key(r), sample_key(constructed_dielectric(b).sample(wo, u, ul, s, m)));
        prop_assert_eq!(sample_key(r), sample_key(Bxdf::sample(&b, wo, u, ul, s, m)));
    }

    #[test]
    fn bxdf_conductor(b in raw_brdf(), wo in dir(), wi in dir(), u in vec2(), ul in any_f32(), s in sampling(), m in mode()) {
        prop_assert!(same3(Bxdf::eval(&b, wo, wi, m), b.eval(wo, wi)));
        prop_assert!(same(Bxdf::pdf(&b, wo, wi, s, m), b.pdf(wo, wi, s)));
        // eval_pdf is eval and pdf bit for bit, inherent and through the trait.
        let (f, p) = b.eval_pdf(wo, wi, s);
        prop_assert!(same3(f, b.eval(wo, wi)) && same(p, b.pdf(wo, wi, s)), "{b:?} {wo:?} {wi:?} {s:?}");
        let (tf, tp) = Bxdf::eval_pdf(&b, wo, wi, s, m);
        prop_assert!(same3(tf, f) && same(tp, p));
        prop_assert_eq!(sample_key(Bxdf::sample(&b, wo, u, ul, s, m)), sample_key(b.sample(wo, u, s)));
        let f = Bxdf::flags(&b);
        prop_assert!(f.contains(BxdfFlags::REFLECTION) && !f.is_transmissive() && f.is_delta() == b.is_delta());
    }

    #[test]
    fn transport_mode_from_u32(v in any::<u32>()) {
        let m = TransportMode::from_u32(v);
        prop_assert_eq!(m == TransportMode::Importance, v == 1);
    }

    #[test]
    fn bxdf_flags_methods(a in flags(), b in flags()) {
        let u = a.union(b);
        prop_assert!(u.contains(a) && u.contains(b));
        prop_assert_eq!(a.is_delta(), a.0 & 8 != 0);
        prop_assert_eq!(a.is_transmissive(), a.0 & 2 != 0);
    }

    #[test]
    fn bsdf_sample_is_transmission_and_lobe(wi in dir(), wo in dir()) {
        let s = BsdfSample { wi, weight: Vec3::ONE, pdf: 1.0, is_delta: false };
        let t = s.is_transmission(wo);
        prop_assert_eq!(t, wo.z * wi.z < 0.0);
        prop_assert_eq!(s.lobe(wo), if t { BxdfFlags::TRANSMISSION } else { BxdfFlags::REFLECTION });
    }
}

// ---------------------------------------------------------------------------------------------
// Sampling, mis, frame
// ---------------------------------------------------------------------------------------------

proptest! {
    #![proptest_config(config())]

    #[test]
    fn sampling_from_u32(v in prop_oneof![0u32..8, any::<u32>()]) {
        let s = Sampling::from_u32(v);
        prop_assert!(Sampling::ALL.contains(&s));
        prop_assert!(v > 5 || s as u32 == v);
    }

    #[test]
    fn sampling_name(s in sampling()) {
        let n = s.name();
        prop_assert!(!n.is_empty() && Sampling::ALL.iter().filter(|t| t.name() == n).count() == 1);
        prop_assert!(Sampling::MICROFACET.contains(&s) == (s as u32 <= 3));
    }

    #[test]
    fn mis_balance_heuristic(nf in any_f32(), f in any_f32(), ng in any_f32(), g in any_f32()) {
        let w = balance_heuristic(nf, f, ng, g);
        prop_assert!(unit_interval(w), "{nf} {f} {ng} {g} -> {w}");
    }

    #[test]
    fn mis_power_heuristic(nf in any_f32(), f in any_f32(), ng in any_f32(), g in any_f32()) {
        let w = power_heuristic(nf, f, ng, g);
        prop_assert!(unit_interval(w), "{nf} {f} {ng} {g} -> {w}");
    }

    /// `+inf` for a delta sample (power and balance heuristics then give it weight 1), a
    /// finite non-negative density otherwise.
    #[test]
    fn bsdf_sample_mis_pdf(pdf in any_f32(), is_delta in any::<bool>(), g in any_f32()) {
        let s = BsdfSample { wi: Vec3::Z, weight: Vec3::ONE, pdf, is_delta };
        let m = s.mis_pdf();
        if is_delta {
            prop_assert!(m == f32::INFINITY);
            prop_assert!(g == f32::INFINITY || power_heuristic(1.0, m, 1.0, g) == 1.0, "{g}");
        } else {
            prop_assert!(m.is_finite() && m >= 0.0, "{pdf} -> {m}");
            prop_assert!(pdf.is_nan() || !pdf.is_finite() || pdf < 0.0 || m == pdf, "{pdf} -> {m}");
        }
    }

    /// Orthonormal and right-handed for any `n`.
    #[test]
    fn frame_from_z(n in dir()) {
        let f = Frame::from_z(n);
        for v in [f.x, f.y, f.z] {
            prop_assert!(v.is_finite() && (v.length() - 1.0).abs() < 1e-5, "{n:?} -> {f:?}");
        }
        prop_assert!(f.x.dot(f.y).abs() < 1e-5 && f.x.dot(f.z).abs() < 1e-5 && f.y.dot(f.z).abs() < 1e-5, "{n:?}");
        prop_assert!(f.x.cross(f.y).dot(f.z) > 0.999, "{n:?}");
    }

    #[test]
    fn frame_to_local(f in raw_frame(), v in dir()) {
        prop_assert!(f.to_local(v).is_finite(), "{f:?} {v:?}");
    }

    #[test]
    fn frame_to_world(f in raw_frame(), v in dir()) {
        prop_assert!(f.to_world(v).is_finite(), "{f:?} {v:?}");
    }

    #[test]
    fn frame_reflect(wo in dir(), n in dir()) {
        let r = reflect(wo, n);
        prop_assert!(r.is_finite(), "{wo:?} {n:?} -> {r:?}");
    }
}

// ---------------------------------------------------------------------------------------------
// sequence: u32 arithmetic only; floats in [0, 1) for any state
// ---------------------------------------------------------------------------------------------

proptest! {
    #![proptest_config(config())]

    /// A bijection: distinct inputs, distinct outputs.
    #[test]
    fn sequence_hash_u32(x in any::<u32>(), y in any::<u32>()) {
        prop_assert_eq!(x == y, seq::hash_u32(x) == seq::hash_u32(y));
    }

    /// A bijection of `b` for a fixed `a`.
    #[test]
    fn sequence_hash_combine(a in any::<u32>(), b in any::<u32>(), c in any::<u32>()) {
        prop_assert_eq!(b == c, hash_combine(a, b) == hash_combine(a, c));
    }

    /// In [0, 1), exactly the top 24 bits.
    #[test]
    fn sequence_u32_to_unit_f32(x in any::<u32>()) {
        let u = seq::u32_to_unit_f32(x);
        prop_assert!(unit_open(u));
        prop_assert_eq!((u * 16_777_216.0) as u32, x >> 8);
    }

    #[test]
    fn sequence_sobol(index in any::<u32>(), dim in any::<u32>()) {
        let x = seq::sobol(index, dim);
        prop_assert_eq!(x, seq::sobol(index, dim % SOBOL_DIMENSIONS));
        // XOR of direction words over the set bits of the index.
        let table = &SOBOL_DIRECTIONS[(dim % SOBOL_DIMENSIONS) as usize];
        let reference = (0..32).filter(|k| index >> k & 1 == 1).fold(0, |x, k| x ^ table[k]);
        prop_assert_eq!(x, reference);
    }

    /// A bijection that keeps prefixes: equal top bits in, equal top bits out.
    #[test]
    fn sequence_owen_scramble(x in any::<u32>(), y in any::<u32>(), seed in any::<u32>(), bits in 1u32..32) {
        let (a, b) = (seq::owen_scramble(x, seed), seq::owen_scramble(y, seed));
        prop_assert_eq!(x == y, a == b);
        prop_assert!(x >> bits != y >> bits || a >> bits == b >> bits);
    }

    /// `reverse(owen_scramble(index, group_seed))`.
    #[test]
    fn sequence_shuffle_index_reversed(index in any::<u32>(), g in any::<u32>()) {
        prop_assert_eq!(seq::shuffle_index_reversed(index, g), seq::owen_scramble(index, g).reverse_bits());
    }

    /// `owen_scramble(sobol(reverse(reversed), dim), hash_combine(group_seed, dim % 4))`.
    #[test]
    fn sequence_sobol_owen_shuffled(reversed in any::<u32>(), g in any::<u32>(), dim in any::<u32>()) {
        let expected = seq::owen_scramble(seq::sobol(reversed.reverse_bits(), dim), hash_combine(g, dim & 3));
        prop_assert_eq!(seq::sobol_owen_shuffled(reversed, g, dim), expected);
    }

    #[test]
    fn sequence_sobol_owen_u32(index in any::<u32>(), dim in any::<u32>(), seed in any::<u32>()) {
        let g = hash_combine(seed, dim >> 2);
        let expected = seq::sobol_owen_shuffled(seq::shuffle_index_reversed(index, g), g, dim);
        prop_assert_eq!(seq::sobol_owen_u32(index, dim, seed), expected);
    }

    #[test]
    fn sequence_sobol_owen(index in any::<u32>(), dim in any::<u32>(), seed in any::<u32>()) {
        let u = seq::sobol_owen(index, dim, seed);
        prop_assert!(unit_open(u));
        prop_assert_eq!(u, seq::u32_to_unit_f32(seq::sobol_owen_u32(index, dim, seed)));
    }

    #[test]
    fn counter_rng_new(seed in any::<u32>(), stream in any::<u32>()) {
        let r = CounterRng::new(seed, stream);
        prop_assert_eq!(r, CounterRng { key: hash_combine(seed, stream), counter: 0 });
    }

    #[test]
    fn counter_rng_get_u32(key in any::<u32>(), counter in any::<u32>(), n in any::<u32>()) {
        let r = CounterRng { key, counter };
        prop_assert_eq!(r.get_u32(n), hash_combine(key, n));
    }

    /// Output `counter`, counter + 1 (wrapping at `u32::MAX`).
    #[test]
    fn counter_rng_next_u32(key in any::<u32>(), counter in prop_oneof![Just(u32::MAX), any::<u32>()]) {
        let mut r = CounterRng { key, counter };
        prop_assert_eq!(r.next_u32(), hash_combine(key, counter));
        prop_assert_eq!(r.counter, counter.wrapping_add(1));
    }

    #[test]
    fn counter_rng_next_f32(key in any::<u32>(), counter in any::<u32>()) {
        let mut r = CounterRng { key, counter };
        let u = r.next_f32();
        prop_assert!(unit_open(u));
        prop_assert_eq!(u, seq::u32_to_unit_f32(hash_combine(key, counter)));
    }

    #[test]
    fn counter_rng_next_vec2(key in any::<u32>(), counter in any::<u32>()) {
        let mut r = CounterRng { key, counter };
        let v = r.next_vec2();
        prop_assert!(unit_open(v.x) && unit_open(v.y));
        prop_assert_eq!(r.counter, counter.wrapping_add(2));
    }

    #[test]
    fn counter_rng_advance(key in any::<u32>(), counter in any::<u32>(), delta in any::<u32>()) {
        let mut r = CounterRng { key, counter };
        r.advance(delta);
        prop_assert_eq!(r.counter, counter.wrapping_add(delta));
    }

    /// The `rand_core` impls: `next_u64` is two outputs (low first), `fill_bytes` their
    /// little-endian bytes for any length, `from_seed` is `new(le(seed[0..4]), le(seed[4..8]))`.
    #[test]
    fn counter_rng_rand_core(key in any::<u32>(), counter in any::<u32>(), len in 0usize..40, seed in any::<[u8; 8]>()) {
        use rand_core::{Rng, SeedableRng};
        let r = CounterRng { key, counter };
        let (lo, hi) = (r.get_u32(counter), r.get_u32(counter.wrapping_add(1)));
        prop_assert_eq!(Rng::next_u64(&mut r.clone()), u64::from(hi) << 32 | u64::from(lo));
        let mut bytes = vec![0u8; len];
        let mut f = r;
        Rng::fill_bytes(&mut f, &mut bytes);
        let expected: Vec<u8> = (0..len.div_ceil(4) as u32)
            .flat_map(|i| r.get_u32(counter.wrapping_add(i)).to_le_bytes())
            .take(len)
            .collect();
        prop_assert_eq!(bytes, expected);
        let s = CounterRng::from_seed(seed);
        let word = |k: usize| u32::from_le_bytes([seed[k], seed[k + 1], seed[k + 2], seed[k + 3]]);
        prop_assert_eq!(s, CounterRng::new(word(0), word(4)));
    }

    #[test]
    fn sequence_kind_from_u32(v in any::<u32>()) {
        let k = SequenceKind::from_u32(v);
        prop_assert_eq!(k == SequenceKind::Sobol, v == 1);
    }

    #[test]
    fn sample_stream_new(sobol in any::<bool>(), seed in any::<u32>(), pixel in any::<u32>(), sample in any::<u32>()) {
        let kind = if sobol { SequenceKind::Sobol } else { SequenceKind::Independent };
        let s = SampleStream::new(kind, seed, pixel, sample);
        prop_assert_eq!(s, SampleStream { kind: kind as u32, seed: hash_combine(seed, pixel), sample_index: sample, dimension: 0 });
        prop_assert_eq!(s.sequence_kind(), kind);
    }

    #[test]
    fn sample_stream_sequence_kind(s in any::<[u32; 4]>()) {
        let s = bytemuck::cast::<[u32; 4], SampleStream>(s);
        prop_assert_eq!(s.sequence_kind(), SequenceKind::from_u32(s.kind));
    }

    #[test]
    fn sample_stream_get_u32(s in any::<[u32; 4]>(), dim in any::<u32>()) {
        let s = bytemuck::cast::<[u32; 4], SampleStream>(s);
        let x = s.get_u32(dim);
        if s.kind == 1 {
            prop_assert_eq!(x, seq::sobol_owen_u32(s.sample_index, dim, s.seed));
        } else {
            prop_assert_eq!(x, hash_combine(hash_combine(s.seed, s.sample_index), dim));
        }
    }

    #[test]
    fn sample_stream_next_1d(s in any::<[u32; 4]>(), near_max in any::<bool>()) {
        let mut s = bytemuck::cast::<[u32; 4], SampleStream>(s);
        if near_max {
            s.dimension |= 0xffff_fffe;
        }
        let d = s.dimension;
        let u = s.next_1d();
        prop_assert!(unit_open(u));
        prop_assert_eq!(u, seq::u32_to_unit_f32(SampleStream { dimension: 0, ..s }.get_u32(d)));
        prop_assert_eq!(s.dimension, d.wrapping_add(1));
    }

    /// Dimensions `d, d + 1` with `d = 4 ceil(dimension / 4)` (wrapping), in [0, 1).
    #[test]
    fn sample_stream_next_2d(s in any::<[u32; 4]>(), near_max in any::<bool>()) {
        let mut s = bytemuck::cast::<[u32; 4], SampleStream>(s);
        if near_max {
            s.dimension |= 0xffff_fffc;
        }
        let d = s.dimension.wrapping_add(3) & !3;
        let p = s.next_2d();
        prop_assert!(unit_open(p.x) && unit_open(p.y));
        prop_assert_eq!(p.x, seq::u32_to_unit_f32(s.get_u32(d)));
        prop_assert_eq!(p.y, seq::u32_to_unit_f32(s.get_u32(d.wrapping_add(1))));
        prop_assert_eq!(s.dimension, d.wrapping_add(2));
    }
}

// ---------------------------------------------------------------------------------------------
// batch
// ---------------------------------------------------------------------------------------------

/// Up to 8 lanes of raw floats per slice, slices of unequal lengths.
fn lanes() -> impl Strategy<Value = Vec<f32>> {
    prop::collection::vec(any_f32(), 0..8)
}

/// Lanes of directions: raw or unit.
fn dir_lanes() -> impl Strategy<Value = Vec<Vec3>> {
    prop::collection::vec(dir(), 0..8)
}

fn split(v: &[Vec3], drop: usize) -> [Vec<f32>; 3] {
    let n = v.len();
    [
        v.iter().map(|w| w.x).collect(),
        v.iter().map(|w| w.y).take(n.saturating_sub(drop)).collect(),
        v.iter().map(|w| w.z).collect(),
    ]
}

proptest! {
    #![proptest_config(config())]

    /// Returns the number of valid lanes among `min` of the lengths; valid lanes have a finite
    /// `wi` above the horizon (unit for a unit `wo`) and a finite positive pdf, the others zero;
    /// as `constructed`; Heitz's sampler or the spherical caps.
    #[test]
    fn batch_sample_vndf(t in raw_dist(), wo in dir_lanes(), u0 in lanes(), u1 in lanes(), drop in 0usize..2, extra in 0usize..3, heitz in any::<bool>()) {
        let sampling = if heitz { Sampling::Vndf } else { Sampling::SphericalCaps };
        let [ox, oy, oz] = split(&wo, drop);
        let run = |t: &TrowbridgeReitz| {
            let n_out = wo.len() + extra;
            let (mut x, mut y, mut z, mut p) = (vec![9.0; n_out], vec![9.0; n_out], vec![9.0; n_out], vec![9.0; n_out]);
            let valid = batch::sample_vndf(
                t,
                Vec3Slices { x: &ox, y: &oy, z: &oz },
                &u0,
                &u1,
                sampling,
                Vec3SlicesMut { x: &mut x, y: &mut y, z: &mut z },
                &mut p,
            );
            (valid, x, y, z, p)
        };
        let (valid, x, y, z, p) = run(&t);
        let n = [ox.len(), oy.len(), oz.len(), u0.len(), u1.len()].into_iter().min().unwrap();
        prop_assert_eq!(valid, (0..n).filter(|&i| p[i] > 0.0).count());
        for i in 0..n {
            let w = Vec3::new(x[i], y[i], z[i]);
            prop_assert!(ok(p[i]), "{t:?} lane {i} pdf {}", p[i]);
            // wi is the reflection of wo: unit for a unit wo.
            let unit_wo = (wo[i].length() - 1.0).abs() < 1e-6;
            prop_assert!(
                if p[i] > 0.0 { w.is_finite() && w.z > 0.0 && (!unit_wo || (w.length() - 1.0).abs() < 1e-4) } else { w == Vec3::ZERO },
                "{t:?} lane {i} wo {:?} wi {w:?} pdf {}", wo[i], p[i]
            );
        }
        // Lanes past n are untouched.
        prop_assert!(p[n..].iter().all(|&v| v == 9.0));
        let c = run(&constructed(t));
        let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        prop_assert!(valid == c.0 && bits(&x) == bits(&c.1) && bits(&y) == bits(&c.2) && bits(&z) == bits(&c.3) && bits(&p) == bits(&c.4), "{t:?}");
    }

    /// Finite, non-negative RGB for `min` of the lengths, lane by lane the scalar `eval`; as
    /// `constructed`.
    #[test]
    fn batch_eval(b in raw_brdf(), wo in dir_lanes(), wi in dir_lanes(), drop in 0usize..2) {
        let [ox, oy, oz] = split(&wo, drop);
        let [ix, iy, iz] = split(&wi, 0);
        let run = |b: &GgxConductor| {
            let n_out = wo.len().max(wi.len());
            let (mut r, mut g, mut bl) = (vec![9.0; n_out], vec![9.0; n_out], vec![9.0; n_out]);
            batch::eval(
                b,
                Vec3Slices { x: &ox, y: &oy, z: &oz },
                Vec3Slices { x: &ix, y: &iy, z: &iz },
                Vec3SlicesMut { x: &mut r, y: &mut g, z: &mut bl },
            );
            (r, g, bl)
        };
        let (r, g, bl) = run(&b);
        let n = [ox.len(), oy.len(), oz.len(), ix.len(), iy.len(), iz.len()].into_iter().min().unwrap();
        for i in 0..n {
            let v = Vec3::new(r[i], g[i], bl[i]);
            prop_assert!(ok3(v), "{b:?} lane {i}: {v:?}");
            // Lane by lane the scalar eval, bit for bit.
            let want = b.eval(Vec3::new(ox[i], oy[i], oz[i]), wi[i]);
            prop_assert!(same3(v, want), "{b:?} lane {i}: {v:?} vs {want:?}");
        }
        let c = run(&constructed_brdf(b));
        let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        prop_assert!(bits(&r) == bits(&c.0) && bits(&g) == bits(&c.1) && bits(&bl) == bits(&c.2), "{b:?}");
    }
}

proptest! {
    #![proptest_config(config())]

    /// Lane by lane `GgxConductor::sample(.., sampling)`'s `wi`, weight and pdf (zeros where it
    /// returns `None` or a delta sample) for `min` of the lengths, all finite, Heitz's sampler
    /// or the spherical caps; the count of valid lanes; later lanes untouched, whichever slice
    /// is the shortest.
    #[test]
    fn batch_sample(b in raw_brdf(), wo in dir_lanes(), u0 in lanes(), u1 in lanes(), drop in 0usize..2, extra in 0usize..3, short in 0usize..3, heitz in any::<bool>()) {
        let sampling = if heitz { Sampling::Vndf } else { Sampling::SphericalCaps };
        let [ox, oy, oz] = split(&wo, drop);
        let n_out = wo.len() + extra;
        let mut out = [(); 7].map(|_| vec![9.0f32; n_out]);
        // One output may be the shortest slice: a weight channel.
        out[5].truncate(wo.len().saturating_sub(short));
        let [x, y, z, wx, wy, wz, p] = &mut out;
        let valid = batch::sample(
            &b,
            Vec3Slices { x: &ox, y: &oy, z: &oz },
            &u0,
            &u1,
            sampling,
            Vec3SlicesMut { x, y, z },
            Vec3SlicesMut { x: wx, y: wy, z: wz },
            p,
        );
        let n = [ox.len(), oy.len(), oz.len(), u0.len(), u1.len(), wz.len()].into_iter().min().unwrap();
        let mut scalar_valid = 0;
        for i in 0..n {
            let s = b.sample(Vec3::new(ox[i], oy[i], oz[i]), Vec2::new(u0[i], u1[i]), sampling).filter(|s| !s.is_delta);
            scalar_valid += s.is_some() as usize;
            let (wi, w, pdf) = s.map_or((Vec3::ZERO, Vec3::ZERO, 0.0), |s| (s.wi, s.weight, s.pdf));
            let (got_wi, got_w) = (Vec3::new(x[i], y[i], z[i]), Vec3::new(wx[i], wy[i], wz[i]));
            prop_assert!(same3(got_wi, wi) && same3(got_w, w) && same(p[i], pdf), "{b:?} {sampling:?} lane {i}: {got_wi:?} {got_w:?} {} vs {wi:?} {w:?} {pdf}", p[i]);
            prop_assert!(got_wi.is_finite() && ok3(got_w) && ok(p[i]), "{b:?} lane {i}");
        }
        prop_assert_eq!(valid, scalar_valid);
        prop_assert!(out.iter().all(|v| v[n..].iter().all(|&x| x == 9.0)), "{b:?}: lanes past {n} written");
    }

    /// Lane by lane `GgxConductor::pdf(.., Vndf)` for `min` of the lengths, finite and >= 0.
    #[test]
    fn batch_pdf(b in raw_brdf(), wo in dir_lanes(), wi in dir_lanes(), drop in 0usize..2, short in 0usize..3) {
        let [ox, oy, oz] = split(&wo, drop);
        let [ix, iy, iz] = split(&wi, 0);
        let mut p = vec![9.0; wo.len().max(wi.len()).saturating_sub(short)];
        batch::pdf(&b, Vec3Slices { x: &ox, y: &oy, z: &oz }, Vec3Slices { x: &ix, y: &iy, z: &iz }, &mut p);
        let n = [ox.len(), oy.len(), oz.len(), ix.len(), iy.len(), iz.len(), p.len()].into_iter().min().unwrap();
        for i in 0..n {
            let want = b.pdf(Vec3::new(ox[i], oy[i], oz[i]), wi[i], Sampling::Vndf);
            prop_assert!(same(p[i], want) && ok(p[i]), "{b:?} lane {i}: {} vs {want}", p[i]);
        }
        prop_assert!(p[n..].iter().all(|&x| x == 9.0));
    }

    /// Lane by lane `TrowbridgeReitz::d` for `min` of the lengths, finite and >= 0.
    #[test]
    fn batch_d(t in raw_dist(), wm in dir_lanes(), drop in 0usize..2, short in 0usize..3) {
        let [x, y, z] = split(&wm, drop);
        let mut out = vec![9.0; wm.len().saturating_sub(short)];
        batch::d(&t, Vec3Slices { x: &x, y: &y, z: &z }, &mut out);
        let n = [x.len(), y.len(), z.len(), out.len()].into_iter().min().unwrap();
        for i in 0..n {
            let want = t.d(wm[i]);
            prop_assert!(same(out[i], want) && ok(out[i]), "{t:?} lane {i}: {} vs {want}", out[i]);
        }
        prop_assert!(out[n..].iter().all(|&v| v == 9.0));
    }
}

// ---------------------------------------------------------------------------------------------
// energy, Fresnel averages, GgxConductorMs
// ---------------------------------------------------------------------------------------------

proptest! {
    #![proptest_config(config())]

    /// In `[0, 1]`; `mu` and `alpha` are clamped to `[0, 1]` with NaN -> 0 (same bits).
    #[test]
    fn energy_albedo(mu in any_f32(), a in field()) {
        let e = albedo(mu, a);
        prop_assert!(unit_interval(e), "{mu} {a} -> {e}");
        prop_assert!(same(e, albedo(clamp01(mu), clamp01(a))), "{mu} {a} -> {e}");
    }

    /// In `[0, 1]`; `alpha` clamped to `[0, 1]` with NaN -> 0 (same bits).
    #[test]
    fn energy_average_albedo(a in field()) {
        let e = average_albedo(a);
        prop_assert!(unit_interval(e), "{a} -> {e}");
        prop_assert!(same(e, average_albedo(clamp01(a))), "{a} -> {e}");
    }

    /// At most 1 and finite (below 0 under `DELTA_ALPHA`); NaN -> 0 as the clamp; the inverse of
    /// `row_alpha` on `[DELTA_ALPHA, 1]`.
    #[test]
    fn energy_alpha_coordinate(a in field()) {
        let t = alpha_coordinate(a);
        prop_assert!(t.is_finite() && t <= 1.0 && t >= alpha_coordinate(0.0), "{a} -> {t}");
        prop_assert!(same(t, alpha_coordinate(clamp01(a))));
        prop_assert_eq!(t >= 0.0, clamp01(a) >= DELTA_ALPHA * (1.0 - 1e-6), "{} -> {}", a, t);
        if (DELTA_ALPHA..=1.0).contains(&a) {
            let back = row_alpha(t);
            prop_assert!((back - a).abs() <= 2e-5 * a, "{a} -> {t} -> {back}");
        }
    }

    /// In `[DELTA_ALPHA, 1]` (never a mirror), 1 at `t = 1`; `t` clamped, NaN -> 0.
    #[test]
    fn energy_row_alpha(t in any_f32()) {
        let a = row_alpha(t);
        prop_assert!((DELTA_ALPHA..=1.0).contains(&a), "{t} -> {a}");
        prop_assert!(same(a, row_alpha(clamp01(t))));
        prop_assert!(!GgxConductor::isotropic(a, Fresnel::One).is_delta());
        prop_assert_eq!(row_alpha(1.0), 1.0);
    }

    /// In `[0, 1]`, `mu^(1/4)`; `mu` clamped, NaN -> 0; the inverse of `column_mu`.
    #[test]
    fn energy_mu_coordinate(mu in any_f32()) {
        let t = mu_coordinate(mu);
        prop_assert!(unit_interval(t), "{mu} -> {t}");
        prop_assert!(same(t, mu_coordinate(clamp01(mu))));
        let back = column_mu(t);
        prop_assert!((back - clamp01(mu)).abs() <= 1e-6 * clamp01(mu).max(1e-30), "{mu} -> {t} -> {back}");
    }

    /// In `[0, 1]`, `t^4`; `t` clamped, NaN -> 0.
    #[test]
    fn energy_column_mu(t in any_f32()) {
        let mu = column_mu(t);
        prop_assert!(unit_interval(mu), "{t} -> {mu}");
        prop_assert!(same(mu, column_mu(clamp01(t))));
    }

    /// In `[ALPHA_MIN, 1]`, between the clamped alphas, the alpha itself when isotropic, and
    /// the same bits as for the constructed distribution.
    #[test]
    fn energy_effective_alpha(t in raw_dist()) {
        let e = effective_alpha(&t);
        let (ax, ay) = t.alphas();
        prop_assert!((ALPHA_MIN..=ALPHA_MAX).contains(&e), "{t:?} -> {e}");
        prop_assert!(e >= ax.min(ay) * (1.0 - 1e-6) && e <= ax.max(ay) * (1.0 + 1e-6), "{t:?} -> {e}");
        if ax == ay {
            prop_assert!((e - ax).abs() <= 1e-6 * ax, "{t:?} -> {e}");
        }
        prop_assert!(same(e, effective_alpha(&constructed(t))), "{t:?} -> {e}");
    }

    /// In `[0, 1]` per channel, at most the (clamped) `F_avg` (`F_ms <= F_avg` for `F_avg <= 1`),
    /// never NaN, including `F_avg = 1, E_avg = 0` (0 / 0); inputs clamped with NaN -> 0.
    #[test]
    fn energy_multiple_scattering_fresnel(r in any_f32(), g in any_f32(), b in any_f32(), e in field()) {
        let f = Vec3::new(r, g, b);
        let m = multiple_scattering_fresnel(f, e);
        prop_assert!(ok3(m) && m.max_element() <= 1.0, "{f:?} {e} -> {m:?}");
        let fc = Vec3::new(clamp01(r), clamp01(g), clamp01(b));
        prop_assert!(m.cmple(fc + 1e-6).all(), "{f:?} {e} -> {m:?}");
        prop_assert!(same3(m, multiple_scattering_fresnel(fc, clamp01(e))), "{f:?} {e} -> {m:?}");
    }

    /// In `[0, 1]` per channel for any kind and raw parameters; the enum agrees bit for bit.
    #[test]
    fn fresnel_params_average(p in raw_fresnel()) {
        let a = p.average();
        prop_assert!(ok3(a) && a.max_element() <= 1.0, "{p:?} -> {a:?}");
        prop_assert!(same3(a, p.to_fresnel().average()), "{p:?} -> {a:?}");
    }

    #[test]
    fn fresnel_average(e in fresnel_enum()) {
        let a = e.average();
        prop_assert!(ok3(a) && a.max_element() <= 1.0, "{e:?} -> {a:?}");
        prop_assert!(same3(a, FresnelParams::from(e).average()), "{e:?} -> {a:?}");
        if e == Fresnel::One {
            prop_assert!((a - Vec3::ONE).abs().max_element() < 1e-6, "{a:?}");
        }
    }

    #[test]
    fn ggx_conductor_ms_new(b in raw_brdf()) {
        let m = GgxConductorMs::new(b);
        prop_assert_eq!(bytemuck::bytes_of(&m.conductor), bytemuck::bytes_of(&b));
        prop_assert!(same3(Vec3::from_array(m.f_avg), b.fresnel.average()));
        prop_assert_eq!(m.compensation, 1);
    }

    #[test]
    fn ggx_conductor_ms_is_compensated(m in raw_ms()) {
        prop_assert_eq!(m.is_compensated(), m.compensation != 0 && !m.conductor.is_delta(), "{:?}", m);
        prop_assert_eq!(m.is_compensated(), constructed_ms(m).is_compensated());
    }

    /// In `[0, 1]` per channel whatever the raw `f_avg`.
    #[test]
    fn ggx_conductor_ms_ms_fresnel(m in raw_ms()) {
        let f = m.ms_fresnel();
        prop_assert!(ok3(f) && f.max_element() <= 1.0, "{m:?} -> {f:?}");
        prop_assert!(same3(f, constructed_ms(m).ms_fresnel()));
    }

    /// Finite, `>= 0`, zero when off, below the horizon or for a mirror; as `constructed`.
    #[test]
    fn ggx_conductor_ms_eval_ms(m in raw_ms(), wo in dir(), wi in dir()) {
        let f = m.eval_ms(wo, wi);
        prop_assert!(ok3(f), "{m:?} {wo:?} {wi:?} -> {f:?}");
        if !(m.is_compensated() && wo.z > 0.0 && wi.z > 0.0) {
            prop_assert_eq!(f, Vec3::ZERO);
        }
        prop_assert!(same3(f, constructed_ms(m).eval_ms(wo, wi)), "{m:?} {wo:?} {wi:?} -> {f:?}");
    }

    /// Finite, `>= 0`, `eval_ss + eval_ms` exactly; as `constructed`.
    #[test]
    fn ggx_conductor_ms_eval(m in raw_ms(), wo in dir(), wi in dir()) {
        let f = m.eval(wo, wi);
        prop_assert!(ok3(f), "{m:?} {wo:?} {wi:?} -> {f:?}");
        prop_assert!(same3(f, m.conductor.eval(wo, wi) + m.eval_ms(wo, wi)));
        prop_assert!(same3(f, constructed_ms(m).eval(wo, wi)), "{m:?} {wo:?} {wi:?} -> {f:?}");
    }

    /// In `[0, 0.999]`, 0 when off or `wo.z <= 0`; as `constructed`.
    #[test]
    fn ggx_conductor_ms_ms_probability(m in raw_ms(), wo in dir()) {
        let p = m.ms_probability(wo);
        prop_assert!((0.0..=0.999).contains(&p), "{m:?} {wo:?} -> {p}");
        if !(m.is_compensated() && wo.z > 0.0) {
            prop_assert_eq!(p, 0.0);
        }
        prop_assert!(same(p, constructed_ms(m).ms_probability(wo)));
    }

    /// Finite, `>= 0`; the conductor's pdf when off; as `constructed`.
    #[test]
    fn ggx_conductor_ms_pdf(m in raw_ms(), wo in dir(), wi in dir(), s in sampling()) {
        let p = m.pdf(wo, wi, s);
        prop_assert!(ok(p), "{m:?} {wo:?} {wi:?} {s:?} -> {p}");
        if !m.is_compensated() {
            prop_assert!(same(p, m.conductor.pdf(wo, wi, s)));
        }
        prop_assert!(same(p, constructed_ms(m).pdf(wo, wi, s)), "{m:?} {wo:?} {wi:?} {s:?} -> {p}");
    }

    /// `Some`: unit `wi` above the horizon, finite weight `>= 0`, pdf finite `> 0` and equal to
    /// `pdf()`, `weight == eval / pdf`; exactly the conductor's sample when off; as `constructed`.
    #[test]
    fn ggx_conductor_ms_sample(m in raw_ms(), wo in dir(), u in vec2(), ul in any_f32(), s in sampling()) {
        let r = m.sample(wo, u, ul, s);
        if let Some(bs) = r {
            prop_assert!((bs.wi.length() - 1.0).abs() < 1e-5 && bs.wi.z > 0.0, "{m:?} {s:?} wi {:?}", bs.wi);
            prop_assert!(ok3(bs.weight), "{m:?} {s:?} weight {:?}", bs.weight);
            prop_assert!(bs.pdf > 0.0 && bs.pdf.is_finite(), "{m:?} {s:?} pdf {}", bs.pdf);
            if m.is_compensated() {
                prop_assert!(!bs.is_delta);
                prop_assert!(same(bs.pdf, m.pdf(wo, bs.wi, s)), "{m:?} {s:?}: {} vs {}", bs.pdf, m.pdf(wo, bs.wi, s));
                prop_assert!(same3(bs.weight, m.eval(wo, bs.wi) / bs.pdf), "{m:?} {s:?}: {:?}", bs.weight);
            }
        }
        if !m.is_compensated() {
            prop_assert_eq!(sample_key(r), sample_key(m.conductor.sample(wo, u, s)));
        }
        prop_assert_eq!(sample_key(r), sample_key(constructed_ms(m).sample(wo, u, ul, s)));
    }

    /// The `Bxdf` impl forwards to the inherent methods (bit for bit, `mode` ignored) and has
    /// the conductor's flags.
    #[test]
    fn bxdf_conductor_ms(m in raw_ms(), wo in dir(), wi in dir(), u in vec2(), ul in any_f32(), s in sampling(), md in mode()) {
        prop_assert!(same3(Bxdf::eval(&m, wo, wi, md), m.eval(wo, wi)));
        prop_assert!(same(Bxdf::pdf(&m, wo, wi, s, md), m.pdf(wo, wi, s)));
        let (f, p) = m.eval_pdf(wo, wi, s);
        prop_assert!(same3(f, m.eval(wo, wi)) && same(p, m.pdf(wo, wi, s)), "{m:?} {wo:?} {wi:?} {s:?}");
        let (tf, tp) = Bxdf::eval_pdf(&m, wo, wi, s, md);
        prop_assert!(same3(tf, f) && same(tp, p));
        prop_assert_eq!(sample_key(Bxdf::sample(&m, wo, u, ul, s, md)), sample_key(m.sample(wo, u, ul, s)));
        prop_assert_eq!(Bxdf::flags(&m), Bxdf::flags(&m.conductor));
    }
}

// ---------------------------------------------------------------------------------------------
// energy_dielectric, GgxDielectricMs
// ---------------------------------------------------------------------------------------------

/// `eta` clamped to `[1, ETA_TABLE_MAX]`, NaN -> 1 (the clamp of the slice coordinate).
fn clamp_slice_eta(eta: f32) -> f32 {
    eta.max(1.0).min(ETA_TABLE_MAX)
}

/// Every accessor hands out its whole table: `dims` multiply to the length, outermost first
/// with the shared `[N_ETA, N_ALPHA]`, and every value is an albedo in `[0, 1]`.
#[test]
fn energy_dielectric_tables_accessors() {
    let tables = [
        dielectric_albedo_outside_table(),
        dielectric_albedo_inside_table(),
        coat_albedo_table(),
        coat_average_albedo_table(),
    ];
    for (values, dims) in tables {
        assert_eq!(values.len(), dims.iter().product::<usize>());
        assert_eq!(dims[..2], tables[0].1[..2]);
        assert!(values.iter().all(|v| unit_interval(*v)));
    }
    assert_eq!(coat_average_albedo_table().1[2], 1);
}

proptest! {
    #![proptest_config(config())]

    /// In `[0, 1]`; `eta` clamped to `[1, ETA_TABLE_MAX]` with NaN -> 1 (same bits); the inverse
    /// of `slice_eta` there.
    #[test]
    fn energy_dielectric_eta_coordinate(eta in prop_oneof![3 => field(), 1 => 1.0f32..3.5]) {
        let t = eta_coordinate(eta);
        prop_assert!(unit_interval(t), "{eta} -> {t}");
        prop_assert!(same(t, eta_coordinate(clamp_slice_eta(eta))), "{eta} -> {t}");
        if (1.0..=ETA_TABLE_MAX).contains(&eta) {
            let back = slice_eta(t);
            prop_assert!((back - eta).abs() <= 2e-6 * eta, "{eta} -> {t} -> {back}");
        }
    }

    /// In `[1, ETA_TABLE_MAX]`, exactly 1 and `ETA_TABLE_MAX` at the ends; `t` clamped, NaN -> 0.
    #[test]
    fn energy_dielectric_slice_eta(t in any_f32()) {
        let eta = slice_eta(t);
        prop_assert!((1.0..=ETA_TABLE_MAX).contains(&eta), "{t} -> {eta}");
        prop_assert!(same(eta, slice_eta(clamp01(t))));
        prop_assert!(slice_eta(0.0) == 1.0 && slice_eta(1.0) == ETA_TABLE_MAX);
    }

    /// In `[DIELECTRIC_ALBEDO_MIN, 1]`; `mu`, `alpha` clamped to `[0, 1]` (NaN -> 0) and `eta'`
    /// through `clamp_eta` (same bits).
    #[test]
    fn energy_dielectric_dielectric_albedo(mu in any_f32(), a in field(), etap in prop_oneof![3 => field(), 1 => 0.2f32..4.0]) {
        let e = dielectric_albedo(mu, a, etap);
        prop_assert!((DIELECTRIC_ALBEDO_MIN..=1.0).contains(&e), "{mu} {a} {etap} -> {e}");
        prop_assert!(same(e, dielectric_albedo(clamp01(mu), clamp01(a), clamp_eta(etap))), "{mu} {a} {etap} -> {e}");
    }

    /// In `[0, 1]`; `mu`, `alpha` clamped to `[0, 1]`, `eta` to `[1, ETA_TABLE_MAX]` (NaN -> 0, 0, 1;
    /// same bits).
    #[test]
    fn energy_dielectric_coat_albedo(mu in any_f32(), a in field(), eta in prop_oneof![3 => field(), 1 => 1.0f32..4.0]) {
        let e = coat_albedo(mu, a, eta);
        prop_assert!(unit_interval(e), "{mu} {a} {eta} -> {e}");
        prop_assert!(same(e, coat_albedo(clamp01(mu), clamp01(a), clamp_slice_eta(eta))), "{mu} {a} {eta} -> {e}");
    }

    /// In `[0, 1]`; clamped as `coat_albedo` (same bits).
    #[test]
    fn energy_dielectric_coat_average_albedo(a in field(), eta in prop_oneof![3 => field(), 1 => 1.0f32..4.0]) {
        let e = coat_average_albedo(a, eta);
        prop_assert!(unit_interval(e), "{a} {eta} -> {e}");
        prop_assert!(same(e, coat_average_albedo(clamp01(a), clamp_slice_eta(eta))), "{a} {eta} -> {e}");
    }

    /// Finite, `>= 0`, symmetric in `mu_o` and `mu_i` (bit for bit); clamped as `coat_albedo`.
    #[test]
    fn energy_dielectric_plastic_base_weight(mo in any_f32(), mi in any_f32(), a in field(), eta in prop_oneof![3 => field(), 1 => 1.0f32..4.0]) {
        let w = plastic_base_weight(mo, mi, a, eta);
        prop_assert!(ok(w), "{mo} {mi} {a} {eta} -> {w}");
        prop_assert!(same(w, plastic_base_weight(mi, mo, a, eta)));
        prop_assert!(same(w, plastic_base_weight(clamp01(mo), clamp01(mi), clamp01(a), clamp_slice_eta(eta))));
    }

    #[test]
    fn ggx_dielectric_ms_new(b in raw_dielectric()) {
        let m = GgxDielectricMs::new(b);
        prop_assert_eq!(bytemuck::bytes_of(&m.dielectric), bytemuck::bytes_of(&b));
        prop_assert_eq!((m.compensation, m.pad), (1, [0; 3]));
    }

    #[test]
    fn ggx_dielectric_ms_is_compensated(m in raw_dielectric_ms()) {
        prop_assert_eq!(m.is_compensated(), m.compensation != 0 && !m.dielectric.is_delta(), "{:?}", m);
        prop_assert_eq!(m.is_compensated(), constructed_dielectric_ms(m).is_compensated());
    }

    /// In `[1, 1 / DIELECTRIC_ALBEDO_MIN]`, exactly 1 when off; as `constructed`.
    #[test]
    fn ggx_dielectric_ms_compensation_scale(m in raw_dielectric_ms(), wo in dir()) {
        let k = m.compensation_scale(wo);
        prop_assert!((1.0..=1.0 / DIELECTRIC_ALBEDO_MIN).contains(&k), "{m:?} {wo:?} -> {k}");
        if !m.is_compensated() {
            prop_assert_eq!(k, 1.0);
        }
        prop_assert!(same(k, constructed_dielectric_ms(m).compensation_scale(wo)), "{m:?} {wo:?} -> {k}");
    }

    /// Finite, `>= 0`: the dielectric's `eval` times the scale (bit for bit; exactly the
    /// dielectric's when off); as `constructed`.
    #[test]
    fn ggx_dielectric_ms_eval(m in raw_dielectric_ms(), wo in dir(), wi in dir(), md in mode()) {
        let f = m.eval(wo, wi, md);
        prop_assert!(ok3(f), "{m:?} {wo:?} {wi:?} -> {f:?}");
        let ss = m.dielectric.eval(wo, wi, md);
        prop_assert!(same3(f, if m.is_compensated() { ss * m.compensation_scale(wo) } else { ss }), "{m:?} -> {f:?}");
        prop_assert!(same3(f, constructed_dielectric_ms(m).eval(wo, wi, md)), "{m:?} {wo:?} {wi:?} -> {f:?}");
    }

    /// Exactly the dielectric's pdf; as `constructed`.
    #[test]
    fn ggx_dielectric_ms_pdf(m in raw_dielectric_ms(), wo in dir(), wi in dir(), s in sampling(), md in mode()) {
        let p = m.pdf(wo, wi, s, md);
        prop_assert!(ok(p), "{m:?} {wo:?} {wi:?} {s:?} -> {p}");
        prop_assert!(same(p, m.dielectric.pdf(wo, wi, s, md)));
        prop_assert!(same(p, constructed_dielectric_ms(m).pdf(wo, wi, s, md)));
    }

    /// The dielectric's sample (same `wi`, `pdf`, `is_delta`, `None`s) with a rough sample's
    /// weight times the scale when compensated; `Some`: unit `wi` off the horizon, finite weight
    /// `>= 0`, pdf finite `> 0`; exactly the dielectric's when off; as `constructed`.
    #[test]
    fn ggx_dielectric_ms_sample(m in raw_dielectric_ms(), wo in dir(), u in vec2(), ul in any_f32(), s in sampling(), md in mode()) {
        let r = m.sample(wo, u, ul, s, md);
        let ss = m.dielectric.sample(wo, u, ul, s, md);
        if let Some(bs) = r {
            prop_assert!((bs.wi.length() - 1.0).abs() < 1e-5 && bs.wi.z != 0.0, "{m:?} {s:?} wi {:?}", bs.wi);
            prop_assert!(ok3(bs.weight), "{m:?} {s:?} weight {:?}", bs.weight);
            prop_assert!(bs.pdf > 0.0 && bs.pdf.is_finite(), "{m:?} {s:?} pdf {}", bs.pdf);
        }
        if m.is_compensated() {
            let scaled = ss.map(|b| if b.is_delta { b } else { BsdfSample { weight: b.weight * m.compensation_scale(wo), ..b } });
            prop_assert_eq!(sample_key(r), sample_key(scaled));
        } else {
            prop_assert_eq!(sample_key(r), sample_key(ss));
        }
        prop_assert_eq!(sample_key(r), sample_key(constructed_dielectric_ms(m).sample(wo, u, ul, s, md)));
    }

    /// The `Bxdf` impl forwards to the inherent methods (bit for bit) and has the dielectric's
    /// flags.
    #[test]
    fn bxdf_dielectric_ms(m in raw_dielectric_ms(), wo in dir(), wi in dir(), u in vec2(), ul in any_f32(), s in sampling(), md in mode()) {
        prop_assert!(same3(Bxdf::eval(&m, wo, wi, md), m.eval(wo, wi, md)));
        prop_assert!(same(Bxdf::pdf(&m, wo, wi, s, md), m.pdf(wo, wi, s, md)));
        let (f, p) = m.eval_pdf(wo, wi, s, md);
        prop_assert!(same3(f, m.eval(wo, wi, md)) && same(p, m.pdf(wo, wi, s, md)), "{m:?} {wo:?} {wi:?} {s:?}");
        let (tf, tp) = Bxdf::eval_pdf(&m, wo, wi, s, md);
        prop_assert!(same3(tf, f) && same(tp, p));
        prop_assert_eq!(sample_key(Bxdf::sample(&m, wo, u, ul, s, md)), sample_key(m.sample(wo, u, ul, s, md)));
        prop_assert_eq!(Bxdf::flags(&m), Bxdf::flags(&m.dielectric));
    }
}

// ThinDielectric

proptest! {
    #![proptest_config(config())]

    /// `new` stores `clamp_eta(eta)`; `reflectance` is in `[0, 1]` for any cosine and any
    /// stored bits, even in the cosine's sign, 1 at grazing incidence.
    #[test]
    fn thin_dielectric_reflectance(eta in any_f32(), bits in any::<u32>(), c in any_f32()) {
        let sheet = ThinDielectric::new(eta);
        prop_assert!(same(sheet.eta, ggx_core::clamp_eta(eta)));
        for t in [sheet, ThinDielectric { eta: f32::from_bits(bits), pad: bits }] {
            let r = t.reflectance(c);
            prop_assert!((0.0..=1.0).contains(&r), "{t:?} cos {c}: {r}");
            prop_assert!(same(r, t.reflectance(-c)));
            prop_assert_eq!(t.reflectance(0.0), 1.0);
        }
    }

    /// `sample`: `None` or the mirror / `-wo` (unit, off the horizon) with weight 1, the lobe's
    /// probability as pdf in `(0, 1]`, delta; `Bxdf` forwards and has both delta lobes.
    #[test]
    fn thin_dielectric_sample(eta in any_f32(), bits in any::<u32>(), wo in dir(), u in vec2(), ul in any_f32(), s in sampling(), md in mode()) {
        for t in [ThinDielectric::new(eta), ThinDielectric { eta: f32::from_bits(bits), pad: 0 }] {
            let r = t.sample(wo, ul);
            if let Some(bs) = r {
                prop_assert!((bs.wi.length() - 1.0).abs() < 1e-5 && bs.wi.z != 0.0, "{t:?} wi {:?}", bs.wi);
                prop_assert!(bs.is_delta && bs.weight == Vec3::ONE, "{t:?} {bs:?}");
                prop_assert!(bs.pdf > 0.0 && bs.pdf <= 1.0, "{t:?} pdf {}", bs.pdf);
            }
            prop_assert_eq!(sample_key(Bxdf::sample(&t, wo, u, ul, s, md)), sample_key(r));
            prop_assert!(same3(Bxdf::eval(&t, wo, wo, md), Vec3::ZERO) && same(Bxdf::pdf(&t, wo, wo, s, md), 0.0));
            prop_assert!(Bxdf::flags(&t).is_delta() && Bxdf::flags(&t).is_transmissive());
        }
    }
}
