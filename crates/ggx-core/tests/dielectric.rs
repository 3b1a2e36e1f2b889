//! `GgxDielectric` (Walter et al. 2007 rough dielectric): f64 reference values of `eval` and
//! `pdf` (tests/support/dielectric_ref.rs, written without ggx-core), `sample` consistency
//! (`weight == eval / pdf`, `pdf == pdf()`), reciprocity in the form of this crate's
//! convention, the delta interface, total internal reflection, the bounded-VNDF fallback and
//! the `Bxdf` trait.

mod support;
mod util;

use ggx_core::{Bxdf, BxdfFlags, Fresnel, GgxConductor, GgxDielectric, Sampling, TransportMode, Vec2, Vec3, warp};
use support::dielectric_ref::{RefDielectric, V};
use util::{Uniforms, dir};

const ETAS: [f32; 4] = [1.5, 1.0 / 1.5, 1.33, 2.4];
const MODES: [TransportMode; 2] = [TransportMode::Radiance, TransportMode::Importance];
const SAMPLERS: [Sampling; 4] = [Sampling::Ndf, Sampling::Vndf, Sampling::SphericalCaps, Sampling::Bounded];

fn alpha_pairs() -> Vec<(f32, f32)> {
    vec![(1e-3, 1e-3), (0.05, 0.05), (0.3, 0.3), (0.7, 0.7), (1.0, 1.0), (0.05, 0.5), (0.5, 0.05)]
}

/// Views on both sides, down to grazing (89.9 degrees), off the symmetry planes.
fn views() -> Vec<Vec3> {
    let mut v = vec![];
    for deg in [0.0f64, 30.0, 60.0, 80.0, 89.0, 89.9] {
        let w = dir(deg.to_radians(), 0.7);
        v.push(w);
        v.push(Vec3::new(w.x, w.y, -w.z));
    }
    v
}

fn v64(w: Vec3) -> V {
    [w.x as f64, w.y as f64, w.z as f64]
}

/// A unit direction uniform on the sphere.
fn sphere_dir(u: Vec2, below: bool) -> Vec3 {
    let w = warp::sample_uniform_hemisphere(u);
    if below { Vec3::new(w.x, w.y, -w.z) } else { w }
}

#[test]
fn eval_and_pdf_match_the_f64_reference() {
    let mut u = Uniforms::new(7);
    let (mut worst_f, mut worst_p, mut n) = (0.0f64, 0.0f64, 0u32);
    let (mut worst_critical, mut n_critical) = (0.0f64, 0u32);
    for (ax, ay) in [(0.05f32, 0.05f32), (0.3, 0.3), (1.0, 1.0), (0.1, 0.6)] {
        for eta in ETAS {
            let b = GgxDielectric::new(ax, ay, eta);
            let r = RefDielectric { ax: ax as f64, ay: ay as f64, eta: eta as f64 };
            for k in 0..400 {
                let wo = sphere_dir(u.next(), k % 2 == 0);
                let wi = sphere_dir(u.next(), k % 3 == 0);
                let tol = r.tolerance(v64(wo), v64(wi));
                let critical = tol > 2e-4;
                for mode in MODES {
                    let radiance = mode == TransportMode::Radiance;
                    let expect = r.eval(v64(wo), v64(wi), radiance);
                    let got = b.eval(wo, wi, mode).x as f64;
                    if expect > 1e-4 {
                        let e = (got - expect).abs() / expect;
                        assert!(e < tol, "{mode:?} a=({ax},{ay}) eta {eta} {wo} {wi}: {got} vs {expect}");
                        if critical {
                            worst_critical = worst_critical.max(e);
                            n_critical += 1;
                        } else {
                            worst_f = worst_f.max(e);
                            n += 1;
                        }
                    } else {
                        assert!(got <= 2e-4, "{wo} {wi}: {got} where the reference is {expect}");
                    }
                }
                for (s, vndf) in [(Sampling::Vndf, true), (Sampling::Ndf, false)] {
                    let expect = r.pdf(v64(wo), v64(wi), vndf);
                    let got = b.pdf(wo, wi, s, TransportMode::Radiance) as f64;
                    if expect > 1e-4 {
                        let e = (got - expect).abs() / expect;
                        assert!(e < tol, "{s:?} a=({ax},{ay}) eta {eta} {wo} {wi}: {got} vs {expect}");
                        if critical {
                            worst_critical = worst_critical.max(e);
                        } else {
                            worst_p = worst_p.max(e);
                        }
                    } else {
                        assert!(got <= 2e-4, "{s:?} {wo} {wi}: {got} where the reference is {expect}");
                    }
                }
            }
        }
    }
    // Hand-picked points: normal incidence transmission, the TIR side and a grazing pair.
    let b = GgxDielectric::isotropic(0.3, 1.5);
    let r = RefDielectric { ax: 0.3, ay: 0.3, eta: 1.5 };
    for (wo, wi) in [
        (Vec3::Z, -Vec3::Z),
        (Vec3::new(0.6, 0.0, -0.8), Vec3::new(-0.6, 0.0, -0.8)),
        (Vec3::new(0.9, 0.0, -0.435_889_9), Vec3::new(-0.9, 0.0, -0.435_889_9)),
        (dir(1.55, 0.3), dir(2.0, 2.5)),
    ] {
        let expect = r.eval(v64(wo), v64(wi), true);
        let got = b.eval(wo, wi, TransportMode::Radiance).x as f64;
        assert!((got - expect).abs() <= 1e-5 * expect.max(1.0), "{wo} {wi}: {got} vs {expect}");
    }
    println!(
        "{n} values; worst relative error: eval {worst_f:.2e}, pdf {worst_p:.2e}; \
         {n_critical} eval values near the critical angle (bound 1e-4 + 3e-7 e^2 / cos^2 above 2e-4): {worst_critical:.2e}"
    );
    assert!(worst_f < 1e-4 && worst_p < 1e-4, "eval {worst_f:e} pdf {worst_p:e}");
}

