//! Ray-triangle acceleration: an obvhs BVH (CWBVH or BVH2) over the scene's world-space
//! triangles, stored in BVH leaf order so a leaf's triangles are contiguous in memory.

use ggx_scene::Triangle;
use glam::{Vec3, Vec3A};
use obvhs::BvhBuildParams;
use obvhs::bvh2::Bvh2;
use obvhs::cwbvh::CwBvh;
use obvhs::ray::{Ray, RayHit};
use obvhs::triangle::Triangle as BvhTriangle;
use std::time::{Duration, Instant};

/// Which obvhs BVH layout to trace against.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum AccelKind {
    /// Compressed wide BVH (8-wide, Ylitie et al. 2017): the faster one on the scenes we
    /// measured (see the crate README), hence the default.
    #[default]
    Cwbvh,
    /// Binary BVH.
    Bvh2,
}

enum Tree {
    Cw(CwBvh),
    Binary(Bvh2),
}

/// A closest hit: triangle index into the scene mesh, distance and barycentrics.
#[derive(Clone, Copy, Debug)]
pub struct Hit {
    /// Index into `Scene::mesh.triangles`.
    pub triangle: u32,
    /// Ray parameter of the hit.
    pub t: f32,
    /// Barycentric weight of `v1`.
    pub b1: f32,
    /// Barycentric weight of `v2`.
    pub b2: f32,
}

/// The BVH plus triangles in leaf order.
pub struct Accel {
    tree: Tree,
    /// Triangles in BVH primitive order (duplicates where the builder split triangles).
    ordered: Vec<BvhTriangle>,
    /// Maps a BVH primitive index back to the scene triangle index.
    primitive_to_triangle: Vec<u32>,
    build_time: Duration,
}

impl Accel {
    /// Builds the BVH over `triangles` with obvhs' "medium" preset (PLOC, pre-splitting).
    pub fn build(triangles: &[Triangle], kind: AccelKind) -> Accel {
        let start = Instant::now();
        let tris: Vec<BvhTriangle> = triangles
            .iter()
            .map(|t| BvhTriangle { v0: Vec3A::from(t.v0), v1: Vec3A::from(t.v1), v2: Vec3A::from(t.v2) })
            .collect();
        let mut core = Duration::ZERO;
        let params = BvhBuildParams::medium_build();
        let (tree, indices) = match kind {
            AccelKind::Cwbvh => {
                let bvh = obvhs::cwbvh::builder::build_cwbvh_from_tris(&tris, params, &mut core);
                let indices = bvh.primitive_indices.clone();
                (Tree::Cw(bvh), indices)
            }
            AccelKind::Bvh2 => {
                let bvh = obvhs::bvh2::builder::build_bvh2_from_tris(&tris, params, &mut core);
                let indices = bvh.primitive_indices.clone();
                (Tree::Binary(bvh), indices)
            }
        };
        let ordered = indices.iter().map(|&i| tris.get(i as usize).copied().unwrap_or_default()).collect();
        Accel { tree, ordered, primitive_to_triangle: indices, build_time: start.elapsed() }
    }

    /// Wall time of [`Accel::build`].
    pub fn build_time(&self) -> Duration {
        self.build_time
    }

    /// Closest hit along `origin + t dir`, `t` in `(0, t_max)`.
    pub fn closest(&self, origin: Vec3, dir: Vec3, t_max: f32) -> Option<Hit> {
        let ray = Ray::new(origin.into(), dir.into(), 0.0, t_max);
        let mut hit = RayHit::none();
        let intersect = |r: &Ray, id: usize| self.ordered.get(id).map_or(f32::INFINITY, |t| t.intersect(r));
        let found = match &self.tree {
            Tree::Cw(b) => b.ray_traverse(ray, &mut hit, intersect),
            Tree::Binary(b) => b.ray_traverse(ray, &mut hit, intersect),
        };
        if !found {
            return None;
        }
        let id = hit.primitive_id as usize;
        let tri = self.ordered.get(id)?;
        let (b1, b2) = barycentrics(tri, origin, dir);
        Some(Hit { triangle: *self.primitive_to_triangle.get(id)?, t: hit.t, b1, b2 })
    }

    /// True when nothing blocks `origin + t dir` for `t` in `(0, t_max)` (shadow rays).
    pub fn unoccluded(&self, origin: Vec3, dir: Vec3, t_max: f32) -> bool {
        let ray = Ray::new(origin.into(), dir.into(), 0.0, t_max);
        let intersect = |r: &Ray, id: usize| self.ordered.get(id).map_or(f32::INFINITY, |t| t.intersect(r));
        match &self.tree {
            Tree::Cw(b) => b.ray_traverse_miss(ray, intersect),
            Tree::Binary(b) => b.ray_traverse_miss(ray, intersect),
        }
    }
}

/// Barycentrics `(b1, b2)` of the ray's intersection with the triangle's plane, Moller &
/// Trumbore 1997: `b1 = (s . p) / det`, `b2 = (d . q) / det` with `p = d x e2`, `q = s x e1`.
fn barycentrics(t: &BvhTriangle, origin: Vec3, dir: Vec3) -> (f32, f32) {
    let (v0, v1, v2) = (Vec3::from(t.v0), Vec3::from(t.v1), Vec3::from(t.v2));
    let (e1, e2) = (v1 - v0, v2 - v0);
    let p = dir.cross(e2);
    let det = e1.dot(p);
    if det == 0.0 || !det.is_finite() {
        return (0.0, 0.0);
    }
    let inv = 1.0 / det;
    let s = origin - v0;
    let q = s.cross(e1);
    let b1 = (s.dot(p) * inv).clamp(0.0, 1.0);
    let b2 = (dir.dot(q) * inv).clamp(0.0, 1.0 - b1);
    (b1, b2)
}
