//! `summary.md`: the machine, the method (one axis at a time, how the target error and the time
//! budget are chosen), one table per scene, the specialization speed-up, the bunny comparison
//! and the checks. Everything but the timings is deterministic.

use super::analysis::{self, SceneAnalysis};
use super::checks::Check;
use super::comparison::Comparison;
use super::configs::{self, bsdf_name};
use super::fireflies;
use super::ladder::{LADDER_SEED, Series};
use super::options::Options;
use super::reference::REFERENCE_SEED;
use super::robust;
use crate::render::Backend;
use std::fmt::Write;
use std::path::{Path, PathBuf};

/// Where and how the run was measured.
#[derive(Clone, Debug, PartialEq)]
pub struct Machine {
    /// CPU model (from `/proc/cpuinfo` where available).
    pub cpu: String,
    /// Worker threads of the CPU renderer.
    pub threads: usize,
    /// The wgpu adapter, `None` with `--no-wgpu`.
    pub adapter: Option<String>,
    /// `release` or `dev`.
    pub profile: &'static str,
}

/// One scene's measurements.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneReport {
    /// Scene name.
    pub name: String,
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// The reference EXR.
    pub reference: PathBuf,
    /// One series per configuration.
    pub series: Vec<Series>,
    /// The SVG plots.
    pub plots: Vec<PathBuf>,
}

/// File name of `p` for links relative to the summary (the reference cache gets its folder).
fn file_name(p: &Path) -> String {
    p.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default()
}

/// Seconds with a precision that suits the magnitude.
fn secs(v: f64) -> String {
    if v >= 100.0 {
        format!("{v:.0}")
    } else if v >= 1.0 {
        format!("{v:.2}")
    } else if v >= 0.01 {
        format!("{v:.3}")
    } else {
        format!("{v:.2e}")
    }
}

/// A relMSE or RMSE.
fn err(v: f64) -> String {
    format!("{v:.3e}")
}

/// The whole file.
pub fn markdown(
    options: &Options,
    machine: &Machine,
    scenes: &[SceneReport],
    comparison: &Comparison,
    checks: &[Check],
) -> String {
    let mut md = String::new();
    header(&mut md, options, machine);
    method(&mut md, options, machine);
    for scene in scenes {
        scene_section(&mut md, scene, machine.adapter.is_some());
    }
    comparison_section(&mut md, comparison);
    let _ = writeln!(md, "## Checks\n");
    for c in checks {
        let _ = writeln!(md, "- [{}] {}: {}", if c.passed { "x" } else { " " }, c.name, c.detail);
    }
    md
}

/// Title, run, machine, adapter and sizes.
fn header(md: &mut String, o: &Options, m: &Machine) {
    let _ = writeln!(md, "# ggx bench: run time against error\n");
    let mode = if o.quick { "`cargo xtask bench --quick` (CI size)" } else { "`cargo xtask bench` (full)" };
    let _ = writeln!(md, "- run: {mode}; build: {}", m.profile);
    let _ = writeln!(md, "- CPU: {}, {} render threads", m.cpu, m.threads);
    match &m.adapter {
        Some(a) => _ = writeln!(md, "- wgpu adapter: {a}"),
        None => _ = writeln!(md, "- wgpu adapter: none, **wgpu not measured** (`--no-wgpu`)"),
    }
    let wgpu = if m.adapter.is_some() { format!(" (wgpu: 1 to {})", o.wgpu_max_spp) } else { String::new() };
    let _ = writeln!(
        md,
        "- scenes: {}; width {} px; spp ladder 1 to {}{wgpu}; references {} spp\n",
        o.scenes.join(", "),
        o.width,
        o.max_spp,
        o.ref_spp
    );
}