#[test]
fn sample_weight_and_pdf_agree_with_eval_and_pdf() {
    let (mut checked, mut transmitted) = (0u64, 0u64);
    let (mut worst_w, mut worst_p) = (0.0f32, 0.0f32);
    for (ax, ay) in alpha_pairs() {
        for eta in ETAS {
            let b = GgxDielectric::new(ax, ay, eta);
            for wo in views() {
                for sampling in SAMPLERS {
                    for mode in MODES {
                        let mut u = Uniforms::new(checked);
                        for _ in 0..300 {
                            let (uv, ul) = (u.next(), u.next().x);
                            let Some(s) = b.sample(wo, uv, ul, sampling, mode) else { continue };
                            assert!(!s.is_delta);
                            assert!((s.wi.length() - 1.0).abs() < 1e-5);
                            let pdf = b.pdf(wo, s.wi, sampling, mode);
                            let f = b.eval(wo, s.wi, mode);
                            assert!(pdf > 0.0 && f.x > 0.0, "{sampling:?} {wo} {}: pdf {pdf} f {f}", s.wi);
                            transmitted += s.is_transmission(wo) as u64;
                            let expect = f.x / pdf;
                            let ew = (s.weight.x - expect).abs() / expect.max(1e-6);
                            let ep = (s.pdf - pdf).abs() / pdf;
                            worst_w = worst_w.max(ew);
                            worst_p = worst_p.max(ep);
                            assert!(
                                ew < 1e-4,
                                "{sampling:?} a=({ax},{ay}) eta {eta} {wo}: weight {} vs {expect}",
                                s.weight
                            );
                            assert!(ep < 1e-4, "{sampling:?} a=({ax},{ay}) eta {eta} {wo}: pdf {} vs {pdf}", s.pdf);
                            checked += 1;
                        }
                    }
                }
            }
        }
    }
    println!(
        "{checked} samples ({transmitted} transmitted); worst relative error: weight {worst_w:.2e}, pdf {worst_p:.2e}"
    );
    assert!(checked > 300_000 && transmitted > 100_000);
}

