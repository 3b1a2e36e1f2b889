//! Wavefront OBJ meshes via `tobj`: triangulated, single-indexed, all objects merged.

use std::io::Cursor;
use std::path::Path;

use glam::Vec3;

use super::Geometry;
use crate::limits::{Limit, Limits, read_regular_file};

/// Parses OBJ text into one triangle mesh. Faces are fan-triangulated; vertex normals are
/// kept when every vertex has one. Material libraries are ignored. Errors on indices out of
/// range, non-finite positions and meshes without triangles, and on more triangles than
/// [`Limits::default`] allows.
pub fn parse_obj(text: &str) -> Result<Geometry, String> {
    parse_obj_with_limits(text, &Limits::default())
}

/// [`parse_obj`] that refuses meshes with more than `limits.max_triangles` triangles, counted
/// from the face lines before anything is built.
pub fn parse_obj_with_limits(text: &str, limits: &Limits) -> Result<Geometry, String> {
    limits.check(Limit::Triangles, "mesh", count_triangles(text)).map_err(|e| e.to_string())?;
    let options = tobj::LoadOptions { single_index: true, triangulate: true, ignore_points: true, ignore_lines: true };
    let (models, _) = tobj::load_obj_buf(&mut Cursor::new(text), &options, |_| Err(tobj::LoadError::OpenFileFailed))
        .map_err(|e| format!("invalid OBJ: {e}"))?;
    let mut g = Geometry { normals: Some(Vec::new()), ..Geometry::default() };
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

/// Triangles that fan triangulation makes of the face (`f`) lines of `text`: `n - 2` per
/// face of `n` vertices.
fn count_triangles(text: &str) -> u64 {
    text.lines()
        .filter_map(|line| line.trim_start().strip_prefix('f'))
        .filter(|rest| rest.starts_with(char::is_whitespace))
        .map(|rest| (rest.split_whitespace().count() as u64).saturating_sub(2))
        .sum()
}

/// Reads and parses the OBJ file at `path`: a regular file of at most
/// `limits.max_mesh_bytes` and `limits.max_triangles` triangles. Errors name the path.
pub(crate) fn load_obj(path: &Path, limits: &Limits) -> Result<Geometry, String> {
    let bytes = read_regular_file(path, "mesh", Limit::MeshBytes, limits)?;
    let text = std::str::from_utf8(&bytes)
        .map_err(|e| format!("{}: cannot read mesh: not UTF-8 text ({e})", path.display()))?;
    parse_obj_with_limits(text, limits).map_err(|e| format!("{}: {e}", path.display()))
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
        let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n  f\t1 2 3\nfoo 1 2 3\nf 1 2\n";
        assert_eq!(count_triangles(text), 3);
        let limits = Limits { max_triangles: 2, ..Limits::default() };
        let msg = parse_obj_with_limits(text, &limits).unwrap_err();
        assert!(msg.contains("needs 3, over the limit of 2") && msg.contains("--max-triangles"), "{msg}");
    }
}
