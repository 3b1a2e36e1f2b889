//! The exact triangles ggx renders, grouped into one mesh per material and shading mode and
//! encoded as binary PLY or Wavefront OBJ for Mitsuba.
//!
//! ggx stores world-space triangles with per-corner shading normals; the groups keep those
//! positions and normals bit for bit (corners shared by equal position, normal and texture
//! coordinates become one vertex). Meshes of anisotropic materials get texture coordinates
//! whose `u` axis is ggx's tangent (see [`tangent`]), because Mitsuba takes a triangle's
//! tangent `dp/du` from its texture coordinates.

use std::collections::HashMap;
use std::fmt::Write as _;

use ggx_film::Vec3;
use ggx_scene::{NO_INDEX, Scene};

/// Triangles of one material with one shading mode, in scene order.
#[derive(Clone, Debug, PartialEq)]
pub struct Group {
    /// Index into the scene's materials.
    pub material: usize,
    /// True when the triangles have shading normals (written per vertex).
    pub smooth: bool,
    /// Indices into the scene's triangles.
    pub triangles: Vec<usize>,
}

/// Groups the scene's triangles by `(material, smooth)`, in order of first appearance.
pub fn groups(scene: &Scene) -> Vec<Group> {
    let mut out: Vec<Group> = Vec::new();
    let mut index: HashMap<(u32, bool), usize> = HashMap::new();
    for (i, t) in scene.mesh.triangles.iter().enumerate() {
        let smooth = t.normals != NO_INDEX && (t.normals as usize) < scene.mesh.shading_normals.len();
        let slot = *index.entry((t.material, smooth)).or_insert_with(|| {
            out.push(Group { material: t.material as usize, smooth, triangles: Vec::new() });
            out.len() - 1
        });
        out[slot].triangles.push(i);
    }
    out
}

/// An indexed mesh: vertices (position, optional normal, optional uv) and triangles.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct IndexedMesh {
    /// Vertex positions.
    pub positions: Vec<[f32; 3]>,
    /// Vertex normals (empty for a flat mesh).
    pub normals: Vec<[f32; 3]>,
    /// Vertex texture coordinates (empty when not written).
    pub uvs: Vec<[f32; 2]>,
    /// Triangles as vertex indices, counter-clockwise (front face `(v1 - v0) x (v2 - v0)`).
    pub faces: Vec<[u32; 3]>,
}

/// ggx-cpu's shading-frame tangent for unit normal `n` (`integrator::shading_frame`): the
/// latitude direction `normalize(y x n)`, or within about 0.5 degrees of the poles
/// (`|y x n|^2 < 1e-4`) the Duff et al. 2017 basis vector
/// `(1 + s n.x^2 a, s n.x n.y a, -s n.x)` with `s = sign(n.z)`, `a = -1 / (s + n.z)`.
pub fn tangent(n: Vec3) -> Vec3 {
    let t = Vec3::Y.cross(n);
    let len2 = t.length_squared();
    if len2 >= 1e-4 {
        return t / len2.sqrt();
    }
    let n = n.normalize_or_zero();
    let n = if n == Vec3::ZERO { Vec3::Z } else { n };
    let s = 1.0f32.copysign(n.z);
    let a = -1.0 / (s + n.z);
    Vec3::new(1.0 + s * n.x * n.x * a, s * n.x * n.y * a, -s * n.x)
}

/// The indexed mesh of `group`: positions and (when smooth) normals exactly as ggx stores
/// them; with `uv`, texture coordinates `(T . p, B . p)` per triangle, where `T` is
/// [`tangent`] of the normal at the triangle's centre projected into its plane and
/// `B = n_f x T`, so that Mitsuba's `dp/du` is `T` (exact for flat triangles, where ggx's
/// tangent is constant over the triangle).
pub fn build(scene: &Scene, group: &Group, uv: bool) -> IndexedMesh {
    let mut mesh = IndexedMesh::default();
    let mut seen: HashMap<[u32; 8], u32> = HashMap::new();
    for &i in &group.triangles {
        let t = &scene.mesh.triangles[i];
        let corners = t.vertices();
        let normals = if group.smooth {
            scene.mesh.shading_normals.get(t.normals as usize).map(|s| s.normals.map(|n| Vec3::new(n[0], n[1], n[2])))
        } else {
            None
        };
        let uvs = uv.then(|| {
            let nf = t.geometric_normal();
            let centre = normals.map_or(nf, |[a, b, c]| (a + b + c).normalize_or_zero());
            let centre = if centre == Vec3::ZERO { nf } else { centre };
            let along = tangent(centre);
            let in_plane = (along - nf * nf.dot(along)).normalize_or_zero();
            let tu = if in_plane == Vec3::ZERO { along } else { in_plane };
            let tv = nf.cross(tu);
            corners.map(|p| [tu.dot(p), tv.dot(p)])
        });
        let mut face = [0u32; 3];
        for (k, slot) in face.iter_mut().enumerate() {
            let p = corners[k].to_array();
            let n = normals.map_or([0.0; 3], |n| n[k].to_array());
            let w = uvs.map_or([0.0; 2], |w| w[k]);
            let key = [p[0], p[1], p[2], n[0], n[1], n[2], w[0], w[1]].map(f32::to_bits);
            *slot = *seen.entry(key).or_insert_with(|| {
                mesh.positions.push(p);
                if normals.is_some() {
                    mesh.normals.push(n);
                }
                if uvs.is_some() {
                    mesh.uvs.push(w);
                }
                (mesh.positions.len() - 1) as u32
            });
        }
        mesh.faces.push(face);
    }
    mesh
}

