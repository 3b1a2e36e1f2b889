//! The two converged references of a scene, rendered once and cached in
//! `target/xtask/peer/reference/`: ggx's by the release `ggx` (keyed by the scene file and the
//! files it names, the size, spp, seed and the sources of the crates that render:
//! [`ggx_sources_hash`]), Mitsuba's by its LLVM
//! variant (keyed by the exported XML and side files, the size, spp, seed and the Mitsuba and
//! Dr.Jit versions). A key change re-renders; stale entries of the same scene and size are
//! removed ([`crate::bench::reference::remove_stale`]).

use std::path::{Path, PathBuf};

use ggx_film::Vec3;

use super::driver::{Driver, RenderRequest, Versions};
use super::ggx_side::{self, RenderJob};
use crate::bench::cache_key::{Fnv64, ReferenceParams, collect_files, key_of_file, renderer_sources_hash};
use crate::bench::reference::{REFERENCE_SEED, remove_stale};

/// Largest Mitsuba pass: its wavefront holds every sample of a pass.
pub const MAX_PASS_SPP: u32 = 64;

/// A converged image.
pub struct Reference {
    /// Linear RGB, row-major, top row first.
    pub pixels: Vec<Vec3>,
    /// The cache file.
    pub path: PathBuf,
    /// Render seconds, `None` when read from the cache.
    pub seconds: Option<f64>,
}

/// The cached image at `path` when it has the expected size and finite pixels.
fn cached(path: &Path, width: u32, height: u32) -> Option<Vec<Vec3>> {
    match ggx_film::read_exr(path) {
        Ok((w, h, pixels)) if (w, h) == (width, height) && pixels.iter().all(|p| p.is_finite()) => Some(pixels),
        _ => None,
    }
}

/// The crates whose sources decide a ggx render besides bench's
/// [`crate::bench::cache_key::RENDERER_CRATES`]: the materials and pass schedule of
/// `ggx-render`.
const MORE_RENDERER_CRATES: [&str; 1] = ["ggx-render"];

/// bench's [`renderer_sources_hash`] of `root` combined with the relative paths and bytes of
/// the files under `crates/<name>/src` of [`MORE_RENDERER_CRATES`], in sorted order.
pub fn ggx_sources_hash(root: &Path) -> Result<u64, String> {
    let mut files = Vec::new();
    for name in MORE_RENDERER_CRATES {
        collect_files(&root.join("crates").join(name).join("src"), &mut files)?;
    }
    files.sort();
    let mut h = Fnv64::default();
    h.field(&renderer_sources_hash(root)?.to_le_bytes());
    for path in &files {
        h.field(path.strip_prefix(root).unwrap_or(path).to_string_lossy().as_bytes());
        h.field(&std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?);
    }
    Ok(h.finish())
}

/// ggx's reference of `scene` at `width x height` (`width` passed to `ggx render --width`).
pub fn ggx(
    bin: &Path,
    scene: &Path,
    name: &str,
    size: [u32; 2],
    width_override: Option<u32>,
    spp: u32,
    cache: &Path,
) -> Result<Reference, String> {
    let [width, height] = size;
    let params = ReferenceParams {
        width,
        height,
        spp,
        seed: REFERENCE_SEED,
        config: "peer-ggx-release-sobol".into(),
        renderer: ggx_sources_hash(&crate::render::workspace_root())?,
    };
    let key = key_of_file(scene, &params)?;
    let prefix = format!("{name}-ggx-{width}x{height}-{spp}spp-");
    let path = cache.join(format!("{prefix}{key:016x}.exr"));
    if let Some(pixels) = cached(&path, width, height) {
        eprintln!("  ggx reference: {} (cached)", path.display());
        return Ok(Reference { pixels, path, seconds: None });
    }
    remove_stale(cache, &prefix, &path);
    eprintln!("  ggx reference: rendering {width}x{height} at {spp} spp");
    let stats = path.with_extension("json");
    let job = RenderJob {
        scene,
        out: &path,
        stats: &stats,
        spp,
        seed: REFERENCE_SEED as u32,
        threads: 0,
        width: width_override,
    };
    let s = ggx_side::render(bin, &job)?;
    let _ = std::fs::remove_file(&stats);
    let pixels = cached(&path, width, height).ok_or_else(|| format!("{}: unreadable or wrong size", path.display()))?;
    eprintln!("  ggx reference: {} ({:.1} s)", path.display(), s.seconds);
    Ok(Reference { pixels, path, seconds: Some(s.seconds) })
}

