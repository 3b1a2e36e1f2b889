//! Chi-square goodness of fit of `GgxDielectric::sample` against `pdf` on the whole sphere
//! (reflection and transmission, `wo` on both sides), support/chi2.rs with
//! `Chi2Config::sphere()` (102 x 101 bins, 10^6 samples, lost-sample bin, significance 0.01
//! with a Sidak correction over the run). The default grid is small for CI;
//! `GGX_CHI2_FULL=1` runs every sampler x eta {1.5, 1/1.5, 1.33, 2.4} x alpha
//! {1e-3, 0.05, 0.3, 1, (0.05, 0.5)} x view {0, 60, 85, 89.5 degrees, outside and inside}.
//! The last test proves the suite rejects a density without the transmission Jacobian and
//! one without its `eta'^2` (pbrt-v4 #30).

mod support;

use ggx_core::{GgxDielectric, Sampling, TransportMode, Vec3};
use rand_core::{Rng, SeedableRng};
use support::chi2::{Chi2Config, Chi2Outcome, chi2_test, sidak_significance};

const ETAS: [f32; 4] = [1.5, 1.0 / 1.5, 1.33, 2.4];

fn wo_at(deg: f64, inside: bool) -> Vec3 {
    let (t, p) = (deg.to_radians(), 0.7f64);
    let z = if inside { -t.cos() } else { t.cos() };
    Vec3::new((t.sin() * p.cos()) as f32, (t.sin() * p.sin()) as f32, z as f32)
}

/// One test; `pdf_fix` lets the self-test corrupt the density.
fn run_one(
    b: &GgxDielectric,
    wo: Vec3,
    sampling: Sampling,
    seed: u64,
    pdf_fix: impl Fn(Vec3, f64) -> f64,
) -> Chi2Outcome {
    let cfg = Chi2Config { seed, ..Chi2Config::sphere() };
    let mut lobe_rng = rand_pcg::Pcg64::seed_from_u64(seed ^ 0x10be);
    let m = TransportMode::Radiance;
    chi2_test(
        &cfg,
        |u| {
            let ul = (lobe_rng.next_u32() >> 8) as f32 / 16_777_216.0;
            b.sample(wo, u, ul, sampling, m).map(|s| s.wi)
        },
        |wi| pdf_fix(wi, b.pdf(wo, wi, sampling, m) as f64),
    )
}

/// (sampler, eta, alphas, view degrees, inside).
type Case = (Sampling, f32, (f32, f32), f64, bool);

fn grid() -> Vec<Case> {
    let full = std::env::var("GGX_CHI2_FULL").is_ok_and(|v| v == "1");
    let mut v = vec![];
    if full {
        for s in [Sampling::Ndf, Sampling::Vndf, Sampling::SphericalCaps, Sampling::Bounded] {
            for eta in ETAS {
                for a in [(1e-3, 1e-3), (0.05, 0.05), (0.3, 0.3), (1.0, 1.0), (0.05, 0.5)] {
                    for deg in [0.0, 60.0, 85.0, 89.5] {
                        for inside in [false, true] {
                            v.push((s, eta, a, deg, inside));
                        }
                    }
                }
            }
        }
    } else {
        // Every sampler and eta, both sides, alphas from 1e-3 to 1, down to grazing.
        let picks: [((f32, f32), f64); 4] =
            [((0.3, 0.3), 60.0), ((1e-3, 1e-3), 30.0), ((1.0, 1.0), 89.5), ((0.05, 0.5), 85.0)];
        for (i, s) in [Sampling::Ndf, Sampling::Vndf, Sampling::SphericalCaps].into_iter().enumerate() {
            for (j, eta) in ETAS.into_iter().enumerate() {
                let (a, deg) = picks[(i + j) % 4];
                v.push((s, eta, a, deg, (i + j) % 2 == 1));
            }
        }
    }
    v
}

#[test]
fn chi2_dielectric_on_the_sphere() {
    let grid = grid();
    let significance = sidak_significance(0.01, grid.len());
    let (mut failures, mut min_p) = (vec![], 1.0f64);
    for (k, &(s, eta, (ax, ay), deg, inside)) in grid.iter().enumerate() {
        let b = GgxDielectric::new(ax, ay, eta);
        let o = run_one(&b, wo_at(deg, inside), s, 0xd1e1 + k as u64, |_, p| p);
        min_p = min_p.min(o.p_value);
        let side = if inside { "in " } else { "out" };
        let line = format!("{:<14} eta {eta:<6.4} a=({ax},{ay}) {deg:>4} deg {side}  {}", s.name(), o.summary());
        println!("{line}");
        if !o.passes(significance) {
            failures.push(line);
        }
    }
    println!("{} tests, smallest p-value {min_p:.3e}, threshold {significance:.3e}", grid.len());
    assert!(failures.is_empty(), "chi-square failures:\n{}", failures.join("\n"));
}

/// The suite has power on the transmitted lobe: dropping the Jacobian `dwm/dwi` (the
/// density of the normal instead of the direction) or its `eta'^2` (pbrt-v4 #30) is rejected.
#[test]
fn chi2_rejects_a_wrong_transmission_density() {
    let significance = sidak_significance(0.01, grid().len());
    for eta in [1.5f32, 1.0 / 1.5] {
        let b = GgxDielectric::isotropic(0.3, eta);
        let wo = wo_at(30.0, false);
        let etap = if wo.z > 0.0 { eta } else { 1.0 / eta } as f64;
        let missing_eta2 = |wi: Vec3, p: f64| if wi.z * wo.z < 0.0 { p / (etap * etap) } else { p };
        let missing_jacobian = |wi: Vec3, p: f64| {
            if wi.z * wo.z >= 0.0 {
                return p;
            }
            let wm = (wo + etap as f32 * wi).normalize();
            let (co, ci) = ((wo.dot(wm)) as f64, (wi.dot(wm)) as f64);
            p / (etap * etap * ci.abs() / ((co + etap * ci) * (co + etap * ci)))
        };
        let o = run_one(&b, wo, Sampling::Vndf, 1, missing_eta2);
        println!("eta {eta}, missing eta'^2: {}", o.summary());
        assert!(!o.passes(significance));
        let o = run_one(&b, wo, Sampling::Vndf, 2, missing_jacobian);
        println!("eta {eta}, missing Jacobian: {}", o.summary());
        assert!(!o.passes(significance));
    }
}
