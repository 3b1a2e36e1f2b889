//! The speed goals of issue 10, read off one peer run: each goal with its measured ratio and
//! whether this run meets it. A goal not met does not fail the run (it is a target, not a
//! correctness check); the table says where ggx stands.

use std::fmt::Write as _;

use super::metrics;
use super::microbench::BATCH_VNDF;
use super::report::{MicroReport, SceneReport, find};
use super::series::Renderer;

/// One goal on one scene (or on the micro-benchmark).
#[derive(Clone, Debug, PartialEq)]
pub struct Goal {
    /// What is compared.
    pub name: String,
    /// Scene name, or `micro-benchmark`.
    pub scene: String,
    /// The measured ratio (NaN when a series is missing).
    pub measured: f64,
    /// The target the ratio must reach.
    pub target: f64,
    /// `true`: the ratio must be at least `target`; `false`: at most.
    pub at_least: bool,
}

impl Goal {
    /// Whether this run meets the goal (never with a NaN ratio).
    pub fn met(&self) -> bool {
        if self.at_least { self.measured >= self.target } else { self.measured <= self.target }
    }
}

/// Camera samples/s ggx ÷ Mitsuba `llvm_ad_rgb` at least this.
pub const LLVM_THROUGHPUT: f64 = 1.0;
/// Camera samples/s ggx ÷ Mitsuba `scalar_rgb` at least this.
pub const SCALAR_THROUGHPUT: f64 = 3.0;
/// Equal-time efficiency `(relMSE x s)_Mitsuba / (relMSE x s)_ggx` at least this.
pub const EFFICIENCY: f64 = 2.0;
/// Batch VNDF sampling: Mitsuba's per-core rate ÷ ggx-core's at most this.
pub const BATCH_VNDF_RATIO: f64 = 2.0;

/// The goals of every scene at `threads` threads, then the micro-benchmark's.
pub fn goals(scenes: &[SceneReport], threads: usize, micro: &MicroReport) -> Vec<Goal> {
    let mut out = Vec::new();
    for s in scenes {
        let tp = |r| find(&s.series, r, threads).map_or(f64::NAN, |x| metrics::throughput(&x.rungs));
        let eff = |r| find(&s.series, r, threads).map_or(f64::NAN, |x| metrics::efficiency(&x.rungs));
        let ggx = tp(Renderer::GgxSobol);
        let goal = |name: &str, measured, target| Goal {
            name: name.into(),
            scene: s.name.clone(),
            measured,
            target,
            at_least: true,
        };
        out.push(goal("camera samples/s, ggx ÷ Mitsuba llvm_ad_rgb", ggx / tp(Renderer::MitsubaLlvm), LLVM_THROUGHPUT));
        out.push(goal(
            "camera samples/s, ggx ÷ Mitsuba scalar_rgb",
            ggx / tp(Renderer::MitsubaScalar),
            SCALAR_THROUGHPUT,
        ));
        out.push(goal(
            "equal-time efficiency, ggx ÷ Mitsuba llvm_ad_rgb",
            eff(Renderer::MitsubaLlvm) / eff(Renderer::GgxSobol),
            EFFICIENCY,
        ));
    }
    let ggx = micro.ggx.get(BATCH_VNDF.ggx).copied().unwrap_or(f64::NAN);
    let mitsuba = micro
        .mitsuba
        .iter()
        .find(|(t, _)| *t == 1)
        .and_then(|(_, m)| m.per_second.get(BATCH_VNDF.mitsuba).copied())
        .unwrap_or(f64::NAN);
    out.push(Goal {
        name: "batch VNDF sampling per core, Mitsuba ÷ ggx-core".into(),
        scene: "micro-benchmark".into(),
        measured: mitsuba / ggx,
        target: BATCH_VNDF_RATIO,
        at_least: false,
    });
    out
}

/// The goals as a markdown section.
pub fn section(md: &mut String, goals: &[Goal], threads: usize) {
    let met = goals.iter().filter(|g| g.met()).count();
    let _ = writeln!(
        md,
        "## Speed goals\n\nIssue 10's targets, all-core rows ({threads} threads) and the one-thread micro-benchmark: \
         {met} of {} met in this run.\n\n| goal | scene | measured | target | met |\n|---|---|---:|---:|---|",
        goals.len()
    );
    for g in goals {
        let _ = writeln!(
            md,
            "| {} | {} | {:.2}× | {} {:.1}× | {} |",
            g.name,
            g.scene,
            g.measured,
            if g.at_least { "≥" } else { "≤" },
            g.target,
            if g.met() { "yes" } else { "no" }
        );
    }
    md.push('\n');
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::peer::driver::Micro;
    use crate::peer::report::tests::{scene, series};

    /// ggx at 3x Mitsuba llvm's samples/s and 9x scalar's with the same error per sample (so
    /// 3x llvm's efficiency): every render goal met; the batch sampler 2.5x behind: not met.
    #[test]
    fn ratios_and_verdicts() {
        let mut scene = scene();
        scene.series = vec![
            series(Renderer::GgxSobol, 2, 9.0, 0.1),
            series(Renderer::MitsubaLlvm, 2, 3.0, 0.1),
            series(Renderer::MitsubaScalar, 2, 1.0, 0.1),
        ];
        let micro = MicroReport {
            ggx: [("batch/sample_vndf".to_string(), 1e8)].into_iter().collect(),
            mitsuba: vec![(1, Micro { per_second: [("sample_reflect".to_string(), 2.5e8)].into_iter().collect() })],
        };
        let g = goals(std::slice::from_ref(&scene), 2, &micro);
        let measured: Vec<f64> = g.iter().map(|g| (g.measured * 1e6).round() / 1e6).collect();
        assert_eq!(measured, [3.0, 9.0, 3.0, 2.5]);
        assert_eq!(g.iter().map(Goal::met).collect::<Vec<_>>(), [true, true, true, false]);
        let mut md = String::new();
        section(&mut md, &g, 2);
        assert!(md.contains("3 of 4 met"), "{md}");
        assert!(
            md.contains("| batch VNDF sampling per core, Mitsuba ÷ ggx-core | micro-benchmark | 2.50× | ≤ 2.0× | no |"),
            "{md}"
        );
        // A missing series is never met.
        let g = goals(std::slice::from_ref(&scene), 1, &MicroReport::default());
        assert!(g.iter().all(|g| g.measured.is_nan() && !g.met()), "{g:?}");
    }
}
