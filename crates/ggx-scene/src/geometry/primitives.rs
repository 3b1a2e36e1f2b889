//! Flat primitives: the unit rectangle, the unit cube and the unit disk.

use std::f32::consts::TAU;

use glam::{Vec2, Vec3};

use super::Geometry;

/// Texture coordinates of a point `(x, y)` of a unit face (`[-0.5, 0.5]^2`): `u = x + 0.5`
/// to the right, `v = 0.5 - y` down the image (glTF's convention, `(0, 0)` top-left).
fn face_uv(x: f32, y: f32) -> Vec2 {
    Vec2::new(x + 0.5, 0.5 - y)
}

/// The unit square `[-0.5, 0.5]^2` in the xy plane at z = 0, front face +z (2 triangles),
/// the whole texture across it (`face_uv`).
pub fn rectangle() -> Geometry {
    let corners = [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)];
    Geometry {
        positions: corners.iter().map(|&(x, y)| Vec3::new(x, y, 0.0)).collect(),
        uvs: Some(corners.iter().map(|&(x, y)| face_uv(x, y)).collect()),
        indices: vec![[0, 1, 2], [0, 2, 3]],
        ..Geometry::default()
    }
}

/// The unit cube `[-0.5, 0.5]^3`, front faces outwards (12 triangles).
///
/// Face `(axis a, sign s)`: centre `s/2 e_a`, spanned by `u = e_(a+1)`, `v = e_(a+2)` with
/// `u x v = e_a`; the winding is flipped for `s < 0` so every normal points outwards. Each
/// face holds the whole texture (`face_uv` of its `(u, v)` coordinates).
pub fn cube() -> Geometry {
    let mut g = Geometry { uvs: Some(Vec::new()), ..Geometry::default() };
    for axis in 0..3 {
        let (n, u, v) = (Vec3::AXES[axis], Vec3::AXES[(axis + 1) % 3], Vec3::AXES[(axis + 2) % 3]);
        for s in [-1.0f32, 1.0] {
            let base = g.positions.len() as u32;
            let c = 0.5 * s * n;
            for (du, dv) in [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)] {
                g.positions.push(c + du * u + dv * v);
                if let Some(uvs) = &mut g.uvs {
                    uvs.push(face_uv(du, dv));
                }
            }
            let quad = if s > 0.0 { [[0, 1, 2], [0, 2, 3]] } else { [[0, 2, 1], [0, 3, 2]] };
            g.indices.extend(quad.map(|t| t.map(|i| base + i)));
        }
    }
    g
}

/// The unit disk (radius 1) in the xy plane at z = 0, front face +z, as a fan of
/// `segments` triangles around the centre; the texture's inscribed disk across it.
pub fn disk(segments: u32) -> Geometry {
    let mut positions = vec![Vec3::ZERO];
    positions.extend((0..segments).map(|i| {
        let phi = TAU * i as f32 / segments as f32;
        Vec3::new(phi.cos(), phi.sin(), 0.0)
    }));
    let uvs = positions.iter().map(|p| face_uv(0.5 * p.x, 0.5 * p.y)).collect();
    let indices = (0..segments).map(|i| [0, 1 + i, 1 + (i + 1) % segments]).collect();
    Geometry { positions, uvs: Some(uvs), indices, ..Geometry::default() }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn normals(g: &Geometry) -> Vec<Vec3> {
        g.indices
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| g.positions[i as usize]);
                (b - a).cross(c - a).normalize()
            })
            .collect()
    }

    #[test]
    fn rectangle_faces_plus_z() {
        let g = rectangle();
        assert!((g.area() - 1.0).abs() < 1e-6);
        assert!(normals(&g).iter().all(|n| *n == Vec3::Z));
    }

    #[test]
    fn cube_faces_outwards() {
        let g = cube();
        assert_eq!(g.indices.len(), 12);
        assert!((g.area() - 6.0).abs() < 1e-5);
        for (t, n) in g.indices.iter().zip(normals(&g)) {
            let centroid = t.iter().map(|&i| g.positions[i as usize]).sum::<Vec3>() / 3.0;
            assert!(n.dot(centroid) > 0.0);
        }
    }

    #[test]
    fn disk_area_converges_to_pi() {
        let g = disk(64);
        assert_eq!(g.indices.len(), 64);
        // Area of a regular n-gon of circumradius 1: n/2 sin(2 pi / n).
        assert!((g.area() - 32.0 * (TAU / 64.0).sin()).abs() < 1e-4);
        assert!(normals(&g).iter().all(|n| (*n - Vec3::Z).length() < 1e-5));
    }
}
