//! `cargo xtask stress [--quick] [--samples N]`: numerical stability sweep of ggx-core.
//!
//! Every `Sampling` technique through `GgxConductor::sample` (with `Fresnel::One` and a
//! conductor) and the four raw `TrowbridgeReitz::sample_wm_*` samplers run over alphas from
//! 1e-7 to 1 with anisotropy up to 1:100, views from the normal to below the horizon and a
//! u grid holding 0 and 1 - ulp plus deterministic random points ([`grid`], [`sweep`]).
//! `GgxDielectric::sample` runs with each technique it accepts (NDF, VNDF, spherical caps,
//! bounded) in both transport modes over the same alphas, six indices of refraction (1.5,
//! 1/1.5, 1.33, 2.4 and the clamp bounds 1e-2, 1e2) and views on both sides of the surface,
//! at the horizon and around the critical angle, with `u_lobe` from 0 to 1 - ulp.
//! Every returned sample is checked ([`method`]) and counted ([`tally`]); the lost share at
//! grazing views is measured separately ([`horizon`]).
//!
//! The run fails on any NaN or infinity and on any accepted invalid sample (below the
//! horizon or, for the dielectric, on the wrong side for its lobe; not unit; pdf `<= 0`;
//! weight `<= 0`, dielectric `< 0`; weight over its bound); `weight != eval / pdf`
//! fails only above [`MISMATCH_SHARE`] of a method's samples, since ill-conditioned grazing
//! pairs can legitimately differ; its worst examples are printed for a human to judge.
//! Raw normals whose own density is zero are reported but do not fail (see
//! [`tally::Check::ZeroDensity`]).

pub mod grid;
pub mod horizon;
pub mod method;
pub mod sweep;
pub mod table;
pub mod tally;

use method::{Method, PDF_FLOOR, WEIGHT_TOLERANCE};
use std::time::Instant;
use tally::{Check, Example, Tally};

/// Samples per method of `--quick`.
pub const QUICK_SAMPLES: u64 = 1_000_000;
/// Samples per method of the full run.
pub const FULL_SAMPLES: u64 = 100_000_000;
/// Share of a method's samples above which weight or pdf disagreements fail the run.
pub const MISMATCH_SHARE: f64 = 1e-6;

/// Command-line options of `stress`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Options {
    /// `--quick`: the CI-sized run.
    pub quick: bool,
    /// Samples per method (`--samples N`, else by `quick`).
    pub samples: u64,
}

impl Options {
    /// The run `cargo xtask ci` does: `stress --quick`.
    pub fn quick() -> Options {
        Options { quick: true, samples: QUICK_SAMPLES }
    }

    /// Parses the arguments after `stress`: `--quick`, `--samples N` (or `--samples=N`;
    /// `N` an integer or a float such as `1e8`).
    pub fn parse(args: &[String]) -> Result<Options, String> {
        let (mut quick, mut samples) = (false, None);
        let mut args = args.iter();
        while let Some(arg) = args.next() {
            match arg.as_str() {
                "--quick" => quick = true,
                "--samples" => samples = Some(parse_count(args.next().ok_or("stress: --samples needs a value")?)?),
                a if a.starts_with("--samples=") => samples = Some(parse_count(&a["--samples=".len()..])?),
                a => return Err(format!("stress: unknown argument `{a}`")),
            }
        }
        Ok(Options { quick, samples: samples.unwrap_or(if quick { QUICK_SAMPLES } else { FULL_SAMPLES }) })
    }
}

/// A positive count written as an integer (`100000000`, `100_000_000`) or a float (`1e8`).
fn parse_count(s: &str) -> Result<u64, String> {
    let clean = s.replace('_', "");
    let n = clean.parse::<u64>().ok().or_else(|| {
        let f = clean.parse::<f64>().ok()?;
        (f.is_finite() && f >= 0.0 && f.fract() == 0.0 && f < 1.8e19).then_some(f as u64)
    });
    n.filter(|&n| n > 0).ok_or_else(|| format!("stress: `{s}` is not a positive sample count"))
}

