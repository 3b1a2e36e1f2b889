//! Writing a render's result: a plain image, or an exact film (`.exr` with the sums and the
//! render's identity in the header) for `--samples`, `--crop`, `--checkpoint`, `--resume` and
//! `ggx merge`; and reading a film back for `--resume`, checked against the scene.

use std::path::Path;

use anyhow::{Result, bail};
use ggx_film::{Film, FilmInfo, OutputOptions, Window};

/// The largest film file `--resume` and `ggx merge` read: the largest image a scene may ask
/// for.
pub const MAX_FILM_PIXELS: u64 = (ggx_scene::MAX_RESOLUTION as u64) * (ggx_scene::MAX_RESOLUTION as u64);

/// Writes `film` to `path`: a tone-mapped PNG, or an EXR whose header holds `info` (the render's
/// figures included) and, when `exact`, the film's exact sums and counts.
pub fn write(path: &Path, film: &Film, info: &FilmInfo, exact: bool, options: &OutputOptions) -> Result<()> {
    if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("exr")) {
        ggx_film::write_film(path, info, film, exact, options)?;
    } else {
        ggx_film::write_image(path, film.width(), film.height(), &film.mean(), options)?;
    }
    Ok(())
}

/// Fails unless an exact film can be written to `path` (an `.exr`), naming `why` it must be.
pub fn require_exr(path: &Path, why: &str) -> Result<()> {
    if !path.extension().is_some_and(|e| e.eq_ignore_ascii_case("exr")) {
        bail!("{}: {why} writes an exact film, which needs an .exr file", path.display());
    }
    Ok(())
}

/// Reads the film file `path` that `--resume` continues and checks that it was rendered from
/// the scene about to be rendered (`expected`: scene hash, seed, frame, backend, version).
pub fn read_for_resume(path: &Path, expected: &FilmInfo) -> Result<(FilmInfo, Film)> {
    let (info, film) = ggx_film::read_film(path, MAX_FILM_PIXELS)?;
    let shown = path.display();
    if info.scene_hash != expected.scene_hash {
        bail!(
            "{shown}: was rendered from another scene or other settings (scene hash {} here {}): it cannot be continued",
            info.scene_hash,
            expected.scene_hash
        );
    }
    for (what, theirs, ours) in [
        ("seed", info.seed.to_string(), expected.seed.to_string()),
        ("frame", info.frame.to_string(), expected.frame.to_string()),
        ("backend", info.backend.clone(), expected.backend.clone()),
        ("ggx version", info.version.clone(), expected.version.clone()),
    ] {
        if theirs != ours {
            bail!("{shown}: has {what} {theirs}, this render {ours}: it cannot be continued");
        }
    }
    Ok((info, film))
}

/// The range and window to continue: the film's, or `--samples` with the same start and a
/// later end (extending the render); `--crop` must equal the film's window.
pub fn resumed_job(info: &FilmInfo, samples: Option<[u32; 2]>, crop: Option<Window>) -> Result<([u32; 2], Window)> {
    let range = match samples {
        Some(s) if s[0] != info.samples[0] => {
            bail!(
                "--samples {}..{} must start where the film's range does ({}..{})",
                s[0],
                s[1],
                info.samples[0],
                info.samples[1]
            )
        }
        Some(s) => s,
        None => info.samples,
    };
    if let Some(c) = crop
        && c != info.window
    {
        bail!("--crop {c:?} differs from the film's window {:?}", info.window);
    }
    Ok((range, info.window))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn info() -> FilmInfo {
        FilmInfo { samples: [16, 64], window: [0, 0, 8, 8], ..Default::default() }
    }

    #[test]
    fn resumed_ranges_may_only_grow() {
        assert_eq!(resumed_job(&info(), None, None).unwrap(), ([16, 64], [0, 0, 8, 8]));
        assert_eq!(resumed_job(&info(), Some([16, 128]), Some([0, 0, 8, 8])).unwrap(), ([16, 128], [0, 0, 8, 8]));
        let msg = resumed_job(&info(), Some([0, 128]), None).unwrap_err().to_string();
        assert_eq!(msg, "--samples 0..128 must start where the film's range does (16..64)");
        assert!(resumed_job(&info(), None, Some([0, 0, 4, 4])).is_err());
    }

    #[test]
    fn exact_films_need_exr() {
        require_exr(Path::new("a.EXR"), "--samples").unwrap();
        let msg = require_exr(Path::new("a.png"), "--samples").unwrap_err().to_string();
        assert_eq!(msg, "a.png: --samples writes an exact film, which needs an .exr file");
    }
}