/// Binary little-endian PLY: `x y z [nx ny nz] [u v]` as float per vertex, faces as
/// `list uchar int vertex_indices`; `comment` goes into the header (one line).
pub fn to_ply(mesh: &IndexedMesh, comment: &str) -> Vec<u8> {
    let mut header = String::from("ply\nformat binary_little_endian 1.0\n");
    let comment: String = comment.chars().map(|c| if c.is_control() { ' ' } else { c }).collect();
    let _ = writeln!(header, "comment {comment}");
    let _ = writeln!(header, "element vertex {}", mesh.positions.len());
    header.push_str("property float x\nproperty float y\nproperty float z\n");
    if !mesh.normals.is_empty() {
        header.push_str("property float nx\nproperty float ny\nproperty float nz\n");
    }
    if !mesh.uvs.is_empty() {
        header.push_str("property float u\nproperty float v\n");
    }
    let _ = writeln!(header, "element face {}", mesh.faces.len());
    header.push_str("property list uchar int vertex_indices\nend_header\n");
    let per_vertex = 12 + 12 * usize::from(!mesh.normals.is_empty()) + 8 * usize::from(!mesh.uvs.is_empty());
    let mut out = Vec::with_capacity(header.len() + mesh.positions.len() * per_vertex + mesh.faces.len() * 13);
    out.extend_from_slice(header.as_bytes());
    for (i, p) in mesh.positions.iter().enumerate() {
        let mut put = |v: &[f32]| v.iter().for_each(|x| out.extend_from_slice(&x.to_le_bytes()));
        put(p);
        if let Some(n) = mesh.normals.get(i) {
            put(n);
        }
        if let Some(w) = mesh.uvs.get(i) {
            put(w);
        }
    }
    for f in &mesh.faces {
        out.push(3);
        for &v in f {
            // Vertex counts stay far below i32::MAX (ggx's triangle limit is 2^32 - 1 corners
            // at most, and a mesh over 2^31 vertices would not fit the machine).
            out.extend_from_slice(&(v as i32).to_le_bytes());
        }
    }
    out
}

