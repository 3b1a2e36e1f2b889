//! The peer run's outputs as text: `summary.md` (everything a reader needs, the method
//! included), `peer.csv` (one line per rendered rung), `agreement.csv` and `microbench.csv`.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::driver::{Micro, Versions};
use super::metrics::{self, Agreement, Rung};
use super::microbench::OPS;
use super::series::{FirstRender, Renderer, Series};
use crate::bench::checks::Check;
use crate::bench::csv::field;
use crate::bench::interp::Estimate;

/// Where, when and how the run was made.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Run {
    /// `YYYY-MM-DD` (UTC).
    pub date: String,
    /// CPU model and logical CPU count.
    pub cpu: String,
    /// Threads of the all-cores configurations.
    pub threads: usize,
    /// `/proc/loadavg`'s 1-minute average at the start and at the end.
    pub load: (String, String),
    /// ggx's version and commit.
    pub ggx: String,
    /// Mitsuba side.
    pub versions: Versions,
    /// The LLVM library Dr.Jit uses.
    pub llvm: String,
    /// `--quick`.
    pub quick: bool,
    /// Top rung with all threads.
    pub max_spp: u32,
    /// Top rung with one thread.
    pub single_max_spp: u32,
    /// Reference spp.
    pub ref_spp: u32,
    /// Environment-map upsampling of the export.
    pub env_upsample: u32,
    /// Seconds of the whole run.
    pub seconds: f64,
}

/// A reference image: where it is and how long it took (`None`: read from the cache).
#[derive(Clone, Debug, PartialEq)]
pub struct RefInfo {
    /// The EXR.
    pub path: PathBuf,
    /// Render seconds, `None` when cached.
    pub seconds: Option<f64>,
}

/// One scene's results.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneReport {
    /// Name (file stem).
    pub name: String,
    /// The scene file, relative to the workspace.
    pub file: String,
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Triangles (both renderers trace these).
    pub triangles: usize,
    /// The ladders, the baseline (ggx Sobol', all threads) first.
    pub series: Vec<Series>,
    /// Mitsuba's first renders with a cold kernel cache.
    pub first: Vec<FirstRender>,
    /// ggx's reference against Mitsuba's.
    pub agreement: Agreement,
    /// relMSE expected between the references from their own noise.
    pub noise_floor: f64,
    /// ggx's and Mitsuba's references.
    pub references: [RefInfo; 2],
    /// Plots and images, in the output directory.
    pub files: Vec<PathBuf>,
}

/// The micro-benchmark results.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MicroReport {
    /// ggx-core's criterion results: id -> per second (one thread).
    pub ggx: BTreeMap<String, f64>,
    /// Mitsuba's per thread count.
    pub mitsuba: Vec<(usize, Micro)>,
}

/// Relative tolerance of the converged mean luminance ratio.
pub const MEAN_TOLERANCE: f64 = 0.02;
/// Relative tolerance of every region's luminance ratio.
pub const REGION_TOLERANCE: f64 = 0.05;

/// Seconds with a precision that suits the magnitude.
fn secs(v: f64) -> String {
    if v >= 100.0 {
        format!("{v:.0}")
    } else if v >= 1.0 {
        format!("{v:.2}")
    } else {
        format!("{v:.3}")
    }
}

/// Millions per second, two decimals (or three significant digits below 1).
fn mega(v: f64) -> String {
    let m = v * 1e-6;
    if m >= 1.0 { format!("{m:.2}") } else { format!("{m:.3}") }
}

/// A ratio as `1.23×` (`n/a` when not finite).
fn times(v: f64) -> String {
    if v.is_finite() { format!("{v:.2}×") } else { "n/a".into() }
}

/// A ratio near 1 with four decimals.
fn ratio(v: f64) -> String {
    if v.is_finite() { format!("{v:.4}") } else { "-".into() }
}

/// The file name of `p`.
fn file_name(p: &Path) -> String {
    p.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default()
}

