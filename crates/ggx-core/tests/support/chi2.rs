//! Pearson chi-square goodness-of-fit test of a hemispherical direction
//! sampler against the solid-angle pdf it claims.
//!
//! The protocol follows pbrt-v4 (`bsdfs_test.cpp`) and Mitsuba 3 (`chi2.py`):
//! draw many samples, histogram them on a (theta, phi) grid over the upper
//! hemisphere, integrate the claimed pdf over every cell to get the expected
//! counts, pool cells with small expected counts and compare with Pearson's
//! statistic. Samples the sampler rejects (`None`) form one extra "lost" bin
//! whose expected count is the pdf mass missing from the upper hemisphere (or the
//! sphere, with `Chi2Config::sphere` for transmitting BSDFs).
//!
//! ```ignore
//! mod support;
//! use support::chi2::*;
//!
//! let cfg = Chi2Config::default();
//! let outcome = chi2_test(&cfg, |u| my_sample(u), |w| my_pdf(w));
//! assert!(outcome.passes(sidak_significance(0.01, 10)), "{}", outcome.summary());
//! ```

use core::f64::consts::{FRAC_PI_2, PI, TAU};

use glam::{Vec2, Vec3};
use rand_core::{Rng, SeedableRng};
use rand_pcg::Pcg64;

use super::quadrature::{AdaptiveTolerance, Rect, gauss_legendre_5x5, integrate_adaptive};

/// Tolerances of the per-cell pdf integration: a region is accepted when the
/// 5x5 Gauss-Legendre estimate and the sum over its four quadrants agree to
/// 1e-7 relative or 1e-9 absolute (in probability, i.e. 1e-3 expected samples
/// per region at 10^6 samples); at most 12 levels of subdivision.
pub const INTEGRATION_TOLERANCE: AdaptiveTolerance = AdaptiveTolerance { rel: 1e-7, abs: 1e-9, max_depth: 12 };

/// Total expected count below which cells are treated as having zero
/// probability: a cell is "empty" when its expected count is below
/// `EMPTY_CELLS_TOTAL_EXPECTED / cells`. Even if all such cells really held that
/// much probability, a correct sampler would put a sample into any of them with
/// probability at most 1e-6 (union bound), so one sample there is a hard failure.
pub const EMPTY_CELLS_TOTAL_EXPECTED: f64 = 1e-6;

/// Largest accepted deviation of a sample's length from 1.
pub const UNIT_LENGTH_TOLERANCE: f64 = 1e-4;

/// Largest accepted integral of the pdf over the upper hemisphere.
pub const MAX_PDF_INTEGRAL: f64 = 1.0 + 1e-3;

/// Parameters of [`chi2_test`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Chi2Config {
    /// Number of bins uniform in theta over `[0, pi/2]` (upper hemisphere).
    pub theta_bins: usize,
    /// Number of bins uniform in phi over `[0, 2 pi)`. An odd count keeps
    /// features at phi = pi (e.g. the mirror direction of an incident
    /// direction in the xz-plane) off the bin edges.
    pub phi_bins: usize,
    /// Number of sampler calls.
    pub samples: usize,
    /// Seed of the `Pcg64` generating the uniform sample points `u`.
    pub seed: u64,
    /// Cells with a smaller expected count are pooled into one bin.
    pub min_expected: f64,
    /// Bin the whole sphere (theta over `[0, pi]`, for BSDFs that transmit) instead of the
    /// upper hemisphere; samples below the horizon are then valid. Use an even
    /// `theta_bins` so that the horizon is a bin edge.
    pub sphere: bool,
}

impl Default for Chi2Config {
    /// 51 x 101 bins, 10^6 samples, seed 0x5eed, pooling threshold 5.
    fn default() -> Self {
        Self { theta_bins: 51, phi_bins: 101, samples: 1_000_000, seed: 0x5eed, min_expected: 5.0, sphere: false }
    }
}

impl Chi2Config {
    /// The whole-sphere configuration: 102 x 101 bins (the hemisphere's resolution on both
    /// sides, the horizon on a bin edge), 10^6 samples.
    pub fn sphere() -> Self {
        Self { theta_bins: 102, sphere: true, ..Self::default() }
    }

    /// Upper end of the theta range: `pi / 2`, or `pi` for the sphere.
    pub fn theta_max(&self) -> f64 {
        if self.sphere { PI } else { FRAC_PI_2 }
    }
}

