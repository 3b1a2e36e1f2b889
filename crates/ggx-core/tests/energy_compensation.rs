//! Energy compensation (`GgxConductorMs`, Kulla & Conty 2017): the white furnace with and
//! without the multiple-scattering lobe, reciprocity, the sampler's consistency and its
//! chi-square goodness of fit.
//!
//! The single-scattering albedo is an f64 quadrature independent of the table generator's
//! rule (48 x 24 panels of 5-point Gauss-Legendre over the VNDF sampler's unit square, where
//! the generator uses 32 x 16), the multiple-scattering albedo a quadrature of
//! `eval_ms` over `mu_i` (the lobe does not depend on the azimuth).

mod support;
mod util;

use ggx_core::energy::{albedo, average_albedo};
use ggx_core::{Fresnel, GgxConductor, GgxConductorMs, Sampling, Vec2, Vec3};
use support::chi2::{Chi2Config, chi2_test, sidak_significance};
use util::{Uniforms, wo_at};

const GL5_NODES: [f64; 5] = [-0.906179845938664, -0.5384693101056831, 0.0, 0.5384693101056831, 0.906179845938664];
const GL5_WEIGHTS: [f64; 5] =
    [0.23692688505618908, 0.47862867049936647, 128.0 / 225.0, 0.47862867049936647, 0.23692688505618908];

/// Composite 5-point Gauss-Legendre nodes and weights on `[0, 1]`.
fn rule(panels: usize) -> Vec<(f64, f64)> {
    let h = 1.0 / panels as f64;
    (0..panels)
        .flat_map(|p| {
            GL5_NODES.iter().zip(&GL5_WEIGHTS).map(move |(&t, &w)| ((p as f64 + 0.5 * (t + 1.0)) * h, 0.5 * h * w))
        })
        .collect()
}

/// `integral f_ss |wi.z| dwi` (red channel) over the VNDF sampler's unit square, `u.x = 1 -
/// (1 - s)^2` (smooth where the VNDF map has `sqrt(1 - u.x)`).
fn single_albedo(brdf: &GgxConductor, wo: Vec3) -> f64 {
    if brdf.is_delta() {
        return brdf.sample(wo, Vec2::splat(0.5), Sampling::Vndf).map_or(0.0, |s| s.weight.x as f64);
    }
    let mut sum = 0.0;
    for (s, ws) in rule(48) {
        let ux = (1.0 - (1.0 - s) * (1.0 - s)) as f32;
        for (v, wv) in rule(24) {
            if let Some(smp) = brdf.sample(wo, Vec2::new(ux, v as f32), Sampling::Vndf) {
                let pdf = brdf.pdf(wo, smp.wi, Sampling::Vndf) as f64;
                if pdf > 0.0 {
                    sum += ws * 2.0 * (1.0 - s) * wv * brdf.eval(wo, smp.wi).x as f64 / pdf;
                }
            }
        }
    }
    sum
}

/// `integral f_ms |wi.z| dwi = 2 pi integral_0^1 eval_ms(wo, wi(mu)) dmu` (red channel).
fn ms_albedo(ms: &GgxConductorMs, wo: Vec3) -> f64 {
    rule(128)
        .into_iter()
        .map(|(mu, w)| {
            let wi = Vec3::new((1.0 - mu * mu).sqrt() as f32, 0.0, mu as f32);
            w * std::f64::consts::TAU * ms.eval_ms(wo, wi).x as f64
        })
        .sum()
}

/// View direction at cosine `mu`, azimuth 0.7 rad.
fn wo_mu(mu: f32) -> Vec3 {
    let s = (1.0 - mu * mu).max(0.0).sqrt();
    Vec3::new(s * 0.7f32.cos(), s * 0.7f32.sin(), mu)
}