/// The series of `renderer` at `threads`, if measured.
pub(super) fn find(series: &[Series], renderer: Renderer, threads: usize) -> Option<&Series> {
    series.iter().find(|s| s.config.renderer == renderer && s.config.threads == threads)
}

/// The top rung's relMSE and spp.
fn top(s: &Series) -> Option<(u32, f64)> {
    s.rungs.last().map(|r| (r.spp, r.rel_mse))
}

/// Checks of one scene: finite metrics and agreement within the tolerances.
pub fn checks(scene: &SceneReport) -> Vec<Check> {
    let mut bad = Vec::new();
    for s in &scene.series {
        for r in &s.rungs {
            let ok = r.seconds > 0.0 && r.rel_mse.is_finite() && r.rel_mse > 0.0 && r.rel_mse_trimmed.is_finite();
            if !ok {
                bad.push(format!("{} at {} spp: {} s, relMSE {}", s.config.name(), r.spp, r.seconds, r.rel_mse));
            }
        }
    }
    let g = &scene.agreement;
    if !g.rel_mse.is_finite() || g.mean_ratio.iter().any(|r| !r.is_finite()) {
        bad.push(format!("agreement not finite: {g:?}"));
    }
    let finite = Check {
        name: format!("{}: metrics finite", scene.name),
        passed: bad.is_empty(),
        detail: if bad.is_empty() { format!("{} series", scene.series.len()) } else { bad.join("; ") },
    };
    let mean = g.mean_ratio[3];
    let worst = g.worst_region();
    let agree = (mean - 1.0).abs() <= MEAN_TOLERANCE && (worst - 1.0).abs() <= REGION_TOLERANCE;
    let agreement = Check {
        name: format!("{}: converged references agree", scene.name),
        passed: agree,
        detail: format!(
            "mean luminance ratio ggx/Mitsuba {} (tolerance ±{:.0} %), worst of {}x{} regions {} (±{:.0} %)",
            ratio(mean),
            MEAN_TOLERANCE * 100.0,
            g.grid.0,
            g.grid.1,
            ratio(worst),
            REGION_TOLERANCE * 100.0
        ),
    };
    vec![finite, agreement]
}

/// `peer.csv`: one line per rung.
pub fn rungs_csv(scenes: &[SceneReport]) -> String {
    let mut out = String::from(
        "scene,config,renderer,sampler,threads,spp,seconds,jit_seconds,camera_samples,samples_per_second,rel_mse,rel_mse_trimmed\n",
    );
    for s in scenes {
        for series in &s.series {
            let c = series.config;
            for r in &series.rungs {
                let _ = writeln!(
                    out,
                    "{},{},{},{},{},{},{:.6},{:.6},{},{:.0},{:.6e},{:.6e}",
                    field(&s.name),
                    c.name(),
                    c.renderer.name(),
                    c.renderer.sampler(),
                    c.threads,
                    r.spp,
                    r.seconds,
                    r.jit_seconds,
                    r.camera_samples,
                    r.samples_per_second(),
                    r.rel_mse,
                    r.rel_mse_trimmed
                );
            }
        }
    }
    out
}

/// `agreement.csv`: per scene the mean ratios, every region's ratio, the relMSE between the
/// references and the noise floor, one `scene,quantity,value` line each.
pub fn agreement_csv(scenes: &[SceneReport]) -> String {
    let mut out = String::from("scene,quantity,value\n");
    for s in scenes {
        let g = &s.agreement;
        let mut line = |q: String, v: f64| {
            let _ = writeln!(out, "{},{q},{v:.6e}", field(&s.name));
        };
        for (c, v) in ["r", "g", "b", "luminance"].iter().zip(g.mean_ratio) {
            line(format!("mean_ratio_{c}"), v);
        }
        for (i, v) in g.regions.iter().enumerate() {
            line(format!("region_{}_{}_luminance_ratio", i / g.grid.1, i % g.grid.1), *v);
        }
        line("rel_mse".into(), g.rel_mse);
        line("rel_mse_trimmed".into(), g.rel_mse_trimmed);
        line("noise_floor_rel_mse".into(), s.noise_floor);
    }
    out
}