/// Wavefront OBJ: `v`, `vn`, `vt` lines (shortest round-trip decimals, so the floats read back
/// bit for bit) and `f` lines with 1-based `v/vt/vn` indices; `comment` as a `#` line.
pub fn to_obj(mesh: &IndexedMesh, comment: &str) -> String {
    let mut s = String::new();
    let comment: String = comment.chars().map(|c| if c.is_control() { ' ' } else { c }).collect();
    let _ = writeln!(s, "# {comment}");
    for p in &mesh.positions {
        let _ = writeln!(s, "v {} {} {}", p[0], p[1], p[2]);
    }
    for n in &mesh.normals {
        let _ = writeln!(s, "vn {} {} {}", n[0], n[1], n[2]);
    }
    for w in &mesh.uvs {
        let _ = writeln!(s, "vt {} {}", w[0], w[1]);
    }
    let (has_n, has_t) = (!mesh.normals.is_empty(), !mesh.uvs.is_empty());
    for f in &mesh.faces {
        s.push('f');
        for &v in f {
            let i = u64::from(v) + 1;
            let _ = match (has_t, has_n) {
                (false, false) => write!(s, " {i}"),
                (true, false) => write!(s, " {i}/{i}"),
                (false, true) => write!(s, " {i}//{i}"),
                (true, true) => write!(s, " {i}/{i}/{i}"),
            };
        }
        s.push('\n');
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene(text: &str) -> Scene {
        ggx_scene::parse_scene(text, "t.toml", std::path::Path::new(".")).unwrap()
    }

    const TWO_SHAPES: &str = "[camera]\nposition = [0, 1, 5]\nlook_at = [0, 0, 0]\n\
        [materials.w]\ntype = \"diffuse\"\nalbedo = [0.5, 0.5, 0.5]\n\
        [materials.m]\ntype = \"conductor\"\nalpha = [0.1, 0.3]\neta = [1, 1, 1]\nk = [2, 2, 2]\n\
        [[shapes]]\ntype = \"rectangle\"\nmaterial = \"w\"\n\
        [[shapes]]\ntype = \"sphere\"\nmaterial = \"m\"\nsubdivisions = 1\n\
        [[shapes]]\ntype = \"box\"\nmaterial = \"w\"\n";

    #[test]
    fn groups_by_material_and_smoothness() {
        let s = scene(TWO_SHAPES);
        let g = groups(&s);
        let (w, m) = (s.material_index("w").unwrap(), s.material_index("m").unwrap());
        assert_eq!(g.len(), 2);
        assert_eq!((g[0].material, g[0].smooth, g[0].triangles.len()), (w, false, 2 + 12));
        assert_eq!((g[1].material, g[1].smooth, g[1].triangles.len()), (m, true, 80));
        let total: usize = g.iter().map(|g| g.triangles.len()).sum();
        assert_eq!(total, s.mesh.triangles.len());
    }

    #[test]
    fn indexed_mesh_keeps_every_corner_exactly() {
        let s = scene(TWO_SHAPES);
        for g in groups(&s) {
            let m = build(&s, &g, true);
            assert_eq!(m.faces.len(), g.triangles.len());
            assert!(m.positions.len() < 3 * g.triangles.len(), "shared corners are merged");
            assert_eq!(m.uvs.len(), m.positions.len());
            assert_eq!(m.normals.len(), if g.smooth { m.positions.len() } else { 0 });
            for (face, &t) in m.faces.iter().zip(&g.triangles) {
                let tri = &s.mesh.triangles[t];
                assert_eq!(face.map(|v| m.positions[v as usize]), [tri.v0, tri.v1, tri.v2]);
                if g.smooth {
                    let n = s.mesh.shading_normals[tri.normals as usize].normals;
                    assert_eq!(face.map(|v| m.normals[v as usize]), n.map(|n| [n[0], n[1], n[2]]));
                }
            }
        }
    }

    #[test]
    fn texture_coordinates_put_u_along_ggx_tangent() {
        let s = scene(TWO_SHAPES);
        let g = &groups(&s)[0];
        let m = build(&s, g, true);
        // The rectangle faces +z: ggx's tangent is y x z = +x, so u grows with x, v with y.
        let f = m.faces[0];
        let tri = &s.mesh.triangles[g.triangles[0]];
        let (p, w) = (f.map(|v| Vec3::from(m.positions[v as usize])), f.map(|v| m.uvs[v as usize]));
        // dp/du from the texture coordinates (Mitsuba's formula).
        let (d1, d2) = (p[1] - p[0], p[2] - p[0]);
        let (du1, dv1, du2, dv2) = (w[1][0] - w[0][0], w[1][1] - w[0][1], w[2][0] - w[0][0], w[2][1] - w[0][1]);
        let det = du1 * dv2 - dv1 * du2;
        let dp_du = (d1 * dv2 - d2 * dv1) / det;
        assert!((dp_du - tangent(tri.geometric_normal())).length() < 1e-5, "{dp_du}");
        assert!((tangent(Vec3::Z) - Vec3::X).length() < 1e-6);
        // Near the poles the Duff et al. basis: +y gives +x.
        assert!((tangent(Vec3::Y) - Vec3::X).length() < 1e-6);
        assert!((tangent(Vec3::X) - Vec3::new(0.0, 0.0, -1.0)).length() < 1e-6);
    }

    #[test]
    fn ply_and_obj_encodings() {
        let mesh = IndexedMesh {
            positions: vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.1]],
            normals: vec![[0.0, 0.0, 1.0]; 3],
            uvs: vec![],
            faces: vec![[0, 1, 2]],
        };
        let ply = to_ply(&mesh, "material\nx");
        let end = b"end_header\n";
        let at = ply.windows(end.len()).position(|w| w == end).unwrap() + end.len();
        let header = std::str::from_utf8(&ply[..at]).unwrap();
        assert!(header.contains("comment material x\n") && header.contains("element vertex 3\n"), "{header}");
        assert!(header.contains("property float nz\n") && !header.contains("property float u\n"), "{header}");
        assert_eq!(ply.len() - at, 3 * 24 + 13);
        assert_eq!(&ply[at + 3 * 24..], [3, 0, 0, 0, 0, 1, 0, 0, 0, 2, 0, 0, 0]);
        // Vertex 2's z, after its x and y.
        assert_eq!(f32::from_le_bytes(ply[at + 48 + 8..at + 48 + 12].try_into().unwrap()), 0.1);
        let obj = to_obj(&mesh, "m");
        assert!(
            obj.contains("v 0 1 0.1\n") && obj.contains("vn 0 0 1\n") && obj.contains("f 1//1 2//2 3//3\n"),
            "{obj}"
        );
    }
}
