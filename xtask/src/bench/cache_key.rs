//! The cache key of a reference image: a 64-bit FNV-1a hash (stable across Rust releases,
//! unlike `std`'s `DefaultHasher`) over the scene file's bytes, the bytes of the files it
//! references (`file = "..."`: meshes, environment maps), the reference parameters and the
//! sources of the crates that render it ([`renderer_sources_hash`]), so that a change to the
//! renderer never leaves a stale reference behind.

use std::path::{Path, PathBuf};

/// The crates whose sources decide what a CPU reference render contains.
pub const RENDERER_CRATES: [&str; 4] = ["ggx-core", "ggx-scene", "ggx-cpu", "ggx-film"];

/// Bumped when the way references are rendered changes, so that old cache entries are ignored.
const KEY_VERSION: &str = "ggx-bench-reference-v1";

/// Incremental 64-bit FNV-1a.
#[derive(Clone, Copy, Debug)]
pub struct Fnv64(u64);

impl Default for Fnv64 {
    fn default() -> Self {
        Fnv64(0xcbf2_9ce4_8422_2325)
    }
}

impl Fnv64 {
    /// Hashes `bytes` preceded by their length, so that field boundaries matter.
    pub fn field(&mut self, bytes: &[u8]) {
        self.bytes(&(bytes.len() as u64).to_le_bytes());
        self.bytes(bytes);
    }

    /// Hashes raw bytes.
    fn bytes(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0 ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3);
        }
    }

    /// The hash so far.
    pub fn finish(&self) -> u64 {
        self.0
    }
}

/// How a reference is rendered; everything here changes the cache key.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ReferenceParams {
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Samples per pixel.
    pub spp: u32,
    /// Seed of the sample sequence.
    pub seed: u64,
    /// Name of the configuration (see [`super::configs::Config::name`]).
    pub config: String,
    /// [`renderer_sources_hash`] of the workspace.
    pub renderer: u64,
}

/// FNV-1a over the relative path and bytes of every file under `crates/<name>/src` of the
/// [`RENDERER_CRATES`] in `root`, in sorted path order (so the hash does not depend on the
/// order a file system lists directories in).
pub fn renderer_sources_hash(root: &Path) -> Result<u64, String> {
    let mut files = Vec::new();
    for name in RENDERER_CRATES {
        collect_files(&root.join("crates").join(name).join("src"), &mut files)?;
    }
    files.sort();
    let mut h = Fnv64::default();
    for path in &files {
        let relative = path.strip_prefix(root).unwrap_or(path);
        h.field(relative.to_string_lossy().replace('\\', "/").as_bytes());
        h.field(&std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?);
    }
    Ok(h.finish())
}