/// `microbench.csv`: one line per operation.
pub fn micro_csv(m: &MicroReport) -> String {
    let mut out = String::from("operation,ggx_id,ggx_per_second_1t,mitsuba_op");
    for (t, _) in &m.mitsuba {
        let _ = write!(out, ",mitsuba_per_second_{t}t");
    }
    out.push('\n');
    for op in OPS {
        let g = m.ggx.get(op.ggx).copied().unwrap_or(f64::NAN);
        let _ = write!(out, "{},{},{g:.0},{}", field(op.label), op.ggx, op.mitsuba);
        for (_, mi) in &m.mitsuba {
            let _ = write!(out, ",{:.0}", mi.per_second.get(op.mitsuba).copied().unwrap_or(f64::NAN));
        }
        out.push('\n');
    }
    out
}

/// The whole `summary.md`.
pub fn markdown(run: &Run, scenes: &[SceneReport], micro: &MicroReport, checks: &[Check]) -> String {
    let mut md = String::new();
    let v = &run.versions;
    let _ = writeln!(md, "# ggx beside Mitsuba 3 (`cargo xtask peer{}`)\n", if run.quick { " --quick" } else { "" });
    let _ = writeln!(
        md,
        "Measured {} on {}, {} threads for the all-core rows (1-minute load average {} at the start and {} at the \
         end: the machine is shared, so timings carry its noise; the renderers alternate rung by rung so both see \
         the same load). ggx {}, release build; Mitsuba {} and Dr.Jit {} from PyPI (Python {}, NumPy {}), Dr.Jit's \
         LLVM backend on {}. Ladders of 1 to {} spp with all threads and 1 to {} spp with one thread, against each \
         renderer's own {}-spp reference (cached); environment maps exported with {} grid points per texel. The run \
         took {} s.\n",
        run.date,
        run.cpu,
        run.threads,
        run.load.0,
        run.load.1,
        run.ggx,
        v.mitsuba,
        v.drjit,
        v.python,
        v.numpy,
        run.llvm,
        run.max_spp,
        run.single_max_spp,
        run.ref_spp,
        run.env_upsample,
        secs(run.seconds)
    );
    summary_table(&mut md, run, scenes);
    super::goals::section(&mut md, &super::goals::goals(scenes, run.threads, micro), run.threads);
    method(&mut md, run);
    for s in scenes {
        scene_section(&mut md, run, s);
    }
    micro_section(&mut md, micro);
    differences(&mut md);
    let _ = writeln!(md, "## Checks\n");
    for c in checks {
        let _ = writeln!(md, "- [{}] {}: {}", if c.passed { "x" } else { " " }, c.name, c.detail);
    }
    md
}

/// The one table across scenes.
fn summary_table(md: &mut String, run: &Run, scenes: &[SceneReport]) {
    let t = run.threads;
    let _ = writeln!(
        md,
        "## Summary\n\n| scene | ggx M samples/s ({t} t) | Mitsuba llvm M samples/s ({t} t) | Mitsuba ÷ ggx | same, 1 thread | \
         efficiency Mitsuba ÷ ggx | converged mean ratio ggx ÷ Mitsuba | worst region | relMSE between references \
         (noise floor) |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|"
    );
    for s in scenes {
        let tp = |r, th| find(&s.series, r, th).map_or(f64::NAN, |x| metrics::throughput(&x.rungs));
        let eff = |r, th| find(&s.series, r, th).map_or(f64::NAN, |x| metrics::efficiency(&x.rungs));
        let (g, m) = (tp(Renderer::GgxSobol, t), tp(Renderer::MitsubaLlvm, t));
        let (g1, m1) = (tp(Renderer::GgxSobol, 1), tp(Renderer::MitsubaLlvm, 1));
        let e = eff(Renderer::GgxSobol, t) / eff(Renderer::MitsubaLlvm, t);
        let a = &s.agreement;
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {:.2e} ({:.2e}) |",
            s.name,
            mega(g),
            mega(m),
            times(m / g),
            times(m1 / g1),
            times(e),
            ratio(a.mean_ratio[3]),
            ratio(a.worst_region()),
            a.rel_mse,
            s.noise_floor
        );
    }
    md.push('\n');
}