/// Isotropic alphas: table nodes, points between them, and the mirror / near-mirror range.
const ALPHAS: [f32; 16] = [0.0, 0.001, 0.002, 0.005, 0.01, 0.02, 0.05, 0.1, 0.15, 0.25, 0.35, 0.5, 0.6, 0.75, 0.9, 1.0];
/// View cosines, grazing included.
const MUS: [f32; 15] = [1e-4, 1e-3, 3e-3, 0.01, 0.02, 0.05, 0.1, 0.15, 0.2, 0.3, 0.45, 0.6, 0.75, 0.9, 1.0];

/// White furnace: with `F = 1` the compensated albedo is 1 within 1 % for every alpha in
/// [0, 1] and every view angle down to `mu = 1e-4` (below `DELTA_ALPHA` the lobe is a mirror
/// with albedo exactly 1), near-mirror grazing lobes included (their `E` dips at `mu ~ alpha`;
/// the tables' quarter-root axes resolve it). Without compensation the loss is what
/// `examples/albedo.rs` prints.
#[test]
fn white_furnace_is_one_within_one_percent() {
    let (mut worst, mut worst_near_mirror) = ((0.0f64, 0.0f32, 0.0f32), (0.0f64, 0.0f32, 0.0f32));
    println!("alpha  mu      E_ss     E_ss+ms");
    for alpha in ALPHAS {
        let ms = GgxConductorMs::new(GgxConductor::isotropic(alpha, Fresnel::One));
        for mu in MUS {
            let wo = wo_mu(mu);
            let ss = single_albedo(&ms.conductor, wo);
            let total = ss + ms_albedo(&ms, wo);
            let err = (total - 1.0).abs();
            let near_mirror = alpha < 0.01 && mu < 0.02;
            let w = if near_mirror { &mut worst_near_mirror } else { &mut worst };
            if err > w.0 {
                *w = (err, alpha, mu);
            }
            if [0.01f32, 0.1, 0.25, 0.5, 1.0].contains(&alpha) && [1e-3f32, 0.1, 0.45, 1.0].contains(&mu) {
                println!("{alpha:<6} {mu:<7} {ss:.5}  {total:.5}");
            }
            assert!(err < 0.01, "alpha {alpha} mu {mu}: compensated albedo {total} (single {ss})");
        }
    }
    println!("worst |albedo - 1| = {:.2e} at alpha {}, mu {}", worst.0, worst.1, worst.2);
    println!(
        "near mirror (alpha < 0.01, mu < 0.02): worst {:.2e} at alpha {}, mu {}",
        worst_near_mirror.0, worst_near_mirror.1, worst_near_mirror.2
    );
    // Without compensation the loss is real and large at alpha 1 (the test can tell).
    let e_half = single_albedo(&GgxConductor::isotropic(0.5, Fresnel::One), Vec3::Z);
    let e_one = single_albedo(&GgxConductor::isotropic(1.0, Fresnel::One), Vec3::Z);
    println!("uncompensated E(mu = 1): alpha 0.5 {e_half:.4}, alpha 1 {e_one:.4}");
    assert!((0.30..0.32).contains(&e_one) && (0.68..0.70).contains(&e_half), "E(1) = {e_half}, {e_one}");
}

/// Tables against an independent quadrature at points between the nodes: `|E_table - E| <
/// 4e-3` for every alpha from `DELTA_ALPHA` (below it the lobe is a mirror and the tables are
/// not read) and every view cosine, and `E_avg` within 1e-3 (the interpolation error the
/// furnace sees).
#[test]
fn table_interpolation_error_is_small() {
    let (mut worst, mut worst_avg) = ((0.0f64, 0.0, 0.0), 0.0f64);
    for alpha in ALPHAS {
        let brdf = GgxConductor::isotropic(alpha, Fresnel::One);
        for mu in MUS {
            if alpha < ggx_core::DELTA_ALPHA {
                continue;
            }
            let d = (albedo(mu, alpha) as f64 - single_albedo(&brdf, wo_mu(mu))).abs();
            if d > worst.0 {
                worst = (d, alpha, mu);
            }
        }
        // 2 integral E(mu) mu dmu with mu = x^2.
        let avg: f64 =
            rule(16).into_iter().map(|(x, w)| 4.0 * w * x * x * x * single_albedo(&brdf, wo_mu((x * x) as f32))).sum();
        worst_avg = worst_avg.max((average_albedo(alpha) as f64 - avg).abs());
    }
    println!(
        "worst |E_table - E| = {:.2e} at alpha {}, mu {}; worst |E_avg error| = {worst_avg:.2e}",
        worst.0, worst.1, worst.2
    );
    assert!(worst.0 < 4e-3 && worst_avg < 1e-3);
}

