//! Ray-triangle acceleration: a BVH over the scene's world-space triangles (obvhs' binary BVH
//! collapsed into our 8-wide [`WideBvh`], or obvhs' CWBVH or BVH2 as they are), stored in BVH
//! leaf order so a leaf's triangles are contiguous in memory, each with the edges and normal
//! its ray test needs precomputed ([`RayTriangle`]).

use ggx_scene::Triangle;
use glam::{Vec3, Vec3A};
use obvhs::BvhBuildParams;
use obvhs::bvh2::Bvh2;
use obvhs::cwbvh::CwBvh;
use obvhs::ray::{Ray, RayHit};
use obvhs::triangle::Triangle as BvhTriangle;
use std::time::{Duration, Instant};

use crate::wide_bvh::WideBvh;

/// Which BVH layout to trace against.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum AccelKind {
    /// obvhs' binary BVH collapsed into 8-wide nodes of uncompressed boxes, walked nearest
    /// child first (`WideBvh`): the fastest on the scenes we measured (see the crate README),
    /// hence the default. A tree too deep for its traversal stack stays binary.
    #[default]
    Wide,
    /// obvhs' compressed wide BVH (8-wide, Ylitie et al. 2017).
    Cwbvh,
    /// obvhs' binary BVH.
    Bvh2,
}

enum Tree {
    Wide(WideBvh),
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
    ordered: Vec<RayTriangle>,
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
            AccelKind::Wide => {
                let bvh = obvhs::bvh2::builder::build_bvh2_from_tris(&tris, params, &mut core);
                let indices = bvh.primitive_indices.clone();
                match WideBvh::from_bvh2(&bvh) {
                    Some(wide) => (Tree::Wide(wide), indices),
                    None => (Tree::Binary(bvh), indices),
                }
            }
        };
        let ordered = indices.iter().map(|&i| tris.get(i as usize).map(RayTriangle::new).unwrap_or_default()).collect();
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
            Tree::Wide(w) => {
                w.traverse::<true>(&ray, |first, count, t_max| {
                    for p in first..first.saturating_add(count) {
                        let t = intersect(&ray, p as usize);
                        if t < *t_max {
                            (hit.primitive_id, hit.t, *t_max) = (p, t, t);
                        }
                    }
                    false
                });
                hit.t < t_max
            }
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
            Tree::Wide(w) => {
                let mut miss = true;
                w.traverse::<false>(&ray, |first, count, t_max| {
                    miss = !(first..first.saturating_add(count)).any(|p| intersect(&ray, p as usize) < *t_max);
                    !miss
                });
                miss
            }
            Tree::Cw(b) => b.ray_traverse_miss(ray, intersect),
            Tree::Binary(b) => b.ray_traverse_miss(ray, intersect),
        }
    }
}

/// A triangle as the ray test reads it: `v0`, the edges `e1 = v0 - v1` and `e2 = v2 - v0`,
/// and the unnormalized normal `n = e1 x e2`. These are the terms obvhs'
/// `Triangle::intersect` (and `scene.wgsl`'s `triangle_intersect`) derive on every test;
/// computed once here, with the same operations, they give the same bits.
#[derive(Clone, Copy, Default)]
#[repr(C, align(64))]
struct RayTriangle {
    v0: Vec3A,
    e1: Vec3A,
    e2: Vec3A,
    n: Vec3A,
}

impl RayTriangle {
    fn new(t: &BvhTriangle) -> RayTriangle {
        let e1 = t.v0 - t.v1;
        let e2 = t.v2 - t.v0;
        RayTriangle { v0: t.v0, e1, e2, n: e1.cross(e2) }
    }

    /// Möller & Trumbore 1997 in the form of obvhs and `scene.wgsl`: `r = d x (v0 - o)`,
    /// `u = (r . e2) / (n . d)`, `v = (r . e1) / (n . d)`, hit when `u, v, 1 - u - v` have no
    /// sign bit set, `t = (n . (v0 - o)) / (n . d)` in `[tmin, tmax]`; `inf` otherwise.
    #[inline(always)]
    fn intersect(&self, ray: &Ray) -> f32 {
        let c = self.v0 - ray.origin;
        let r = ray.direction.cross(c);
        let inv_det = 1.0 / self.n.dot(ray.direction);
        let u = r.dot(self.e2) * inv_det;
        let v = r.dot(self.e1) * inv_det;
        let w = 1.0 - u - v;
        // A sign bit on any of u, v, w (-0.0 included) misses, as in obvhs.
        let signs = u.to_bits() | v.to_bits() | w.to_bits();
        if inv_det != 0.0 && signs & 0x8000_0000 == 0 {
            let t = self.n.dot(c) * inv_det;
            if t >= ray.tmin && t <= ray.tmax {
                return t;
            }
        }
        f32::INFINITY
    }
}

/// Barycentrics `(b1, b2)` of the ray's intersection with the triangle's plane, Moller &
/// Trumbore 1997: `b1 = (s . p) / det`, `b2 = (d . q) / det` with `p = d x e2`, `q = s x e1`.
/// (`v1 - v0` is `-(v0 - v1)` exactly: rounding to nearest is symmetric.)
fn barycentrics(t: &RayTriangle, origin: Vec3, dir: Vec3) -> (f32, f32) {
    let (v0, e1, e2) = (Vec3::from(t.v0), -Vec3::from(t.e1), Vec3::from(t.e2));
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