/// How the numbers are defined.
fn method(md: &mut String, run: &Run) {
    let _ = writeln!(
        md,
        "## Method\n\n\
         - **Same scene.** Each scene file is exported with `ggx export --format mitsuba`: the exact triangles ggx \
         renders (its shading normals kept), diffuse and conductor materials (`roughconductor`, GGX, visible-normal \
         sampling, eta/k), emitters, the environment, the camera (`fov_axis = y`) and `max_depth` + 1 (Mitsuba \
         counts path segments). No Russian roulette, single scattering on both sides.\n\
         - **Samplers.** ggx's default is Owen-scrambled Sobol'; Mitsuba's is `independent`. `ggx (independent)` is \
         the like-for-like row; Mitsuba's rows use `independent`.\n\
         - **Timing.** ggx: `ggx render --stats`' render time (scene load and BVH build excluded), the release \
         binary. Mitsuba: wall clock around `mi.render` and `dr.eval` in passes of at most 64 spp (scene load and \
         BVH build excluded; JIT compilation included where it happens: the first render of each scene and variant \
         runs with a cold kernel cache and is reported on its own). Same thread count on both sides: {} and 1.\n\
         - **Throughput**: camera samples/s, `sum(samples) / sum(seconds)` over the rungs from top/8 up.\n\
         - **relMSE** of every rung against the renderer's own reference (`ggx_film::compare`, epsilon 1e-2); \
         **relMSE × s** is the median over the same upper rungs (constant once the error falls as 1/spp); the \
         **efficiency ratio** is `(relMSE s)_ggx / (relMSE s)_other`: above 1 the other reaches an error sooner. \
         **relMSE at equal time** reads each curve at the ggx baseline's top-rung time (`≈`: extrapolated as 1/t).\n\
         - **Converged agreement**: ggx's reference against Mitsuba's: ratio of the means (R, G, B, luminance), the \
         luminance ratio in each region of a 4 x 4 grid, and relMSE between the two beside the noise floor (the two \
         references' own noise, each extrapolated from its ladder's top rung as 1/spp). A physics difference shows \
         as a ratio away from 1 and a relMSE well above the floor. Checked: mean within ±{:.0} %, regions within \
         ±{:.0} %.\n",
        run.threads,
        MEAN_TOLERANCE * 100.0,
        REGION_TOLERANCE * 100.0
    );
}

/// The model differences between the renderers that the agreement measures (found with this
/// command; the numbers above say how large they are in each run).
fn differences(md: &mut String) {
    let _ = writeln!(
        md,
        "## Known differences\n\n\
         Where the references differ beyond their noise, these are the causes found so far:\n\n\
         - **Smith G2.** ggx's conductor uses the height-correlated masking-shadowing `1 / (1 + Λo + Λi)`, \
         Mitsuba's `roughconductor` the separable `G1(o) G1(i)`, which is smaller. The difference grows with alpha \
         and at grazing angles: on the anisotropic scene's brushed plane (alpha up to 0.36) ggx is brighter by 1 % \
         near the camera and 3 % toward the horizon (the regions of the lower rows).\n\
         - **Shading normals at silhouettes.** A camera ray that hits a triangle whose interpolated shading \
         normal faces away from it ends the path in ggx (black); Mitsuba's `twosided` shades it. On the smooth \
         bunny this darkens a few pixels at the ear and the head's outline (under 1 % of the pixels, most of the \
         relMSE between the references); with `smooth = false` the means agree to 2e-4.\n\
         - **Environment filtering.** ggx looks up the nearest texel, Mitsuba interpolates bilinearly between \
         grid points; the export resamples the map with {} points per texel, so the two differ only in the last \
         1/{0} of a texel at each texel edge, symmetrically (the mean is kept).\n",
        super::ENV_UPSAMPLE
    );
}

