//! `cargo xtask bench`: run time against error, the convergence study of the path tracers.
//!
//! For every bench scene and configuration, a ladder of 1, 2, 4, ... spp is rendered, each
//! rung an independent render with a fixed seed ([`ladder`]), timed by the renderer and
//! compared (RMSE, relMSE) with a converged reference rendered once with the best
//! configuration at high spp and cached by scene content and renderer sources ([`reference`],
//! [`cache_key`]).
//!
//! **One axis at a time.** The axes are BSDF sampling (cosine, NDF, VNDF, spherical caps,
//! bounded VNDF), light strategy (BSDF only, NEE only, MIS), sequence (independent, sobol),
//! backend (cpu, wgpu) and kernel (specialized, generic). Their cross product, 120
//! configurations per scene, is too big to measure, so [`configs`] varies one axis at a time
//! from the baseline `vndf-mis-sobol-cpu-spec`: 5 + 2 + 1 + 1 + 1 = 10 configurations.
//!
//! Outputs (default `target/xtask/bench/full/`, `--quick`: `target/xtask/bench/quick/`):
//! `bench.csv` ([`csv`]), two log-log SVG plots per scene ([`plots`]), `summary.md`
//! ([`summary`], with the numbers of [`analysis`]: time to reach a target relMSE, relMSE at
//! equal time, specialization speed-up), and the bunny comparison of cosine, NDF and VNDF
//! sampling with firefly counts ([`comparison`], [`fireflies`]). The run fails when one of the
//! [`checks`] fails (after writing everything), so `--quick` is a real test in CI.
//!
//! The wgpu configuration runs by default and in `--quick`; without an adapter that is an
//! error, not a silent skip (`--no-wgpu` leaves it out, and the summary says so).

mod analysis;
pub(crate) mod cache_key;
pub(crate) mod checks;
mod comparison;
mod configs;
pub(crate) mod csv;
pub(crate) mod files;
mod fireflies;
pub(crate) mod interp;
pub(crate) mod ladder;
mod options;
pub(crate) mod plots;
pub(crate) mod reference;
pub(crate) mod robust;
mod summary;

use crate::render::{self, Backend, Overrides};
use options::{Command, Options, USAGE};
use std::path::Path;
use std::time::Instant;
use summary::{Machine, SceneReport};

/// Runs `cargo xtask bench` with the arguments after `bench` (see [`options::USAGE`]).
pub fn run(args: &[String]) -> Result<(), String> {
    match options::parse(args)? {
        Command::Help => {
            println!("{USAGE}");
            Ok(())
        }
        Command::Run(options) => study(&options),
    }
}

