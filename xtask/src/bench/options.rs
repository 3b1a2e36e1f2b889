//! The command line of `cargo xtask bench`: flags, their defaults for the full and the
//! `--quick` run, and validation (every bad value is an `Err` naming the flag).

use ggx_scene::{MAX_RESOLUTION, MAX_SPP};
use std::path::PathBuf;

/// Printed by `--help` and after an unknown or malformed flag.
pub const USAGE: &str = "usage: cargo xtask bench [--quick] [--scenes a,b] [--width W] [--max-spp N] [--ref-spp N]
                         [--no-wgpu] [--out DIR] [--help]

Convergence study: every scene is rendered with 10 configurations (the baseline VNDF + MIS +
sobol + cpu + specialized kernel, and one axis changed at a time: BSDF sampling cosine / NDF /
spherical caps / bounded VNDF, light strategy BSDF-only / NEE-only, independent sampler, wgpu
backend, generic kernel) at 1, 2, 4, ... spp, each rung an independent render with a fixed seed,
timed and compared with a cached high-spp reference. Then the bunny comparison: cosine vs NDF vs
VNDF sampling side by side, with firefly counts.

  --quick        the CI-sized run (three-spheres, width 32, ladder to 16 spp, reference 256 spp,
                 wgpu ladder to 4 spp, bunny comparison 64 px wide at 64 spp); checks fail the run
  --scenes a,b   scenes by name or path (default: three-spheres,cornell,bunny,glass; --quick: three-spheres)
  --width W      image width in pixels, height from the scene's aspect (default 128; --quick: 32)
  --max-spp N    top of the spp ladder, powers of two up to N (default 256; --quick: 16); the wgpu
                 ladder stops at min(N, 32) (--quick: min(N, 4)): lavapipe is ~25x slower than the CPU
  --ref-spp N    reference spp, at least 4 x --max-spp (default 4096; --quick: 256); the bunny
                 comparison uses min(512, N / 4) spp (--quick: min(64, N / 4)) at width 160 (--quick: 64)
  --no-wgpu      skip the wgpu configuration (otherwise a missing adapter is an error)
  --out DIR      output directory (default target/xtask/bench/full, --quick: target/xtask/bench/quick);
                 references are cached in target/xtask/bench/reference/ whatever DIR is
  --help         this text";

/// Sizes of one preset (the full run or `--quick`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Preset {
    scenes: &'static [&'static str],
    width: u32,
    max_spp: u32,
    ref_spp: u32,
    wgpu_cap: u32,
    compare_width: u32,
    compare_spp: u32,
}

/// The full run, sized for the README figures (about 15 minutes on 2 cores). `glass` compares
/// the samplers on transmission (cosine and uniform fall back to VNDF there, bounded VNDF to
/// spherical caps).
const FULL: Preset = Preset {
    scenes: &["three-spheres", "cornell", "bunny", "glass"],
    width: 128,
    max_spp: 256,
    ref_spp: 4096,
    wgpu_cap: 32,
    compare_width: 160,
    compare_spp: 512,
};

/// `--quick`: what CI runs, well under 3 minutes on 2 cores with lavapipe.
const QUICK: Preset = Preset {
    scenes: &["three-spheres"],
    width: 32,
    max_spp: 16,
    ref_spp: 256,
    wgpu_cap: 4,
    compare_width: 64,
    compare_spp: 64,
};

/// The reference must have at least this many times the spp of the ladder's top rung (its own
/// noise then adds at most 1/4 to the measured relMSE of that rung).
pub const REF_SPP_FACTOR: u32 = 4;

/// Validated options of one bench run.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Options {
    /// `--quick`: the CI-sized run.
    pub quick: bool,
    /// Scene names or paths, in the order given.
    pub scenes: Vec<String>,
    /// Image width of the ladder renders and the reference.
    pub width: u32,
    /// Top rung of the CPU ladder.
    pub max_spp: u32,
    /// Top rung of the wgpu ladder (`min(max_spp, cap)`).
    pub wgpu_max_spp: u32,
    /// Samples per pixel of the references.
    pub ref_spp: u32,
    /// Whether the wgpu configuration runs (`--no-wgpu` turns it off).
    pub wgpu: bool,
    /// `--out DIR`, or `None` for the default under `target/xtask/bench/`.
    pub out: Option<PathBuf>,
    /// Width of the bunny comparison images.
    pub compare_width: u32,
    /// Samples per pixel of the bunny comparison.
    pub compare_spp: u32,
}

