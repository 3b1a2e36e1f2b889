//! Chi-square goodness of fit of every sampler against its claimed density (the pbrt-v4 /
//! Mitsuba 3 protocol, see `support/chi2.rs`): alpha {0.05, 0.1, 0.3, 0.7, 1.0} and the
//! anisotropic pairs (0.05, 0.5), (0.5, 0.05); incidence {0, 30, 60, 80, 89} degrees;
//! 10^6 samples each, significance 0.01 with a Sidak correction over all 210 tests; a
//! sample in a zero-density cell, a non-unit or below-horizon sample, or a density that
//! integrates to more than one fails outright. Samples lost below the horizon form their
//! own bin, so the rate of `None` is tested too.

mod support;
mod util;

use ggx_core::{Fresnel, GgxConductor, Sampling};
use support::chi2::{Chi2Config, chi2_test, sidak_significance};
use util::{INCIDENCES_DEG, alpha_pairs, wo_at};

const TESTS: usize = 7 * 5 * 6;

fn run(sampling: Sampling) {
    let significance = sidak_significance(0.01, TESTS);
    let mut failures = vec![];
    let mut min_p = 1.0f64;
    for (i, (ax, ay)) in alpha_pairs().into_iter().enumerate() {
        let brdf = GgxConductor::new(ax, ay, Fresnel::One);
        for (j, inc) in INCIDENCES_DEG.into_iter().enumerate() {
            let wo = wo_at(inc);
            let cfg =
                Chi2Config { seed: (sampling as u64) << 16 | (i as u64) << 8 | j as u64, ..Chi2Config::default() };
            let outcome =
                chi2_test(&cfg, |u| brdf.sample(wo, u, sampling).map(|s| s.wi), |wi| brdf.pdf(wo, wi, sampling) as f64);
            min_p = min_p.min(outcome.p_value);
            let line = format!("{:<14} a=({ax:<4},{ay:<4}) {inc:>2} deg  {}", sampling.name(), outcome.summary());
            println!("{line}");
            if !outcome.passes(significance) {
                failures.push(line);
            }
        }
    }
    println!("{}: 35 tests, smallest p-value {min_p:.3e}, threshold {significance:.3e}", sampling.name());
    assert!(failures.is_empty(), "chi-square failures:\n{}", failures.join("\n"));
}

#[test]
fn chi2_ndf() {
    run(Sampling::Ndf);
}

#[test]
fn chi2_vndf() {
    run(Sampling::Vndf);
}

#[test]
fn chi2_spherical_caps() {
    run(Sampling::SphericalCaps);
}

#[test]
fn chi2_bounded() {
    run(Sampling::Bounded);
}

#[test]
fn chi2_cosine() {
    run(Sampling::Cosine);
}

#[test]
fn chi2_uniform() {
    run(Sampling::Uniform);
}

/// The test has power on these very lobes: VNDF samples checked against the NDF density
/// (both correct distributions of *something*, differing by a few percent) must fail.
#[test]
fn chi2_rejects_a_mismatched_density() {
    let brdf = GgxConductor::isotropic(0.3, Fresnel::One);
    let wo = wo_at(60.0);
    let outcome = chi2_test(
        &Chi2Config::default(),
        |u| brdf.sample(wo, u, Sampling::Vndf).map(|s| s.wi),
        |wi| brdf.pdf(wo, wi, Sampling::Ndf) as f64,
    );
    println!("mismatch: {}", outcome.summary());
    assert!(!outcome.passes(sidak_significance(0.01, TESTS)));
}
