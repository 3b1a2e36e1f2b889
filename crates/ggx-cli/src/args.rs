//! The command line: `ggx render`, `ggx merge`, `ggx info` and `ggx export`, parsed and range-checked by clap (whose
//! usage errors exit with code 2).

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand, ValueEnum};
use ggx_scene::{MAX_RESOLUTION, MAX_SEED, MAX_SPP};

use crate::limits_args::LimitArgs;

const EXAMPLES: &str = "\
Examples:
  ggx render scenes/cornell.toml -o cornell.png
  ggx render scenes/cornell.toml -o cornell.exr --spp 4096 --time 60
  ggx render scenes/furnace.toml -o furnace.png --width 512 --tonemap clamp
  ggx info scenes/bunny.toml
  ggx render scenes/cornell.toml --samples 0..512 -o part-0.exr
  ggx render scenes/cornell.toml --samples 512..1024 -o part-1.exr
  ggx merge part-0.exr part-1.exr -o cornell.exr
  ggx export scenes/peer/three-spheres.toml --format mitsuba -o peer/three-spheres.xml

Exit codes: 0 success, 1 error, 2 usage error, 130 interrupted (the partial image is written).";

const RENDER_EXAMPLES: &str = "\
Examples:
  ggx render scenes/cornell.toml -o cornell.png
  ggx render scenes/cornell.toml -o cornell.exr --spp 100000 --time 30
  ggx render scenes/bunny.toml -o bunny.png --width 1280 --exposure 0.5 --threads 8
  ggx render scenes/cornell.toml -o bench.exr --accel bvh2 --generic
  ggx render scenes/cornell.toml -o part.exr --samples 256..512 --crop 0,0,128,128
  ggx render scenes/cornell.toml -o cornell.exr --checkpoint cornell.ckpt.exr --checkpoint-every 30
  ggx render scenes/cornell.toml -o cornell.exr --resume cornell.ckpt.exr
  ggx render scenes/turntable.toml -o 'frames/turntable-####.png' --frames 0..49

Ctrl-C (or SIGTERM) stops the render and still writes the image of what was rendered (the
finished tiles of the pass in flight included; an EXR then records each pixel's sample
count); press it again to quit at once. The exit code is then 130.";

const MERGE_EXAMPLES: &str = "\
Examples:
  ggx merge parts/part-*.exr -o final.exr
  ggx merge parts/part-*.exr -o final.png --exposure 1
  ggx merge parts/part-*.exr -o preview.exr --allow-missing

The parts must come from the same scene, settings, seed, frame, backend and ggx version and
hold disjoint samples; the merged image is the same, bit for bit, as one render of them all.";

const EXPORT_EXAMPLES: &str = "\
Examples:
  ggx export scenes/peer/three-spheres.toml --format mitsuba -o peer/three-spheres.xml
  ggx export scenes/peer/bunny.toml -o bunny.xml --width 512 --spp 1024 --env-upsample 4
  python3 -c \"import mitsuba as mi; mi.set_variant('llvm_ad_rgb'); \\
    mi.Bitmap(mi.render(mi.load_file('peer/three-spheres.xml'))).write('m.exr')\"

Writes the exact triangles ggx renders (one mesh file per material beside the XML, shading
normals kept), diffuse and conductor materials (eta/k or F = 1; rough, anisotropic or smooth),
emitters, a constant or map environment (the map resampled onto Mitsuba's grid and axes), the
camera (fov_axis y) and the path integrator (max_depth = ggx's + 1: Mitsuba counts path
segments). A used material without a one-to-one twin (plastic, dielectric, Schlick f0, energy
compensation on) is refused, naming it.";

/// Renders GGX microfacet scenes with a CPU path tracer.
#[derive(Debug, Parser)]
#[command(name = "ggx", version, propagate_version = true, after_help = EXAMPLES)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Render a scene to an EXR or PNG image.
    #[command(after_help = RENDER_EXAMPLES)]
    Render(RenderArgs),
    /// Print what a scene contains, its settings and BVH build times.
    Info(InfoArgs),
    /// Add film files rendered with --samples, --crop or --checkpoint into one image.
    #[command(after_help = MERGE_EXAMPLES)]
    Merge(MergeArgs),
    /// Write a scene for another renderer (Mitsuba 3), with its meshes and environment map.
    #[command(after_help = EXPORT_EXAMPLES)]
    Export(ExportArgs),
}

