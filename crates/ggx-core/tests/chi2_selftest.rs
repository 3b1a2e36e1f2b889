//! Self-tests of the chi-square test support module (`tests/support`): the
//! chi-square survival function against reference values, correct samplers
//! passing and wrong samplers failing. Uses only the support module, glam and
//! the random number crates, so it does not depend on the crate's API.

mod support;

use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI, TAU};
use std::time::Instant;

use glam::{Vec2, Vec3};
use support::chi2::*;
use support::quadrature::{AdaptiveTolerance, Rect, gauss_legendre_5x5, integrate_adaptive};

/// Significance for the samplers that must pass: 1% overall over the three
/// correct-sampler tests.
fn significance() -> f64 {
    sidak_significance(0.01, 3)
}

fn assert_rel(actual: f64, expected: f64, rel: f64, what: &str) {
    let err = ((actual - expected) / expected).abs();
    assert!(err <= rel, "{what}: got {actual:e}, expected {expected:e} (relative error {err:e} > {rel:e})");
}

#[test]
fn chi2_survival_matches_reference_values() {
    // (dof, x, Q) with Q from mpmath's regularized upper incomplete gamma at
    // 40 digits.
    let table: [(f64, f64, f64); 17] = [
        (1.0, 3.841458820694124, 0.05000000000000006),
        (10.0, 23.209251158954356, 0.010000000000000012),
        (100.0, 135.80672317102676, 0.010000000000000031),
        (5000.0, 5000.0, 0.4973403788923451),
        (5000.0, 5300.0, 0.0015958249441347307),
        (5000.0, 4700.0, 0.9988765386162006),
        (5000.0, 5500.0, 6.203019945328596e-07),
        (5000.0, 6000.0, 2.5217184417547448e-21),
        (20000.0, 20500.0, 0.006517863488342559),
        (999.0, 1000.0, 0.48513148927490146),
        (3.0, 0.01, 0.9997348349413444),
        (1.0, 1e-6, 0.9992021155721779),
        (1.0, 0.5, 0.4795001221869535),
        (50.0, 20.0, 0.9999530506185732),
        (7.0, 200.0, 1.1477812240142598e-39),
        (2.0, 1400.0, 9.85967654375977e-305),
        (1.0, 700.0, 2.9902269751246203e-154),
    ];
    for (dof, x, q) in table {
        assert_rel(chi2_survival(x, dof), q, 1e-10, &format!("Q(dof {dof}, x {x})"));
    }
    // Closed forms: dof 2 gives exp(-x/2), dof 4 gives exp(-x/2) (1 + x/2).
    for x in [1e-3, 0.5, 1.0, 2.0, 3.0, 10.0, 50.0, 300.0] {
        assert_rel(chi2_survival(x, 2.0), (-x / 2.0).exp(), 1e-12, "dof 2");
        let q4 = (-x / 2.0).exp() * (1.0 + x / 2.0);
        assert_rel(chi2_survival(x, 4.0), q4, 1e-12, "dof 4");
    }
    // Edge cases and monotonicity at large dof.
    assert_eq!(chi2_survival(0.0, 3.0), 1.0);
    assert_eq!(chi2_survival(-1.0, 3.0), 1.0);
    assert_eq!(chi2_survival(f64::INFINITY, 3.0), 0.0);
    assert!(chi2_survival(f64::NAN, 3.0).is_nan());
    let mut last = 1.0;
    for i in 0..=100 {
        let q = chi2_survival(4000.0 + 20.0 * i as f64, 5000.0);
        assert!((0.0..=last).contains(&q), "not monotonic at step {i}");
        last = q;
    }
}