/// Result of [`chi2_test`].
#[derive(Debug, Clone, PartialEq)]
pub struct Chi2Outcome {
    /// Pearson's statistic over the (pooled) bins.
    pub statistic: f64,
    /// Degrees of freedom: number of bins - 1.
    pub dof: usize,
    /// Probability that a correct sampler gives a statistic at least this large.
    pub p_value: f64,
    /// Number of sampler calls that returned `Some`.
    pub accepted: u64,
    /// Number of sampler calls that returned `None`.
    pub lost_observed: u64,
    /// Expected number of `None`s: `samples * (1 - pdf_integral)`, clamped at 0.
    pub lost_expected: f64,
    /// Integral of the pdf over the upper hemisphere.
    pub pdf_integral: f64,
    /// Hard failures (invalid samples, samples in empty cells, pdf integral
    /// above 1, invalid pdf values); `None` if the sampler is consistent.
    pub failure: Option<String>,
    /// Number of pdf evaluations spent integrating the cells.
    pub pdf_evals: u64,
    /// Number of integration regions accepted at the depth cap without
    /// converging (0 when every cell met [`INTEGRATION_TOLERANCE`]).
    pub unconverged_regions: u64,
    /// The bin contributing most to the statistic, described in words.
    pub worst_bin: String,
}

impl Chi2Outcome {
    /// True when there is no hard failure and `p_value >= significance`.
    pub fn passes(&self, significance: f64) -> bool {
        self.failure.is_none() && self.p_value >= significance
    }

    /// One line with the statistic, dof, p-value, accepted/lost counts, pdf
    /// integral, integration cost, the worst bin and any failure.
    pub fn summary(&self) -> String {
        let mut s = format!(
            "chi2 = {:.3}, dof = {}, p = {:.4e}, accepted = {}, lost = {} (expected {:.2}), \
             pdf integral = {:.8}, pdf evals = {}, unconverged regions = {}, worst bin: {}",
            self.statistic,
            self.dof,
            self.p_value,
            self.accepted,
            self.lost_observed,
            self.lost_expected,
            self.pdf_integral,
            self.pdf_evals,
            self.unconverged_regions,
            self.worst_bin,
        );
        if let Some(f) = &self.failure {
            s.push_str(", FAILURE: ");
            s.push_str(f);
        }
        s
    }
}

/// Šidák-corrected per-test significance level so that `tests` independent
/// tests at that level reject a correct sampler with total probability `alpha`:
/// `1 - (1 - alpha)^(1 / tests)`.
pub fn sidak_significance(alpha: f64, tests: usize) -> f64 {
    assert!(tests > 0, "sidak_significance: tests must be positive");
    -((-alpha).ln_1p() / tests as f64).exp_m1()
}

/// Survival function of the chi-square distribution: `P(X > x)` for
/// `X ~ chi^2(dof)`, i.e. the regularized upper incomplete gamma function
/// `Q(dof / 2, x / 2)`. Relative accuracy about 1e-10 or better.
pub fn chi2_survival(x: f64, dof: f64) -> f64 {
    if x.is_nan() || dof.is_nan() || dof <= 0.0 {
        return f64::NAN;
    }
    if x <= 0.0 {
        return 1.0;
    }
    if x == f64::INFINITY {
        return 0.0;
    }
    gamma_q(0.5 * dof, 0.5 * x)
}

/// Regularized upper incomplete gamma function `Q(a, x)` for `a > 0, x > 0`:
/// power series of `P = 1 - Q` for `x < a + 1`, Lentz's continued fraction for
/// `Q` otherwise (Numerical Recipes' `gser`/`gcf`).
fn gamma_q(a: f64, x: f64) -> f64 {
    const EPS: f64 = 1e-16;
    const TINY: f64 = 1e-300;
    // Each method converges in O(sqrt(a)) iterations near x ~ a.
    let max_iter = 1000 + 20 * (a.sqrt() as usize);
    // ln(x^a e^-x / Gamma(a)).
    let log_prefactor = a * x.ln() - x - ln_gamma(a);
    if x < a + 1.0 {
        let mut ap = a;
        let mut term = 1.0 / a;
        let mut sum = term;
        for _ in 0..max_iter {
            ap += 1.0;
            term *= x / ap;
            sum += term;
            if term.abs() < sum.abs() * EPS {
                break;
            }
        }
        1.0 - sum * log_prefactor.exp()
    } else {
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / TINY;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..max_iter {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < TINY {
                d = TINY;
            }
            c = b + an / c;
            if c.abs() < TINY {
                c = TINY;
            }
            d = 1.0 / d;
            let delta = d * c;
            h *= delta;
            if (delta - 1.0).abs() < EPS {
                break;
            }
        }
        (log_prefactor.exp() * h).min(1.0)
    }
}

