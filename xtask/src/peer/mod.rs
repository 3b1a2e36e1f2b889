//! `cargo xtask peer`: ggx beside Mitsuba 3 on the same scene files, in one run.
//!
//! [`setup`] installs what is missing (LLVM 19, a venv with the pinned Mitsuba), builds the
//! release `ggx` and starts the Mitsuba [`driver`]. Then, per scene (`scenes/peer/*.toml`):
//! `ggx export --format mitsuba`, Mitsuba's first render with a cold kernel cache, both
//! converged references ([`reference`], cached), and the spp ladders of every configuration
//! ([`series::configs`]) interleaved rung by rung, ggx through `ggx render --stats`
//! ([`ggx_side`]) and Mitsuba through the driver, each rung measured against its renderer's own
//! reference. [`metrics`] turns the ladders into throughput, efficiency and agreement,
//! [`microbench`] runs the GGX micro-benchmarks, and [`report`] and [`images`] write
//! `summary.md`, the CSVs, the plots and the references side by side under
//! `target/xtask/peer/{full,quick}/`. The run fails when a check fails (after writing
//! everything): metrics that are not finite, references that disagree, missing outputs.
//!
//! Not part of `cargo xtask ci`: the Mitsuba wheel is large and the full run takes long.

mod driver;
pub(crate) mod ggx_side;
mod goals;
mod images;
mod metrics;
mod microbench;
mod options;
mod reference;
mod report;
mod series;
mod setup;

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use driver::{Driver, RenderRequest};
use metrics::Rung;
use options::{Command as Cli, Options, USAGE};
use report::{MicroReport, RefInfo, Run, SceneReport};
use series::{Config, FirstRender, Renderer, Series};

use crate::bench::files::write_atomic;
use crate::bench::ladder::spp_ladder;
use crate::bench::robust::{TRIM, trimmed_rel_mse};
use crate::render;

/// Grid points per ggx texel in the exported environment maps.
pub const ENV_UPSAMPLE: u32 = 4;
/// Seed of every ladder rung (references use bench's `REFERENCE_SEED`).
pub const LADDER_SEED: u32 = 1;
/// The agreement grid.
pub const GRID: (usize, usize) = (4, 4);

/// Runs `cargo xtask peer` with the arguments after `peer`.
pub fn run(args: &[String]) -> Result<(), String> {
    match options::parse(args)? {
        Cli::Help => {
            println!("{USAGE}");
            Ok(())
        }
        Cli::Run(o) => compare(&o),
    }
}

/// `scenes/peer/NAME.toml`, or `NAME` itself when it is a file.
fn scene_path(name: &str) -> Result<PathBuf, String> {
    let direct = PathBuf::from(name);
    if direct.is_file() {
        return Ok(direct);
    }
    let path = render::scenes_dir().join("peer").join(format!("{name}.toml"));
    if path.is_file() { Ok(path) } else { Err(format!("no scene `{name}` (looked for {})", path.display())) }
}

/// The 1-minute load average (`/proc/loadavg`), or `?`.
fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .ok()
        .and_then(|s| s.split_whitespace().next().map(String::from))
        .unwrap_or_else(|| "?".into())
}

/// The CPU: bench's model line, with the x86 family and model numbers and the widest vector
/// extension from `/proc/cpuinfo` (what Dr.Jit's JIT compiles for; ggx is built for the
/// default target).
fn cpu_description() -> String {
    let info = std::fs::read_to_string("/proc/cpuinfo").unwrap_or_default();
    let field = |key: &str| {
        info.lines()
            .find(|l| l.split(':').next().is_some_and(|k| k.trim() == key))
            .and_then(|l| l.split_once(':'))
            .map(|(_, v)| v.trim().to_owned())
    };
    let mut parts = Vec::new();
    if let (Some(f), Some(m)) = (field("cpu family"), field("model")) {
        parts.push(format!("family {f}, model {m}"));
    }
    let flags = field("flags").unwrap_or_default();
    let has = |f: &str| flags.split_whitespace().any(|x| x == f);
    if has("avx512f") {
        parts.push("AVX-512".into());
    } else if has("avx2") {
        parts.push("AVX2".into());
    }
    let model = crate::bench::cpu_model();
    if parts.is_empty() { model } else { format!("{model}; {}", parts.join(", ")) }
}

/// Output of a command's stdout, trimmed, or `None`.
fn command_output(program: &str, args: &[&str]) -> Option<String> {
    let out = Command::new(program).args(args).output().ok().filter(|o| o.status.success())?;
    Some(String::from_utf8_lossy(&out.stdout).trim().to_owned())
}

