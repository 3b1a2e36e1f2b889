//! `ggx merge`: adds film files of disjoint samples into the image of their union, one part
//! at a time.

use std::io::Write as _;
use std::path::Path;

use anyhow::{Context, Result, bail};
use ggx_film::{Film, Merger, OutputOptions, Part};

use crate::args::MergeArgs;
use crate::exit::Outcome;
use crate::{film_out, output};

/// Bytes per pixel a merge holds at once: the sum (64), the merger's per-pixel bookkeeping
/// (16), one part (64) and its EXR decode buffers (68: the R, G, B and exact channels).
const MERGE_BYTES_PER_PIXEL: u64 = 64 + 16 + 64 + 68;

/// Runs `ggx merge`: checks every part's header first (same scene, settings and size), then
/// reads the parts one by one in order of their first sample and adds them; writes the sum,
/// or fails naming what is missing (unless `--allow-missing`).
pub fn run(args: &MergeArgs) -> Result<Outcome> {
    let inputs: Vec<&Path> = args.parts.iter().map(|p| p.as_path()).collect();
    output::check(&args.output, &inputs)?;
    let mut headers = Vec::with_capacity(args.parts.len().min(1 << 16));
    for path in &args.parts {
        let (info, size) = ggx_film::read_film_info(path)?;
        headers.push((path.as_path(), info, size));
    }
    let Some((first, info, size)) = headers.first().cloned() else { bail!("no parts to merge") };
    let pixels = u64::from(size[0]) * u64::from(size[1]);
    let limits = args.limits.limits();
    let needed = pixels.saturating_mul(MERGE_BYTES_PER_PIXEL);
    if pixels > film_out::MAX_FILM_PIXELS || needed > limits.max_memory {
        bail!(
            "merging {}x{} films needs {} MiB, over the limit of {} MiB (max_memory; raise it with --max-memory)",
            size[0],
            size[1],
            needed >> 20,
            limits.max_memory >> 20
        );
    }
    let mut merger = Merger::new(&first.display().to_string(), &info, size).map_err(anyhow::Error::msg)?;
    for (path, info, size) in &headers {
        merger.check(&path.display().to_string(), info, *size).map_err(anyhow::Error::msg)?;
    }
    headers.sort_by_key(|(_, info, _)| info.samples);
    for (path, _, _) in &headers {
        let (info, film): (_, Film) = ggx_film::read_film(path, pixels)?;
        let part = Part { name: path.display().to_string(), info, film };
        merger.add(&part).map_err(anyhow::Error::msg)?;
    }
    let merged = merger.finish();
    if !merged.missing.is_empty() {
        let list = merged.missing.join("\n  ");
        if !args.allow_missing {
            bail!("the parts do not cover every sample:\n  {list}\n(render the missing samples, or --allow-missing)");
        }
        let exr = args.output.extension().is_some_and(|e| e.eq_ignore_ascii_case("exr"));
        if exr && !merged.contiguous {
            bail!(
                "the parts leave gaps inside pixels' samples, which a film cannot record (a .png can show them):\n  {list}"
            );
        }
        eprintln!("warning: writing an incomplete image:\n  {list}");
    }
    let options = OutputOptions { exposure: args.exposure, tonemap: crate::render_cmd::tone_map(args.tonemap) };
    film_out::write(&args.output, &merged.film, &merged.info, true, &options)?;
    let [a, b] = merged.info.samples;
    let (w, h) = (merged.film.width(), merged.film.height());
    let count = headers.len();
    let line = format!("merged {count} parts: samples {a}..{b}, {w}x{h} -> {}", args.output.display());
    writeln!(std::io::stdout(), "{line}").context("cannot write to stdout")?;
    Ok(Outcome::Done)
}