/// `ggx render`.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// Scene file (TOML), or a glTF file (.gltf, .glb).
    pub scene: PathBuf,

    /// glTF camera and environment.
    #[command(flatten, next_help_heading = "glTF")]
    pub gltf: crate::scene_load::GltfArgs,

    /// Output image: .exr (linear HDR) or .png (tone-mapped sRGB), chosen by the extension.
    /// With --frames, runs of `#` in the name are the zero-padded frame number.
    #[arg(short, long, value_name = "OUT")]
    pub output: PathBuf,

    /// Render only samples [A, B) of every pixel; the output (.exr) is then an exact film
    /// that `ggx merge` adds to the other parts.
    #[arg(long, value_name = "A..B", value_parser = parse_range)]
    pub samples: Option<[u32; 2]>,

    /// Render only the pixels [X0, X1) x [Y0, Y1); the output (.exr) is an exact film.
    #[arg(long, value_name = "X0,Y0,X1,Y1", value_parser = parse_window)]
    pub crop: Option<[u32; 4]>,

    /// Write the exact film to this .exr file every --checkpoint-every seconds (atomically)
    /// and when the render ends; `--resume FILE` continues it.
    #[arg(long, value_name = "FILE.exr")]
    pub checkpoint: Option<PathBuf>,

    /// Seconds between checkpoints (written at the end of a pass).
    #[arg(long, value_name = "SECONDS", default_value_t = 60.0, value_parser = parse_interval)]
    pub checkpoint_every: f32,

    /// Continue the render saved in this film file (a checkpoint, or an interrupted part):
    /// the final image is the same, bit for bit, as one never interrupted. Give --samples to
    /// extend its range (same start, a later end).
    #[arg(long, value_name = "FILE.exr")]
    pub resume: Option<PathBuf>,

    /// The frame of an animated camera ([[camera.keys]]) to render [default: 0].
    #[arg(long, value_name = "N", conflicts_with = "frames",
          value_parser = clap::value_parser!(u32).range(0..i64::from(ggx_scene::MAX_FRAMES)))]
    pub frame: Option<u32>,

    /// Render frames [A, B) of an animated camera, one image each (`#` in the output name).
    #[arg(long, value_name = "A..B", value_parser = parse_range, conflicts_with_all = ["resume", "checkpoint"])]
    pub frames: Option<[u32; 2]>,

    /// Samples per pixel [default: the scene's integrator.spp].
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=i64::from(MAX_SPP)))]
    pub spp: Option<u32>,

    /// Time budget: stop when it is used up, even with fewer than --spp samples per pixel;
    /// 0 means no budget [default: the scene's integrator.time].
    #[arg(long, value_name = "SECONDS", allow_negative_numbers = true, value_parser = parse_seconds)]
    pub time: Option<f32>,

    /// Seed of the sample sequence, in [0, 4294967295]: each gives a different image
    /// [default: the scene's integrator.seed].
    #[arg(long, value_name = "S", value_parser = clap::value_parser!(u64).range(0..=MAX_SEED))]
    pub seed: Option<u64>,

    /// The image size.
    #[command(flatten)]
    pub size: SizeArgs,

    /// Worker threads; 0 uses every core.
    #[arg(long, value_name = "N", default_value_t = 0, value_parser = clap::value_parser!(u16).range(0..=MAX_THREADS))]
    pub threads: u16,

    /// Where to render.
    #[arg(long, value_enum, default_value_t = Backend::Cpu)]
    pub backend: Backend,

    /// Exposure in stops: the image is scaled by 2^STOPS before it is written.
    #[arg(long, value_name = "STOPS", default_value_t = 0.0, allow_negative_numbers = true, value_parser = parse_exposure)]
    pub exposure: f32,

    /// Tone curve of PNG output (EXR output stays linear).
    #[arg(long, value_enum, default_value_t = ToneMapArg::Aces)]
    pub tonemap: ToneMapArg,

    /// Ray-tracing acceleration structure.
    #[arg(long, value_enum, default_value_t = AccelArg::Wide)]
    pub accel: AccelArg,

    /// Use the generic kernel instead of the one specialized to the scene's features
    /// (for benchmarking the specialization).
    #[arg(long)]
    pub generic: bool,

    /// Also write the render's statistics as JSON: scene, backend, adapter, kernel, spp,
    /// time, camera samples/s, rays/s and the time of every pass (with --frames, one file per
    /// frame: `#` in the name).
    #[arg(long, value_name = "FILE.json")]
    pub stats: Option<PathBuf>,

    /// Energy compensation of every GGX material (multiple scattering: Kulla & Conty for
    /// conductors, the albedo scale for dielectrics, the coat's 1 - E for plastics)
    /// [default: the scene's integrator.energy_compensation if given, else each material's
    /// energy_compensation, itself on by default].
    #[arg(long, value_enum, value_name = "ON|OFF")]
    pub energy_compensation: Option<OnOff>,

    /// Limits on what is read and allocated.
    #[command(flatten, next_help_heading = "Limits")]
    pub limits: LimitArgs,
}