/// The whole study: ladders per scene, the bunny comparison, outputs, checks.
fn study(o: &Options) -> Result<(), String> {
    let start = Instant::now();
    let bench_dir = render::output_dir("bench")?;
    let out = o.out.clone().unwrap_or_else(|| bench_dir.join(if o.quick { "quick" } else { "full" }));
    let cache = bench_dir.join("reference");
    for dir in [&out, &cache] {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    let paths = render::scene_paths(&o.scenes)?;
    let names: Vec<String> = paths.iter().map(|p| render::scene_name(p)).collect();
    if let Some((i, dup)) = names.iter().enumerate().find(|(i, n)| names[..*i].contains(n)) {
        return Err(format!("bench: scene `{dup}` is given twice (entry {})", i + 1));
    }
    let gpu = if o.wgpu {
        Some(render::gpu_context().map_err(|e| format!("{e}; pass --no-wgpu to measure the CPU backend only"))?)
    } else {
        None
    };
    let machine = Machine {
        cpu: cpu_model(),
        threads: rayon::current_num_threads(),
        adapter: gpu.as_ref().map(|g| g.describe()),
        profile: if cfg!(debug_assertions) {
            "dev profile (ggx-core, ggx-cpu and external crates at opt-level 3)"
        } else {
            "release profile"
        },
    };
    let configs = configs::all(o.wgpu);
    let mut scenes = Vec::new();
    let mut outputs = Vec::new();
    for (path, name) in paths.iter().zip(&names) {
        let base = render::load(path, Overrides { width: o.width, spp: 1 })?;
        let [width, height] = base.camera.resolution;
        eprintln!("\n{name}: {width}x{height}, {} configurations", configs.len());
        let reference = reference::load_or_render(path, &base, o.ref_spp, &cache)?;
        let mut series = Vec::new();
        for &config in &configs {
            let max = if config.backend == Backend::Wgpu { o.wgpu_max_spp } else { o.max_spp };
            series.push(ladder::run(&base, config, max, &reference.pixels, gpu.as_ref())?);
        }
        let plots = plots::write(&out, name, &series)?;
        outputs.extend(plots.iter().cloned());
        scenes.push(SceneReport { name: name.clone(), width, height, reference: reference.path, series, plots });
    }
    let comparison = comparison::run(o.compare_width, o.compare_spp, o.ref_spp, &out, &cache)?;
    outputs.push(comparison.png.clone());
    outputs.extend(comparison.entries.iter().map(|e| e.exr.clone()));

    let csv_path = out.join("bench.csv");
    let table: Vec<(String, Vec<ladder::Series>)> = scenes.iter().map(|s| (s.name.clone(), s.series.clone())).collect();
    files::write_atomic(&csv_path, csv::format(&table).as_bytes())?;
    outputs.push(csv_path);

    let mut all_checks: Vec<checks::Check> = scenes.iter().flat_map(|s| checks::ladders(&s.name, &s.series)).collect();
    all_checks.extend(checks::comparison(&comparison));
    all_checks.push(checks::files(&outputs));
    let summary_path = out.join("summary.md");
    let md = summary::markdown(o, &machine, &scenes, &comparison, &all_checks);
    files::write_atomic(&summary_path, md.as_bytes())?;

    report(&out, &summary_path, &all_checks, start.elapsed().as_secs_f64())
}

/// Prints the checks and where the outputs are; fails when a check failed.
fn report(out: &Path, summary: &Path, checks: &[checks::Check], seconds: f64) -> Result<(), String> {
    eprintln!("\nchecks:");
    for c in checks {
        eprintln!("  [{}] {}: {}", if c.passed { "ok" } else { "FAIL" }, c.name, c.detail);
    }
    eprintln!("\nbench: outputs in {}, summary {} ({seconds:.1} s)", out.display(), summary.display());
    let failed: Vec<&str> = checks.iter().filter(|c| !c.passed).map(|c| c.name.as_str()).collect();
    if failed.is_empty() {
        Ok(())
    } else {
        Err(format!("bench: {} check(s) failed: {}", failed.len(), failed.join("; ")))
    }
}

/// The CPU model from `/proc/cpuinfo`, else the architecture.
pub(crate) fn cpu_model() -> String {
    let model = std::fs::read_to_string("/proc/cpuinfo").ok().and_then(|info| {
        info.lines()
            .find(|l| l.starts_with("model name"))
            .and_then(|l| l.split_once(':'))
            .map(|(_, m)| m.trim().to_string())
    });
    let logical = std::thread::available_parallelism().map_or(0, usize::from);
    format!("{} ({logical} logical CPUs)", model.unwrap_or_else(|| std::env::consts::ARCH.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    #[test]
    fn help_is_not_an_error_and_unknown_flags_are() {
        assert_eq!(run(&["--help".into()]), Ok(()));
        let e = run(&["--bogus".into()]).unwrap_err();
        assert!(e.contains("unknown argument `--bogus`") && e.contains("usage:"), "{e}");
    }

    #[test]
    fn report_fails_on_a_failed_check() {
        let ok = checks::Check { name: "a".into(), passed: true, detail: String::new() };
        let bad = checks::Check { name: "b".into(), passed: false, detail: "x".into() };
        let p = PathBuf::from("x");
        assert!(report(&p, &p, std::slice::from_ref(&ok), 1.0).is_ok());
        assert_eq!(report(&p, &p, &[ok, bad], 1.0), Err("bench: 1 check(s) failed: b".into()));
    }
}
