//! Energy: with `Fresnel::One` the directional albedo `E(wo) = integral f |cos wi| dwi` of
//! every technique's estimator agrees with an f64 quadrature of the BRDF, and neither
//! exceeds one (single scattering loses energy; it can never create it).
//!
//! Tolerance: each estimate must lie within `z` standard errors of the reference, where `z`
//! is the two-sided threshold at significance 0.01 with a Sidak correction over all
//! comparisons (about 4 sigma for ~250 comparisons; a fixed 3 sigma would fail by chance in
//! roughly half of all runs at this number of comparisons).

mod util;

use ggx_core::{Fresnel, GgxConductor, Sampling, reflect};
use util::{INCIDENCES_DEG, Uniforms, alpha_pairs, hemisphere_integral, wo_at};

/// Albedo by quadrature over the half vector (where the lobe is centred on +z):
/// `E = integral f(wo, wi) |wi.z| 4 |wo.wm| dwm`, `wi = reflect(wo, wm)`.
fn albedo_reference(brdf: &GgxConductor, wo: ggx_core::Vec3) -> f64 {
    hemisphere_integral(3000, 1024, |wm| {
        let c = wo.dot(wm);
        if c <= 0.0 {
            return 0.0;
        }
        let wi = reflect(wo, wm);
        brdf.eval(wo, wi).x as f64 * 4.0 * c as f64
    })
}

/// Inverse of the standard normal upper tail by bisection on erfc.
fn z_for_two_sided(p: f64) -> f64 {
    let (mut lo, mut hi) = (0.0f64, 10.0f64);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if erfc(mid / std::f64::consts::SQRT_2) > p { lo = mid } else { hi = mid }
    }
    lo
}

/// Complementary error function (Numerical Recipes erfcc, relative error < 1.2e-7).
fn erfc(x: f64) -> f64 {
    let z = x.abs();
    let t = 1.0 / (1.0 + 0.5 * z);
    let r = t
        * (-z * z - 1.26551223
            + t * (1.00002368
                + t * (0.37409196
                    + t * (0.09678418
                        + t * (-0.18628806
                            + t * (0.27886807
                                + t * (-1.13520398 + t * (1.48851587 + t * (-0.82215223 + t * 0.17087277)))))))))
            .exp();
    if x >= 0.0 { r } else { 2.0 - r }
}

#[test]
fn estimators_agree_with_quadrature_and_never_exceed_one() {
    const N: usize = 100_000;
    let configs: Vec<_> =
        alpha_pairs().into_iter().flat_map(|a| INCIDENCES_DEG.into_iter().map(move |i| (a, i))).collect();
    let tests = configs.len() * Sampling::ALL.len();
    let z_crit = z_for_two_sided(1.0 - (1.0f64 - 0.01).powf(1.0 / tests as f64));
    println!("{tests} comparisons, z threshold {z_crit:.2}");
    let mut worst_z = 0.0f64;
    for (seed, ((ax, ay), inc)) in configs.into_iter().enumerate() {
        let brdf = GgxConductor::new(ax, ay, Fresnel::One);
        let wo = wo_at(inc);
        let reference = albedo_reference(&brdf, wo);
        assert!(reference <= 1.0 + 1e-4, "albedo {reference} > 1 at ({ax},{ay}) {inc} deg");
        let mut line = format!("a=({ax:<4},{ay:<4}) {inc:>4} deg  E={reference:.5}");
        for sampling in Sampling::ALL {
            let mut u = Uniforms::new(seed as u64 * 16 + sampling as u64);
            let (mut sum, mut sum2) = (0.0f64, 0.0f64);
            for _ in 0..N {
                let w = brdf.sample(wo, u.next(), sampling).map_or(0.0, |s| s.weight.x as f64);
                sum += w;
                sum2 += w * w;
            }
            let mean = sum / N as f64;
            let sigma = ((sum2 / N as f64 - mean * mean).max(0.0) / N as f64).sqrt();
            let z = (mean - reference).abs() / sigma.max(1e-7);
            worst_z = worst_z.max(z);
            line += &format!("  {}={mean:.5}", sampling.name());
            assert!(z < z_crit, "{sampling:?} a=({ax},{ay}) {inc} deg: estimate {mean} vs {reference} (z = {z:.2})");
            assert!(mean <= 1.0 + z_crit * sigma, "{sampling:?}: albedo estimate {mean} exceeds 1");
        }
        println!("{line}");
    }
    println!("worst z = {worst_z:.2}");
}