/// Anisotropic lobes read the tables at the RMS alpha ([`ggx_core::energy::effective_alpha`]):
/// every pair stays within its measured furnace error plus about 10 % (worst 3.1 % for an
/// anisotropy ratio up to 4, at (0.25, 1); 1.1 % at (0.1, 0.4)). Kulla & Conty's
/// `sqrt(alpha_x alpha_y)` fails every pair (6.9 % at (0.1, 0.4), 18 % at (0.25, 1), 45 % at
/// (0.01, 1)): the bounds are tight enough to tell the two apart.
#[test]
fn anisotropic_furnace_error_is_bounded() {
    // (alpha_x, alpha_y, bound on |albedo - 1| over the view cosines).
    const PAIRS: [(f32, f32, f64); 8] = [
        (0.1, 0.4, 0.012),
        (0.4, 0.1, 0.018),
        (0.3, 0.6, 0.006),
        (0.25, 1.0, 0.034),
        (0.05, 0.5, 0.018),
        (0.5, 0.05, 0.027),
        (0.2, 1.0, 0.036),
        (0.01, 1.0, 0.039),
    ];
    let (mut worst, mut failures) = (0.0f64, vec![]);
    for (ax, ay, bound) in PAIRS {
        let ms = GgxConductorMs::new(GgxConductor::new(ax, ay, Fresnel::One));
        let mut line = format!("a=({ax},{ay}):");
        let mut pair = 0.0f64;
        for mu in [0.01f32, 0.1, 0.3, 0.6, 1.0] {
            let wo = wo_mu(mu);
            let total = single_albedo(&ms.conductor, wo) + ms_albedo(&ms, wo);
            line += &format!(" mu {mu}: {total:.4}");
            pair = pair.max((total - 1.0).abs());
        }
        println!("{line}  worst {pair:.2e} (bound {bound})");
        if pair >= bound {
            failures.push(format!("a=({ax},{ay}): {pair:.3e} >= {bound}"));
        }
        if ax.max(ay) / ax.min(ay) <= 4.0 {
            worst = worst.max(pair);
        }
    }
    println!("anisotropic (ratio <= 4): worst |albedo - 1| = {worst:.2e}");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The near-mirror grazing corner, densely (12 alphas and 12 view cosines per decade, alpha in
/// [DELTA_ALPHA, 0.02], mu in [1e-4, 0.1]), where a `sqrt(alpha)` x `sqrt(mu)` table missed
/// by 3.3 %: the furnace stays within 1 % (measured worst 4.9e-3; 0.6 % asserted).
#[test]
fn near_mirror_grazing_furnace_is_within_one_percent() {
    let mut worst = (0.0f64, 0.0f32, 0.0f32);
    for a in 0..=16 {
        let alpha = 10f32.powf(-3.0 + a as f32 / 12.0);
        let ms = GgxConductorMs::new(GgxConductor::isotropic(alpha, Fresnel::One));
        for m in 0..=36 {
            let mu = 10f32.powf(-4.0 + m as f32 / 12.0);
            let wo = wo_mu(mu);
            let err = (single_albedo(&ms.conductor, wo) + ms_albedo(&ms, wo) - 1.0).abs();
            if err > worst.0 {
                worst = (err, alpha, mu);
            }
        }
    }
    println!("near mirror, dense: worst |albedo - 1| = {:.2e} at alpha {}, mu {}", worst.0, worst.1, worst.2);
    assert!(worst.0 < 0.006, "{worst:?}");
}

fn fresnels() -> [Fresnel; 4] {
    [
        Fresnel::One,
        Fresnel::Conductor { eta: Vec3::new(0.2, 0.92, 1.1), k: Vec3::new(3.9, 2.45, 2.2) },
        Fresnel::Schlick { f0: Vec3::new(0.95, 0.64, 0.54) },
        Fresnel::Dielectric { eta: 1.5 },
    ]
}

/// `f_ms(wo, wi) = f_ms(wi, wo)`, and so the whole compensated BRDF.
#[test]
fn compensation_lobe_is_reciprocal() {
    let mut u = Uniforms::new(5);
    for (ax, ay) in [(0.3f32, 0.3f32), (1.0, 1.0), (0.05, 0.5)] {
        let ms = GgxConductorMs::new(GgxConductor::new(ax, ay, fresnels()[1]));
        for _ in 0..5000 {
            let wo = ggx_core::warp::sample_uniform_hemisphere(u.next());
            let wi = ggx_core::warp::sample_uniform_hemisphere(u.next());
            let a = ms.eval_ms(wo, wi) / wi.z;
            let b = ms.eval_ms(wi, wo) / wo.z;
            assert!((a - b).abs().max_element() <= 1e-5 * a.abs().max_element().max(1e-3), "{a} vs {b}");
            let a = ms.eval(wo, wi) / wi.z;
            let b = ms.eval(wi, wo) / wo.z;
            assert!((a - b).abs().max_element() <= 1e-3 * a.abs().max_element().max(1e-2), "{a} vs {b}");
        }
    }
}

/// `weight == eval / pdf` and `pdf == pdf()` for every technique, both lobes, four Fresnels.
#[test]
fn sample_weight_and_pdf_agree_with_eval_and_pdf() {
    let (mut checked, mut ms_lobe) = (0u64, 0u64);
    let mut worst = 0.0f32;
    for (ax, ay) in [(0.05f32, 0.05f32), (0.3, 0.3), (1.0, 1.0), (0.05, 0.5)] {
        for fresnel in fresnels() {
            let ms = GgxConductorMs::new(GgxConductor::new(ax, ay, fresnel));
            for inc in [0.0f32, 45.0, 80.0, 89.0] {
                let wo = wo_at(inc);
                let p_ms = ms.ms_probability(wo);
                for sampling in Sampling::ALL {
                    let mut u = Uniforms::new(checked);
                    for _ in 0..500 {
                        let ul = u.next();
                        let Some(s) = ms.sample(wo, u.next(), ul.x, sampling) else { continue };
                        assert!(!s.is_delta && s.wi.z > 0.0);
                        ms_lobe += (ul.x < p_ms) as u64;
                        let pdf = ms.pdf(wo, s.wi, sampling);
                        assert_eq!(s.pdf, pdf);
                        let expect = ms.eval(wo, s.wi) / pdf;
                        let e = ((s.weight - expect).abs() / expect.abs().max(Vec3::splat(1e-6))).max_element();
                        worst = worst.max(e);
                        assert!(e < 1e-5, "{sampling:?}: weight {} vs {expect}", s.weight);
                        checked += 1;
                    }
                }
            }
        }
    }
    println!("{checked} samples ({ms_lobe} from the compensation lobe), worst weight error {worst:.2e}");
    assert!(ms_lobe > 1000);
}

/// `compensation = 0` (and a mirror) is exactly `GgxConductor`, bit for bit.
#[test]
fn without_compensation_it_is_the_conductor() {
    let mut u = Uniforms::new(11);
    for alpha in [0.0f32, 0.3, 1.0] {
        let c = GgxConductor::isotropic(alpha, fresnels()[1]);
        let mut off = GgxConductorMs::new(c);
        if alpha > 0.0 {
            off.compensation = 0;
        }
        for _ in 0..2000 {
            let (wo, wi, uu, ul) = (
                ggx_core::warp::sample_uniform_hemisphere(u.next()),
                ggx_core::warp::sample_uniform_hemisphere(u.next()),
                u.next(),
                u.next().x,
            );
            assert_eq!(off.eval(wo, wi), c.eval(wo, wi));
            assert_eq!(off.pdf(wo, wi, Sampling::Vndf), c.pdf(wo, wi, Sampling::Vndf));
            assert_eq!(off.sample(wo, uu, ul, Sampling::Vndf), c.sample(wo, uu, Sampling::Vndf));
        }
    }
}

/// Monte Carlo furnace through the compensated sampler: the mean weight with `F = 1` is 1
/// (within 4 standard errors), so sampling, pdf and eval agree on the integral.
#[test]
fn sampler_estimates_unit_albedo() {
    for (alpha, inc) in [(0.3f32, 30.0f32), (1.0, 0.0), (1.0, 80.0), (0.6, 60.0)] {
        let ms = GgxConductorMs::new(GgxConductor::isotropic(alpha, Fresnel::One));
        let wo = wo_at(inc);
        let mut u = Uniforms::new(alpha.to_bits() as u64 ^ inc.to_bits() as u64);
        let n = 200_000;
        let (mut s1, mut s2) = (0.0f64, 0.0f64);
        for _ in 0..n {
            let ul = u.next().x;
            let w = ms.sample(wo, u.next(), ul, Sampling::Vndf).map_or(0.0, |s| s.weight.x as f64);
            s1 += w;
            s2 += w * w;
        }
        let mean = s1 / n as f64;
        let sigma = ((s2 / n as f64 - mean * mean).max(0.0) / n as f64).sqrt();
        println!("alpha {alpha} inc {inc}: mean weight {mean:.5} +- {sigma:.1e}");
        assert!((mean - 1.0).abs() < 4.0 * sigma + 0.01, "alpha {alpha} inc {inc}: {mean}");
    }
}

/// Chi-square of the mixture sampler against `pdf()` (both lobes; `u_lobe` from a second
/// stream), 4 configurations x 2 techniques, Sidak-corrected 0.01; a density without the
/// compensation lobe must be rejected.
#[test]
fn chi2_compensated_sampler() {
    const TESTS: usize = 8;
    let significance = sidak_significance(0.01, TESTS);
    let configs = [((0.3f32, 0.3f32), 30.0f32), ((1.0, 1.0), 0.0), ((0.6, 0.6), 80.0), ((0.1, 0.5), 60.0)];
    let mut failures = vec![];
    for (i, ((ax, ay), inc)) in configs.into_iter().enumerate() {
        let ms = GgxConductorMs::new(GgxConductor::new(ax, ay, Fresnel::One));
        let wo = wo_at(inc);
        for sampling in [Sampling::Vndf, Sampling::Bounded] {
            let mut lobe = Uniforms::new(1000 + i as u64);
            let cfg = Chi2Config { seed: (i as u64) << 8 | sampling as u64, samples: 300_000, ..Chi2Config::default() };
            let outcome = chi2_test(
                &cfg,
                |u| ms.sample(wo, u, lobe.next().x, sampling).map(|s| s.wi),
                |wi| ms.pdf(wo, wi, sampling) as f64,
            );
            let line = format!("a=({ax},{ay}) {inc} deg {}: {}", sampling.name(), outcome.summary());
            println!("{line}");
            if !outcome.passes(significance) {
                failures.push(line);
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    // Power: the single-scattering pdf alone does not describe the mixture.
    let ms = GgxConductorMs::new(GgxConductor::isotropic(1.0, Fresnel::One));
    let wo = wo_at(0.0);
    let mut lobe = Uniforms::new(7);
    let outcome = chi2_test(
        &Chi2Config { samples: 300_000, ..Chi2Config::default() },
        |u| ms.sample(wo, u, lobe.next().x, Sampling::Vndf).map(|s| s.wi),
        |wi| ms.conductor.pdf(wo, wi, Sampling::Vndf) as f64,
    );
    println!("mismatch: {}", outcome.summary());
    assert!(!outcome.passes(significance));
}
