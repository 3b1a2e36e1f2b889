//! Icosphere tessellation of the unit sphere.

use std::collections::HashMap;

use glam::Vec3;

use super::Geometry;

/// The unit sphere as an icosahedron whose triangles are split in four `subdivisions` times
/// (`20 * 4^subdivisions` triangles), new vertices projected onto the sphere. Shading
/// normals (the unit positions) are included when `smooth`. Faces point outwards.
pub fn icosphere(subdivisions: u32, smooth: bool) -> Geometry {
    // Icosahedron vertices: cyclic permutations of (0, +-1, +-t), t = golden ratio.
    let t = (1.0 + 5f32.sqrt()) / 2.0;
    let mut positions: Vec<Vec3> = [
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ]
    .iter()
    .map(|p| Vec3::from(*p).normalize())
    .collect();
    let mut indices: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..subdivisions {
        let mut midpoints = HashMap::new();
        let mut midpoint = |a: u32, b: u32, positions: &mut Vec<Vec3>| {
            *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
                positions.push((positions[a as usize] + positions[b as usize]).normalize());
                positions.len() as u32 - 1
            })
        };
        indices = indices
            .iter()
            .flat_map(|&[a, b, c]| {
                let ab = midpoint(a, b, &mut positions);
                let bc = midpoint(b, c, &mut positions);
                let ca = midpoint(c, a, &mut positions);
                [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
            })
            .collect();
    }
    let normals = smooth.then(|| positions.clone());
    Geometry { positions, normals, indices, ..Geometry::default() }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn icosphere_is_closed_outward_and_converges() {
        let g = icosphere(3, true);
        assert_eq!(g.indices.len(), 20 * 64);
        // Euler characteristic of a closed genus-0 mesh: V - E + F = 2, with E = 3F/2.
        assert_eq!(g.positions.len() as i64 - 3 * 1280 / 2 + 1280, 2);
        for t in &g.indices {
            let [a, b, c] = t.map(|i| g.positions[i as usize]);
            assert!((b - a).cross(c - a).dot(a + b + c) > 0.0);
        }
        let area = g.area();
        assert!((area - 4.0 * std::f32::consts::PI).abs() < 0.05 * area, "{area}");
    }
}