/// One scene's tables.
fn scene_section(md: &mut String, run: &Run, s: &SceneReport) {
    let _ = writeln!(
        md,
        "## {}\n\n`{}`, {}x{}, {} triangles. References: ggx {} ({}), Mitsuba {} ({}).\n",
        s.name,
        s.file,
        s.width,
        s.height,
        s.triangles,
        file_name(&s.references[0].path),
        s.references[0].seconds.map_or("cached".into(), |t| format!("{} s", secs(t))),
        file_name(&s.references[1].path),
        s.references[1].seconds.map_or("cached".into(), |t| format!("{} s", secs(t))),
    );
    let baseline = find(&s.series, Renderer::GgxSobol, run.threads);
    let t_equal = baseline.and_then(|b| b.rungs.last()).map_or(f64::NAN, Rung::steady_seconds);
    let base_eff = baseline.map_or(f64::NAN, |b| metrics::efficiency(&b.rungs));
    let base_at = baseline.map(|b| metrics::rel_mse_at(&b.rungs, t_equal));
    let _ = writeln!(
        md,
        "| configuration | top spp | M camera samples/s | vs ggx (Sobol'), same threads | JIT in the ladder (s) | \
         relMSE at top | relMSE × s | efficiency vs ggx | relMSE at {} s | vs ggx |\n\
         |---|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
        secs(t_equal)
    );
    for series in &s.series {
        let c = series.config;
        let tp = metrics::throughput(&series.rungs);
        let base_tp =
            find(&s.series, Renderer::GgxSobol, c.threads).map_or(f64::NAN, |b| metrics::throughput(&b.rungs));
        let eff = metrics::efficiency(&series.rungs);
        let (top_spp, top_rel) = top(series).unwrap_or((0, f64::NAN));
        let at = metrics::rel_mse_at(&series.rungs, t_equal);
        let at_ratio = match (at, base_at) {
            (Estimate::Interpolated(a) | Estimate::Extrapolated(a), Some(Estimate::Interpolated(b))) => times(b / a),
            _ => "-".into(),
        };
        let same_threads = c.threads == run.threads;
        let _ = writeln!(
            md,
            "| {} | {top_spp} | {} | {} | {} | {:.3e} | {:.3e} | {} | {} | {} |",
            c.label(),
            mega(tp),
            times(tp / base_tp),
            secs(series.rungs.iter().map(|r| r.jit_seconds).sum()),
            top_rel,
            eff,
            if same_threads { times(base_eff / eff) } else { "-".into() },
            if same_threads { at.show(|v| format!("{v:.3e}")) } else { "-".into() },
            if same_threads { at_ratio } else { "-".into() },
        );
    }
    md.push('\n');
    if !s.first.is_empty() {
        let _ = writeln!(
            md,
            "Mitsuba's first render of the scene with a cold Dr.Jit kernel cache ({} threads), beside the same spp \
             in the ladder (steady state):\n\n\
             | variant | spp | first render (s) | of which JIT (s) | ladder rung, without JIT (s) |\n|---|---:|---:|---:|---:|",
            run.threads
        );
        for f in &s.first {
            let warm = find(&s.series, f.renderer, run.threads)
                .and_then(|x| x.rungs.iter().find(|r| r.spp == f.spp))
                .map_or("-".into(), |r| secs(r.steady_seconds()));
            let _ = writeln!(
                md,
                "| {} | {} | {} | {} | {warm} |",
                f.renderer.label(),
                f.spp,
                secs(f.seconds),
                secs(f.jit_seconds)
            );
        }
        md.push('\n');
    }
    let g = &s.agreement;
    let _ = writeln!(
        md,
        "Converged agreement, ggx ÷ Mitsuba: mean R {}, G {}, B {}, luminance {}; relMSE between the references \
         {:.3e} ({:.3e} without the worst 1 % of pixels), noise floor {:.3e}. Luminance ratio per region:\n",
        ratio(g.mean_ratio[0]),
        ratio(g.mean_ratio[1]),
        ratio(g.mean_ratio[2]),
        ratio(g.mean_ratio[3]),
        g.rel_mse,
        g.rel_mse_trimmed,
        s.noise_floor
    );
    let columns: Vec<String> = (1..=g.grid.1).map(|j| j.to_string()).collect();
    let _ = writeln!(md, "| row / column | {} |\n|---|{}", columns.join(" | "), "---:|".repeat(g.grid.1));
    for (i, row) in g.regions.chunks(g.grid.1.max(1)).enumerate() {
        let cells: Vec<String> = row.iter().map(|&r| ratio(r)).collect();
        let _ = writeln!(md, "| {} | {} |", i + 1, cells.join(" | "));
    }
    md.push('\n');
    for f in &s.files {
        let name = file_name(f);
        if name.ends_with(".png") {
            let _ = writeln!(md, "![{} references, ggx left, Mitsuba right]({name})\n", s.name);
        } else {
            let _ = writeln!(md, "- [{name}]({name})");
        }
    }
    md.push('\n');
}