/// Every file under `dir`, recursively (an iterative walk: no recursion depth to run out of).
pub(crate) fn collect_files(dir: &Path, out: &mut Vec<PathBuf>) -> Result<(), String> {
    let mut pending = vec![dir.to_path_buf()];
    while let Some(dir) = pending.pop() {
        let entries = std::fs::read_dir(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        for entry in entries {
            let path = entry.map_err(|e| format!("{}: {e}", dir.display()))?.path();
            if path.is_dir() { pending.push(path) } else { out.push(path) }
        }
    }
    Ok(())
}

/// The relative paths in `file = "..."` entries of a scene file (the TOML keys naming meshes and
/// environment maps), in order of appearance. A plain scan, not a TOML parser: it only decides
/// which extra bytes go into the key, and the scene loader validates the file anyway.
pub fn referenced_files(scene_text: &str) -> Vec<String> {
    let mut files = Vec::new();
    for line in scene_text.lines() {
        let mut rest = line.split('#').next().unwrap_or("");
        while let Some(pos) = rest.find("file") {
            let before_ok = rest[..pos].chars().next_back().is_none_or(|c| !(c.is_alphanumeric() || c == '_'));
            let after = rest[pos + 4..].trim_start();
            rest = &rest[pos + 4..];
            if !before_ok {
                continue;
            }
            let Some(value) = after.strip_prefix('=').map(str::trim_start) else { continue };
            let Some(quoted) = value.strip_prefix('"') else { continue };
            if let Some(end) = quoted.find('"') {
                files.push(quoted[..end].to_string());
            }
        }
    }
    files
}

/// The key of `params` for the scene file with bytes `scene_bytes` and referenced files
/// `(name, bytes)` (bytes `None` when the file could not be read).
pub fn key(scene_bytes: &[u8], files: &[(String, Option<Vec<u8>>)], params: &ReferenceParams) -> u64 {
    let mut h = Fnv64::default();
    h.field(KEY_VERSION.as_bytes());
    h.field(scene_bytes);
    for (name, bytes) in files {
        h.field(name.as_bytes());
        h.field(bytes.as_deref().unwrap_or(b"<unreadable>"));
    }
    for n in [u64::from(params.width), u64::from(params.height), u64::from(params.spp), params.seed] {
        h.field(&n.to_le_bytes());
    }
    h.field(params.config.as_bytes());
    h.field(&params.renderer.to_le_bytes());
    h.finish()
}

/// [`key`] of the scene file at `path` and the files it references (relative to its directory).
pub fn key_of_file(path: &Path, params: &ReferenceParams) -> Result<u64, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let dir = path.parent().unwrap_or(Path::new("."));
    let files: Vec<(String, Option<Vec<u8>>)> = referenced_files(&String::from_utf8_lossy(&bytes))
        .into_iter()
        .map(|name| {
            let content = std::fs::read(dir.join(&name)).ok();
            (name, content)
        })
        .collect();
    Ok(key(&bytes, &files, params))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn params() -> ReferenceParams {
        ReferenceParams {
            width: 32,
            height: 24,
            spp: 256,
            seed: 7,
            config: "vndf-mis-sobol-cpu-spec".into(),
            renderer: 0x1234,
        }
    }

    #[test]
    fn fnv_known_value() {
        // FNV-1a 64 of the empty input is the offset basis; of "a" it is 0xaf63dc4c8601ec8c.
        assert_eq!(Fnv64::default().finish(), 0xcbf2_9ce4_8422_2325);
        let mut h = Fnv64::default();
        h.bytes(b"a");
        assert_eq!(h.finish(), 0xaf63_dc4c_8601_ec8c);
    }

    #[test]
    fn key_changes_with_scene_assets_and_params() {
        let base = key(b"[camera]\nfov_y = 40\n", &[], &params());
        assert_eq!(base, key(b"[camera]\nfov_y = 40\n", &[], &params()), "deterministic");
        assert_ne!(base, key(b"[camera]\nfov_y = 41\n", &[], &params()), "scene bytes");
        let mesh = |b: &[u8]| vec![("m.obj".to_string(), Some(b.to_vec()))];
        assert_ne!(key(b"s", &mesh(b"v 0 0 0"), &params()), key(b"s", &mesh(b"v 0 0 1"), &params()), "asset bytes");
        assert_ne!(key(b"s", &mesh(b"v"), &params()), key(b"s", &[("m.obj".into(), None)], &params()));
        for changed in [
            ReferenceParams { width: 33, ..params() },
            ReferenceParams { height: 25, ..params() },
            ReferenceParams { spp: 512, ..params() },
            ReferenceParams { seed: 8, ..params() },
            ReferenceParams { config: "ndf-mis-sobol-cpu-spec".into(), ..params() },
            ReferenceParams { renderer: 0x1235, ..params() },
        ] {
            assert_ne!(key(b"s", &[], &params()), key(b"s", &[], &changed), "{changed:?}");
        }
    }

    #[test]
    fn key_of_file_follows_the_file() {
        let dir = std::env::temp_dir().join(format!("ggx-bench-key-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let scene = dir.join("s.toml");
        std::fs::write(&scene, "file = \"m.obj\"\n").unwrap();
        std::fs::write(dir.join("m.obj"), "v 0 0 0\n").unwrap();
        let a = key_of_file(&scene, &params()).unwrap();
        std::fs::write(dir.join("m.obj"), "v 0 0 1\n").unwrap();
        let b = key_of_file(&scene, &params()).unwrap();
        std::fs::write(&scene, "file = \"m.obj\" # changed\n").unwrap();
        let c = key_of_file(&scene, &params()).unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
        assert!(a != b && b != c && a != c);
        assert!(key_of_file(&dir.join("missing.toml"), &params()).is_err());
    }

    #[test]
    fn renderer_hash_follows_every_source_file() {
        let root = std::env::temp_dir().join(format!("ggx-bench-sources-{}", std::process::id()));
        for name in RENDERER_CRATES {
            std::fs::create_dir_all(root.join("crates").join(name).join("src/sub")).unwrap();
            std::fs::write(root.join("crates").join(name).join("src/lib.rs"), name).unwrap();
        }
        let deep = root.join("crates/ggx-cpu/src/sub/deep.rs");
        std::fs::write(&deep, "fn a() {}").unwrap();
        let a = renderer_sources_hash(&root).unwrap();
        assert_eq!(a, renderer_sources_hash(&root).unwrap(), "deterministic");
        std::fs::write(&deep, "fn b() {}").unwrap();
        let b = renderer_sources_hash(&root).unwrap();
        std::fs::rename(&deep, root.join("crates/ggx-cpu/src/sub/moved.rs")).unwrap();
        let c = renderer_sources_hash(&root).unwrap();
        // Files outside the renderer crates' src do not count.
        std::fs::write(root.join("crates/ggx-cpu/README.md"), "docs").unwrap();
        let d = renderer_sources_hash(&root).unwrap();
        std::fs::remove_dir_all(root.join("crates/ggx-film")).unwrap();
        let missing = renderer_sources_hash(&root);
        std::fs::remove_dir_all(&root).unwrap();
        assert!(a != b && b != c && a != c, "content and name count");
        assert_eq!(c, d);
        assert!(missing.unwrap_err().contains("ggx-film"));
    }

    #[test]
    fn renderer_hash_of_this_workspace() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap();
        assert!(renderer_sources_hash(root).is_ok());
    }

    #[test]
    fn finds_referenced_files() {
        let text = "file = \"assets/bunny.obj\"   # 9.7 units\n\
                    [environment]\n  file=\"maps/sky.hdr\"\n\
                    # file = \"commented.obj\"\n\
                    profile = \"x\"\nmy_file = \"no\"\nfiles = [1]\n\
                    shape = { type = \"mesh\", file = \"inline.obj\" }\n";
        assert_eq!(referenced_files(text), ["assets/bunny.obj", "maps/sky.hdr", "inline.obj"]);
    }
}
