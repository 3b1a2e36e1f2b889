//! The command line of `cargo xtask peer`: flags, the full and `--quick` presets, validation
//! (every bad value is an `Err` naming the flag).

use ggx_scene::{MAX_RESOLUTION, MAX_SPP};
use std::path::PathBuf;

/// Printed by `--help` and after an unknown or malformed flag.
pub const USAGE: &str = "usage: cargo xtask peer [--quick] [--scenes a,b] [--width W] [--max-spp N] [--ref-spp N]
                        [--single-max-spp N] [--out DIR] [--help]

ggx beside Mitsuba 3 on the same scene files, in one run. Installs what it needs (Debian's
libllvm19 with apt-get, a Python venv under target/xtask/peer/venv with pinned mitsuba and
drjit from PyPI), builds the release ggx, exports every scene with `ggx export --format
mitsuba`, then renders each on both renderers with the same thread counts (all cores and 1),
the spp ladders interleaved rung by rung, against each renderer's own cached high-spp
reference. Reports camera samples/s and their ratio, relMSE at equal time and the efficiency
ratio, the converged agreement of the two references (mean and per-region ratios, relMSE) and
Mitsuba's GGX micro-benchmark beside ggx-core's criterion benchmark. Fails when the references
disagree beyond the tolerances or a metric is not finite.

  --quick              small sizes for iteration (width 64, ladder to 16 spp, references 256 spp,
                       1-thread ladders to 4 spp); the full run takes tens of minutes on 2 cores
                       the first time (references are cached)
  --scenes a,b         scenes by name (scenes/peer/NAME.toml) or path
                       (default: three-spheres,bunny,anisotropic)
  --width W            image width (height from the aspect ratio; default: each scene's own)
  --max-spp N          top of the ladder with all threads, powers of two (default 256; --quick: 16)
  --ref-spp N          references, at least 4 x --max-spp (default 4096; --quick: 256)
  --single-max-spp N   top of the 1-thread ladders (default 64; --quick: 4)
  --out DIR            output directory (default target/xtask/peer/full or .../quick)
  --help               this text";

/// The default scenes, under `scenes/peer/`.
pub const SCENES: [&str; 3] = ["three-spheres", "bunny", "anisotropic"];

/// The reference must have at least this many times the spp of the top rung.
pub const REF_SPP_FACTOR: u32 = 4;

/// Validated options of one run.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Options {
    /// `--quick`.
    pub quick: bool,
    /// Scene names or paths.
    pub scenes: Vec<String>,
    /// Width override (`None`: the scene's).
    pub width: Option<u32>,
    /// Top rung with all threads.
    pub max_spp: u32,
    /// Reference spp.
    pub ref_spp: u32,
    /// Top rung of the 1-thread ladders.
    pub single_max_spp: u32,
    /// `--out DIR`.
    pub out: Option<PathBuf>,
}

/// What the command line asks for.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Command {
    /// `--help`.
    Help,
    /// Run the comparison.
    Run(Options),
}

/// A number flag's value in `[lo, hi]`.
fn number(flag: &str, value: &str, lo: u32, hi: u32) -> Result<u32, String> {
    match value.parse::<u32>() {
        Ok(n) if (lo..=hi).contains(&n) => Ok(n),
        _ => Err(format!("{flag}: expected a whole number in [{lo}, {hi}], got `{value}`\n\n{USAGE}")),
    }
}

