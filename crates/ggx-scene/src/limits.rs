//! [`Limits`]: the largest inputs the loaders read and the most memory a render may take,
//! checked before anything big is allocated. Every limit can be raised (`ggx render
//! --max-memory 32G`, …) and every refusal names the limit and the flag that raises it.

use std::fmt;
use std::fs::File;
use std::io::Read as _;
use std::path::Path;

/// Upper bounds on what is read and allocated. [`Limits::default`] suits a desktop machine;
/// each field has a `ggx` flag of the same name (`max_memory` is `--max-memory`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Limits {
    /// Largest scene file read, in bytes.
    pub max_scene_bytes: u64,
    /// Largest mesh file (OBJ) read, in bytes.
    pub max_mesh_bytes: u64,
    /// Largest image (environment map) decoded, in pixels (`width * height`); each side is
    /// also at most [`crate::MAX_MAP_SIZE`].
    pub max_map_pixels: u64,
    /// Most triangles a scene may have after tessellation.
    pub max_triangles: u64,
    /// Most memory, in bytes, that loading and rendering a scene may need (meshes, BVH,
    /// maps, film), estimated before it is allocated.
    pub max_memory: u64,
}

/// One mebibyte.
const MIB: u64 = 1 << 20;
/// One gibibyte.
const GIB: u64 = 1 << 30;

impl Default for Limits {
    fn default() -> Self {
        Self {
            max_scene_bytes: 64 * MIB,
            max_mesh_bytes: 2 * GIB,
            max_map_pixels: 16384 * 8192,
            max_triangles: 64_000_000,
            max_memory: 16 * GIB,
        }
    }
}

/// Which limit was exceeded, for messages and for callers that branch on it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Limit {
    /// [`Limits::max_scene_bytes`].
    SceneBytes,
    /// [`Limits::max_mesh_bytes`].
    MeshBytes,
    /// [`Limits::max_map_pixels`].
    MapPixels,
    /// [`Limits::max_triangles`].
    Triangles,
    /// [`Limits::max_memory`].
    Memory,
}

impl Limit {
    /// The `ggx` flag that raises this limit.
    pub fn flag(self) -> &'static str {
        match self {
            Self::SceneBytes => "--max-scene-bytes",
            Self::MeshBytes => "--max-mesh-bytes",
            Self::MapPixels => "--max-map-pixels",
            Self::Triangles => "--max-triangles",
            Self::Memory => "--max-memory",
        }
    }

    /// The field of [`Limits`] that holds this limit.
    pub fn field(self) -> &'static str {
        match self {
            Self::SceneBytes => "max_scene_bytes",
            Self::MeshBytes => "max_mesh_bytes",
            Self::MapPixels => "max_map_pixels",
            Self::Triangles => "max_triangles",
            Self::Memory => "max_memory",
        }
    }

    /// Whether values of this limit are byte counts (shown as KiB, MiB, GiB).
    fn is_bytes(self) -> bool {
        matches!(self, Self::SceneBytes | Self::MeshBytes | Self::Memory)
    }

    /// `value` in this limit's unit: bytes as [`format_bytes`], counts as plain numbers.
    pub fn format(self, value: u64) -> String {
        if self.is_bytes() { format_bytes(value) } else { value.to_string() }
    }
}

impl Limits {
    /// The value of `limit`.
    pub fn get(&self, limit: Limit) -> u64 {
        match limit {
            Limit::SceneBytes => self.max_scene_bytes,
            Limit::MeshBytes => self.max_mesh_bytes,
            Limit::MapPixels => self.max_map_pixels,
            Limit::Triangles => self.max_triangles,
            Limit::Memory => self.max_memory,
        }
    }

    /// `Ok` when `needed <= limit`, else a [`LimitError`] saying what needed how much.
    pub fn check(&self, limit: Limit, what: impl Into<String>, needed: u64) -> Result<(), LimitError> {
        let max = self.get(limit);
        if needed <= max { Ok(()) } else { Err(LimitError { limit, what: what.into(), needed, max }) }
    }
}

/// An input or allocation over one of the [`Limits`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LimitError {
    /// The limit exceeded.
    pub limit: Limit,
    /// What needed it, e.g. `"scene file"` or `"environment map 100000x100000"`.
    pub what: String,
    /// How much was needed (at least; reading stops at the limit).
    pub needed: u64,
    /// The limit in force.
    pub max: u64,
}

impl fmt::Display for LimitError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let l = self.limit;
        write!(
            f,
            "{} needs {}, over the limit of {} ({}; raise it with {})",
            self.what,
            l.format(self.needed),
            l.format(self.max),
            l.field(),
            l.flag()
        )
    }
}

impl std::error::Error for LimitError {}

/// `bytes` in the largest binary unit that keeps it >= 1, e.g. `1.5 GiB`, `512 B`.
pub fn format_bytes(bytes: u64) -> String {
    const UNITS: [&str; 7] = ["B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"];
    let mut value = bytes as f64;
    let mut unit = 0;
    while value >= 1024.0 && unit + 1 < UNITS.len() {
        value /= 1024.0;
        unit += 1;
    }
    if unit == 0 { format!("{bytes} B") } else { format!("{value:.1} {}", UNITS[unit]) }
}