/// Runs the sweep and the grazing-loss measurement, prints the tables, and fails if any
/// method produced an invalid sample.
pub fn run(options: &Options) -> Result<(), String> {
    let start = Instant::now();
    let plan = sweep::Plan::new(options.samples);
    println!("{}", describe(&plan, options));
    let tallies = plan.run();
    let sweep_s = start.elapsed().as_secs_f64();
    let total: u64 = tallies.iter().map(|t| t.samples).sum();
    println!("{}", report(&plan, &tallies));
    println!("{}", examples(&plan, &tallies));

    let horizon_start = Instant::now();
    let horizon_samples = (options.samples / 10).max(10_000);
    let losses = horizon::measure(horizon_samples);
    let horizon_s = horizon_start.elapsed().as_secs_f64();
    println!("{}", horizon::report(&losses));

    let threads = rayon::current_num_threads();
    let horizon_total: u64 = losses.iter().map(|l| l.samples).sum();
    println!("sweep: {total} samples in {sweep_s:.1} s, {:.3e} samples/s on {threads} threads", total as f64 / sweep_s);
    println!("grazing loss: {horizon_total} samples in {horizon_s:.1} s; wall {:.1} s", start.elapsed().as_secs_f64());
    verdict(&plan.methods, &tallies)
}

/// The header: what is swept and how many samples each method gets.
fn describe(plan: &sweep::Plan, options: &Options) -> String {
    let list = |v: &[f32]| v.iter().map(|c| format!("{c:?}")).collect::<Vec<_>>().join(" ");
    let cos = list(&grid::cos_thetas());
    let u = list(&grid::U_VALUES);
    let views = grid::cos_thetas().len() * grid::AZIMUTHS.len();
    let etas = list(&grid::ETAS);
    let d_cos = list(&grid::dielectric_cos_thetas(grid::ETAS[0]));
    let d_views: usize = grid::ETAS.iter().map(|&e| grid::dielectric_cos_thetas(e).len()).sum::<usize>()
        * grid::DIELECTRIC_AZIMUTHS.len();
    let conductor = plan.ranges[0].len();
    let dielectric = plan.ranges[1].len();
    let d_points = plan.grids[1].len();
    let d_fixed = plan.fixed[1].len();
    format!(
        "stress{}: ggx-core numerical sweep, at least {} samples per method\n\
         alphas: {} log-spaced from {:e} to 1, each as (a,a) (a,a/10) (a,a/100) (a/100,a) = {} pairs \
         (clamped by the core)\n\
         cos theta: {cos}\n\
         azimuths (rad): {:?} -> {views} views, {} cases\n\
         u: {}x{} grid of {} on every case, plus CounterRng points on each case where u matters \
         (view above the horizon, lobe not a delta) to reach the budget\n\
         dielectric: the same alpha pairs x eta {etas} (clamped to [{:e}, {:e}]) x views on both sides, \
         cos theta for eta {:?}: {d_cos} (the last 5: the critical angle region, f32 neighbours of \
         sqrt(1 - eta'^2) and sin theta {:?} relatively off, on the side of total internal reflection; \
         likewise for each eta) x azimuths {:?} -> {d_views} (eta, view) pairs, {dielectric} cases\n\
         dielectric u: the {d_points} points of the u grid with u_lobe cycling through {}, plus CounterRng \
         (u, u_lobe) to reach the budget, on each case where u matters (view off the surface, lobe not a delta); \
         elsewhere the {d_fixed} points of every u_lobe at u = (0, 0) and (1 - ulp, 1 - ulp)",
        if options.quick { " --quick" } else { "" },
        options.samples,
        grid::ALPHA_COUNT,
        grid::ALPHA_LO,
        grid::alpha_pairs().len(),
        grid::AZIMUTHS,
        conductor,
        grid::U_VALUES.len(),
        grid::U_VALUES.len(),
        u,
        ggx_core::ETA_MIN,
        ggx_core::ETA_MAX,
        grid::ETAS[0],
        grid::CRITICAL_OFFSETS,
        grid::DIELECTRIC_AZIMUTHS,
        list(&grid::U_LOBE_VALUES),
    )
}