/// How the numbers are made: configurations, ladder, error, target, budget, speed-up.
fn method(md: &mut String, o: &Options, m: &Machine) {
    let names: Vec<String> = configs::all(m.adapter.is_some()).iter().map(|c| format!("`{}`", c.name())).collect();
    let _ = writeln!(md, "## Method\n");
    let _ = writeln!(
        md,
        "- **Configurations**: the full cross product (5 BSDF samplers x 3 light strategies x 2 samplers x \
         2 backends x 2 kernels = 120 per scene) is too big, so one axis at a time is varied from the \
         baseline `{}` (VNDF, MIS, sobol, cpu, specialized kernel): 4 other BSDF samplers, 2 light \
         strategies, 1 sampler, 1 backend, 1 kernel. Names read `bsdf-light-sampler-backend-kernel`: {}.",
        configs::BASELINE.name(),
        names.join(", ")
    );
    let wgpu = if m.adapter.is_some() {
        format!(
            " The wgpu ladder stops at {} spp: a software adapter such as lavapipe is many times slower \
             than the CPU renderer (the tables' samples/s column says by how much).",
            o.wgpu_max_spp
        )
    } else {
        String::new()
    };
    let _ = writeln!(
        md,
        "- **Ladder**: 1, 2, 4, ... spp, each rung an independent render with seed {LADDER_SEED}; time = the \
         renderer's own wall time (BVH build and shader compilation excluded).{wgpu}"
    );
    let _ = writeln!(
        md,
        "- **Error**: relMSE = mean over pixels and channels of (x - ref)^2 / (ref^2 + {}) and RMSE, against \
         a reference of {} spp rendered with the baseline on the CPU with seed {REFERENCE_SEED:#x} (cached \
         per scene content and renderer sources in `target/xtask/bench/reference/`). At {}x the top rung's spp, its own \
         noise adds roughly {:.0} % to the baseline's top-rung relMSE, less to the noisier configurations. \
         Trimmed relMSE leaves out the {}% of pixels with the largest errors: it shows how the bulk of the \
         image converges when a few fireflies dominate relMSE, and is what the convergence check judges.",
        ggx_film::REL_EPSILON,
        o.ref_spp,
        o.ref_spp / o.max_spp.max(1),
        100.0 * f64::from(o.max_spp) / f64::from(o.ref_spp),
        100.0 * robust::TRIM
    );
    let _ = writeln!(
        md,
        "- **Time to reach X**: X = {} x the baseline's relMSE at its top rung (reachable by the baseline by \
         construction): the time from which the curve stays at or below X, log-log interpolated between the \
         last rung above X and the next. `≤` = no rung above X; `≈` = the top rung is still above X, \
         extrapolated from it with relMSE ∝ 1/time.",
        analysis::TARGET_FACTOR
    );
    let _ = writeln!(
        md,
        "- **relMSE at equal time**: at T = the baseline's time at its top rung, log-log interpolated; `≈` = \
         beyond the configuration's measured times, extrapolated from its slowest rung with relMSE ∝ 1/time; \
         `n/a (< 1st rung)` = T is shorter than its 1-spp render."
    );
    let _ = writeln!(
        md,
        "- **Specialization**: specialized over generic kernel = median over the rungs of the ratio of \
         camera samples per second.\n"
    );
}

/// One scene: reference, plots, table, speed-up.
fn scene_section(md: &mut String, s: &SceneReport, wgpu_measured: bool) {
    let _ = writeln!(md, "## {} ({} x {})\n", s.name, s.width, s.height);
    let plots: Vec<String> = s.plots.iter().map(|p| format!("[{0}]({0})", file_name(p))).collect();
    let _ = writeln!(md, "Reference: `reference/{}`. Plots: {}.\n", file_name(&s.reference), plots.join(", "));
    let Some(a) = analysis::analyse(&s.series) else {
        let _ = writeln!(md, "No baseline measured: no analysis.\n");
        return;
    };
    scene_table(md, &a);
    let mut speed: Vec<String> = a
        .speedups
        .iter()
        .map(|sp| format!("{} {:.3}x (median of {} rungs)", sp.backend.name(), sp.ratio, sp.rungs))
        .collect();
    if !a.speedups.iter().any(|sp| sp.backend == Backend::Wgpu) {
        speed.push(if wgpu_measured {
            "wgpu not measured (the kernel axis is varied on the baseline backend, cpu, only)".into()
        } else {
            "wgpu not measured (`--no-wgpu`)".into()
        });
    }
    let _ = writeln!(md, "Specialized over generic kernel, samples/s: {}.\n", speed.join("; "));
}

/// The per-configuration table of one scene.
fn scene_table(md: &mut String, a: &SceneAnalysis) {
    let _ =
        writeln!(md, "Target X = relMSE {}; time budget T = {} s.\n", err(a.target_rel_mse), secs(a.budget_seconds));
    let _ = writeln!(
        md,
        "| configuration | differs in | top spp | time at top (s) | relMSE at top | trimmed relMSE at top | \
         time to relMSE X (s) | relMSE at T | M samples/s (median) |"
    );
    let _ = writeln!(md, "|---|---|---:|---:|---:|---:|---:|---:|---:|");
    for r in &a.rows {
        let _ = writeln!(
            md,
            "| `{}` | {} | {} | {} | {} | {} | {} | {} | {:.3} |",
            r.config.name(),
            r.config.label(),
            r.top.spp,
            secs(r.top.seconds),
            err(r.top.rel_mse),
            err(r.top.rel_mse_trimmed),
            r.time_to_target.show(secs),
            r.rel_mse_at_budget.show(err),
            r.samples_per_second * 1e-6
        );
    }
    let _ = writeln!(md);
}