/// Parses the arguments after `peer` (`--flag value` or `--flag=value`).
pub fn parse(args: &[String]) -> Result<Command, String> {
    let mut quick = false;
    let (mut scenes, mut width, mut max_spp, mut ref_spp, mut single, mut out) = (None, None, None, None, None, None);
    let mut i = 0;
    while i < args.len() {
        let (flag, inline) = match args[i].split_once('=') {
            Some((f, v)) if f.starts_with("--") => (f.to_owned(), Some(v.to_owned())),
            _ => (args[i].clone(), None),
        };
        let mut value = || -> Result<String, String> {
            if let Some(v) = inline.clone() {
                return Ok(v);
            }
            i += 1;
            args.get(i).cloned().ok_or_else(|| format!("{flag} needs a value\n\n{USAGE}"))
        };
        match flag.as_str() {
            "--help" | "-h" => return Ok(Command::Help),
            "--quick" => quick = true,
            "--scenes" => {
                let v = value()?;
                let list: Vec<String> =
                    v.split(',').map(str::trim).filter(|s| !s.is_empty()).map(String::from).collect();
                if list.is_empty() {
                    return Err(format!("--scenes: no scene named in `{v}`\n\n{USAGE}"));
                }
                scenes = Some(list);
            }
            "--width" => width = Some(number("--width", &value()?, 1, MAX_RESOLUTION)?),
            "--max-spp" => max_spp = Some(number("--max-spp", &value()?, 1, MAX_SPP)?),
            "--ref-spp" => ref_spp = Some(number("--ref-spp", &value()?, 1, MAX_SPP)?),
            "--single-max-spp" => single = Some(number("--single-max-spp", &value()?, 1, MAX_SPP)?),
            "--out" => out = Some(PathBuf::from(value()?)),
            other => return Err(format!("unknown argument `{other}`\n\n{USAGE}")),
        }
        i += 1;
    }
    let (d_width, d_max, d_ref, d_single) = if quick { (Some(64), 16, 256, 4) } else { (None, 256, 4096, 64) };
    let o = Options {
        quick,
        scenes: scenes.unwrap_or_else(|| SCENES.iter().map(|s| s.to_string()).collect()),
        width: width.or(d_width),
        max_spp: max_spp.unwrap_or(d_max),
        ref_spp: ref_spp.unwrap_or(d_ref),
        single_max_spp: single.unwrap_or(d_single),
        out,
    };
    if u64::from(o.ref_spp) < u64::from(o.max_spp) * u64::from(REF_SPP_FACTOR) {
        return Err(format!(
            "--ref-spp {} must be at least {REF_SPP_FACTOR} x --max-spp {} (the reference's noise must stay small)",
            o.ref_spp, o.max_spp
        ));
    }
    Ok(Command::Run(o))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(args: &[&str]) -> Result<Options, String> {
        match parse(&args.iter().map(|s| s.to_string()).collect::<Vec<_>>())? {
            Command::Run(o) => Ok(o),
            Command::Help => Err("help".into()),
        }
    }

    #[test]
    fn presets_and_flags() {
        let full = run(&[]).unwrap();
        assert_eq!((full.width, full.max_spp, full.ref_spp, full.single_max_spp), (None, 256, 4096, 64));
        assert_eq!(full.scenes, SCENES);
        let quick = run(&["--quick"]).unwrap();
        assert_eq!((quick.width, quick.max_spp, quick.ref_spp, quick.single_max_spp), (Some(64), 16, 256, 4));
        let o = run(&["--quick", "--scenes=bunny, x.toml", "--width", "32", "--max-spp=8", "--out", "d"]).unwrap();
        assert_eq!((o.scenes.clone(), o.width, o.max_spp), (vec!["bunny".to_string(), "x.toml".into()], Some(32), 8));
        assert_eq!(o.out, Some(PathBuf::from("d")));
    }

    #[test]
    fn errors_name_the_flag() {
        assert_eq!(parse(&["--help".into()]), Ok(Command::Help));
        assert!(run(&["--bogus"]).unwrap_err().contains("unknown argument `--bogus`"));
        assert!(run(&["--width", "0"]).unwrap_err().starts_with("--width"));
        assert!(run(&["--max-spp"]).unwrap_err().contains("needs a value"));
        assert!(run(&["--scenes", ","]).unwrap_err().contains("no scene"));
        assert!(run(&["--max-spp", "256", "--ref-spp", "512"]).unwrap_err().contains("at least 4 x"));
    }
}