/// This crate's convention: `f(wo, wi) = eval / |wi.z|`, `n(w)` the index of `w`'s side (1
/// above, `eta` below). Radiance: `f(wo, wi) / n(wo)^2 == f(wi, wo) / n(wi)^2`; importance:
/// `f(wo, wi) / n(wi)^2 == f(wi, wo) / n(wo)^2`; and the adjoint `f_rad(wo, wi) == f_imp(wi, wo)`.
#[test]
fn bsdf_is_reciprocal_in_the_generalized_form() {
    let mut u = Uniforms::new(99);
    let (mut worst, mut n) = (0.0f32, 0u32);
    let (mut worst_critical, mut n_critical) = (0.0f32, 0u32);
    for (ax, ay) in alpha_pairs().into_iter().skip(1) {
        for eta in ETAS {
            let b = GgxDielectric::new(ax, ay, eta);
            let r = RefDielectric { ax: ax as f64, ay: ay as f64, eta: eta as f64 };
            let index = |w: Vec3| if w.z > 0.0 { 1.0 } else { eta };
            for k in 0..4000 {
                let wo = sphere_dir(u.next(), k % 2 == 0);
                let wi = sphere_dir(u.next(), k % 4 < 2);
                let tol = r.tolerance(v64(wo), v64(wi)) as f32;
                let critical = tol > 2e-4;
                let f = |a: Vec3, c: Vec3, m| b.eval(a, c, m).x / c.z.abs();
                let (fr, fr_adj) = (f(wo, wi, TransportMode::Radiance), f(wi, wo, TransportMode::Radiance));
                let (fi, fi_adj) = (f(wo, wi, TransportMode::Importance), f(wi, wo, TransportMode::Importance));
                let pairs = [
                    (fr / (index(wo) * index(wo)), fr_adj / (index(wi) * index(wi))),
                    (fi / (index(wi) * index(wi)), fi_adj / (index(wo) * index(wo))),
                    (fr, fi_adj),
                ];
                for (a, c) in pairs {
                    if !(a.is_finite() && c.is_finite()) || a.max(c) < 1e-6 {
                        continue;
                    }
                    let e = (a - c).abs() / a.max(c);
                    if critical {
                        worst_critical = worst_critical.max(e);
                        n_critical += 1;
                    } else {
                        worst = worst.max(e);
                        n += 1;
                    }
                    assert!(e <= tol, "a=({ax},{ay}) eta {eta} {wo} {wi}: {a} vs {c}");
                }
            }
        }
    }
    println!(
        "{n} pairs; worst relative reciprocity error {worst:.2e}; {n_critical} pairs near \
         the critical angle (bound 1e-4 + 3e-7 e^2 / cos^2 above 2e-4): {worst_critical:.2e}"
    );
    assert!(n > 50_000);
}

#[test]
fn smooth_interface_is_a_delta_with_the_lobe_probability_as_pdf() {
    for eta in ETAS {
        for alpha in [0.0, 1e-7, 1e-4, 9.9e-4] {
            let b = GgxDielectric::new(alpha, alpha * 0.5, eta);
            assert!(b.is_delta() && b.flags().is_delta() && b.flags().is_transmissive());
            for wo in views() {
                let etap = if wo.z > 0.0 { eta } else { 1.0 / eta };
                let f = Fresnel::Dielectric { eta }.eval(wo.z).x;
                let mut lobes = [0u32; 2];
                for k in 0..64 {
                    let ul = (k as f32 + 0.5) / 64.0;
                    for mode in MODES {
                        let Some(s) = b.sample(wo, Vec2::new(0.3, 0.8), ul, Sampling::Vndf, mode) else {
                            panic!("smooth {eta} {wo}: no sample")
                        };
                        assert!(s.is_delta);
                        assert_eq!(b.eval(wo, s.wi, mode), Vec3::ZERO);
                        assert_eq!(b.pdf(wo, s.wi, Sampling::Vndf, mode), 0.0);
                        if s.is_transmission(wo) {
                            lobes[1] += 1;
                            assert!((s.pdf - (1.0 - f)).abs() < 1e-6);
                            let w = if mode == TransportMode::Radiance { 1.0 / (etap * etap) } else { 1.0 };
                            assert!((s.weight.x - w).abs() < 1e-5 * w);
                            // Snell: n_o sin_o = n_i sin_i.
                            let (so, si) = (wo.truncate().length(), s.wi.truncate().length());
                            assert!((so - etap * si).abs() < 1e-5, "{wo} -> {}", s.wi);
                            assert!(s.wi.truncate().dot(wo.truncate()) <= 0.0);
                        } else {
                            lobes[0] += 1;
                            assert!((s.pdf - f).abs() < 1e-6 && s.weight == Vec3::ONE);
                            assert_eq!(s.wi, Vec3::new(-wo.x, -wo.y, wo.z));
                        }
                    }
                }
                if f >= 1.0 {
                    assert_eq!(lobes[1], 0, "total internal reflection must always reflect");
                }
                assert!(lobes[0] + lobes[1] == 128);
            }
        }
    }
    assert!(!GgxDielectric::new(1e-3, 1e-3, 1.5).is_delta());
}