/// The micro-benchmark table.
fn micro_section(md: &mut String, m: &MicroReport) {
    let _ = writeln!(
        md,
        "## GGX micro-benchmark\n\nggx-core: its criterion benchmark (`cargo bench -p ggx-core --bench core`, one \
         thread, 1024 cached inputs per iteration, default target CPU; the batch rows pick the CPU's widest vector \
         ISA at run time). Mitsuba: `MicrofacetDistribution` and \
         `roughconductor` (GGX, visible normals, F = 1) in `llvm_ad_rgb`, {} lanes per launch, JIT-compiled for this \
         CPU, best of 5. Alpha 0.3, cosine-distributed directions on both sides. Millions per second:\n",
        super::microbench::LANES
    );
    let mut header = String::from("| operation | ggx-core, 1 thread |");
    let mut rule = String::from("|---|---:|");
    for (t, _) in &m.mitsuba {
        let _ = write!(header, " Mitsuba, {t} thread{} |", if *t == 1 { "" } else { "s" });
        rule.push_str("---:|");
    }
    header.push_str(" Mitsuba ÷ ggx, 1 thread |");
    rule.push_str("---:|");
    let _ = writeln!(md, "{header}\n{rule}");
    for op in OPS {
        let g = m.ggx.get(op.ggx).copied().unwrap_or(f64::NAN);
        let mut line = format!("| {} (`{}` / `{}`) | {} |", op.label, op.ggx, op.mitsuba, mega(g));
        let mut one = f64::NAN;
        for (t, mi) in &m.mitsuba {
            let v = mi.per_second.get(op.mitsuba).copied().unwrap_or(f64::NAN);
            if *t == 1 {
                one = v;
            }
            let _ = write!(line, " {} |", mega(v));
        }
        let _ = write!(line, " {} |", times(one / g));
        let _ = writeln!(md, "{line}");
    }
    md.push('\n');
}

#[cfg(test)]
pub(super) mod tests {
    use super::super::series::Config;
    use super::*;

    pub(in crate::peer) fn series(renderer: Renderer, threads: usize, speed: f64, rel: f64) -> Series {
        let rungs = [1u32, 2, 4, 8]
            .iter()
            .map(|&spp| Rung {
                spp,
                seconds: f64::from(spp) / speed,
                jit_seconds: 0.0,
                camera_samples: u64::from(spp) * 1000,
                rel_mse: rel / f64::from(spp),
                rel_mse_trimmed: rel / f64::from(spp),
            })
            .collect();
        Series { config: Config { renderer, threads, max_spp: 8 }, rungs }
    }