/// `--width` and `--height`, shared by `ggx render` and `ggx export`.
#[derive(Debug, Args)]
pub struct SizeArgs {
    /// Image width; alone, the height follows the scene's aspect ratio.
    #[arg(long, value_name = "W", value_parser = clap::value_parser!(u32).range(1..=i64::from(MAX_RESOLUTION)))]
    pub width: Option<u32>,

    /// Image height; alone, the width follows the scene's aspect ratio.
    #[arg(long, value_name = "H", value_parser = clap::value_parser!(u32).range(1..=i64::from(MAX_RESOLUTION)))]
    pub height: Option<u32>,
}

/// `ggx info`.
#[derive(Debug, Args)]
pub struct InfoArgs {
    /// Scene file (TOML), or a glTF file (.gltf, .glb).
    pub scene: PathBuf,

    /// glTF camera and environment.
    #[command(flatten, next_help_heading = "glTF")]
    pub gltf: crate::scene_load::GltfArgs,

    /// Limits on what is read and allocated.
    #[command(flatten, next_help_heading = "Limits")]
    pub limits: LimitArgs,
}

/// `ggx merge`.
#[derive(Debug, Args)]
pub struct MergeArgs {
    /// Film files (.exr written with --samples, --crop or --checkpoint, or by ggx merge).
    #[arg(required = true, value_name = "PART")]
    pub parts: Vec<PathBuf>,

    /// Output: .exr (an exact film: it can be merged again or resumed) or .png.
    #[arg(short, long, value_name = "OUT")]
    pub output: PathBuf,

    /// Write the image even when samples or pixels are missing (each pixel then averages
    /// the samples it has; the film records the counts).
    #[arg(long)]
    pub allow_missing: bool,

    /// Exposure in stops: the image is scaled by 2^STOPS before it is written.
    #[arg(long, value_name = "STOPS", default_value_t = 0.0, allow_negative_numbers = true, value_parser = parse_exposure)]
    pub exposure: f32,

    /// Tone curve of PNG output (EXR output stays linear).
    #[arg(long, value_enum, default_value_t = ToneMapArg::Aces)]
    pub tonemap: ToneMapArg,

    /// Limits on what is read and allocated.
    #[command(flatten, next_help_heading = "Limits")]
    pub limits: LimitArgs,
}

