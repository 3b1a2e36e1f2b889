//! The numbers the summary reports per scene, derived from the measured ladders: the target
//! error and the common time budget (both taken from the baseline's top rung), each
//! configuration's time to reach that error and error at that time, and the speed-up of the
//! specialized over the generic kernel.

use super::configs::{Axis, BASELINE, Config};
use super::interp::{Estimate, x_to_reach, y_at};
use super::ladder::{Rung, Series};
use crate::render::Backend;

/// The target relMSE is this many times the baseline's relMSE at its top rung (reachable by
/// the baseline by construction, a yardstick for the others).
pub const TARGET_FACTOR: f64 = 2.0;

/// One configuration's row of the summary.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// The configuration.
    pub config: Config,
    /// The top rung measured.
    pub top: Rung,
    /// Seconds to reach the scene's target relMSE.
    pub time_to_target: Estimate,
    /// relMSE after the scene's time budget.
    pub rel_mse_at_budget: Estimate,
    /// Median camera samples per second over the rungs.
    pub samples_per_second: f64,
}

/// Specialized over generic kernel on one backend.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Speedup {
    /// The backend.
    pub backend: Backend,
    /// Median over common rungs of (specialized samples/s) / (generic samples/s).
    pub ratio: f64,
    /// Number of rungs both ran.
    pub rungs: usize,
}

/// Everything the summary says about one scene.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneAnalysis {
    /// `TARGET_FACTOR` x the baseline's relMSE at its top rung.
    pub target_rel_mse: f64,
    /// The baseline's time at its top rung, in seconds.
    pub budget_seconds: f64,
    /// One row per configuration, in the study's order.
    pub rows: Vec<Row>,
    /// Specialized vs generic speed-ups, per backend where both were measured.
    pub speedups: Vec<Speedup>,
}

/// The median of `values` (the mean of the middle two for an even count); `None` when empty.
pub fn median(values: &[f64]) -> Option<f64> {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| !x.is_nan()).collect();
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    Some(if n % 2 == 1 { v[n / 2] } else { 0.5 * (v[n / 2 - 1] + v[n / 2]) })
}

/// Analyses one scene's series; the first series of axis [`Axis::Baseline`] sets the target
/// and the budget. `None` when there is no baseline or it has no rungs.
pub fn analyse(series: &[Series]) -> Option<SceneAnalysis> {
    let baseline = series.iter().find(|s| s.config.axis() == Axis::Baseline)?;
    let top = baseline.rungs.last()?;
    let target_rel_mse = TARGET_FACTOR * top.rel_mse;
    let budget_seconds = top.seconds;
    let rows = series
        .iter()
        .filter_map(|s| {
            let top = *s.rungs.last()?;
            let curve: Vec<(f64, f64)> = s.rungs.iter().map(|r| (r.seconds, r.rel_mse)).collect();
            let rates: Vec<f64> = s.rungs.iter().map(Rung::samples_per_second).collect();
            Some(Row {
                config: s.config,
                top,
                time_to_target: x_to_reach(&curve, target_rel_mse),
                rel_mse_at_budget: y_at(&curve, budget_seconds),
                samples_per_second: median(&rates).unwrap_or(0.0),
            })
        })
        .collect();
    Some(SceneAnalysis { target_rel_mse, budget_seconds, rows, speedups: speedups(series) })
}