/// Reads the regular file at `path`, refusing anything else (a directory, a FIFO that could
/// block forever, a device such as `/dev/zero` that never ends) and files over `max` bytes
/// of `limit`. The error names the path and what is wrong; `what` says what the file is
/// (`"scene file"`, `"mesh"`).
pub fn read_regular_file(path: &Path, what: &str, limit: Limit, limits: &Limits) -> Result<Vec<u8>, String> {
    read_regular_file_or(path, what, limit, limits).map_err(|e| e.to_string())
}

/// Why [`read_regular_file_or`] read nothing.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ReadError {
    /// The file is missing, unreadable, a directory or not a regular file: the message,
    /// which starts with the path.
    Io(String),
    /// The file is larger than the limit.
    Limit(LimitError),
}

impl fmt::Display for ReadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Io(message) => f.write_str(message),
            Self::Limit(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for ReadError {}

/// [`read_regular_file`] with an error that tells a file over the limit ([`ReadError::Limit`])
/// from one that cannot be read ([`ReadError::Io`]); both display the same text.
pub fn read_regular_file_or(path: &Path, what: &str, limit: Limit, limits: &Limits) -> Result<Vec<u8>, ReadError> {
    read_regular_file_within(path, what, &[limit], limits)
}

/// [`read_regular_file_or`] that checks the file's size against each of `bounds` (e.g. the
/// mesh size and the memory left), before reading and again after, and reads at most the
/// smallest of them plus one byte.
pub(crate) fn read_regular_file_within(
    path: &Path,
    what: &str,
    bounds: &[Limit],
    limits: &Limits,
) -> Result<Vec<u8>, ReadError> {
    let shown = crate::shorten::short_path(path);
    let io = |e: &dyn fmt::Display| ReadError::Io(format!("{shown}: cannot read {what}: {e}"));
    let (file, len) = open_regular(path).map_err(|e| io(&e))?;
    let check = |size: u64| {
        bounds.iter().try_for_each(|&l| limits.check(l, format!("{shown}: {what}"), size)).map_err(ReadError::Limit)
    };
    check(len)?;
    let max = bounds.iter().map(|&l| limits.get(l)).min().unwrap_or(u64::MAX);
    // The file may grow between the size check and the read: never read more than the limit.
    let mut bytes = Vec::with_capacity(usize::try_from(len).unwrap_or(0));
    file.take(max.saturating_add(1)).read_to_end(&mut bytes).map_err(|e| io(&e))?;
    check(bytes.len() as u64)?;
    Ok(bytes)
}

/// Opens `path` if it is a regular file and returns it with its size. A directory ("is a
/// directory") or a FIFO (which could block forever), socket or device ("not a regular
/// file") is refused before it is opened. The error is the reason alone, without the path.
pub(crate) fn open_regular(path: &Path) -> Result<(File, u64), String> {
    let meta = std::fs::metadata(path).map_err(|e| e.to_string())?;
    if meta.is_dir() {
        return Err("is a directory".into());
    }
    if !meta.is_file() {
        return Err("not a regular file (a FIFO, socket or device)".into());
    }
    Ok((File::open(path).map_err(|e| e.to_string())?, meta.len()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_name_the_limit_and_the_flag() {
        let limits = Limits { max_memory: 4 * GIB, ..Limits::default() };
        let err = limits.check(Limit::Memory, "film 16384x16384", 5 * GIB + GIB / 2).unwrap_err();
        assert_eq!(
            err.to_string(),
            "film 16384x16384 needs 5.5 GiB, over the limit of 4.0 GiB (max_memory; raise it with --max-memory)"
        );
        let err = limits.check(Limit::Triangles, "scene", 70_000_000).unwrap_err();
        assert!(err.to_string().contains("needs 70000000, over the limit of 64000000"), "{err}");
        assert!(limits.check(Limit::Memory, "x", 4 * GIB).is_ok());
    }

    #[test]
    fn bytes_are_shown_in_binary_units() {
        assert_eq!(format_bytes(0), "0 B");
        assert_eq!(format_bytes(1023), "1023 B");
        assert_eq!(format_bytes(1536), "1.5 KiB");
        assert_eq!(format_bytes(3 * GIB), "3.0 GiB");
        assert_eq!(format_bytes(u64::MAX), "16.0 EiB");
    }

    #[test]
    fn only_regular_files_within_the_limit_are_read() {
        let dir = std::env::temp_dir().join(format!("ggx-limits-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("s.toml");
        std::fs::write(&file, b"0123456789").unwrap();
        let limits = Limits { max_scene_bytes: 10, ..Limits::default() };
        assert_eq!(read_regular_file(&file, "scene file", Limit::SceneBytes, &limits).unwrap(), b"0123456789");
        let small = Limits { max_scene_bytes: 9, ..Limits::default() };
        let msg = read_regular_file(&file, "scene file", Limit::SceneBytes, &small).unwrap_err();
        assert!(
            msg.contains("scene file needs 10 B, over the limit of 9 B") && msg.contains("--max-scene-bytes"),
            "{msg}"
        );
        let msg = read_regular_file(&dir, "scene file", Limit::SceneBytes, &limits).unwrap_err();
        assert!(msg.ends_with("is a directory"), "{msg}");
        #[cfg(unix)]
        {
            let msg = read_regular_file(Path::new("/dev/zero"), "scene file", Limit::SceneBytes, &limits).unwrap_err();
            assert!(msg.contains("not a regular file"), "{msg}");
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
