//! Property tests over any f32 input, NaN, infinities, subnormals, 0 and 1 - ulp included,
//! alphas from 1e-7 to 1: nothing panics, nothing returns NaN or infinity, returned
//! directions are unit length within 1e-5 and above the horizon, weights and pdfs are
//! never negative.

use ggx_core::math::ONE_MINUS_EPSILON;
use ggx_core::mis::{balance_heuristic, power_heuristic};
use ggx_core::{Frame, Fresnel, GgxConductor, Sampling, TrowbridgeReitz, Vec2, Vec3, warp};
use proptest::prelude::*;
use proptest::test_runner::RngSeed;

/// Any f32, with the special values over-represented.
fn any_f32() -> impl Strategy<Value = f32> {
    prop_oneof![
        3 => proptest::num::f32::ANY,
        2 => -1.0f32..=1.0,
        2 => prop::sample::select(vec![
            0.0, -0.0, 1.0, -1.0, ONE_MINUS_EPSILON, -ONE_MINUS_EPSILON, 1e-45, -1e-45, f32::MIN_POSITIVE,
            f32::NAN, f32::INFINITY, f32::NEG_INFINITY, f32::MAX, f32::MIN, 1e-7, 1e-20, 0.5,
        ]),
    ]
}

/// A unit-ish direction, possibly grazing (cos down to 1e-7), possibly special.
fn direction() -> impl Strategy<Value = Vec3> {
    prop_oneof![
        3 => (any_f32(), any_f32(), any_f32()).prop_map(|(x, y, z)| Vec3::new(x, y, z)),
        3 => (0.0f32..1.0, 0.0f32..1.0).prop_map(|(a, b)| warp::sample_uniform_hemisphere(Vec2::new(a, b))),
        2 => (-7.0f32..0.0, 0.0f32..6.3).prop_map(|(e, phi)| {
            let z = 10f32.powf(e);
            let r = (1.0 - z * z).sqrt();
            Vec3::new(r * phi.cos(), r * phi.sin(), z)
        }),
    ]
}

fn alpha() -> impl Strategy<Value = f32> {
    prop_oneof![4 => (-7.0f32..=0.0).prop_map(|e| 10f32.powf(e)), 1 => any_f32()]
}

fn fresnel() -> impl Strategy<Value = Fresnel> {
    prop_oneof![
        Just(Fresnel::One),
        (any_f32(), any_f32(), any_f32()).prop_map(|(a, b, c)| Fresnel::Schlick { f0: Vec3::new(a, b, c) }),
        (any_f32(), any_f32()).prop_map(|(e, k)| Fresnel::Conductor { eta: Vec3::splat(e), k: Vec3::splat(k) }),
        Just(Fresnel::Conductor { eta: Vec3::new(0.2, 0.92, 1.1), k: Vec3::new(3.9, 2.45, 2.2) }),
        any_f32().prop_map(|eta| Fresnel::Dielectric { eta }),
    ]
}

fn ok(x: f32) -> bool {
    x.is_finite() && x >= 0.0
}

fn ok3(v: Vec3) -> bool {
    ok(v.x) && ok(v.y) && ok(v.z)
}

/// Found by CI: wo ~ -wi at grazing angles rounds `wo.wm` below zero, which made the NDF
/// pdf negative. A back-facing half vector now gives eval = pdf = 0 for microfacet sampling.
#[test]
fn back_facing_half_vector_from_rounding_gives_zero() {
    let brdf = GgxConductor::new(1.0, 1.0, Fresnel::Dielectric { eta: 1.5 });
    let wo = Vec3::new(-0.795_087_7, 1e-45, 1e-7);
    let wi = Vec3::new(1.372_513_5, 1e-45, 4.750_493e-7);
    for s in Sampling::ALL {
        let p = brdf.pdf(wo, wi, s);
        assert!(ok(p), "pdf {s:?} {p}");
    }
    assert_eq!(brdf.pdf(wo, wi, Sampling::Ndf), 0.0);
    assert_eq!(brdf.eval(wo, wi), Vec3::ZERO);
}

