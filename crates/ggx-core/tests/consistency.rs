//! Internal consistency of `GgxConductor`: for every technique, the weight returned by
//! `sample` equals `eval / pdf` and its pdf equals `pdf()` (relative 1e-4 where pdf > 1e-3),
//! and the BRDF is reciprocal, `f(wo, wi) = f(wi, wo)`.

mod util;

use ggx_core::{Fresnel, GgxConductor, Sampling, Vec3};
use util::{INCIDENCES_DEG, Uniforms, alpha_pairs, wo_at};

fn fresnels() -> [Fresnel; 3] {
    [
        Fresnel::One,
        Fresnel::Conductor { eta: Vec3::new(0.2, 0.92, 1.1), k: Vec3::new(3.9, 2.45, 2.2) },
        Fresnel::Schlick { f0: Vec3::new(0.95, 0.64, 0.54) },
    ]
}

#[test]
fn sample_weight_and_pdf_agree_with_eval_and_pdf() {
    let mut checked = 0u64;
    let (mut worst_w, mut worst_p) = (0.0f32, 0.0f32);
    for (ax, ay) in alpha_pairs() {
        for fresnel in fresnels() {
            let brdf = GgxConductor::new(ax, ay, fresnel);
            for inc in INCIDENCES_DEG {
                let wo = wo_at(inc);
                for sampling in Sampling::ALL {
                    let mut u = Uniforms::new(checked);
                    for _ in 0..2000 {
                        let Some(s) = brdf.sample(wo, u.next(), sampling) else { continue };
                        assert!(!s.is_delta);
                        let pdf = brdf.pdf(wo, s.wi, sampling);
                        if pdf <= 1e-3 {
                            continue;
                        }
                        let f = brdf.eval(wo, s.wi);
                        let expect = f / pdf;
                        let ew = ((s.weight - expect).abs() / expect.abs().max(Vec3::splat(1e-6))).max_element();
                        let ep = (s.pdf - pdf).abs() / pdf;
                        worst_w = worst_w.max(ew);
                        worst_p = worst_p.max(ep);
                        assert!(ew < 1e-4, "{sampling:?} a=({ax},{ay}) inc {inc}: weight {} vs {}", s.weight, expect);
                        assert!(ep < 1e-4, "{sampling:?} a=({ax},{ay}) inc {inc}: pdf {} vs {pdf}", s.pdf);
                        checked += 1;
                    }
                }
            }
        }
    }
    println!("{checked} samples checked; worst relative error: weight {worst_w:.2e}, pdf {worst_p:.2e}");
    assert!(checked > 500_000);
}

#[test]
fn brdf_is_reciprocal() {
    let mut u = Uniforms::new(99);
    for (ax, ay) in alpha_pairs() {
        let brdf = GgxConductor::new(ax, ay, fresnels()[1]);
        for _ in 0..5000 {
            let wo = ggx_core::warp::sample_uniform_hemisphere(u.next());
            let wi = ggx_core::warp::sample_uniform_hemisphere(u.next());
            // eval returns f |cos wi|: divide it out.
            let a = brdf.eval(wo, wi) / wi.z;
            let b = brdf.eval(wi, wo) / wo.z;
            assert!((a - b).abs().max_element() <= 2e-5 * a.max_element().max(1e-3), "{wo} {wi}: {a} vs {b}");
        }
    }
}

#[test]
fn mirror_lobe_is_a_delta() {
    let f = Fresnel::Conductor { eta: Vec3::new(0.2, 0.92, 1.1), k: Vec3::new(3.9, 2.45, 2.2) };
    for alpha in [0.0, 1e-7, 1e-4, 9.9e-4] {
        let brdf = GgxConductor::new(alpha, alpha * 0.5, f);
        assert!(brdf.is_delta());
        let wo = wo_at(40.0);
        let s = brdf.sample(wo, ggx_core::Vec2::new(0.3, 0.8), Sampling::Vndf).unwrap();
        assert!(s.is_delta && s.pdf == 1.0);
        assert!((s.wi - Vec3::new(-wo.x, -wo.y, wo.z)).length() < 1e-6);
        assert!((s.weight - f.eval(wo.z)).length() < 1e-6);
        assert_eq!(brdf.eval(wo, s.wi), Vec3::ZERO);
        assert_eq!(brdf.pdf(wo, s.wi, Sampling::Vndf), 0.0);
    }
    assert!(!GgxConductor::new(1e-3, 1e-3, f).is_delta());
}

#[test]
fn samples_below_the_horizon_and_back_facing_views_are_rejected() {
    let brdf = GgxConductor::isotropic(0.5, Fresnel::One);
    let mut u = Uniforms::new(5);
    for s in Sampling::ALL {
        for _ in 0..100 {
            assert!(brdf.sample(Vec3::new(0.3, 0.0, -0.95), u.next(), s).is_none());
            assert!(brdf.sample(Vec3::X, u.next(), s).is_none());
        }
    }
    assert_eq!(brdf.eval(Vec3::Z, -Vec3::Z), Vec3::ZERO);
    assert_eq!(brdf.pdf(Vec3::Z, Vec3::new(0.6, 0.0, -0.8), Sampling::Vndf), 0.0);
}