/// Specialized over generic speed-up for every backend that has both kernels at the baseline's
/// other settings: the median over the rungs both ran of the ratio of samples/s.
pub fn speedups(series: &[Series]) -> Vec<Speedup> {
    let mut out = Vec::new();
    for backend in [Backend::Cpu, Backend::Wgpu] {
        let find = |specialize: bool| {
            series.iter().find(|s| {
                let c = s.config;
                c == Config { backend, specialize, ..BASELINE }
            })
        };
        let (Some(spec), Some(generic)) = (find(true), find(false)) else { continue };
        let ratios: Vec<f64> = spec
            .rungs
            .iter()
            .filter_map(|s| {
                let g = generic.rungs.iter().find(|g| g.spp == s.spp)?;
                let (a, b) = (s.samples_per_second(), g.samples_per_second());
                (a > 0.0 && b > 0.0).then_some(a / b)
            })
            .collect();
        if let Some(ratio) = median(&ratios) {
            out.push(Speedup { backend, ratio, rungs: ratios.len() });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use ggx_scene::BsdfStrategy;

    fn rung(spp: u32, seconds: f64, rel_mse: f64) -> Rung {
        Rung {
            spp,
            seconds,
            rmse: rel_mse.sqrt(),
            rel_mse,
            rel_mse_trimmed: rel_mse,
            camera_samples: u64::from(spp) * 100,
            rays: 0,
        }
    }

    /// relMSE = 1 / spp, `seconds_per_spp` seconds per spp.
    fn series(config: Config, seconds_per_spp: f64, scale: f64) -> Series {
        let rungs = [1, 2, 4, 8].map(|s| rung(s, seconds_per_spp * f64::from(s), scale / f64::from(s))).to_vec();
        Series { config, rungs }
    }

    #[test]
    fn median_of_odd_even_and_empty() {
        assert_eq!(median(&[3.0, 1.0, 2.0]), Some(2.0));
        assert_eq!(median(&[4.0, 1.0, 2.0, 3.0]), Some(2.5));
        assert_eq!(median(&[f64::NAN]), None);
        assert_eq!(median(&[]), None);
    }

    #[test]
    fn target_budget_and_rows() {
        let cosine = Config { bsdf: BsdfStrategy::Cosine, ..BASELINE };
        let generic = Config { specialize: false, ..BASELINE };
        let all = [series(BASELINE, 0.1, 1.0), series(cosine, 0.1, 4.0), series(generic, 0.2, 1.0)];
        let a = analyse(&all).unwrap();
        // Baseline top rung: 8 spp, 0.8 s, relMSE 1/8.
        assert_eq!((a.target_rel_mse, a.budget_seconds), (0.25, 0.8));
        let value = |e: Estimate| match e {
            Estimate::Interpolated(v) | Estimate::AtMost(v) | Estimate::Extrapolated(v) => v,
            Estimate::BelowRange | Estimate::Unavailable => f64::NAN,
        };
        let t = |i: usize| value(a.rows[i].time_to_target);
        let e = |i: usize| value(a.rows[i].rel_mse_at_budget);
        // Baseline reaches 0.25 at 4 spp = 0.4 s; cosine (4x the error) needs 16 spp = 1.6 s,
        // beyond its ladder: extrapolated with 1/t.
        assert!((t(0) - 0.4).abs() < 1e-12 && (t(1) - 1.6).abs() < 1e-12 && (t(2) - 0.8).abs() < 1e-12);
        assert!(matches!(a.rows[1].time_to_target, Estimate::Extrapolated(_)));
        assert!((e(0) - 0.125).abs() < 1e-12 && (e(1) - 0.5).abs() < 1e-12 && (e(2) - 0.25).abs() < 1e-12);
        assert_eq!(a.rows[0].samples_per_second, 1000.0);
        // The generic kernel takes twice as long: specialized is 2x faster on the CPU.
        assert_eq!(a.speedups, [Speedup { backend: Backend::Cpu, ratio: 2.0, rungs: 4 }]);
    }

    #[test]
    fn no_baseline_no_analysis() {
        let cosine = Config { bsdf: BsdfStrategy::Cosine, ..BASELINE };
        assert_eq!(analyse(&[series(cosine, 0.1, 1.0)]), None);
        assert_eq!(analyse(&[Series { config: BASELINE, rungs: vec![] }]), None);
        assert!(speedups(&[series(BASELINE, 0.1, 1.0)]).is_empty(), "no generic kernel measured");
    }
}