/// Independent reference for even dof: `Q(k, x) = P(Poisson(x) < k)`, summed
/// from term ratios around the mode so that no gamma function is involved.
fn poisson_cdf_below(k: usize, x: f64) -> f64 {
    let mode = x.floor() as usize;
    let (mut below, mut total) = (0.0, 0.0);
    // Terms relative to the mode's term, walking down then up.
    let mut t = 1.0;
    for j in (0..=mode).rev() {
        total += t;
        if j < k {
            below += t;
        }
        t *= j as f64 / x;
        if t < 1e-300 {
            break;
        }
    }
    let mut t = 1.0;
    for j in mode + 1.. {
        t *= x / j as f64;
        total += t;
        if j < k {
            below += t;
        }
        if t < 1e-18 * total {
            break;
        }
    }
    below / total
}

#[test]
fn chi2_survival_matches_poisson_sums_at_large_dof() {
    for (dof, x) in [(5000, 4800.0), (5000, 5000.0), (5000, 5200.0), (2000, 2100.0)] {
        let reference = poisson_cdf_below(dof / 2, x / 2.0);
        assert_rel(chi2_survival(x, dof as f64), reference, 1e-9, "even dof");
    }
}

#[test]
fn sidak_significance_matches_definition() {
    assert_rel(sidak_significance(0.01, 1), 0.01, 1e-14, "one test");
    let s = sidak_significance(0.01, 20);
    assert_rel(1.0 - (1.0 - s).powi(20), 0.01, 1e-12, "20 tests");
    assert!(s < 0.01 / 20.0 * 1.01 && s > 0.01 / 20.0);
}

// --- Samplers -------------------------------------------------------------

/// Minimal f64 vector helpers (glam's f64 types are not enabled in the crate).
type D3 = [f64; 3];

fn add(a: D3, b: D3) -> D3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

fn scale(a: D3, s: f64) -> D3 {
    [a[0] * s, a[1] * s, a[2] * s]
}

