//! The flattened world-space triangle soup every shape is turned into, in GPU-uploadable
//! (`bytemuck::Pod`, std430-compatible) records.

use bytemuck::{Pod, Zeroable};
use glam::{Vec2, Vec3, Vec4};

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
    #[inline]
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
    #[inline]
    pub fn interpolate(&self, b1: f32, b2: f32) -> Vec3 {
        let [n0, n1, n2] = self.normals.map(|n| Vec3::new(n[0], n[1], n[2]));
        ((1.0 - b1 - b2) * n0 + b1 * n1 + b2 * n2).normalize_or_zero()
    }
}

/// Texture coordinates at the three vertices of a triangle, 32 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct TriangleUvs {
    /// `[u0, v0, u1, v1, u2, v2, 0, 0]`.
    pub uv: [f32; 8],
}

impl TriangleUvs {
    /// Packs three coordinates.
    pub fn new(uv: [Vec2; 3]) -> Self {
        let [a, b, c] = uv;
        Self { uv: [a.x, a.y, b.x, b.y, c.x, c.y, 0.0, 0.0] }
    }

    /// Vertex `i`'s coordinates (`i` in 0..3).
    pub fn at(&self, i: usize) -> Vec2 {
        Vec2::new(self.uv[2 * i], self.uv[2 * i + 1])
    }

    /// Barycentric interpolation `b0 uv0 + b1 uv1 + b2 uv2` with `b0 = 1 - b1 - b2`.
    #[inline]
    pub fn interpolate(&self, b1: f32, b2: f32) -> Vec2 {
        (1.0 - b1 - b2) * self.at(0) + b1 * self.at(1) + b2 * self.at(2)
    }
}

/// Tangents `(x, y, z, w)` at the three vertices of a triangle, 48 bytes; all zero when the
/// mesh gave none (the renderers then take the tangent from the texture coordinates).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct TriangleTangents {
    /// `[x, y, z, w]` per vertex, `w` = +-1 the bitangent's sign.
    pub tangents: [[f32; 4]; 3],
}

impl TriangleTangents {
    /// Packs three tangents.
    pub fn new(t: [Vec4; 3]) -> Self {
        Self { tangents: t.map(|v| v.to_array()) }
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
    /// Texture coordinates, parallel to `shading_normals` (indexed by [`Triangle::normals`]),
    /// or empty when no triangle has any: a triangle with texture coordinates always has a
    /// shading-normal record (its flat normal when the mesh gave none).
    pub uvs: Vec<TriangleUvs>,
    /// Tangents, parallel to `shading_normals`, or empty when no mesh gave any.
    pub tangents: Vec<TriangleTangents>,
}

impl TriangleMesh {
    /// Appends the per-vertex records of one triangle and returns their index (what
    /// [`Triangle::normals`] holds), keeping `uvs` and `tangents` parallel to
    /// `shading_normals` (zero records for triangles without them). `None` past `u32`.
    pub fn push_attributes(
        &mut self,
        normals: ShadingNormals,
        uvs: Option<TriangleUvs>,
        tangents: Option<TriangleTangents>,
    ) -> Option<u32> {
        let index = u32::try_from(self.shading_normals.len()).ok().filter(|&i| i != NO_INDEX)?;
        let n = self.shading_normals.len();
        if uvs.is_some() && self.uvs.len() < n {
            self.uvs.resize(n, TriangleUvs::default());
        }
        if tangents.is_some() && self.tangents.len() < n {
            self.tangents.resize(n, TriangleTangents::default());
        }
        self.shading_normals.push(normals);
        if uvs.is_some() || !self.uvs.is_empty() {
            self.uvs.push(uvs.unwrap_or_default());
        }
        if tangents.is_some() || !self.tangents.is_empty() {
            self.tangents.push(tangents.unwrap_or_default());
        }
        Some(index)
    }

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
        assert_eq!(size_of::<TriangleUvs>(), 32);
        assert_eq!(size_of::<TriangleTangents>(), 48);
    }

    #[test]
    fn attributes_stay_parallel() {
        let n = ShadingNormals::new([Vec3::Z; 3]);
        let uv = TriangleUvs::new([Vec2::ZERO, Vec2::X, Vec2::Y]);
        let mut mesh = TriangleMesh::default();
        assert_eq!(mesh.push_attributes(n, None, None), Some(0));
        assert!(mesh.uvs.is_empty());
        assert_eq!(mesh.push_attributes(n, Some(uv), None), Some(1));
        assert_eq!(mesh.push_attributes(n, None, Some(TriangleTangents::new([Vec4::X; 3]))), Some(2));
        assert_eq!((mesh.uvs.len(), mesh.tangents.len()), (3, 3));
        assert_eq!(mesh.uvs[0], TriangleUvs::default());
        assert_eq!(mesh.uvs[1].interpolate(0.25, 0.5), Vec2::new(0.25, 0.5));
        // The first record with coordinates in an empty table.
        let mut mesh = TriangleMesh::default();
        assert_eq!(mesh.push_attributes(n, Some(uv), None), Some(0));
        assert_eq!(mesh.push_attributes(n, None, None), Some(1));
        assert_eq!(mesh.uvs, vec![uv, TriangleUvs::default()]);
        assert!(mesh.tangents.is_empty());
    }
}