/// `ggx export`.
#[derive(Debug, Args)]
pub struct ExportArgs {
    /// Scene file (TOML).
    pub scene: PathBuf,

    /// The other renderer's format.
    #[arg(long, value_enum, default_value_t = ExportFormat::Mitsuba)]
    pub format: ExportFormat,

    /// The scene file to write (.xml); meshes and the environment map go beside it, named
    /// after it.
    #[arg(short, long, value_name = "OUT.xml")]
    pub output: PathBuf,

    /// Mesh file format.
    #[arg(long, value_enum, default_value_t = MeshFormatArg::Ply)]
    pub mesh_format: MeshFormatArg,

    /// Grid points per ggx texel in the exported environment map: Mitsuba interpolates
    /// bilinearly where ggx looks up the nearest texel, and the difference shrinks as 1/K.
    #[arg(long, value_name = "K", default_value_t = 2, value_parser = clap::value_parser!(u32).range(1..=i64::from(crate::mitsuba::envmap::MAX_UPSAMPLE)))]
    pub env_upsample: u32,

    /// Samples per pixel [default: the scene's integrator.spp].
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=i64::from(MAX_SPP)))]
    pub spp: Option<u32>,

    /// Seed of Mitsuba's sampler [default: the scene's integrator.seed].
    #[arg(long, value_name = "S", value_parser = clap::value_parser!(u64).range(0..=MAX_SEED))]
    pub seed: Option<u64>,

    /// The image size.
    #[command(flatten)]
    pub size: SizeArgs,

    /// The frame of an animated camera ([[camera.keys]]) to export [default: 0].
    #[arg(long, value_name = "N")]
    pub frame: Option<u32>,

    /// Energy compensation of every GGX material; Mitsuba's conductors are single-scattering,
    /// so a compensated conductor is refused [default: the scene's].
    #[arg(long, value_enum, value_name = "ON|OFF")]
    pub energy_compensation: Option<OnOff>,

    /// Limits on what is read and allocated.
    #[command(flatten, next_help_heading = "Limits")]
    pub limits: LimitArgs,
}

/// `ggx export --format`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ExportFormat {
    /// Mitsuba 3 scene XML (version 3.0.0).
    Mitsuba,
}

/// `ggx export --mesh-format`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum MeshFormatArg {
    /// Binary little-endian PLY.
    Ply,
    /// Wavefront OBJ.
    Obj,
}

/// Largest accepted `--threads`.
const MAX_THREADS: i64 = 4096;

/// `--backend`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Backend {
    /// The CPU path tracer.
    Cpu,
    /// The GPU path tracer (wgpu).
    Wgpu,
    /// wgpu when available, else the CPU.
    Auto,
}

/// A switch given on the command line.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum OnOff {
    /// Enabled.
    On,
    /// Disabled.
    Off,
}

/// `--tonemap`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ToneMapArg {
    /// ACES filmic curve (Narkowicz's fit).
    Aces,
    /// Reinhard, x / (1 + x).
    Reinhard,
    /// Clip to [0, 1].
    Clamp,
}

/// `--accel`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum AccelArg {
    /// 8-wide BVH of uncompressed boxes, nearest child first.
    Wide,
    /// Compressed wide BVH (8-wide).
    Cwbvh,
    /// Binary BVH.
    Bvh2,
}

/// `--time`: a finite number of seconds >= 0 (0: no budget). Budgets too long for a
/// `Duration` are no budget in effect (the renderers treat them so).
fn parse_seconds(s: &str) -> Result<f32, String> {
    match s.trim().parse::<f32>() {
        Ok(t) if t >= 0.0 && t.is_finite() => Ok(t),
        Ok(_) => Err(format!("must be a finite number of seconds >= 0 (0: no budget), got {s}")),
        Err(e) => Err(format!("not a number of seconds ({e})")),
    }
}