/// The cache key of Mitsuba's reference: the XML and every file beside it that it names
/// (`files`), the size, spp, seed and versions.
pub fn mitsuba_key(
    xml: &Path,
    files: &[PathBuf],
    size: [u32; 2],
    spp: u32,
    versions: &Versions,
) -> Result<u64, String> {
    let mut h = Fnv64::default();
    h.field(b"ggx-peer-mitsuba-reference-v1");
    for p in std::iter::once(xml).chain(files.iter().map(PathBuf::as_path)) {
        h.field(p.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default().as_bytes());
        h.field(&std::fs::read(p).map_err(|e| format!("{}: {e}", p.display()))?);
    }
    for n in [u64::from(size[0]), u64::from(size[1]), u64::from(spp), REFERENCE_SEED] {
        h.field(&n.to_le_bytes());
    }
    h.field(versions.mitsuba.as_bytes());
    h.field(versions.drjit.as_bytes());
    Ok(h.finish())
}

/// Mitsuba's reference of the exported scene `xml` (with its side `files`), rendered in the
/// LLVM variant on `threads` threads.
#[allow(clippy::too_many_arguments)]
pub fn mitsuba(
    driver: &mut Driver,
    versions: &Versions,
    xml: &Path,
    files: &[PathBuf],
    name: &str,
    size: [u32; 2],
    spp: u32,
    threads: usize,
    cache: &Path,
) -> Result<Reference, String> {
    let [width, height] = size;
    let key = mitsuba_key(xml, files, size, spp, versions)?;
    let prefix = format!("{name}-mitsuba-{width}x{height}-{spp}spp-");
    let path = cache.join(format!("{prefix}{key:016x}.exr"));
    if let Some(pixels) = cached(&path, width, height) {
        eprintln!("  Mitsuba reference: {} (cached)", path.display());
        return Ok(Reference { pixels, path, seconds: None });
    }
    remove_stale(cache, &prefix, &path);
    eprintln!("  Mitsuba reference: rendering {width}x{height} at {spp} spp");
    let r = driver.render(&RenderRequest {
        variant: "llvm_ad_rgb",
        scene: xml,
        threads,
        spp,
        seed: REFERENCE_SEED as u32,
        max_pass_spp: MAX_PASS_SPP,
        out: &path,
    })?;
    let pixels = cached(&path, width, height)
        .ok_or_else(|| format!("{}: unreadable, wrong size or not finite", path.display()))?;
    eprintln!("  Mitsuba reference: {} ({:.1} s)", path.display(), r.seconds);
    Ok(Reference { pixels, path, seconds: Some(r.seconds) })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ggx_sources_hash_covers_ggx_render() {
        let root = crate::render::workspace_root();
        let a = ggx_sources_hash(&root).unwrap();
        assert_eq!(a, ggx_sources_hash(&root).unwrap());
        assert_ne!(a, renderer_sources_hash(&root).unwrap());
    }

    #[test]
    fn mitsuba_key_follows_files_and_versions() {
        let dir = std::env::temp_dir().join(format!("xtask-peer-key-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let (xml, ply) = (dir.join("s.xml"), dir.join("s-0-a.ply"));
        std::fs::write(&xml, "<scene/>").unwrap();
        std::fs::write(&ply, "ply").unwrap();
        let v = Versions { mitsuba: "3.9.1".into(), drjit: "1.5.0".into(), ..Versions::default() };
        let files = [ply.clone()];
        let a = mitsuba_key(&xml, &files, [4, 4], 64, &v).unwrap();
        assert_eq!(a, mitsuba_key(&xml, &files, [4, 4], 64, &v).unwrap());
        assert_ne!(a, mitsuba_key(&xml, &files, [4, 4], 128, &v).unwrap());
        assert_ne!(
            a,
            mitsuba_key(&xml, &files, [4, 4], 64, &Versions { mitsuba: "3.9.2".into(), ..v.clone() }).unwrap()
        );
        std::fs::write(&ply, "ply2").unwrap();
        let b = mitsuba_key(&xml, &files, [4, 4], 64, &v).unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
        assert_ne!(a, b);
        assert!(mitsuba_key(&xml, &files, [4, 4], 64, &v).is_err(), "a missing file is an error");
    }
}