/// The per-method table.
fn report(plan: &sweep::Plan, tallies: &[Tally]) -> String {
    let mut header = vec!["method", "samples", "rejected"];
    header.extend(Check::ALL.map(Check::label));
    header.extend(["compared", "max w err", "max weight", "bound", "ns/sample"]);
    let rows: Vec<Vec<String>> = plan
        .methods
        .iter()
        .zip(tallies)
        .map(|(m, t)| {
            let mut row = vec![
                m.name(),
                t.samples.to_string(),
                format!("{:.2}%", 100.0 * t.rejected as f64 / t.samples.max(1) as f64),
            ];
            row.extend(Check::ALL.map(|c| t.count(c).to_string()));
            let is_normal = matches!(m, Method::Normal(_));
            row.push(if is_normal { "-".into() } else { t.compared.to_string() });
            row.push(t.worst.first().map_or("-".into(), |e| format!("{:.1e}", e.error)));
            row.push(if is_normal { "-".into() } else { format!("{:.4e}", t.max_weight) });
            row.push(m.bound().into());
            row.push(format!("{:.0}", t.nanos as f64 / t.samples.max(1) as f64));
            row
        })
        .collect();
    let mut out = table::render(&header, &rows);
    for note in notes() {
        out += &format!("{note}\n");
    }
    out
}

/// What the columns of the per-method table count.
fn notes() -> Vec<String> {
    vec![
        "rejected: share of None (normal samplers: of zero normals); views at or below the horizon are always \
         rejected."
            .into(),
        format!(
            "w!=f/p: relative difference > {WEIGHT_TOLERANCE:e} from eval(wo, wi) / pdf(wo, wi) where pdf > \
             {PDF_FLOOR:e}; delta lobes: weight != F(wo.z), pdf != 1 or wi not the mirror (dielectric: the mirror \
             with pdf F(wo.z) and weight 1 where u_lobe < F, else the refracted direction with pdf 1 - F and \
             weight s). p!=pdf(): the sample's pdf against pdf()."
        ),
        "compared: accepted samples where that comparison applied; max w err: the largest relative difference seen."
            .into(),
        "p(wm)=0: normal samplers only, a returned normal whose own density (D wm.z, D_wo, bounded) is 0, i.e. \
         back-facing or horizontal; reported, does not fail (GgxConductor::sample rejects such normals)."
            .into(),
        "bound w<=F: weight <= F(wo.wm) <= 1 (+1e-5). w<=s (dielectric): weight <= s (relative 1e-5), s = \
         1 / eta'^2 for transmitted radiance, else 1. none: NDF, cosine and uniform weights have no bound of 1; \
         delta lobes of every technique are still held to weight == F <= 1 (dielectric: weight == s)."
            .into(),
        "below-hz: wi.z <= 0 (normal samplers: wm.z < 0) or a view at or below the horizon, in an accepted sample. \
         Dielectric: wi on the wrong side for the lobe that u_lobe selects (reflection where u_lobe < F(wo.wm), \
         wm recomputed from u; it must keep wo's side, transmission must cross), or wi.z == 0."
            .into(),
        "w|p<=0: pdf <= 0 or a weight channel <= 0; dielectric: weight < 0 (a zero weight, G2 underflowing, is \
         valid)."
            .into(),
        "ns/sample: thread time per sample, checks included.".into(),
    ]
}

/// The first failing sample of each check, and the worst weight disagreements.
fn examples(plan: &sweep::Plan, tallies: &[Tally]) -> String {
    let mut out = String::new();
    for (m, t) in plan.methods.iter().zip(tallies) {
        for check in Check::ALL.into_iter().filter(|&c| c != Check::WeightMismatch) {
            if let Some(e) = t.first[check as usize] {
                out += &format!(
                    "{} {}: {} samples, first: {}\n",
                    m.name(),
                    check.label(),
                    t.count(check),
                    show(plan, *m, e)
                );
            }
        }
    }
    let mismatched: Vec<(&Method, &Tally)> =
        plan.methods.iter().zip(tallies).filter(|(_, t)| t.count(Check::WeightMismatch) > 0).collect();
    if mismatched.is_empty() {
        let mut all: Vec<(Method, Example)> =
            plan.methods.iter().zip(tallies).flat_map(|(&m, t)| t.worst.iter().map(move |&e| (m, e))).collect();
        all.sort_by(|a, b| b.1.error.total_cmp(&a.1.error));
        out += "w!=f/p: every method within tolerance; the worst over all methods:\n";
        for (m, e) in all.into_iter().take(tally::WORST) {
            out += &format!("  {}: {}\n", m.name(), show(plan, m, e));
        }
    }
    for (m, t) in mismatched {
        out += &format!(
            "{} w!=f/p: {} of {} compared ({:.2e} of samples); worst:\n",
            m.name(),
            t.count(Check::WeightMismatch),
            t.compared,
            t.count(Check::WeightMismatch) as f64 / t.samples as f64
        );
        for e in &t.worst {
            out += &format!("  {}\n", show(plan, *m, *e));
        }
    }
    out
}