/// `ln Gamma(x)` for `x > 0` by the Lanczos approximation (g = 7, 9 terms;
/// relative error of Gamma around 1e-15), with reflection below 1/2.
fn ln_gamma(x: f64) -> f64 {
    const G: f64 = 7.0;
    const COEFFS: [f64; 9] = [
        0.9999999999998099,
        676.5203681218851,
        -1259.1392167224028,
        771.3234287776531,
        -176.6150291621406,
        12.507343278686905,
        -0.13857109526572012,
        9.984369578019572e-6,
        1.5056327351493116e-7,
    ];
    if x < 0.5 {
        // Gamma(x) Gamma(1 - x) = pi / sin(pi x).
        return (PI / (PI * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let t = x + G + 0.5;
    let mut series = COEFFS[0];
    for (i, c) in COEFFS.iter().enumerate().skip(1) {
        series += c / (x + i as f64);
    }
    0.5 * TAU.ln() + (x + 0.5) * t.ln() - t + series.ln()
}

/// Uniform `f32` in `[0, 1)` with 24 random bits.
fn uniform_f32(rng: &mut Pcg64) -> f32 {
    (rng.next_u32() >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
}

/// Collects hard failures: counts per kind plus the first example of each.
#[derive(Default)]
struct Failures {
    kinds: Vec<(&'static str, u64, String)>,
}

impl Failures {
    fn add(&mut self, kind: &'static str, example: impl FnOnce() -> String) {
        self.add_n(kind, 1, example);
    }

    fn add_n(&mut self, kind: &'static str, count: u64, example: impl FnOnce() -> String) {
        match self.kinds.iter_mut().find(|(k, _, _)| *k == kind) {
            Some(entry) => entry.1 += count,
            None => self.kinds.push((kind, count, example())),
        }
    }

    fn into_message(self) -> Option<String> {
        if self.kinds.is_empty() {
            return None;
        }
        let parts: Vec<String> = self
            .kinds
            .into_iter()
            .map(|(kind, count, example)| format!("{count} x {kind} (first: {example})"))
            .collect();
        Some(parts.join("; "))
    }
}

/// Integrals of a pdf over the cells of a (theta, phi) grid on the upper
/// hemisphere, as computed by [`integrate_cells`].
#[derive(Debug, Clone, PartialEq)]
pub struct CellIntegrals {
    /// Number of bins uniform in theta over `[0, pi/2]`.
    pub theta_bins: usize,
    /// Number of bins uniform in phi over `[0, 2 pi)`.
    pub phi_bins: usize,
    /// `∫_cell pdf dω`, indexed by `theta_bin * phi_bins + phi_bin`.
    pub integrals: Vec<f64>,
    /// Number of pdf evaluations.
    pub pdf_evals: u64,
    /// Regions accepted at the depth cap without converging.
    pub unconverged_regions: u64,
    /// Number of negative, NaN or infinite pdf values met (integrated as 0).
    pub invalid_pdf_values: u64,
    /// The first invalid pdf value met, described in words.
    pub invalid_pdf_example: Option<String>,
}

impl CellIntegrals {
    /// Integral over the whole upper hemisphere (sum over the cells).
    pub fn total(&self) -> f64 {
        self.integrals.iter().sum()
    }

    /// Integral over one cell.
    pub fn cell(&self, theta_bin: usize, phi_bin: usize) -> f64 {
        self.integrals[theta_bin * self.phi_bins + phi_bin]
    }
}

/// Integrates `pdf(w) dω = pdf sin θ dθ dφ` over every cell of a grid of
/// `theta_bins` x `phi_bins` cells uniform in theta over `[0, pi/2]` and phi
/// over `[0, 2 pi)`, adaptively to [`INTEGRATION_TOLERANCE`].
///
/// The pdf is evaluated at directions built in f64 and rounded to `f32`.
/// Negative, NaN or infinite values are counted and integrated as 0.
pub fn integrate_cells(theta_bins: usize, phi_bins: usize, pdf: impl Fn(Vec3) -> f64) -> CellIntegrals {
    integrate_cells_to(FRAC_PI_2, theta_bins, phi_bins, pdf)
}

/// [`integrate_cells`] with theta over `[0, theta_max]` (`pi` for the whole sphere).
pub fn integrate_cells_to(
    theta_max: f64,
    theta_bins: usize,
    phi_bins: usize,
    pdf: impl Fn(Vec3) -> f64,
) -> CellIntegrals {
    let d_theta = theta_max / theta_bins as f64;
    let d_phi = TAU / phi_bins as f64;
    let mut out = CellIntegrals {
        theta_bins,
        phi_bins,
        integrals: Vec::with_capacity(theta_bins * phi_bins),
        pdf_evals: 0,
        unconverged_regions: 0,
        invalid_pdf_values: 0,
        invalid_pdf_example: None,
    };
    for it in 0..theta_bins {
        for ip in 0..phi_bins {
            let cell =
                Rect::new(it as f64 * d_theta, (it + 1) as f64 * d_theta, ip as f64 * d_phi, (ip + 1) as f64 * d_phi);
            let rule = |r: &Rect| {
                gauss_legendre_5x5(r, f64::sin_cos, f64::sin_cos, |(sin_t, cos_t), (sin_p, cos_p)| {
                    out.pdf_evals += 1;
                    let w = Vec3::new((sin_t * cos_p) as f32, (sin_t * sin_p) as f32, cos_t as f32);
                    let p = pdf(w);
                    if p.is_finite() && p >= 0.0 {
                        p * sin_t
                    } else {
                        out.invalid_pdf_values += 1;
                        if out.invalid_pdf_example.is_none() {
                            out.invalid_pdf_example = Some(format!("pdf({w}) = {p}"));
                        }
                        0.0
                    }
                })
            };
            let result = integrate_adaptive(cell, None, INTEGRATION_TOLERANCE, rule);
            out.unconverged_regions += result.unconverged;
            out.integrals.push(result.value);
        }
    }
    out
}

/// Runs the chi-square goodness-of-fit test of `sample` against `pdf`.
///
/// `sample(u)` maps a uniform point `u` in `[0, 1)^2` to a unit direction with
/// `z > 0`, or returns `None` when the sampler rejects (e.g. below the
/// horizon). `pdf(w)` is the solid-angle density the sampler claims for its
/// returned samples (0 for `z <= 0`); its integral over the upper hemisphere
/// may be below 1, the missing mass being the expected rate of `None`s.
///
/// Expected counts are `samples * ∫_cell pdf dω` with `dω = sin θ dθ dφ`,
/// integrated adaptively per cell (see [`INTEGRATION_TOLERANCE`]); cells with
/// expected counts below `cfg.min_expected` (and the lost bin, if small) are
/// pooled. Use [`Chi2Outcome::passes`] to decide.
pub fn chi2_test(
    cfg: &Chi2Config,
    mut sample: impl FnMut(Vec2) -> Option<Vec3>,
    pdf: impl Fn(Vec3) -> f64,
) -> Chi2Outcome {
    assert!(cfg.theta_bins > 0 && cfg.phi_bins > 0, "chi2_test: need at least one bin per axis");
    assert!(cfg.samples > 0, "chi2_test: need at least one sample");
    assert!(cfg.min_expected > 0.0, "chi2_test: min_expected must be positive");
    let (nt, np) = (cfg.theta_bins, cfg.phi_bins);
    let n_cells = nt * np;
    let d_theta = cfg.theta_max() / nt as f64;
    let d_phi = TAU / np as f64;
    let n = cfg.samples as f64;
    let mut failures = Failures::default();

    // Histogram the samples.
    let mut observed = vec![0u64; n_cells];
    let mut accepted = 0u64;
    let mut lost_observed = 0u64;
    let mut rng = Pcg64::seed_from_u64(cfg.seed);
    for _ in 0..cfg.samples {
        let u = Vec2::new(uniform_f32(&mut rng), uniform_f32(&mut rng));
        let Some(w) = sample(u) else {
            lost_observed += 1;
            continue;
        };
        accepted += 1;
        if !w.is_finite() {
            failures.add("non-finite sample", || format!("u = {u}, w = {w}"));
            continue;
        }
        let (x, y, z) = (w.x as f64, w.y as f64, w.z as f64);
        let len = (x * x + y * y + z * z).sqrt();
        if (len - 1.0).abs() > UNIT_LENGTH_TOLERANCE {
            failures.add("non-unit sample", || format!("u = {u}, w = {w}, |w| = {len}"));
            continue;
        }
        if z < 0.0 && !cfg.sphere {
            failures.add("sample below the horizon (z < 0)", || format!("u = {u}, w = {w}"));
            continue;
        }
        let theta = (z / len).clamp(-1.0, 1.0).acos();
        let mut phi = y.atan2(x);
        if phi < 0.0 {
            phi += TAU;
        }
        let it = ((theta / d_theta) as usize).min(nt - 1);
        let ip = ((phi / d_phi) as usize).min(np - 1);
        observed[it * np + ip] += 1;
    }

    // Integrate the pdf over every cell.
    let cells = integrate_cells_to(cfg.theta_max(), nt, np, pdf);
    if let Some(example) = &cells.invalid_pdf_example {
        failures.add_n("invalid pdf value (negative, NaN or infinite)", cells.invalid_pdf_values, || example.clone());
    }
    let pdf_integral = cells.total();
    let expected: Vec<f64> = cells.integrals.iter().map(|i| n * i).collect();
    if pdf_integral > MAX_PDF_INTEGRAL {
        failures.add("pdf integral over the domain above 1", || format!("{pdf_integral}"));
    }
    let lost_expected = (n * (1.0 - pdf_integral)).max(0.0);

    let describe = |bin: usize| -> String {
        if bin == LOST {
            return "lost (sampler returned None)".to_owned();
        }
        let (it, ip) = (bin / np, bin % np);
        format!(
            "theta [{:.2}, {:.2}] deg, phi [{:.2}, {:.2}] deg",
            (it as f64 * d_theta).to_degrees(),
            ((it + 1) as f64 * d_theta).to_degrees(),
            (ip as f64 * d_phi).to_degrees(),
            ((ip + 1) as f64 * d_phi).to_degrees(),
        )
    };

    // Samples in cells the pdf says are empty.
    let empty_threshold = EMPTY_CELLS_TOTAL_EXPECTED / n_cells as f64;
    for (bin, (&obs, &exp)) in observed.iter().zip(&expected).enumerate() {
        if obs > 0 && exp < empty_threshold {
            failures.add_n("sample in a cell with (near) zero expected count", obs, || {
                format!("{}: observed {obs}, expected {exp:.3e}", describe(bin))
            });
        }
    }

    // Bins: (expected, observed, label): a cell index, LOST or POOLED.
    const LOST: usize = usize::MAX;
    const POOLED: usize = usize::MAX - 1;
    let mut bins: Vec<(f64, f64, usize)> =
        expected.iter().zip(&observed).enumerate().map(|(i, (&e, &o))| (e, o as f64, i)).collect();
    bins.push((lost_expected, lost_observed as f64, LOST));
    bins.sort_by(|a, b| a.0.total_cmp(&b.0));
    let split = bins.partition_point(|b| b.0 < cfg.min_expected);
    let (pooled_exp, pooled_obs) = bins[..split].iter().fold((0.0, 0.0), |(e, o), b| (e + b.0, o + b.1));
    // (expected, observed, label, pooled bins merged into it).
    let mut final_bins: Vec<(f64, f64, usize, usize)> =
        bins[split..].iter().map(|&(e, o, label)| (e, o, label, 0)).collect();
    if pooled_exp >= cfg.min_expected || final_bins.is_empty() {
        final_bins.push((pooled_exp, pooled_obs, POOLED, split));
    } else if pooled_exp > 0.0 || pooled_obs > 0.0 {
        // Too small on its own: merge into the smallest remaining bin.
        let smallest = &mut final_bins[0];
        smallest.0 += pooled_exp;
        smallest.1 += pooled_obs;
        smallest.3 = split;
    }

    let mut statistic = 0.0;
    let mut worst = (f64::NEG_INFINITY, 0);
    for (i, (e, o, _, _)) in final_bins.iter().enumerate() {
        let term = (o - e) * (o - e) / e;
        statistic += term;
        if term > worst.0 {
            worst = (term, i);
        }
    }
    let worst_bin = final_bins.get(worst.1).map_or_else(String::new, |&(e, o, label, pooled)| {
        let mut name = if label == POOLED { String::new() } else { describe(label) };
        if pooled > 0 {
            if !name.is_empty() {
                name.push_str(" + ");
            }
            name.push_str(&format!("{pooled} pooled small bins"));
        }
        format!("{name}: observed {o}, expected {e:.2}")
    });
    let dof = final_bins.len() - 1;
    let p_value = if dof == 0 {
        failures.add("degenerate test (a single bin)", || "increase samples or lower min_expected".to_owned());
        f64::NAN
    } else {
        chi2_survival(statistic, dof as f64)
    };

    Chi2Outcome {
        statistic,
        dof,
        p_value,
        accepted,
        lost_observed,
        lost_expected,
        pdf_integral,
        failure: failures.into_message(),
        pdf_evals: cells.pdf_evals,
        unconverged_regions: cells.unconverged_regions,
        worst_bin,
    }
}
