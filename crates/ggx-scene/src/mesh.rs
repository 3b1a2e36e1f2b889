//! The flattened world-space triangle soup every shape is turned into, in GPU-uploadable
//! (`bytemuck::Pod`, std430-compatible) records.

use bytemuck::{Pod, Zeroable};
use glam::Vec3;

/// Marks an absent index in [`Triangle::normals`] and [`Triangle::emitter`].
pub const NO_INDEX: u32 = u32::MAX;

/// One world-space triangle: three `(vec3<f32>, u32)` rows, 48 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct Triangle {
    /// First vertex.
    pub v0: [f32; 3],
    /// Index into [`crate::Scene::materials`].
    pub material: u32,
    /// Second vertex.
    pub v1: [f32; 3],
    /// Index into [`TriangleMesh::shading_normals`], or [`NO_INDEX`] for flat shading.
    pub normals: u32,
    /// Third vertex.
    pub v2: [f32; 3],
    /// Index into [`crate::AreaLights::emitters`], or [`NO_INDEX`] when not emissive.
    pub emitter: u32,
}

impl Triangle {
    /// The three vertices.
    pub fn vertices(&self) -> [Vec3; 3] {
        [self.v0, self.v1, self.v2].map(Vec3::from)
    }

    /// `(v1 - v0) x (v2 - v0)`: points to the front face, length twice the area.
    pub fn cross(&self) -> Vec3 {
        let [a, b, c] = self.vertices();
        (b - a).cross(c - a)
    }

    /// Surface area.
    pub fn area(&self) -> f32 {
        0.5 * self.cross().length()
    }

    /// Unit geometric normal (front face), zero for degenerate triangles.
    pub fn geometric_normal(&self) -> Vec3 {
        self.cross().normalize_or_zero()
    }
}

/// Unit shading normals at the three vertices of a triangle (`w` = 0), 48 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct ShadingNormals {
    /// `[x, y, z, 0]` per vertex.
    pub normals: [[f32; 4]; 3],
}

impl ShadingNormals {
    /// Packs three unit normals.
    pub fn new(n: [Vec3; 3]) -> Self {
        Self { normals: n.map(|n| n.extend(0.0).to_array()) }
    }

    /// Barycentric interpolation `normalize(b0 n0 + b1 n1 + b2 n2)` with `b0 = 1 - b1 - b2`.
    pub fn interpolate(&self, b1: f32, b2: f32) -> Vec3 {
        let [n0, n1, n2] = self.normals.map(|n| Vec3::new(n[0], n[1], n[2]));
        ((1.0 - b1 - b2) * n0 + b1 * n1 + b2 * n2).normalize_or_zero()
    }
}

/// All triangles of the scene in world space. Each shape's triangles are contiguous and in
/// shape order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriangleMesh {
    /// The triangles.
    pub triangles: Vec<Triangle>,
    /// Shading normals of the triangles that have them.
    pub shading_normals: Vec<ShadingNormals>,
}

impl TriangleMesh {
    /// World-space bounds `(min, max)`; `None` when empty.
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        let mut it = self.triangles.iter().flat_map(Triangle::vertices);
        let first = it.next()?;
        Some(it.fold((first, first), |(lo, hi), p| (lo.min(p), hi.max(p))))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn records_are_48_bytes() {
        assert_eq!(size_of::<Triangle>(), 48);
        assert_eq!(size_of::<ShadingNormals>(), 48);
    }
}