/// `A..B` with `A < B`: a half-open range of samples or frames.
fn parse_range(s: &str) -> Result<[u32; 2], String> {
    let bad = || format!("expected A..B with whole numbers A < B (samples or frames [A, B)), got `{s}`");
    let (a, b) = s.trim().split_once("..").ok_or_else(bad)?;
    let (a, b): (u32, u32) = (a.trim().parse().map_err(|_| bad())?, b.trim().parse().map_err(|_| bad())?);
    if a >= b {
        return Err(bad());
    }
    Ok([a, b])
}

/// `X0,Y0,X1,Y1` with `X0 < X1`, `Y0 < Y1` (checked against the image size later).
fn parse_window(s: &str) -> Result<[u32; 4], String> {
    let bad = || format!("expected X0,Y0,X1,Y1 with X0 < X1 and Y0 < Y1 (pixels), got `{s}`");
    let values: Vec<u32> = s.split(',').map(|v| v.trim().parse().map_err(|_| bad())).collect::<Result<_, _>>()?;
    match <[u32; 4]>::try_from(values) {
        Ok([x0, y0, x1, y1]) if x0 < x1 && y0 < y1 => Ok([x0, y0, x1, y1]),
        _ => Err(bad()),
    }
}

/// `--checkpoint-every`: a finite number of seconds > 0.
fn parse_interval(s: &str) -> Result<f32, String> {
    match s.trim().parse::<f32>() {
        Ok(t) if t > 0.0 && t.is_finite() => Ok(t),
        _ => Err(format!("must be a number of seconds > 0, got {s}")),
    }
}

/// `--exposure`: a finite number of stops small enough that 2^stops stays finite.
fn parse_exposure(s: &str) -> Result<f32, String> {
    match s.trim().parse::<f32>() {
        Ok(e) if (-64.0..=64.0).contains(&e) => Ok(e),
        Ok(_) => Err(format!("must be in [-64, 64] stops, got {s}")),
        Err(e) => Err(format!("not a number of stops ({e})")),
    }
}

#[cfg(test)]
mod tests {
    use clap::CommandFactory;

    use super::*;

    fn parse(args: &[&str]) -> Result<RenderArgs, clap::Error> {
        let cli = Cli::try_parse_from(["ggx", "render", "s.toml", "-o", "x.png"].iter().chain(args))?;
        match cli.command {
            Command::Render(r) => Ok(r),
            _ => unreachable!("parsed a render command"),
        }
    }

    #[test]
    fn command_is_well_formed() {
        Cli::command().debug_assert();
    }

    #[test]
    fn defaults_and_values() {
        let r = parse(&[]).unwrap();
        assert_eq!((r.spp, r.time, r.threads, r.backend), (None, None, 0, Backend::Cpu));
        assert_eq!((r.exposure, r.tonemap, r.accel, r.generic), (0.0, ToneMapArg::Aces, AccelArg::Wide, false));
        assert_eq!(r.energy_compensation, None);
        assert_eq!(parse(&["--energy-compensation", "off"]).unwrap().energy_compensation, Some(OnOff::Off));
        assert_eq!(parse(&["--energy-compensation", "on"]).unwrap().energy_compensation, Some(OnOff::On));
        assert!(parse(&["--energy-compensation", "maybe"]).is_err());
        let r = parse(&["--spp", "8", "--time", "1.5", "--exposure", "-2", "--accel", "bvh2", "--generic"]).unwrap();
        assert_eq!((r.spp, r.time, r.exposure, r.accel, r.generic), (Some(8), Some(1.5), -2.0, AccelArg::Bvh2, true));
        // 0 is no budget, as `time = 0` in a scene; huge budgets are accepted (no budget in effect).
        assert_eq!(parse(&["--time", "0"]).unwrap().time, Some(0.0));
        assert_eq!(parse(&["--time", "2e19"]).unwrap().time, Some(2e19));
        assert_eq!(parse(&["--seed", "4294967295"]).unwrap().seed, Some(4_294_967_295));
    }

