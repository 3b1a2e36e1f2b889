//! Converged reference images: rendered once with the baseline configuration at high spp and
//! cached as `<scene>-<w>x<h>-<spp>spp-<key>.exr`, where the key ([`super::cache_key`]) covers
//! the scene file, the files it references, the reference parameters and the renderer's
//! sources, so a reference is re-rendered exactly when one of those changes. Its seed differs
//! from the ladder's so that the reference's noise is not correlated with the errors it
//! measures.

use super::cache_key::{ReferenceParams, key_of_file, renderer_sources_hash};
use super::configs::BASELINE;
use crate::render::{self, Backend};
use ggx_film::{OutputOptions, Vec3, read_exr, write_image};
use ggx_scene::Scene;
use std::path::{Path, PathBuf};

/// Seed of every reference render (the ladders use [`super::ladder::LADDER_SEED`]).
pub const REFERENCE_SEED: u64 = 0x9e37_79b9;

/// A reference image and where it came from.
pub struct Reference {
    /// Linear RGB, row-major, top row first.
    pub pixels: Vec<Vec3>,
    /// The cache file.
    pub path: PathBuf,
}

/// The reference of `scene` (already loaded from `scene_path` at the bench's resolution) at
/// `spp`, read from `cache_dir` or rendered on the CPU with the baseline configuration and
/// stored there. Stale entries of the same scene, size and spp are removed.
pub fn load_or_render(scene_path: &Path, scene: &Scene, spp: u32, cache_dir: &Path) -> Result<Reference, String> {
    let [width, height] = scene.camera.resolution;
    let renderer = renderer_sources_hash(&render::workspace_root())?;
    let params = ReferenceParams { width, height, spp, seed: REFERENCE_SEED, config: BASELINE.name(), renderer };
    let key = key_of_file(scene_path, &params)?;
    let prefix = format!("{}-{width}x{height}-{spp}spp-", render::scene_name(scene_path));
    let path = cache_dir.join(format!("{prefix}{key:016x}.exr"));
    if path.is_file() {
        match read_exr(&path) {
            Ok((w, h, pixels)) if (w, h) == (width, height) && pixels.iter().all(|p| p.is_finite()) => {
                eprintln!("  reference: {} (cached)", path.display());
                return Ok(Reference { pixels, path });
            }
            Ok(_) => eprintln!("  reference: {} has the wrong size or non-finite pixels; re-rendering", path.display()),
            Err(e) => eprintln!("  reference: {e}; re-rendering"),
        }
    }
    remove_stale(cache_dir, &prefix, &path);
    let mut reference_scene = scene.clone();
    BASELINE.apply(&mut reference_scene);
    reference_scene.integrator.seed = REFERENCE_SEED;
    reference_scene.integrator.spp = spp;
    let samples = u64::from(width) * u64::from(height) * u64::from(spp);
    eprintln!("  reference: rendering {width}x{height} at {spp} spp ({:.1} M camera samples)", samples as f64 * 1e-6);
    let result = render::render(&reference_scene, Backend::Cpu, BASELINE.specialize, None)?;
    if result.spp != spp {
        return Err(format!("reference of {}: rendered {} of {spp} spp", scene_path.display(), result.spp));
    }
    let pixels = result.film.mean();
    if let Some(i) = pixels.iter().position(|p| !p.is_finite()) {
        return Err(format!("reference of {}: pixel {i} is not finite ({})", scene_path.display(), pixels[i]));
    }
    write_image(&path, width, height, &pixels, &OutputOptions::default()).map_err(|e| e.to_string())?;
    eprintln!("  reference: {} ({:.1} s)", path.display(), result.elapsed.as_secs_f64());
    Ok(Reference { pixels, path })
}

/// Removes `<prefix>*.exr` files in `dir` other than `keep`: references of an older version of
/// the scene (best effort).
pub(crate) fn remove_stale(dir: &Path, prefix: &str, keep: &Path) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    for path in entries.filter_map(|e| e.ok().map(|e| e.path())) {
        let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        if path != keep && name.starts_with(prefix) && name.ends_with(".exr") {
            eprintln!("  reference: removing stale {}", path.display());
            let _ = std::fs::remove_file(&path);
        }
    }
}