proptest! {
    // A fixed seed keeps CI reproducible; `cargo xtask stress` explores fresh inputs each run.
    #![proptest_config(ProptestConfig {
        cases: 20_000,
        rng_seed: RngSeed::Fixed(0x6767_7863),
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn brdf_never_produces_invalid_values(
        ax in alpha(), ay in alpha(), f in fresnel(), wo in direction(), wi in direction(),
        u in (any_f32(), any_f32()),
    ) {
        let brdf = GgxConductor::new(ax, ay, f);
        let u = Vec2::new(u.0, u.1);
        prop_assert!(ok3(brdf.eval(wo, wi)), "eval {:?}", brdf.eval(wo, wi));
        for s in Sampling::ALL {
            let p = brdf.pdf(wo, wi, s);
            prop_assert!(ok(p), "pdf {s:?} {p}");
            if let Some(bs) = brdf.sample(wo, u, s) {
                prop_assert!((bs.wi.length() - 1.0).abs() < 1e-5, "{s:?} |wi| = {}", bs.wi.length());
                prop_assert!(bs.wi.z > 0.0, "{s:?} below horizon {:?}", bs.wi);
                prop_assert!(ok3(bs.weight), "{s:?} weight {:?}", bs.weight);
                prop_assert!(bs.pdf > 0.0 && bs.pdf.is_finite(), "{s:?} pdf {}", bs.pdf);
            }
        }
    }

    #[test]
    fn distribution_terms_are_finite_and_bounded(ax in alpha(), ay in alpha(), w in direction(), v in direction()) {
        let d = TrowbridgeReitz::new(ax, ay);
        prop_assert!(ok(d.d(w)));
        prop_assert!(!d.lambda(w).is_nan() && d.lambda(w) >= 0.0);
        for g in [d.g1(w), d.g2(w, v), d.g2_separable(w, v)] {
            prop_assert!(ok(g) && g <= 1.0 + 1e-6, "G {g}");
        }
        prop_assert!(ok(d.d_visible(w, v)));
        prop_assert!(ok(d.pdf_wi_bounded(w, v)));
        let u = Vec2::new(v.x, v.y);
        for m in [d.sample_wm_ndf(u), d.sample_wm_vndf(w, u), d.sample_wm_spherical_caps(w, u), d.sample_wm_bounded(w, u)] {
            prop_assert!(m == Vec3::ZERO || ((m.length() - 1.0).abs() < 1e-5 && m.z >= 0.0), "wm {m:?}");
        }
    }

    #[test]
    fn helpers_never_produce_invalid_values(w in direction(), c in any_f32(), e in any_f32(), p in any_f32(), q in any_f32()) {
        let frame = Frame::from_z(w);
        prop_assert!(frame.x.is_finite() && frame.y.is_finite() && frame.z.is_finite());
        prop_assert!((frame.x.length() - 1.0).abs() < 1e-5 && frame.x.dot(frame.z).abs() < 1e-5);
        for f in [Fresnel::Dielectric { eta: e }, Fresnel::Conductor { eta: Vec3::splat(e), k: Vec3::splat(p) },
                  Fresnel::SchlickF90 { f0: Vec3::splat(e), f90: Vec3::splat(p) }] {
            let r = f.eval(c);
            prop_assert!(ok3(r) && r.max_element() <= 1.0, "{f:?} {c} -> {r:?}");
        }
        for h in [balance_heuristic, power_heuristic] {
            for m in [h(1.0, p, 1.0, q), h(c, p, e, q), h(e, f32::INFINITY, c, q)] {
                prop_assert!((0.0..=1.0).contains(&m), "MIS weight {m}");
            }
        }
        let v = Vec3::new(p, q, c);
        for r in [ggx_core::reflect(v, w), ggx_core::reflect(w, v), frame.to_local(v), frame.to_world(v)] {
            prop_assert!(r.is_finite(), "{r:?}");
        }
        let s = ggx_core::fresnel::fresnel_schlick(c, Vec3::splat(e), Vec3::splat(p));
        prop_assert!(s.is_finite(), "schlick {s:?}");
        prop_assert!(ok(TrowbridgeReitz::new(p, q).pdf_wm_ndf(v)));
        for s in [warp::sample_cosine_hemisphere(Vec2::new(p, q)), warp::sample_uniform_hemisphere(Vec2::new(p, q))] {
            prop_assert!((s.length() - 1.0).abs() < 1e-5 && s.z > 0.0);
        }
    }
}