/// The checkout's commit (`git rev-parse --short HEAD`) and whether its tree has changes
/// not committed (`git status --porcelain`).
fn revision() -> Revision {
    let root = render::workspace_root();
    let git = |args: &[&str]| {
        let mut all = vec!["-C", root.to_str().unwrap_or(".")];
        all.extend_from_slice(args);
        command_output("git", &all)
    };
    Revision {
        commit: git(&["rev-parse", "--short", "HEAD"]).unwrap_or_else(|| "unknown commit".into()),
        dirty: git(&["status", "--porcelain"]).is_some_and(|s| !s.is_empty()),
    }
}

/// A commit and whether the tree had uncommitted changes.
#[derive(Clone, Debug, PartialEq)]
struct Revision {
    commit: String,
    dirty: bool,
}

/// What the report says the binaries were built from: the revision at the start of the run
/// (`start`, taken before the builds), and a note when the checkout was not the same at the end
/// (`end`), so that an edit made while the renders ran is not mistaken for the measured code.
fn describe_revision(start: &Revision, end: &Revision) -> String {
    let built = format!("at {}{}", start.commit, if start.dirty { " with uncommitted changes" } else { "" });
    if start == end {
        return built;
    }
    let now = format!("{}{}", end.commit, if end.dirty { " with uncommitted changes" } else { "" });
    format!("{built} (built at the start of the run; the checkout was {now} at its end)")
}