fn dot(a: D3, b: D3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: D3, b: D3) -> D3 {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

fn normalize(a: D3) -> D3 {
    scale(a, 1.0 / dot(a, a).sqrt())
}

fn to_f64(w: Vec3) -> D3 {
    [w.x as f64, w.y as f64, w.z as f64]
}

fn to_f32(a: D3) -> Vec3 {
    Vec3::new(a[0] as f32, a[1] as f32, a[2] as f32)
}

/// Shirley-Chiu concentric map of `[0,1)^2` onto the unit disk.
fn concentric_disk(u: Vec2) -> (f64, f64) {
    let (ox, oy) = (2.0 * u.x as f64 - 1.0, 2.0 * u.y as f64 - 1.0);
    if ox == 0.0 && oy == 0.0 {
        return (0.0, 0.0);
    }
    let (r, angle) =
        if ox.abs() > oy.abs() { (ox, FRAC_PI_4 * (oy / ox)) } else { (oy, FRAC_PI_2 - FRAC_PI_4 * (ox / oy)) };
    (r * angle.cos(), r * angle.sin())
}

/// Cosine-weighted hemisphere sampling (Malley's method).
fn sample_cosine(u: Vec2) -> Option<Vec3> {
    let (x, y) = concentric_disk(u);
    let z = (1.0 - x * x - y * y).max(0.0).sqrt();
    Some(to_f32(normalize([x, y, z])))
}

fn pdf_cosine(w: Vec3) -> f64 {
    if w.z > 0.0 { w.z as f64 / PI } else { 0.0 }
}

fn pdf_uniform(w: Vec3) -> f64 {
    if w.z > 0.0 { 1.0 / TAU } else { 0.0 }
}

/// Phong-like lobe `(n + 1) / (2 pi) cos^n` around an axis tilted from +z
/// towards +x; samples below the horizon are rejected.
#[derive(Clone, Copy)]
struct Lobe {
    exponent: f64,
    axis: D3,
    tangent: D3,
}

impl Lobe {
    fn new(exponent: f64, tilt_degrees: f64) -> Self {
        let (s, c) = tilt_degrees.to_radians().sin_cos();
        Self { exponent, axis: [s, 0.0, c], tangent: [c, 0.0, -s] }
    }

    /// Inverts the marginal CDF `P(cos <= c) = c^(n+1)`, in f64 and using
    /// `1 - u` so that no sample lands exactly at 90 degrees from the axis.
    fn sample(&self, u: Vec2) -> Option<Vec3> {
        let e = (1.0 - u.x as f64).ln() / (self.exponent + 1.0);
        let cos_t = e.exp();
        let sin_t = (-(2.0 * e).exp_m1()).sqrt();
        let (sin_p, cos_p) = (TAU * u.y as f64).sin_cos();
        let bitangent = cross(self.axis, self.tangent);
        let w = add(add(scale(self.tangent, sin_t * cos_p), scale(bitangent, sin_t * sin_p)), scale(self.axis, cos_t));
        (w[2] > 0.0).then(|| to_f32(w))
    }

    fn pdf(&self, w: Vec3) -> f64 {
        if w.z <= 0.0 {
            return 0.0;
        }
        let c = dot(normalize(to_f64(w)), self.axis).max(0.0);
        (self.exponent + 1.0) / TAU * c.powf(self.exponent)
    }
}

/// A small configuration for the tests of hard failures.
fn small_config() -> Chi2Config {
    Chi2Config { theta_bins: 9, phi_bins: 17, samples: 20_000, ..Chi2Config::default() }
}

// --- Quadrature -----------------------------------------------------------

#[test]
fn gauss_legendre_is_exact_for_degree_nine() {
    let rect = Rect::new(-0.5, 1.5, 0.25, 2.0);
    let got = gauss_legendre_5x5(&rect, |x| x, |y| y, |x, y| x.powi(9) * y.powi(8) + 3.0 * x * y);
    let px = |x: f64| x.powi(10) / 10.0;
    let py = |y: f64| y.powi(9) / 9.0;
    let exact =
        (px(1.5) - px(-0.5)) * (py(2.0) - py(0.25)) + 3.0 * (1.5f64.powi(2) - 0.25) / 2.0 * (4.0 - 0.0625) / 2.0;
    assert_rel(got, exact, 1e-13, "degree 9");
}

#[test]
fn adaptive_quadrature_integrates_a_narrow_gaussian() {
    // A 2D Gaussian of width 1e-2 off-center in the unit square; its integral
    // over the plane is 1 and the square holds all of it.
    let sigma = 1e-2;
    let f = |x: f64, y: f64| {
        let (dx, dy) = (x - 0.3141, y - 0.2718);
        (-(dx * dx + dy * dy) / (2.0 * sigma * sigma)).exp() / (TAU * sigma * sigma)
    };
    let tol = AdaptiveTolerance { rel: 1e-10, abs: 1e-12, max_depth: 20 };
    let result =
        integrate_adaptive(Rect::new(0.0, 1.0, 0.0, 1.0), None, tol, |r| gauss_legendre_5x5(r, |x| x, |y| y, f));
    assert_rel(result.value, 1.0, 1e-9, "narrow Gaussian");
    assert_eq!(result.unconverged, 0);
    assert!(result.rule_applications < 10_000, "{result:?}");
}

#[test]
fn cell_integrals_of_a_peaked_lobe_match_closed_form() {
    // Around the pole the lobe's mass in the ring theta in [a, b] is
    // cos^(n+1) a - cos^(n+1) b; tilted, its total is 1.
    let d_theta = FRAC_PI_2 / 51.0;
    for exponent in [2000.0, 100_000.0] {
        let lobe = Lobe::new(exponent, 0.0);
        let cells = integrate_cells(51, 101, |w| lobe.pdf(w));
        assert_eq!(cells.unconverged_regions, 0);
        assert!(cells.pdf_evals < 3_000_000, "{}", cells.pdf_evals);
        for it in 0..51 {
            let ring: f64 = (0..101).map(|ip| cells.cell(it, ip)).sum();
            let (a, b) = (it as f64 * d_theta, (it + 1) as f64 * d_theta);
            let exact = a.cos().powf(exponent + 1.0) - b.cos().powf(exponent + 1.0);
            assert!((ring - exact).abs() <= 1e-7 * exact + 1e-8, "n {exponent}, ring {it}: {ring:e} vs {exact:e}");
        }
        let tilted = Lobe::new(exponent, 45.0);
        let cells = integrate_cells(51, 101, |w| tilted.pdf(w));
        assert_rel(cells.total(), 1.0, 1e-6, "tilted lobe total");
    }
}

// --- Correct samplers pass ------------------------------------------------

#[test]
fn cosine_sampler_passes() {
    let outcome = chi2_test(&Chi2Config::default(), sample_cosine, pdf_cosine);
    println!("cosine: {}", outcome.summary());
    assert!(outcome.passes(significance()), "{}", outcome.summary());
    assert_rel(outcome.pdf_integral, 1.0, 1e-6, "cosine pdf integral");
    assert_eq!(outcome.lost_observed, 0);
}

#[test]
fn peaked_lobe_at_pole_passes() {
    let lobe = Lobe::new(2000.0, 0.0);
    let start = Instant::now();
    let outcome = chi2_test(&Chi2Config::default(), |u| lobe.sample(u), |w| lobe.pdf(w));
    println!(
        "lobe n=2000 at pole: {:.3} s, {} pdf evals: {}",
        start.elapsed().as_secs_f64(),
        outcome.pdf_evals,
        outcome.summary()
    );
    assert!(outcome.passes(significance()), "{}", outcome.summary());
    assert_rel(outcome.pdf_integral, 1.0, 1e-6, "lobe pdf integral");
    assert!(outcome.pdf_evals < 3_000_000, "{}", outcome.summary());
}

#[test]
fn lobe_tilted_to_85_degrees_passes_with_lost_samples() {
    let lobe = Lobe::new(2000.0, 85.0);
    let start = Instant::now();
    let outcome = chi2_test(&Chi2Config::default(), |u| lobe.sample(u), |w| lobe.pdf(w));
    println!(
        "lobe n=2000 at 85 deg: {:.3} s, {} pdf evals: {}",
        start.elapsed().as_secs_f64(),
        outcome.pdf_evals,
        outcome.summary()
    );
    assert!(outcome.passes(significance()), "{}", outcome.summary());
    // The lost bin is large enough to be a bin of its own and was exercised.
    assert!(outcome.lost_expected >= 5.0, "{}", outcome.summary());
    assert!(outcome.lost_observed > 0, "{}", outcome.summary());
    assert!(outcome.pdf_evals < 3_000_000, "{}", outcome.summary());
}

// --- Wrong samplers fail --------------------------------------------------

#[test]
fn cosine_samples_against_uniform_pdf_fail() {
    let outcome = chi2_test(&Chi2Config::default(), sample_cosine, pdf_uniform);
    println!("cosine vs uniform: {}", outcome.summary());
    assert!(outcome.failure.is_none(), "{}", outcome.summary());
    assert!(!outcome.passes(1e-6), "{}", outcome.summary());
}

#[test]
fn lobe_exponent_mismatch_fails() {
    let sampled = Lobe::new(2000.0, 0.0);
    let claimed = Lobe::new(1900.0, 0.0);
    let outcome = chi2_test(&Chi2Config::default(), |u| sampled.sample(u), |w| claimed.pdf(w));
    println!("lobe 2000 vs 1900: {}", outcome.summary());
    assert!(outcome.failure.is_none(), "{}", outcome.summary());
    assert!(!outcome.passes(1e-6), "{}", outcome.summary());
}

/// The tilted lobe, additionally rejecting `u.x < fraction`; the remaining
/// `u.x` is remapped so that the accepted samples keep the right shape and
/// only their number is wrong.
fn lossy_lobe_outcome(fraction: f32) -> Chi2Outcome {
    let lobe = Lobe::new(2000.0, 85.0);
    let sample = |u: Vec2| {
        if u.x < fraction {
            return None;
        }
        lobe.sample(Vec2::new((u.x - fraction) / (1.0 - fraction), u.y))
    };
    chi2_test(&Chi2Config::default(), sample, |w| lobe.pdf(w))
}

#[test]
fn sampler_losing_one_percent_more_fails() {
    let outcome = lossy_lobe_outcome(0.01);
    println!("lobe losing 1%: {}", outcome.summary());
    assert!(outcome.failure.is_none(), "{}", outcome.summary());
    assert!(!outcome.passes(1e-6), "{}", outcome.summary());
    assert!(outcome.lost_observed > 9_000, "{}", outcome.summary());
}

#[test]
fn sampler_losing_a_fifth_of_a_percent_more_fails_through_the_lost_bin() {
    // Spread over the cells a 0.2% deficit is invisible (about 4 units of
    // chi^2 at 5000 dof); only the lost bin sees it.
    let outcome = lossy_lobe_outcome(0.002);
    println!("lobe losing 0.2%: {}", outcome.summary());
    assert!(!outcome.passes(1e-6), "{}", outcome.summary());
    assert!(outcome.worst_bin.starts_with("lost"), "{}", outcome.summary());
}

#[test]
fn sample_in_zero_pdf_region_fails() {
    // Every 10^5th sample goes to 60 degrees from the axis, where cos^2000
    // underflows to exactly 0.
    let lobe = Lobe::new(2000.0, 0.0);
    let (s, c) = 60f64.to_radians().sin_cos();
    let stray = to_f32([s, 0.0, c]);
    let mut calls = 0u64;
    let sample = |u: Vec2| {
        calls += 1;
        if calls.is_multiple_of(100_000) { Some(stray) } else { lobe.sample(u) }
    };
    let outcome = chi2_test(&Chi2Config::default(), sample, |w| lobe.pdf(w));
    println!("zero-pdf region: {}", outcome.summary());
    let failure = outcome.failure.as_deref().unwrap_or("");
    assert!(failure.contains("zero expected count"), "{}", outcome.summary());
    assert!(!outcome.passes(0.0));
}

#[test]
fn invalid_samples_fail() {
    type Sampler = fn(Vec2) -> Option<Vec3>;
    let cases: [(&str, Sampler, &str); 4] = [
        ("NaN", |u| sample_cosine(u).map(|w| if u.x < 1e-3 { Vec3::NAN } else { w }), "non-finite"),
        ("inf", |u| sample_cosine(u).map(|w| if u.x < 1e-3 { w * f32::INFINITY } else { w }), "non-finite"),
        ("non-unit", |u| sample_cosine(u).map(|w| if u.x < 1e-3 { w * 1.001 } else { w }), "non-unit"),
        ("below horizon", |u| sample_cosine(u).map(|w| if u.x < 1e-3 { -w } else { w }), "below the horizon"),
    ];
    for (name, sampler, expected) in cases {
        let outcome = chi2_test(&small_config(), sampler, pdf_cosine);
        let failure = outcome.failure.as_deref().unwrap_or("");
        assert!(failure.contains(expected), "{name}: {}", outcome.summary());
        assert!(!outcome.passes(0.0), "{name}");
    }
    // The unmodified sampler passes with the small configuration.
    let outcome = chi2_test(&small_config(), sample_cosine, pdf_cosine);
    assert!(outcome.passes(0.01), "{}", outcome.summary());
}

#[test]
fn invalid_pdfs_fail() {
    let too_large = chi2_test(&small_config(), sample_cosine, |w| 2.0 * pdf_cosine(w));
    let failure = too_large.failure.as_deref().unwrap_or("");
    assert!(failure.contains("above 1"), "{}", too_large.summary());
    assert_rel(too_large.pdf_integral, 2.0, 1e-6, "doubled pdf");

    let negative = chi2_test(&small_config(), sample_cosine, |w| if w.x > 0.9 { -1.0 } else { pdf_cosine(w) });
    let failure = negative.failure.as_deref().unwrap_or("");
    assert!(failure.contains("invalid pdf value"), "{}", negative.summary());

    let nan = chi2_test(&small_config(), sample_cosine, |w| if w.y > 0.9 { f64::NAN } else { pdf_cosine(w) });
    let failure = nan.failure.as_deref().unwrap_or("");
    assert!(failure.contains("invalid pdf value"), "{}", nan.summary());
}