    #[test]
    fn ranges_windows_and_frames() {
        let r = parse(&["--samples", "16..48", "--crop", "0,8,32,40", "--frame", "3"]).unwrap();
        assert_eq!((r.samples, r.crop, r.frame), (Some([16, 48]), Some([0, 8, 32, 40]), Some(3)));
        assert_eq!(parse(&["--frames", "0..49"]).unwrap().frames, Some([0, 49]));
        for bad in [&["--samples", "8..8"][..], &["--samples", "9..3"], &["--samples", "3"], &["--crop", "1,1,1,2"]] {
            let err = parse(bad).unwrap_err();
            assert_eq!(err.exit_code(), 2, "{bad:?}");
        }
        assert!(parse(&["--frame", "1", "--frames", "0..2"]).is_err());
        assert!(parse(&["--frame", "4294967295"]).is_err());
        assert!(parse(&["--frames", "0..2", "--resume", "x.exr"]).is_err());
        assert!(parse(&["--checkpoint-every", "0"]).is_err());
        let cli = Cli::try_parse_from(["ggx", "merge", "a.exr", "b.exr", "-o", "m.png", "--allow-missing"]).unwrap();
        let Command::Merge(m) = cli.command else { unreachable!("parsed a merge command") };
        assert_eq!((m.parts.len(), m.allow_missing), (2, true));
        assert!(Cli::try_parse_from(["ggx", "merge", "-o", "m.png"]).is_err());
    }

    #[test]
    fn export_arguments() {
        let cli = Cli::try_parse_from(["ggx", "export", "s.toml", "--format", "mitsuba", "-o", "s.xml"]).unwrap();
        let Command::Export(e) = cli.command else { unreachable!("parsed an export command") };
        assert_eq!((e.format, e.mesh_format, e.env_upsample), (ExportFormat::Mitsuba, MeshFormatArg::Ply, 2));
        assert_eq!((e.spp, e.size.width, e.energy_compensation), (None, None, None));
        let cli = Cli::try_parse_from([
            "ggx",
            "export",
            "s.toml",
            "-o",
            "s.xml",
            "--mesh-format",
            "obj",
            "--env-upsample",
            "4",
            "--spp",
            "8",
            "--width",
            "64",
            "--energy-compensation",
            "off",
        ])
        .unwrap();
        let Command::Export(e) = cli.command else { unreachable!("parsed an export command") };
        assert_eq!((e.mesh_format, e.env_upsample, e.spp, e.size.width), (MeshFormatArg::Obj, 4, Some(8), Some(64)));
        assert_eq!(e.energy_compensation, Some(OnOff::Off));
        for bad in [&["--format", "pbrt"][..], &["--env-upsample", "0"], &["--env-upsample", "9"], &["--spp", "0"]] {
            let args = [&["ggx", "export", "s.toml", "-o", "s.xml"][..], bad].concat();
            assert_eq!(Cli::try_parse_from(args).unwrap_err().exit_code(), 2, "{bad:?}");
        }
    }

    #[test]
    fn a_negative_time_gets_a_message_about_time() {
        let err = parse(&["--time", "-1"]).unwrap_err().to_string();
        assert!(err.contains("must be a finite number of seconds >= 0"), "{err}");
    }

    #[test]
    fn rejects_out_of_range_values() {
        for bad in [
            &["--spp", "0"][..],
            &["--spp", "-3"],
            &["--time", "-1"],
            &["--time", "-0.5"],
            &["--seed", "4294967296"],
            &["--seed", "18446744073709551615"],
            &["--time", "nan"],
            &["--time", "inf"],
            &["--width", "0"],
            &["--height", "99999"],
            &["--exposure", "1e9"],
            &["--threads", "100000"],
            &["--backend", "vulkan"],
            &["--tonemap", "filmic"],
        ] {
            let err = parse(bad).unwrap_err();
            assert_eq!(err.exit_code(), 2, "{bad:?}");
        }
    }
}