/// The bunny comparison's table.
fn comparison_section(md: &mut String, c: &Comparison) {
    let _ = writeln!(md, "## Bunny: cosine vs NDF vs VNDF sampling (after J. Schutte 2018)\n");
    let (png, reference) = (file_name(&c.png), file_name(&c.reference));
    let _ = writeln!(
        md,
        "`scenes/bunny.toml` (gold conductor, alpha 0.05, environment light only) at {} x {}, {} spp, the \
         scene's MIS and sobol, CPU; only the BSDF sampler changes. Left to right: cosine, NDF, VNDF: \
         [{png}]({png}). Reference: `reference/{reference}` ({} spp). A firefly is a pixel whose luminance \
         exceeds {} x max(reference luminance, {:e}).\n",
        c.width,
        c.height,
        c.spp,
        c.ref_spp,
        fireflies::FACTOR,
        fireflies::FLOOR
    );
    let _ = writeln!(md, "| sampler | relMSE | RMSE | fireflies | time (s) | EXR |");
    let _ = writeln!(md, "|---|---:|---:|---:|---:|---|");
    for e in &c.entries {
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} | [{5}]({5}) |",
            bsdf_name(e.bsdf),
            err(e.rel_mse),
            err(e.rmse),
            e.fireflies,
            secs(e.seconds),
            file_name(&e.exr)
        );
    }
    let _ = writeln!(md);
}

#[cfg(test)]
mod tests {
    use super::super::checks::Check;
    use super::super::comparison::Entry;
    use super::super::configs::{BASELINE, Config};
    use super::super::ladder::Rung;
    use super::super::options::{self, Command};
    use super::*;
    use ggx_scene::BsdfStrategy;

    fn series(config: Config, seconds_per_spp: f64) -> Series {
        let rungs = [1u32, 2, 4]
            .map(|spp| Rung {
                spp,
                seconds: seconds_per_spp * f64::from(spp),
                rmse: 0.1,
                rel_mse: 0.5 / f64::from(spp),
                rel_mse_trimmed: 0.4 / f64::from(spp),
                camera_samples: u64::from(spp) * 1000,
                rays: 0,
            })
            .to_vec();
        Series { config, rungs }
    }

    #[test]
    fn sections_and_numbers() {
        let Ok(Command::Run(o)) = options::parse(&["--quick".to_string(), "--no-wgpu".to_string()]) else {
            panic!("options")
        };
        let machine = Machine { cpu: "test CPU".into(), threads: 2, adapter: None, profile: "release profile" };
        let scene = SceneReport {
            name: "three-spheres".into(),
            width: 32,
            height: 32,
            reference: PathBuf::from("/x/reference/three-spheres-32x32-256spp-0123.exr"),
            series: vec![series(BASELINE, 0.01), series(Config { specialize: false, ..BASELINE }, 0.02)],
            plots: vec![PathBuf::from("/out/three-spheres-relmse-vs-time.svg")],
        };
        let entry = |bsdf, fireflies| Entry {
            bsdf,
            rel_mse: 0.01,
            rmse: 0.1,
            fireflies,
            seconds: 0.5,
            exr: PathBuf::from(format!("/out/bunny-{}-64spp.exr", bsdf_name(bsdf))),
        };
        let comparison = Comparison {
            width: 64,
            height: 64,
            spp: 64,
            ref_spp: 256,
            reference: PathBuf::from("/x/bunny-64x64-256spp-1.exr"),
            png: PathBuf::from("/out/bunny-cosine-ndf-vndf-64spp.png"),
            entries: vec![entry(BsdfStrategy::Cosine, 7), entry(BsdfStrategy::Vndf, 0)],
        };
        let checks = [Check { name: "c".into(), passed: false, detail: "d".into() }];
        let md = markdown(&o, &machine, &[scene], &comparison, &checks);
        for want in [
            "- CPU: test CPU, 2 render threads",
            "**wgpu not measured** (`--no-wgpu`)",
            "spp ladder 1 to 16; references 256 spp",
            "## three-spheres (32 x 32)",
            "[three-spheres-relmse-vs-time.svg](three-spheres-relmse-vs-time.svg)",
            // Baseline top rung: 4 spp, 0.04 s, relMSE 0.125; target 0.25 reached at 2 spp = 0.02 s.
            "Target X = relMSE 2.500e-1; time budget T = 0.040 s.",
            "| `vndf-mis-sobol-cpu-spec` | baseline (VNDF, MIS, sobol, cpu, specialized) | 4 | 0.040 | 1.250e-1 | \
             1.000e-1 | 0.020 | 1.250e-1 | 0.100 |",
            "| `vndf-mis-sobol-cpu-generic` | kernel: generic | 4 | 0.080 | 1.250e-1 | 1.000e-1 | 0.040 | 2.500e-1 | \
             0.050 |",
            "cpu 2.000x (median of 3 rungs); wgpu not measured (`--no-wgpu`)",
            "| cosine | 1.000e-2 | 1.000e-1 | 7 | 0.500 | [bunny-cosine-64spp.exr](bunny-cosine-64spp.exr) |",
            "- [ ] c: d",
        ] {
            assert!(md.contains(want), "missing {want:?} in\n{md}");
        }
        assert!(!md.contains("wgpu ladder stops"), "no wgpu sentence without wgpu");
    }
}
