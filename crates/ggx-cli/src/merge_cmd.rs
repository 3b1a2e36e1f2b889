//! `ggx merge`: adds film files of disjoint samples into the image of their union.

use std::io::Write as _;

use anyhow::{Context, Result, bail};
use ggx_film::{OutputOptions, Part};

use crate::args::MergeArgs;
use crate::exit::Outcome;
use crate::{film_out, output};

/// Runs `ggx merge`: reads and checks every part, then writes the sum, or fails naming what
/// is missing (unless `--allow-missing`).
pub fn run(args: &MergeArgs) -> Result<Outcome> {
    let inputs: Vec<&std::path::Path> = args.parts.iter().map(|p| p.as_path()).collect();
    output::check(&args.output, &inputs)?;
    let mut parts = Vec::with_capacity(args.parts.len().min(4096));
    let max_pixels =
        film_out::MAX_FILM_PIXELS.min(args.limits.limits().max_memory / ggx_film::Film::BYTES_PER_PIXEL as u64);
    for path in &args.parts {
        let (info, film) = ggx_film::read_film(path, max_pixels)?;
        parts.push(Part { name: path.display().to_string(), info, film });
    }
    let count = parts.len();
    let merged = ggx_film::merge_films(parts).map_err(anyhow::Error::msg)?;
    if !merged.missing.is_empty() {
        let list = merged.missing.join("\n  ");
        if !args.allow_missing {
            bail!("the parts do not cover every sample:\n  {list}\n(render the missing samples, or --allow-missing)");
        }
        if !merged.contiguous {
            bail!("the parts leave gaps inside pixels' samples, which a film cannot record:\n  {list}");
        }
        eprintln!("warning: writing an incomplete image:\n  {list}");
    }
    let options = OutputOptions { exposure: args.exposure, tonemap: crate::render_cmd::tone_map(args.tonemap) };
    film_out::write(&args.output, &merged.film, &merged.info, true, &options)?;
    let [a, b] = merged.info.samples;
    let (w, h) = (merged.film.width(), merged.film.height());
    let line = format!("merged {count} parts: samples {a}..{b}, {w}x{h} -> {}", args.output.display());
    writeln!(std::io::stdout(), "{line}").context("cannot write to stdout")?;
    Ok(Outcome::Done)
}
