//! Wavefront OBJ meshes via `tobj`: triangulated, single-indexed, all objects merged.

use std::io::Cursor;
use std::path::Path;

use glam::Vec3;

use super::Geometry;
use super::obj_indices::check_face_indices;
use crate::limits::{Limit, Limits, ReadError, read_regular_file_within};
use crate::shorten::short_path;

/// Bytes `tobj` may hold per `v`, `vn` or `vt` line while it parses: up to six `f32` (a
/// position and a vertex colour) in vectors that grow by doubling, so up to three times
/// that while one is reallocated.
///
/// These three bounds are upper bounds from `tobj`'s record sizes, checked against a
/// measurement (2026-12-01, `/usr/bin/time -v` on the dev `ggx info`): an OBJ of 1 M `v`
/// lines and 1 M triangle faces peaks 326 MB above an empty scene, BVH included, where
/// the bounds allow 600 MB for the parse alone.
pub(crate) const OBJ_BYTES_PER_VERTEX_LINE: u64 = 3 * 24;

/// Bytes `tobj` may hold per `f` or `l` line while it parses: a 104-byte face record in a
/// vector that grows by doubling (three times that while it is reallocated).
pub(crate) const OBJ_BYTES_PER_FACE_LINE: u64 = 3 * 104;

/// Bytes `tobj` may hold per vertex of an `f` or `l` line while it parses: its 24-byte index
/// triple, in the line's own vector (three times that while it is reallocated).
pub(crate) const OBJ_BYTES_PER_FACE_VERTEX: u64 = 3 * 24;

/// Parses OBJ text into one triangle mesh. Faces are fan-triangulated; vertex normals are
/// kept when every vertex has one. Material libraries are ignored. Errors on indices out of
/// range (checked before `tobj` reads them, naming the line), non-finite positions and meshes
/// without triangles, and on more triangles or memory than [`Limits::default`] allows.
pub fn parse_obj(text: &str) -> Result<Geometry, String> {
    parse_obj_with_limits(text, &Limits::default())
}

/// [`parse_obj`] within `limits`, checked from the text before anything is built: the
/// triangles that its face lines make against `limits.max_triangles`, and the text and the
/// parser's buffers (per `v`, `vn`, `vt`, `f` and `l` line and face vertex) against
/// `limits.max_memory`.
pub fn parse_obj_with_limits(text: &str, limits: &Limits) -> Result<Geometry, String> {
    parse_obj_checked(text, limits).map_err(|e| e.to_string())
}

/// [`parse_obj_with_limits`] with an error that tells a mesh over `limits`
/// ([`ReadError::Limit`]) from an invalid one ([`ReadError::Io`]).
pub(crate) fn parse_obj_checked(text: &str, limits: &Limits) -> Result<Geometry, ReadError> {
    let counts = LineCounts::of(text);
    limits.check(Limit::Triangles, "mesh", counts.triangles).map_err(ReadError::Limit)?;
    let what = format!(
        "mesh of {} vertex and {} face lines (its text and parse buffers)",
        counts.vertex_lines, counts.face_lines
    );
    limits.check(Limit::Memory, what, counts.parse_bytes(text.len() as u64)).map_err(ReadError::Limit)?;
    check_face_indices(text).map_err(|e| ReadError::Io(format!("invalid OBJ: {e}")))?;
    parse_obj_unchecked(text).map_err(ReadError::Io)
}

/// Parses `text` without checking it against any limit.
fn parse_obj_unchecked(text: &str) -> Result<Geometry, String> {
    let options = tobj::LoadOptions { single_index: true, triangulate: true, ignore_points: true, ignore_lines: true };
    let (models, _) = tobj::load_obj_buf(&mut Cursor::new(text), &options, |_| Err(tobj::LoadError::OpenFileFailed))
        .map_err(|e| format!("invalid OBJ: {e}"))?;
    let mut g = Geometry { normals: Some(Vec::new()), uvs: Some(Vec::new()), ..Geometry::default() };
    for model in &models {
        let m = &model.mesh;
        let base = g.positions.len();
        let offset = u32::try_from(base).map_err(|_| "more than 2^32 vertices".to_string())?;
        let count = m.positions.len() / 3;
        let vertices = m.positions.chunks_exact(3).map(|p| Vec3::new(p[0], p[1], p[2]));
        g.positions.extend(vertices);
        if let Some(p) = g.positions[base..].iter().find(|p| !p.is_finite()) {
            return Err(format!("non-finite vertex position {p}"));
        }
        if m.normals.len() == m.positions.len() {
            if let Some(n) = &mut g.normals {
                n.extend(m.normals.chunks_exact(3).map(|n| Vec3::new(n[0], n[1], n[2])));
            }
        } else {
            g.normals = None;
        }
        // `vt` has v up the image; ggx's (glTF's) v runs down it.
        if m.texcoords.len() / 2 == count {
            if let Some(uv) = &mut g.uvs {
                uv.extend(m.texcoords.chunks_exact(2).map(|t| glam::Vec2::new(t[0], 1.0 - t[1])));
            }
        } else {
            g.uvs = None;
        }
        for t in m.indices.chunks_exact(3) {
            if let Some(&i) = t.iter().find(|&&i| i as usize >= count) {
                return Err(format!("face index {} out of range (1..={count})", i as u64 + 1));
            }
            let shifted = [t[0], t[1], t[2]].map(|i| i.checked_add(offset));
            let [Some(a), Some(b), Some(c)] = shifted else { return Err("more than 2^32 vertices".into()) };
            g.indices.push([a, b, c]);
        }
    }
    if g.indices.is_empty() {
        return Err("the mesh has no triangles".into());
    }
    Ok(g)
}