/// What the command line asks for.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Command {
    /// `--help`: print [`USAGE`].
    Help,
    /// Run the study.
    Run(Options),
}

/// Flags as given, before defaults and validation.
#[derive(Default)]
struct Raw {
    quick: bool,
    help: bool,
    no_wgpu: bool,
    scenes: Option<Vec<String>>,
    width: Option<u32>,
    max_spp: Option<u32>,
    ref_spp: Option<u32>,
    out: Option<PathBuf>,
}

/// Parses the arguments after `bench`. Flags take their value as the next argument or after
/// `=` (`--width 64`, `--width=64`); a repeated flag keeps its last value.
pub fn parse(args: &[String]) -> Result<Command, String> {
    let mut raw = Raw::default();
    let mut args = args.iter();
    while let Some(arg) = args.next() {
        let (flag, inline) = match arg.split_once('=') {
            Some((f, v)) if f.starts_with("--") => (f, Some(v.to_string())),
            _ => (arg.as_str(), None),
        };
        let mut value = || -> Result<String, String> {
            match &inline {
                Some(v) => Ok(v.clone()),
                None => args.next().cloned().ok_or_else(|| format!("bench: {flag} needs a value\n\n{USAGE}")),
            }
        };
        match flag {
            "--quick" | "--no-wgpu" | "--help" | "-h" if inline.is_some() => {
                return Err(format!("bench: {flag} takes no value\n\n{USAGE}"));
            }
            "--quick" => raw.quick = true,
            "--no-wgpu" => raw.no_wgpu = true,
            "--help" | "-h" => raw.help = true,
            "--scenes" => raw.scenes = Some(parse_scenes(&value()?)?),
            "--width" => raw.width = Some(parse_u32("--width", &value()?, MAX_RESOLUTION)?),
            "--max-spp" => raw.max_spp = Some(parse_u32("--max-spp", &value()?, MAX_SPP)?),
            "--ref-spp" => raw.ref_spp = Some(parse_u32("--ref-spp", &value()?, MAX_SPP)?),
            "--out" => raw.out = Some(PathBuf::from(non_empty("--out", value()?)?)),
            _ => return Err(format!("bench: unknown argument `{arg}`\n\n{USAGE}")),
        }
    }
    if raw.help {
        return Ok(Command::Help);
    }
    build(raw).map(Command::Run)
}

/// Applies the preset's defaults to the flags given and checks the combination.
fn build(raw: Raw) -> Result<Options, String> {
    let preset = if raw.quick { QUICK } else { FULL };
    let max_spp = raw.max_spp.unwrap_or(preset.max_spp);
    let ref_spp = raw.ref_spp.unwrap_or(preset.ref_spp);
    if u64::from(ref_spp) < u64::from(REF_SPP_FACTOR) * u64::from(max_spp) {
        return Err(format!(
            "bench: --ref-spp {ref_spp} is too low for --max-spp {max_spp}: the reference needs at least \
             {REF_SPP_FACTOR} x the ladder's top spp, so that its own noise stays small"
        ));
    }
    Ok(Options {
        quick: raw.quick,
        scenes: raw.scenes.unwrap_or_else(|| preset.scenes.iter().map(|s| s.to_string()).collect()),
        width: raw.width.unwrap_or(preset.width),
        max_spp,
        wgpu_max_spp: max_spp.min(preset.wgpu_cap),
        ref_spp,
        wgpu: !raw.no_wgpu,
        out: raw.out,
        compare_width: preset.compare_width,
        compare_spp: preset.compare_spp.min(ref_spp / REF_SPP_FACTOR).max(1),
    })
}

