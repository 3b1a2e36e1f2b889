//! Object-space triangle geometry for every shape type, and the affine shape transform.

mod obj;
mod obj_indices;
mod primitives;
mod sphere;
mod transform;

pub(crate) use obj::load_obj;
pub use obj::{parse_obj, parse_obj_with_limits};
pub use primitives::{cube, disk, rectangle};
pub use sphere::icosphere;
pub(crate) use transform::build_transform;

use glam::{Vec2, Vec3, Vec4};

/// An indexed triangle mesh in object space.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Geometry {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Per-vertex shading normals, parallel to `positions`, when the shape has them.
    pub normals: Option<Vec<Vec3>>,
    /// Per-vertex texture coordinates (glTF's `TEXCOORD_0`: `(0, 0)` is the image's top-left
    /// corner), parallel to `positions`.
    pub uvs: Option<Vec<Vec2>>,
    /// Per-vertex tangents `(x, y, z, w)` (glTF's `TANGENT`: the bitangent is
    /// `w (normal x tangent)`), parallel to `positions`.
    pub tangents: Option<Vec<Vec4>>,
    /// Counter-clockwise triangles (the front face's normal is `(p1 - p0) x (p2 - p0)`).
    pub indices: Vec<[u32; 3]>,
}

impl Geometry {
    /// Total surface area.
    pub fn area(&self) -> f32 {
        self.indices
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| self.positions[i as usize]);
                0.5 * (b - a).cross(c - a).length()
            })
            .sum()
    }

    /// Bytes that the vertex, normal and index arrays hold (their capacity).
    pub(crate) fn heap_bytes(&self) -> u64 {
        let vec3 = size_of::<Vec3>() as u64;
        let positions = self.positions.capacity() as u64 * vec3;
        let normals = self.normals.as_ref().map_or(0, |n| n.capacity() as u64 * vec3);
        let uvs = self.uvs.as_ref().map_or(0, |n| n.capacity() as u64 * size_of::<Vec2>() as u64);
        let tangents = self.tangents.as_ref().map_or(0, |n| n.capacity() as u64 * size_of::<Vec4>() as u64);
        let indices = self.indices.capacity() as u64 * size_of::<[u32; 3]>() as u64;
        positions.saturating_add(normals).saturating_add(uvs).saturating_add(tangents).saturating_add(indices)
    }
}