/// What the lines of an OBJ text make, counted before it is parsed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct LineCounts {
    /// `v`, `vn` and `vt` lines.
    vertex_lines: u64,
    /// `f` and `l` lines.
    face_lines: u64,
    /// Vertices of the `f` and `l` lines.
    face_vertices: u64,
    /// Triangles that fan triangulation makes of the `f` lines: `n - 2` per face of `n`
    /// vertices.
    triangles: u64,
}

impl LineCounts {
    /// Counts the lines of `text` by their first word, as `tobj` reads them.
    fn of(text: &str) -> Self {
        let mut counts = Self::default();
        for line in text.lines() {
            let mut words = line.split_whitespace();
            match words.next() {
                Some("v" | "vn" | "vt") => counts.vertex_lines += 1,
                Some(kind @ ("f" | "l")) => {
                    let vertices = words.count() as u64;
                    counts.face_lines += 1;
                    counts.face_vertices += vertices;
                    if kind == "f" {
                        counts.triangles += vertices.saturating_sub(2);
                    }
                }
                _ => {}
            }
        }
        counts
    }

    /// Memory of parsing: `text_bytes` of text and the parser's buffers.
    fn parse_bytes(&self, text_bytes: u64) -> u64 {
        text_bytes
            .saturating_add(self.vertex_lines.saturating_mul(OBJ_BYTES_PER_VERTEX_LINE))
            .saturating_add(self.face_lines.saturating_mul(OBJ_BYTES_PER_FACE_LINE))
            .saturating_add(self.face_vertices.saturating_mul(OBJ_BYTES_PER_FACE_VERTEX))
    }
}

/// Reads and parses the OBJ file at `path`: a regular file of at most
/// `limits.max_mesh_bytes` and `limits.max_memory` bytes, then [`parse_obj_checked`]. Errors
/// name the path (shortened).
pub(crate) fn load_obj(path: &Path, limits: &Limits) -> Result<Geometry, ReadError> {
    let shown = short_path(path);
    let bytes = read_regular_file_within(path, "mesh", &[Limit::MeshBytes, Limit::Memory], limits)?;
    let text = std::str::from_utf8(&bytes)
        .map_err(|e| ReadError::Io(format!("{shown}: cannot read mesh: not UTF-8 text ({e})")))?;
    parse_obj_checked(text, limits).map_err(|e| match e {
        ReadError::Io(m) => ReadError::Io(format!("{shown}: {m}")),
        ReadError::Limit(e) => ReadError::Limit(crate::LimitError { what: format!("{shown}: {}", e.what), ..e }),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quad_is_triangulated_with_normals() {
        let g = parse_obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1 4//1\n").unwrap();
        assert_eq!(g.indices.len(), 2);
        assert_eq!(g.normals.as_ref().map(Vec::len), Some(g.positions.len()));
        assert!((g.area() - 1.0).abs() < 1e-6);
    }

    #[test]
    fn bad_meshes_are_errors() {
        assert!(parse_obj("").unwrap_err().contains("no triangles"));
        assert!(parse_obj("v 0 0 0\nf 1 2 3\n").is_err());
        assert!(parse_obj("v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap_err().contains("non-finite"));
    }

    #[test]
    fn triangles_are_counted_before_the_mesh_is_built() {
        let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n  f\t1 2 3\nfoo 1 2 3\nf 1 2\nl 1 2\nvn 0 0 1\n";
        let counts = LineCounts::of(text);
        let expected = LineCounts { vertex_lines: 5, face_lines: 4, face_vertices: 11, triangles: 3 };
        assert_eq!(counts, expected);
        let limits = Limits { max_triangles: 2, ..Limits::default() };
        let msg = parse_obj_with_limits(text, &limits).unwrap_err();
        assert!(msg.contains("needs 3, over the limit of 2") && msg.contains("--max-triangles"), "{msg}");
    }

    #[test]
    fn vertex_lines_count_against_memory_before_parsing() {
        // A million vertices and one face: one triangle, but 72 MB of parse buffers.
        let mut text = "v 0 0 0\n".repeat(1_000_000);
        text.push_str("f 1 2 3\n");
        let needed = text.len() as u64 + 1_000_000 * OBJ_BYTES_PER_VERTEX_LINE + OBJ_BYTES_PER_FACE_LINE + 3 * 24 * 3;
        let limits = Limits { max_memory: needed - 1, ..Limits::default() };
        let msg = parse_obj_with_limits(&text, &limits).unwrap_err();
        assert!(msg.contains("mesh of 1000000 vertex and 1 face lines") && msg.contains("max_memory"), "{msg}");
        let limits = Limits { max_memory: needed, ..Limits::default() };
        assert_eq!(parse_obj_with_limits(&text, &limits).unwrap().indices.len(), 1);
    }
}
