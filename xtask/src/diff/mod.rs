//! `cargo xtask diff [--quick] [--width W] [--spp N] [SCENES...]`: renders each scene on the CPU
//! and wgpu backends with the same seed and sample count and compares the images.
//!
//! Both backends draw the same sample streams in the same order, so they trace the same paths
//! until a float difference flips a branch (see `crates/ggx-wgpu/tests/render_parity.rs`).
//! Per scene, under `target/xtask/diff/<scene>/`: `cpu.exr`, `wgpu.exr`, `diff.png` (largest
//! relative channel error per pixel, log scale 1e-7 to 1 through magma) and `flip.png` (the
//! FLIP error map); `target/xtask/diff/report.md` tabulates RMSE, relative MSE, max relative
//! error, the share of pixels over the pixel tolerance and mean FLIP against the scene's bounds
//! in `scenes/tolerances/diff.toml`. Any scene over a bound, or no wgpu adapter, is a failure.

mod flip_tool;
mod images;
mod report;
mod tolerances;

use crate::render::{self, Backend, Overrides};
use ggx_cpu::AccelKind;
use ggx_film::{OutputOptions, compare, write_image};
use report::{Report, Row};
use std::path::PathBuf;
use tolerances::Tolerances;

/// Usage of `diff`.
const USAGE: &str = "usage: cargo xtask diff [--quick] [--width W] [--spp N] [--cpu-bvh wide|cwbvh|bvh2] [SCENES...]
  --quick          width 48, 8 spp (what `cargo xtask ci` runs)
  --width W        image width; the height follows the scene's aspect ratio (default 128)
  --spp N          samples per pixel (default 32)
  --cpu-bvh KIND   the CPU backend's BVH: wide (default, what `ggx render` uses), cwbvh, or bvh2
                   (the layout the wgpu backend traces, so ties between triangles resolve alike)
  SCENES           scene names (e.g. cornell) or paths; default: every scenes/*.toml";

/// Parsed arguments.
#[derive(Clone, Debug, PartialEq)]
pub struct Options {
    /// Image size and sample count.
    pub overrides: Overrides,
    /// Scene names or paths; empty = all.
    pub scenes: Vec<String>,
    /// The CPU backend's BVH layout.
    pub cpu_bvh: AccelKind,
}

impl Options {
    /// Parses the arguments after `diff`.
    pub fn parse(args: &[String]) -> Result<Options, String> {
        let mut options =
            Options { overrides: Overrides { width: 128, spp: 32 }, scenes: Vec::new(), cpu_bvh: AccelKind::default() };
        let mut it = args.iter();
        while let Some(arg) = it.next() {
            let mut number = |flag: &str| -> Result<u32, String> {
                let v = it.next().ok_or_else(|| format!("{flag} needs a value\n\n{USAGE}"))?;
                match v.parse::<u32>() {
                    Ok(n) if n > 0 => Ok(n),
                    _ => Err(format!("{flag}: `{v}` is not a positive integer\n\n{USAGE}")),
                }
            };
            match arg.as_str() {
                "--quick" => options.overrides = Overrides { width: 48, spp: 8 },
                "--width" => options.overrides.width = number("--width")?,
                "--spp" => options.overrides.spp = number("--spp")?,
                "--cpu-bvh" => {
                    options.cpu_bvh = match it.next().map(String::as_str) {
                        Some("wide") => AccelKind::Wide,
                        Some("cwbvh") => AccelKind::Cwbvh,
                        Some("bvh2") => AccelKind::Bvh2,
                        other => {
                            return Err(format!("--cpu-bvh: expected wide, cwbvh or bvh2, got {other:?}\n\n{USAGE}"));
                        }
                    }
                }
                "-h" | "--help" => return Err(USAGE.into()),
                flag if flag.starts_with('-') => return Err(format!("unknown option `{flag}`\n\n{USAGE}")),
                scene => options.scenes.push(scene.into()),
            }
        }
        Ok(options)
    }
}

/// Runs the diff; `Err` when any scene fails its tolerances or cannot be rendered.
pub fn run(args: &[String]) -> Result<(), String> {
    let options = Options::parse(args)?;
    let paths = render::scene_paths(&options.scenes)?;
    let all: Vec<String> = render::scene_paths(&[])?.iter().map(|p| render::scene_name(p)).collect();
    let tolerances = Tolerances::load(&render::scenes_dir().join("tolerances/diff.toml"), &all)?;
    let ctx = render::gpu_context()?;
    let flip_tool = flip_tool::FlipTool::build()?;
    let out = render::output_dir("diff")?;
    let mut report = {
        // Relative to the workspace, so a committed copy of the report names no machine's paths.
        let root = render::workspace_root();
        let bounds = tolerances.path().strip_prefix(&root).unwrap_or(tolerances.path()).to_owned();
        Report::new(ctx.describe(), options.overrides, bounds, format!("{:?}", options.cpu_bvh))
    };
    for path in &paths {
        let name = render::scene_name(path);
        let row = diff_scene(path, &name, &options, &tolerances, &ctx, &flip_tool, out.join(&name))?;
        eprintln!("{}", row.line());
        report.rows.push(row);
    }
    let report_path = out.join("report.md");
    std::fs::write(&report_path, report.markdown()).map_err(|e| format!("{}: {e}", report_path.display()))?;
    eprintln!("diff: report in {}", report_path.display());
    let failed: Vec<&str> = report.rows.iter().filter(|r| !r.passed()).map(|r| r.scene.as_str()).collect();
    if failed.is_empty() { Ok(()) } else { Err(format!("over tolerance: {}", failed.join(", "))) }
}

/// Renders one scene on both backends, writes its images and measures the difference.
fn diff_scene(
    path: &std::path::Path,
    name: &str,
    options: &Options,
    tolerances: &Tolerances,
    ctx: &ggx_wgpu::GpuContext,
    flip_tool: &flip_tool::FlipTool,
    dir: PathBuf,
) -> Result<Row, String> {
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let scene = render::load(path, options.overrides)?;
    let [width, height] = scene.camera.resolution;
    let cpu = render::render_with(&scene, Backend::Cpu, true, None, options.cpu_bvh)?;
    let gpu = render::render(&scene, Backend::Wgpu, true, Some(ctx)).map_err(|e| format!("{name}: {e}"))?;
    let (a, b) = (gpu.film.mean(), cpu.film.mean());
    let output = OutputOptions::default();
    for (file, pixels) in [("cpu.exr", &b), ("wgpu.exr", &a)] {
        write_image(&dir.join(file), width, height, pixels, &output).map_err(|e| e.to_string())?;
    }
    images::write_png(&dir.join("diff.png"), width, height, &images::false_colour(&a, &b))?;
    let flip = flip_tool.measure(&dir.join("wgpu.exr"), &dir.join("cpu.exr"), &dir.join("flip.png"))?;
    let tolerance = tolerances.get(name);
    let metrics = compare(&a, &b, tolerance.pixel).map_err(|e| format!("{name}: {e}"))?;
    Ok(Row {
        scene: name.into(),
        resolution: [width, height],
        spp: cpu.spp.min(gpu.spp),
        kernel: cpu.kernel,
        cpu_seconds: cpu.elapsed.as_secs_f64(),
        gpu_seconds: gpu.elapsed.as_secs_f64(),
        metrics,
        flip,
        tolerance,
        same_spp: cpu.spp == gpu.spp && cpu.kernel == gpu.kernel,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(s: &str) -> Vec<String> {
        s.split_whitespace().map(String::from).collect()
    }

    #[test]
    fn parses_flags_and_scenes() {
        let o = Options::parse(&args("--quick cornell bunny")).unwrap();
        assert_eq!(o.overrides.width, 48);
        assert_eq!(o.overrides.spp, 8);
        assert_eq!(o.scenes, ["cornell", "bunny"]);
        let o = Options::parse(&args("--width 64 --spp 4")).unwrap();
        assert_eq!((o.overrides.width, o.overrides.spp), (64, 4));
        assert!(o.scenes.is_empty());
        assert_eq!(o.cpu_bvh, AccelKind::Wide);
        assert_eq!(Options::parse(&args("--cpu-bvh bvh2")).unwrap().cpu_bvh, AccelKind::Bvh2);
        assert_eq!(Options::parse(&args("--cpu-bvh cwbvh")).unwrap().cpu_bvh, AccelKind::Cwbvh);
        assert!(Options::parse(&args("--cpu-bvh kd")).is_err());
    }

    #[test]
    fn rejects_bad_arguments() {
        for bad in ["--width", "--width 0", "--spp x", "--frobnicate", "--cpu-bvh", "--cpu-bvh bvh4"] {
            let e = Options::parse(&args(bad)).unwrap_err();
            assert!(e.contains("usage"), "{bad}: {e}");
        }
    }
}