/// Inside glass (eta 1.5) beyond the critical angle every rough sample whose microfacet
/// sees total internal reflection reflects: pbrt-v3 #254 (the half vector must be turned
/// outward before Fresnel is evaluated).
#[test]
fn total_internal_reflection_reflects_with_probability_one() {
    let b = GgxDielectric::isotropic(0.02, 1.5);
    let wo = Vec3::new(0.9, 0.0, -0.435_889_9);
    let mut u = Uniforms::new(3);
    let (mut refl, mut n) = (0, 0);
    for _ in 0..20_000 {
        let Some(s) = b.sample(wo, u.next(), u.next().x, Sampling::Vndf, TransportMode::Radiance) else { continue };
        n += 1;
        refl += (!s.is_transmission(wo)) as u32;
        assert!((s.pdf - b.pdf(wo, s.wi, Sampling::Vndf, TransportMode::Radiance)).abs() <= 1e-4 * s.pdf);
    }
    // At alpha 0.02 nearly every visible normal is within a few degrees of +z: TIR.
    assert!(refl as f64 > 0.999 * n as f64, "{refl} of {n} reflected");
    let mirror = Vec3::new(-wo.x, -wo.y, wo.z);
    assert!(b.pdf(wo, mirror, Sampling::Vndf, TransportMode::Radiance) > 0.0);
    assert_eq!(
        GgxDielectric::isotropic(0.0, 1.5)
            .sample(wo, Vec2::ZERO, 0.999, Sampling::Vndf, TransportMode::Radiance)
            .unwrap()
            .pdf,
        1.0
    );
}

/// Bounded VNDF is a reflection bound: for the dielectric it samples spherical caps, bit
/// for bit, with the spherical-cap density.
#[test]
fn bounded_falls_back_to_spherical_caps() {
    let mut u = Uniforms::new(11);
    for (ax, ay) in alpha_pairs() {
        for eta in ETAS {
            let b = GgxDielectric::new(ax, ay, eta);
            for wo in views() {
                for _ in 0..50 {
                    let (uv, ul) = (u.next(), u.next().x);
                    let m = TransportMode::Radiance;
                    let bounded = b.sample(wo, uv, ul, Sampling::Bounded, m);
                    assert_eq!(bounded, b.sample(wo, uv, ul, Sampling::SphericalCaps, m));
                    let wi = sphere_dir(u.next(), ul < 0.5);
                    let p = b.pdf(wo, wi, Sampling::Bounded, m);
                    assert_eq!(p.to_bits(), b.pdf(wo, wi, Sampling::SphericalCaps, m).to_bits());
                }
            }
        }
    }
}

#[test]
fn cosine_and_uniform_are_refused() {
    let b = GgxDielectric::isotropic(0.3, 1.5);
    let mut u = Uniforms::new(1);
    for s in [Sampling::Cosine, Sampling::Uniform] {
        for wo in views() {
            let wi = sphere_dir(u.next(), true);
            assert!(b.sample(wo, u.next(), 0.5, s, TransportMode::Radiance).is_none());
            assert_eq!(b.pdf(wo, wi, s, TransportMode::Radiance), 0.0);
        }
    }
    assert!(b.sample(Vec3::X, Vec2::splat(0.5), 0.5, Sampling::Vndf, TransportMode::Radiance).is_none());
}

fn through_trait<B: Bxdf>(b: &B, wo: Vec3, u: Vec2, ul: f32) -> (Option<ggx_core::BsdfSample>, Vec3, f32, BxdfFlags) {
    let m = TransportMode::Radiance;
    let s = b.sample(wo, u, ul, Sampling::Vndf, m);
    let wi = s.map_or(Vec3::Z, |s| s.wi);
    (s, b.eval(wo, wi, m), b.pdf(wo, wi, Sampling::Vndf, m), b.flags())
}

#[test]
fn the_bxdf_trait_dispatches_to_the_inherent_methods() {
    let c = GgxConductor::isotropic(0.3, Fresnel::One);
    let d = GgxDielectric::isotropic(0.3, 1.5);
    let wo = dir(0.7, 0.2);
    let (uv, ul) = (Vec2::new(0.3, 0.6), 0.9);
    let (s, f, p, flags) = through_trait(&c, wo, uv, ul);
    assert_eq!(s, c.sample(wo, uv, Sampling::Vndf));
    assert_eq!((f, p), (c.eval(wo, s.unwrap().wi), c.pdf(wo, s.unwrap().wi, Sampling::Vndf)));
    assert_eq!(flags, BxdfFlags::REFLECTION.union(BxdfFlags::GLOSSY));
    assert_eq!(s.unwrap().lobe(wo), BxdfFlags::REFLECTION);
    let (s, f, p, flags) = through_trait(&d, wo, uv, ul);
    let s = s.unwrap();
    assert!(s.is_transmission(wo) && s.lobe(wo) == BxdfFlags::TRANSMISSION);
    assert_eq!(f, d.eval(wo, s.wi, TransportMode::Radiance));
    assert_eq!(p, d.pdf(wo, s.wi, Sampling::Vndf, TransportMode::Radiance));
    assert!(flags.contains(BxdfFlags::REFLECTION.union(BxdfFlags::TRANSMISSION)) && !flags.is_delta());
    assert_eq!(TransportMode::from_u32(1), TransportMode::Importance);
    assert_eq!(TransportMode::from_u32(7), TransportMode::Radiance);
}