/// An integer in `1..=max`.
fn parse_u32(flag: &str, s: &str, max: u32) -> Result<u32, String> {
    match s.trim().parse::<u32>() {
        Ok(n) if (1..=max).contains(&n) => Ok(n),
        _ => Err(format!("bench: {flag} `{s}` is not an integer from 1 to {max}")),
    }
}

/// `a,b,c` into names; empty entries are an error.
fn parse_scenes(s: &str) -> Result<Vec<String>, String> {
    let names: Vec<String> = s.split(',').map(|n| n.trim().to_string()).collect();
    if names.iter().any(String::is_empty) {
        return Err(format!("bench: --scenes `{s}` has an empty name (expected e.g. `cornell,bunny`)"));
    }
    Ok(names)
}

/// The value unless it is empty.
fn non_empty(flag: &str, s: String) -> Result<String, String> {
    if s.is_empty() { Err(format!("bench: {flag} needs a non-empty value")) } else { Ok(s) }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse_strs(args: &[&str]) -> Result<Command, String> {
        parse(&args.iter().map(|s| s.to_string()).collect::<Vec<_>>())
    }

    fn options(args: &[&str]) -> Options {
        match parse_strs(args) {
            Ok(Command::Run(o)) => o,
            other => panic!("{args:?}: {other:?}"),
        }
    }

    #[test]
    fn defaults() {
        let full = options(&[]);
        assert_eq!(full.scenes, ["three-spheres", "cornell", "bunny", "glass"]);
        assert_eq!((full.width, full.max_spp, full.wgpu_max_spp, full.ref_spp), (128, 256, 32, 4096));
        assert_eq!((full.compare_width, full.compare_spp), (160, 512));
        assert!(full.wgpu && !full.quick && full.out.is_none());
        let quick = options(&["--quick"]);
        assert_eq!(quick.scenes, ["three-spheres"]);
        assert_eq!((quick.width, quick.max_spp, quick.wgpu_max_spp, quick.ref_spp), (32, 16, 4, 256));
        assert_eq!((quick.compare_width, quick.compare_spp), (64, 64));
    }

    #[test]
    fn flags_with_and_without_equals() {
        let o = options(&["--quick", "--scenes", "cornell, bunny", "--width=48", "--max-spp", "2", "--ref-spp=64"]);
        assert_eq!(o.scenes, ["cornell", "bunny"]);
        assert_eq!((o.width, o.max_spp, o.wgpu_max_spp, o.ref_spp), (48, 2, 2, 64));
        // The comparison never has more than a quarter of the reference's spp.
        assert_eq!(o.compare_spp, 16);
        let o = options(&["--no-wgpu", "--out", "x/y", "--width", "10", "--width", "20"]);
        assert!(!o.wgpu);
        assert_eq!(o.out, Some(PathBuf::from("x/y")));
        assert_eq!(o.width, 20, "the last value wins");
    }

    #[test]
    fn help() {
        assert_eq!(parse_strs(&["--help"]), Ok(Command::Help));
        assert_eq!(parse_strs(&["--quick", "-h"]), Ok(Command::Help));
    }

    #[test]
    fn errors() {
        let err = |args: &[&str]| parse_strs(args).unwrap_err();
        assert!(err(&["--fast"]).contains("unknown argument `--fast`"));
        assert!(err(&["--fast"]).contains("usage: cargo xtask bench"));
        assert!(err(&["extra"]).contains("unknown argument `extra`"));
        assert!(err(&["--width"]).contains("--width needs a value"));
        assert!(err(&["--width", "0"]).contains("--width `0` is not an integer from 1 to 16384"));
        assert!(err(&["--width", "-3"]).contains("not an integer"));
        assert!(err(&["--max-spp", "many"]).contains("--max-spp `many`"));
        assert!(err(&["--scenes", "a,,b"]).contains("empty name"));
        assert!(err(&["--out="]).contains("non-empty"));
        assert!(err(&["--quick=yes"]).contains("--quick takes no value"));
        assert!(err(&["--max-spp", "2048"]).contains("--ref-spp 4096 is too low for --max-spp 2048"));
        assert!(err(&["--quick", "--ref-spp", "63"]).contains("too low"));
    }
}
