//! Wavefront OBJ meshes via `tobj`: triangulated, single-indexed, all objects merged.

use std::io::Cursor;
use std::path::Path;

use glam::Vec3;

use super::Geometry;

/// Parses OBJ text into one triangle mesh. Faces are fan-triangulated; vertex normals are
/// kept when every vertex has one. Material libraries are ignored. Errors on indices out of
/// range, non-finite positions and meshes without triangles.
pub fn parse_obj(text: &str) -> Result<Geometry, String> {
    let options = tobj::LoadOptions { single_index: true, triangulate: true, ignore_points: true, ignore_lines: true };
    let (models, _) = tobj::load_obj_buf(&mut Cursor::new(text), &options, |_| Err(tobj::LoadError::OpenFileFailed))
        .map_err(|e| format!("invalid OBJ: {e}"))?;
    let mut g = Geometry { normals: Some(Vec::new()), ..Geometry::default() };
    for model in &models {
        let m = &model.mesh;
        let base = g.positions.len();
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
            g.indices.push([t[0], t[1], t[2]].map(|i| i + base as u32));
        }
    }
    if g.indices.is_empty() {
        return Err("the mesh has no triangles".into());
    }
    Ok(g)
}

/// Reads and parses an OBJ file.
pub(crate) fn load_obj(path: &Path) -> Result<Geometry, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    parse_obj(&text).map_err(|e| format!("{}: {e}", path.display()))
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
}