/// An example with its inputs (as passed to the core), outputs and, where compared, the
/// expected weight and the relative error.
fn show(plan: &sweep::Plan, method: Method, e: Example) -> String {
    let c = &plan.cases[e.case()];
    let inputs = format!(
        "alpha=({:?}, {:?}) wo={} (cos {:?}, phi {}) u=({:?}, {:?})",
        c.alpha.0,
        c.alpha.1,
        v3(c.wo),
        c.cos_theta,
        c.phi,
        e.u.x,
        e.u.y
    );
    match method {
        Method::Normal(_) => format!("{inputs} -> wm={} (wo.wm {:?}) density={:?}", v3(e.wi), c.wo.dot(e.wi), e.pdf),
        Method::Brdf(..) | Method::Dielectric(..) => {
            let mut out = match (method, c.eta) {
                (Method::Dielectric(_, mode), Some(eta)) => {
                    let lobe = if c.wo.z * e.wi.z < 0.0 { "T" } else { "R" };
                    format!(
                        "{inputs} u_lobe={:?} eta={eta:?} {} -> {lobe} wi={} weight={} pdf={:?}",
                        e.u_lobe,
                        method::mode_name(mode),
                        v3(e.wi),
                        v3(e.weight),
                        e.pdf
                    )
                }
                _ => format!("{inputs} -> wi={} weight={} pdf={:?}", v3(e.wi), v3(e.weight), e.pdf),
            };
            if !e.error.is_nan() {
                out += &format!(" want={} err={:.3e}", v3(e.want), e.error);
            }
            out
        }
    }
}

/// `[x, y, z]` with round-trip (shortest exact) components.
fn v3(v: ggx_core::Vec3) -> String {
    format!("[{:?}, {:?}, {:?}]", v.x, v.y, v.z)
}

/// `Ok` when no method has a hard failure and no mismatch share exceeds [`MISMATCH_SHARE`].
fn verdict(methods: &[Method], tallies: &[Tally]) -> Result<(), String> {
    let mut failures = Vec::new();
    for (m, t) in methods.iter().zip(tallies) {
        for check in Check::ALL {
            let n = t.count(check);
            let fails = check.fail_share(MISMATCH_SHARE).is_some_and(|share| n as f64 > share * t.samples as f64);
            if fails {
                failures.push(format!("{} {} {n}", m.name(), check.label()));
            }
        }
    }
    if failures.is_empty() {
        println!("stress: no invalid sample");
        Ok(())
    } else {
        Err(format!("stress: {} failing counts: {}", failures.len(), failures.join("; ")))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(s: &[&str]) -> Vec<String> {
        s.iter().map(|a| a.to_string()).collect()
    }

    #[test]
    fn options_parse() {
        assert_eq!(Options::parse(&[]), Ok(Options { quick: false, samples: FULL_SAMPLES }));
        assert_eq!(Options::parse(&args(&["--quick"])), Ok(Options::quick()));
        assert_eq!(Options::parse(&args(&["--samples", "1e7"])).map(|o| o.samples), Ok(10_000_000));
        assert_eq!(Options::parse(&args(&["--quick", "--samples=2_000"])).map(|o| o.samples), Ok(2000));
        assert!(Options::parse(&args(&["--samples"])).is_err());
        assert!(Options::parse(&args(&["--samples", "0"])).is_err());
        assert!(Options::parse(&args(&["--samples", "1.5"])).is_err());
        assert!(Options::parse(&args(&["--fast"])).is_err());
    }

    #[test]
    fn verdict_fails_on_any_invalid_sample_and_on_mismatches_above_the_share() {
        let methods = [Method::all()[0]];
        let tally = |check: Check, n: u64| {
            let mut t = Tally { samples: 10_000_000, ..Tally::default() };
            t.counts[check as usize] = n;
            vec![t]
        };
        assert!(verdict(&methods, &tally(Check::NonUnit, 0)).is_ok());
        assert!(verdict(&methods, &tally(Check::NonUnit, 1)).is_err());
        assert!(verdict(&methods, &tally(Check::OverBound, 1)).is_err());
        assert!(verdict(&methods, &tally(Check::WeightMismatch, 10)).is_ok());
        assert!(verdict(&methods, &tally(Check::WeightMismatch, 11)).is_err());
        assert!(verdict(&methods, &tally(Check::ZeroDensity, 1000)).is_ok());
    }
}