/// The whole comparison.
fn compare(o: &Options) -> Result<(), String> {
    let start = Instant::now();
    let load_start = load_average();
    let peer_dir = render::output_dir("peer")?;
    let out = o.out.clone().unwrap_or_else(|| peer_dir.join(if o.quick { "quick" } else { "full" }));
    let cache = peer_dir.join("reference");
    let work = peer_dir.join("work");
    for dir in [&out, &cache, &work] {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    let paths: Vec<PathBuf> = o.scenes.iter().map(|s| scene_path(s)).collect::<Result<_, _>>()?;
    // Before `setup` builds the release ggx (and the micro-benchmark builds ggx-core's bench):
    // the sources the binaries are built from.
    let built_from = revision();
    let setup = setup::ensure(&peer_dir)?;
    let threads = std::thread::available_parallelism().map_or(1, usize::from);

    eprintln!("\n==> GGX micro-benchmark: ggx-core's criterion benchmark");
    let mut micro = MicroReport { ggx: microbench::run_ggx(if o.quick { 1 } else { 3 })?, mitsuba: Vec::new() };
    let mut driver = Driver::start(&setup, &peer_dir.join("jit-home"))?;
    let versions = driver.hello()?;
    eprintln!(
        "\n==> Mitsuba {} / Dr.Jit {} (Python {}, LLVM {})",
        versions.mitsuba,
        versions.drjit,
        versions.python,
        setup.llvm.display()
    );
    let mut thread_counts = vec![1];
    if threads > 1 {
        thread_counts.push(threads);
    }
    for &t in &thread_counts {
        eprintln!("  Mitsuba GGX micro-benchmark, {t} thread(s)");
        micro.mitsuba.push((t, driver.microbench(t, microbench::LANES, 5, microbench::ALPHA)?));
    }

    let configs = series::configs(threads, o.max_spp, o.single_max_spp);
    let mut scenes = Vec::new();
    let mut outputs = Vec::new();
    for path in &paths {
        let report = scene(o, &setup, &mut driver, &versions, path, &configs, threads, &cache, &work, &out)?;
        outputs.extend(report.files.iter().cloned());
        scenes.push(report);
    }
    drop(driver);

    let mut checks: Vec<_> = scenes.iter().flat_map(report::checks).collect();
    for (name, text) in [
        ("peer.csv", report::rungs_csv(&scenes)),
        ("agreement.csv", report::agreement_csv(&scenes)),
        ("microbench.csv", report::micro_csv(&micro)),
    ] {
        let p = out.join(name);
        write_atomic(&p, text.as_bytes())?;
        outputs.push(p);
    }
    checks.push(crate::bench::checks::files(&outputs));
    let run = Run {
        date: command_output("date", &["-u", "+%Y-%m-%d"]).unwrap_or_else(|| "?".into()),
        cpu: cpu_description(),
        threads,
        load: (load_start, load_average()),
        ggx: format!("{} {}", env!("CARGO_PKG_VERSION"), describe_revision(&built_from, &revision())),
        versions,
        llvm: setup.llvm.display().to_string(),
        quick: o.quick,
        max_spp: o.max_spp,
        single_max_spp: o.single_max_spp,
        ref_spp: o.ref_spp,
        env_upsample: ENV_UPSAMPLE,
        seconds: start.elapsed().as_secs_f64(),
    };
    let summary = out.join("summary.md");
    write_atomic(&summary, report::markdown(&run, &scenes, &micro, &checks).as_bytes())?;

    eprintln!("\nchecks:");
    for c in &checks {
        eprintln!("  [{}] {}: {}", if c.passed { "ok" } else { "FAIL" }, c.name, c.detail);
    }
    eprintln!("\npeer: outputs in {}, summary {} ({:.0} s)", out.display(), summary.display(), run.seconds);
    let failed: Vec<&str> = checks.iter().filter(|c| !c.passed).map(|c| c.name.as_str()).collect();
    if failed.is_empty() {
        Ok(())
    } else {
        Err(format!("peer: {} check(s) failed: {}", failed.len(), failed.join("; ")))
    }
}

/// One scene: export, first renders, references, interleaved ladders, metrics, figures.
#[allow(clippy::too_many_arguments)]
fn scene(
    o: &Options,
    setup: &setup::Setup,
    driver: &mut Driver,
    versions: &driver::Versions,
    path: &Path,
    configs: &[Config],
    threads: usize,
    cache: &Path,
    work: &Path,
    out: &Path,
) -> Result<SceneReport, String> {
    let name = render::scene_name(path);
    let dir = work.join(&name);
    let export_dir = dir.join("mitsuba");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&export_dir).map_err(|e| format!("{}: {e}", export_dir.display()))?;

    // The scene as both renderers see it.
    let base = ggx_scene::load_scene(path).map_err(|e| e.to_string())?;
    let size = match o.width {
        Some(w) => render::load(path, render::Overrides { width: w, spp: 1 })?.camera.resolution,
        None => base.camera.resolution,
    };
    let [width, height] = size;
    eprintln!("\n{name}: {width}x{height}, {} triangles, {} configurations", base.mesh.triangles.len(), configs.len());
    let xml = export_dir.join(format!("{name}.xml"));
    ggx_side::export(&setup.ggx, path, &xml, o.width, ENV_UPSAMPLE)?;
    let mut side_files: Vec<PathBuf> = std::fs::read_dir(&export_dir)
        .map_err(|e| format!("{}: {e}", export_dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p != &xml)
        .collect();
    side_files.sort();
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let independent = dir.join(format!("{name}-independent.toml"));
    write_atomic(
        &independent,
        ggx_side::independent_variant(&text, path.parent().unwrap_or(Path::new("."))).as_bytes(),
    )?;
    let check = ggx_scene::load_scene(&independent).map_err(|e| format!("the independent-sampler copy: {e}"))?;
    if check.integrator.sampler != ggx_scene::SamplerKind::Independent || check.mesh.triangles != base.mesh.triangles {
        return Err(format!("{}: the independent-sampler copy differs from the scene", independent.display()));
    }

    // Mitsuba's first render of each variant, with a cold kernel cache.
    let mut first = Vec::new();
    for renderer in [Renderer::MitsubaLlvm, Renderer::MitsubaScalar] {
        let variant = renderer.variant().unwrap_or("llvm_ad_rgb");
        let target = dir.join(format!("first-{}.exr", renderer.name()));
        let r = driver.render(&RenderRequest {
            variant,
            scene: &xml,
            threads,
            spp: 1,
            seed: 0,
            max_pass_spp: 1,
            out: &target,
        })?;
        eprintln!("  first {variant} render: {:.3} s (JIT {:.3} s)", r.seconds, r.jit_seconds);
        first.push(FirstRender { renderer, spp: 1, seconds: r.seconds, jit_seconds: r.jit_seconds });
    }

    let ggx_ref = reference::ggx(&setup.ggx, path, &name, size, o.width, o.ref_spp, cache)?;
    let mi_ref = reference::mitsuba(driver, versions, &xml, &side_files, &name, size, o.ref_spp, threads, cache)?;

    // The ladders, interleaved rung by rung.
    let top = configs.iter().map(|c| c.max_spp).max().unwrap_or(1);
    let mut series: Vec<Series> = configs.iter().map(|&config| Series { config, rungs: Vec::new() }).collect();
    for spp in spp_ladder(top) {
        for s in series.iter_mut().filter(|s| spp <= s.config.max_spp) {
            let c = s.config;
            let image = dir.join(format!("{}-{spp}.exr", c.name()));
            let (seconds, jit_seconds, camera_samples) = match c.renderer {
                Renderer::GgxSobol | Renderer::GgxIndependent => {
                    let scene = if c.renderer == Renderer::GgxSobol { path } else { independent.as_path() };
                    let stats = image.with_extension("json");
                    let job = ggx_side::RenderJob {
                        scene,
                        out: &image,
                        stats: &stats,
                        spp,
                        seed: LADDER_SEED,
                        threads: c.threads,
                        width: o.width,
                    };
                    let st = ggx_side::render(&setup.ggx, &job)?;
                    (st.seconds, 0.0, st.camera_samples)
                }
                Renderer::MitsubaLlvm | Renderer::MitsubaScalar => {
                    let variant = c.renderer.variant().unwrap_or("llvm_ad_rgb");
                    let r = driver.render(&RenderRequest {
                        variant,
                        scene: &xml,
                        threads: c.threads,
                        spp,
                        seed: LADDER_SEED,
                        max_pass_spp: reference::MAX_PASS_SPP,
                        out: &image,
                    })?;
                    (r.seconds, r.jit_seconds, u64::from(width) * u64::from(height) * u64::from(spp))
                }
            };
            let (w, h, pixels) = ggx_film::read_exr(&image).map_err(|e| e.to_string())?;
            // Measured: the rung's files are not kept (the references are).
            let _ = std::fs::remove_file(&image);
            let _ = std::fs::remove_file(image.with_extension("json"));
            if (w, h) != (width, height) {
                return Err(format!("{}: {w}x{h}, expected {width}x{height}", image.display()));
            }
            let reference = if c.renderer.variant().is_some() { &mi_ref.pixels } else { &ggx_ref.pixels };
            let rel_mse = ggx_film::compare(&pixels, reference, 1.0).map_err(|e| e.to_string())?.rel_mse;
            let rung = Rung {
                spp,
                seconds,
                jit_seconds,
                camera_samples,
                rel_mse,
                rel_mse_trimmed: trimmed_rel_mse(&pixels, reference, TRIM),
            };
            eprintln!(
                "    {:<22} {spp:>5} spp {:>9.4} s  relMSE {:.3e}  {:.3} M samples/s",
                c.name(),
                seconds,
                rel_mse,
                rung.samples_per_second() * 1e-6
            );
            s.rungs.push(rung);
        }
    }

    let agreement = metrics::agreement(&ggx_ref.pixels, &mi_ref.pixels, width as usize, height as usize, GRID)?;
    let top_of = |r: Renderer| {
        series
            .iter()
            .find(|s| s.config.renderer == r && s.config.threads == threads)
            .and_then(|s| s.rungs.last())
            .map_or((1, f64::NAN), |t| (t.spp, t.rel_mse))
    };
    let noise_floor = metrics::noise_floor(top_of(Renderer::GgxSobol), top_of(Renderer::MitsubaLlvm), o.ref_spp);
    let mut files = images::plots(out, &name, &series)?;
    files.push(images::references_png(out, &name, &ggx_ref.pixels, &mi_ref.pixels, width, height)?);
    let file = path.strip_prefix(render::workspace_root()).unwrap_or(path).display().to_string();
    Ok(SceneReport {
        name,
        file,
        width,
        height,
        triangles: base.mesh.triangles.len(),
        series,
        first,
        agreement,
        noise_floor,
        references: [
            RefInfo { path: ggx_ref.path, seconds: ggx_ref.seconds },
            RefInfo { path: mi_ref.path, seconds: mi_ref.seconds },
        ],
        files,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rev(commit: &str, dirty: bool) -> Revision {
        Revision { commit: commit.into(), dirty }
    }

    #[test]
    fn the_revision_is_the_one_the_binaries_were_built_from() {
        assert_eq!(describe_revision(&rev("1e35cea", false), &rev("1e35cea", false)), "at 1e35cea");
        assert_eq!(
            describe_revision(&rev("1e35cea", true), &rev("1e35cea", true)),
            "at 1e35cea with uncommitted changes"
        );
        // An edit made while the renders ran does not describe the measured binaries.
        assert_eq!(
            describe_revision(&rev("1e35cea", false), &rev("1e35cea", true)),
            "at 1e35cea (built at the start of the run; the checkout was 1e35cea with uncommitted changes at its end)"
        );
        assert_eq!(
            describe_revision(&rev("1e35cea", true), &rev("b4e9ad2", false)),
            "at 1e35cea with uncommitted changes (built at the start of the run; the checkout was b4e9ad2 at its end)"
        );
    }
}
