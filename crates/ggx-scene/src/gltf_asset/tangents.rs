//! MikkTSpace tangents (Mikkelsen 2008, the algorithm the glTF spec prescribes for a
//! normal-mapped mesh without `TANGENT`), through `bevy_mikktspace`.
//!
//! The coordinates go in with `v` flipped (`1 - v`): glTF's `v` runs down the image while its
//! normal maps have +Y up, and tools (Blender's exporter) compute MikkTSpace in the `v`-up
//! space, so the sign `w` comes out as glTF expects (`B = w (N x T)` up the image).

use glam::{Vec2, Vec3, Vec4};

use crate::geometry::Geometry;

/// The mesh as MikkTSpace sees it, with a tangent per triangle corner.
struct Corners<'a> {
    g: &'a Geometry,
    normals: &'a [Vec3],
    uvs: &'a [Vec2],
    tangents: Vec<Vec4>,
}

impl Corners<'_> {
    fn vertex(&self, face: usize, vert: usize) -> usize {
        self.g.indices.get(face).map_or(0, |t| t[vert.min(2)] as usize)
    }
}

impl bevy_mikktspace::Geometry for Corners<'_> {
    fn num_faces(&self) -> usize {
        self.g.indices.len()
    }

    fn num_vertices_of_face(&self, _face: usize) -> usize {
        3
    }

    fn position(&self, face: usize, vert: usize) -> [f32; 3] {
        self.g.positions.get(self.vertex(face, vert)).copied().unwrap_or(Vec3::ZERO).to_array()
    }

    fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
        self.normals.get(self.vertex(face, vert)).copied().unwrap_or(Vec3::Z).to_array()
    }

    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        let uv = self.uvs.get(self.vertex(face, vert)).copied().unwrap_or(Vec2::ZERO);
        [uv.x, 1.0 - uv.y]
    }

    fn set_tangent(&mut self, tangent: Option<bevy_mikktspace::TangentSpace>, face: usize, vert: usize) {
        if let (Some(t), Some(slot)) = (tangent, self.tangents.get_mut(face * 3 + vert.min(2))) {
            let v = Vec4::from(t.tangent_encoded());
            *slot = if v.is_finite() { v } else { Vec4::ZERO };
        }
    }
}

/// `g` (with normals and texture coordinates, without tangents) unwelded, each triangle its
/// own three vertices, with MikkTSpace tangents per vertex; `g` unchanged when it lacks
/// normals or coordinates, or has tangents already.
pub(crate) fn with_mikktspace_tangents(g: Geometry) -> Geometry {
    let (Some(normals), Some(uvs), None) = (g.normals.as_deref(), g.uvs.as_deref(), g.tangents.as_ref()) else {
        return g;
    };
    let corners = g.indices.len() * 3;
    let mut c = Corners { g: &g, normals, uvs, tangents: vec![Vec4::ZERO; corners] };
    // The error type of bevy_mikktspace 1.0 has no values: generation cannot fail.
    let _ = bevy_mikktspace::generate_tangents(&mut c);
    let tangents = c.tangents;
    let at = |i: u32| i as usize;
    let flat = g.indices.iter().flat_map(|t| t.map(at));
    let unweld_vec3 = |v: &[Vec3]| flat.clone().map(|i| v.get(i).copied().unwrap_or(Vec3::ZERO)).collect::<Vec<_>>();
    Geometry {
        positions: unweld_vec3(&g.positions),
        normals: Some(unweld_vec3(normals)),
        uvs: Some(flat.clone().map(|i| uvs.get(i).copied().unwrap_or(Vec2::ZERO)).collect()),
        tangents: Some(tangents),
        indices: (0..g.indices.len() as u32).map(|f| [3 * f, 3 * f + 1, 3 * f + 2]).collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_plane_gets_its_u_axis_and_a_bitangent_up_the_image() {
        // A quad facing +z, u along +x, v down the image (along -y).
        let g = Geometry {
            positions: vec![
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(1.0, 1.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
            ],
            normals: Some(vec![Vec3::Z; 4]),
            uvs: Some(vec![Vec2::new(0.0, 1.0), Vec2::new(1.0, 1.0), Vec2::new(1.0, 0.0), Vec2::new(0.0, 0.0)]),
            tangents: None,
            indices: vec![[0, 1, 2], [0, 2, 3]],
        };
        let out = with_mikktspace_tangents(g);
        assert_eq!(out.positions.len(), 6);
        for t in out.tangents.unwrap() {
            // T = +x, w = +1: B = w (N x T) = +y, up the image.
            assert!((t - Vec4::new(1.0, 0.0, 0.0, 1.0)).length() < 1e-5, "{t}");
        }
    }

    #[test]
    fn meshes_without_what_it_needs_are_unchanged() {
        let g = Geometry { positions: vec![Vec3::ZERO; 3], indices: vec![[0, 1, 2]], ..Geometry::default() };
        assert_eq!(with_mikktspace_tangents(g.clone()), g);
    }
}