    pub(in crate::peer) fn scene() -> SceneReport {
        SceneReport {
            name: "s".into(),
            file: "scenes/peer/s.toml".into(),
            width: 4,
            height: 4,
            triangles: 2,
            series: vec![
                series(Renderer::GgxSobol, 2, 1.0, 0.1),
                series(Renderer::MitsubaLlvm, 2, 4.0, 0.2),
                series(Renderer::GgxSobol, 1, 0.5, 0.1),
                series(Renderer::MitsubaLlvm, 1, 1.0, 0.2),
            ],
            first: vec![FirstRender { renderer: Renderer::MitsubaLlvm, spp: 1, seconds: 0.5, jit_seconds: 0.3 }],
            agreement: Agreement {
                mean_ratio: [1.001, 1.0, 0.999, 1.0005],
                regions: vec![1.0, 1.01, 0.98, f64::NAN],
                grid: (2, 2),
                rel_mse: 1e-4,
                rel_mse_trimmed: 9e-5,
            },
            noise_floor: 8e-5,
            references: [
                RefInfo { path: "a/s-ggx.exr".into(), seconds: Some(12.0) },
                RefInfo { path: "a/s-mitsuba.exr".into(), seconds: None },
            ],
            files: vec!["s-relmse-vs-time.svg".into(), "s-references.png".into()],
        }
    }

    #[test]
    fn summary_has_the_ratios() {
        let run = Run { threads: 2, max_spp: 8, single_max_spp: 8, ref_spp: 64, ..Run::default() };
        let s = scene();
        let c = checks(&s);
        let micro = MicroReport::default();
        let md = markdown(&run, std::slice::from_ref(&s), &micro, &c);
        // Mitsuba 4x the samples/s on two threads, 2x on one; relMSE 2x per sample, so
        // (relMSE s) ggx / Mitsuba = (0.1 / 1) / (0.2 / 4) = 2.
        assert!(
            md.contains("| s | 0.001 | 0.004 | 4.00× | 2.00× | 2.00× | 1.0005 | 0.9800 | 1.00e-4 (8.00e-5) |"),
            "{md}"
        );
        assert!(md.contains("![s references, ggx left, Mitsuba right](s-references.png)"), "{md}");
        assert!(md.contains("- [s-relmse-vs-time.svg](s-relmse-vs-time.svg)"), "{md}");
        assert!(
            md.contains("| row / column | 1 | 2 |\n|---|---:|---:|\n| 1 | 1.0000 | 1.0100 |\n| 2 | 0.9800 | - |"),
            "{md}"
        );
        assert!(md.contains("cached") && md.contains("12.00 s"), "{md}");
        assert!(c.iter().all(|c| c.passed), "{c:?}");
    }

    #[test]
    fn disagreement_fails_the_check() {
        let mut s = scene();
        s.agreement.mean_ratio[3] = 1.05;
        assert!(!checks(&s)[1].passed);
        let mut s = scene();
        s.agreement.regions[1] = 1.2;
        let c = checks(&s);
        assert!(!c[1].passed && c[1].detail.contains("1.2000"), "{c:?}");
        let mut s = scene();
        s.series[0].rungs[0].rel_mse = f64::NAN;
        assert!(!checks(&s)[0].passed);
    }

    #[test]
    fn csv_lines() {
        let s = scene();
        let text = rungs_csv(std::slice::from_ref(&s));
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 1 + 16);
        assert_eq!(lines[1], "s,ggx-sobol-2t,ggx-sobol,sobol,2,1,1.000000,0.000000,1000,1000,1.000000e-1,1.000000e-1");
        let a = agreement_csv(std::slice::from_ref(&s));
        assert!(
            a.contains("s,mean_ratio_luminance,1.000500e0\n")
                && a.contains("s,region_1_0_luminance_ratio,9.800000e-1\n"),
            "{a}"
        );
        let m = micro_csv(&MicroReport {
            ggx: [("scalar/D".to_string(), 2e8)].into_iter().collect(),
            mitsuba: vec![(1, Micro { per_second: [("D".to_string(), 1e9)].into_iter().collect() })],
        });
        assert!(m.starts_with("operation,ggx_id,ggx_per_second_1t,mitsuba_op,mitsuba_per_second_1t\n"), "{m}");
        assert!(m.contains("D(m) (ggx: scalar),scalar/D,200000000,D,1000000000\n"), "{m}");
    }
}
