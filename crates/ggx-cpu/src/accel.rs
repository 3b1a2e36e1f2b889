//! Ray-triangle acceleration: a BVH over the scene's world-space triangles (obvhs' binary BVH
//! collapsed into our 8-wide [`WideBvh`], or obvhs' CWBVH or BVH2 as they are), stored in BVH
//! leaf order so a leaf's triangles are contiguous in memory, each with the edges and normal
//! its ray test needs precomputed ([`RayTriangle`]); the wide tree's leaves hold them up to
//! eight to a [`TrianglePacket`], tested together.

use ggx_scene::Triangle;
use glam::{Vec3, Vec3A};
use obvhs::BvhBuildParams;
use obvhs::bvh2::Bvh2;
use obvhs::cwbvh::CwBvh;
use obvhs::ray::{Ray, RayHit};
use obvhs::triangle::Triangle as BvhTriangle;
use std::time::{Duration, Instant};

use crate::ray_triangle::{PACKET_WIDTH, RayTriangle, TrianglePacket};
use crate::wide_bvh::{Leaf, PacketLeaf, RAYS, RayPacket, WideBvh};

/// Rays [`Accel::closest_packet`] walks the wide tree with at once.
pub const PACKET_RAYS: usize = RAYS;

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
    /// The wide tree; its leaves index `packets` (a leaf of `count` triangles spans
    /// `count.div_ceil(PACKET_WIDTH)` packets).
    Wide {
        bvh: WideBvh,
        packets: Vec<TrianglePacket>,
    },
    Cw {
        bvh: CwBvh,
        primitives: Primitives,
    },
    Binary {
        bvh: Bvh2,
        primitives: Primitives,
    },
}

/// The triangles of an obvhs tree in its primitive order (duplicates where the builder split
/// triangles), and the scene triangle each one is.
struct Primitives {
    ordered: Vec<RayTriangle>,
    triangle: Vec<u32>,
}

impl Primitives {
    #[inline(always)]
    fn intersect(&self, ray: &Ray, id: usize) -> f32 {
        self.ordered.get(id).map_or(f32::INFINITY, |t| t.intersect(ray))
    }

    /// An obvhs traversal's answer as the hit triangle, its scene index and distance (`None`
    /// when nothing was `found`).
    fn hit(&self, found: bool, hit: &RayHit) -> Option<(RayTriangle, u32, f32)> {
        let id = hit.primitive_id as usize;
        found.then_some((*self.ordered.get(id)?, *self.triangle.get(id)?, hit.t))
    }
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

/// The BVH plus its triangles in leaf order.
pub struct Accel {
    tree: Tree,
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
        let primitives = |indices: &[u32]| Primitives {
            ordered: indices.iter().map(|&i| tris.get(i as usize).map(RayTriangle::new).unwrap_or_default()).collect(),
            triangle: indices.to_vec(),
        };
        let tree = match kind {
            AccelKind::Cwbvh => {
                let bvh = obvhs::cwbvh::builder::build_cwbvh_from_tris(&tris, params, &mut core);
                Tree::Cw { primitives: primitives(&bvh.primitive_indices), bvh }
            }
            AccelKind::Bvh2 => {
                let bvh = obvhs::bvh2::builder::build_bvh2_from_tris(&tris, params, &mut core);
                Tree::Binary { primitives: primitives(&bvh.primitive_indices), bvh }
            }
            AccelKind::Wide => {
                let bvh = obvhs::bvh2::builder::build_bvh2_from_tris(&tris, params, &mut core);
                match WideBvh::from_bvh2(&bvh) {
                    Some((mut wide, order)) => {
                        let packets = pack_leaves(&mut wide, &tris, &order);
                        Tree::Wide { bvh: wide, packets }
                    }
                    None => Tree::Binary { primitives: primitives(&bvh.primitive_indices), bvh },
                }
            }
        };
        Accel { tree, build_time: start.elapsed() }
    }

    /// Wall time of [`Accel::build`].
    pub fn build_time(&self) -> Duration {
        self.build_time
    }

    /// Closest hit along `origin + t dir`, `t` in `(0, t_max)`; of two triangles at the same
    /// distance, the first the walk meets. On the wide tree a ray with a NaN component or an
    /// infinite origin hits nothing (obvhs' trees debug-assert a finite ray).
    #[inline(always)]
    pub fn closest(&self, origin: Vec3, dir: Vec3, t_max: f32) -> Option<Hit> {
        let (tri, triangle, t) = match &self.tree {
            Tree::Wide { bvh, packets } => {
                let ray = Ray { tmax: t_max, ..unbounded_ray(origin, dir) };
                let mut leaf = ClosestInPackets { packets, ray: &ray, best: None };
                bvh.traverse::<true>(&ray, &mut leaf);
                let best = leaf.best?;
                let p = packets.get(best.packet)?;
                (p.lane(best.lane), *p.triangle.get(best.lane)?, best.t)
            }
            Tree::Cw { bvh, primitives } => {
                let ray = obvhs_ray(origin, dir, t_max);
                let mut hit = RayHit::none();
                let found = bvh.ray_traverse(ray, &mut hit, |r, id| primitives.intersect(r, id));
                primitives.hit(found, &hit)?
            }
            Tree::Binary { bvh, primitives } => {
                let ray = obvhs_ray(origin, dir, t_max);
                let mut hit = RayHit::none();
                let found = bvh.ray_traverse(ray, &mut hit, |r, id| primitives.intersect(r, id));
                primitives.hit(found, &hit)?
            }
        };
        let (b1, b2) = barycentrics(&tri, origin, dir);
        Some(Hit { triangle, t, b1, b2 })
    }

    /// [`Self::closest`] of every ray `(origin, dir)` of `rays` with `t_max = inf`, into
    /// `hits` (pairs past the shorter of the two are left alone). The wide tree walks each
    /// [`PACKET_RAYS`] rays together (one walk, each box test on all of them at once),
    /// which pays off for coherent rays such as one pixel's camera
    /// rays: each ray gets the distance its own walk finds, bit for bit, and the same triangle
    /// except where two tie, which go to the lower-numbered one (not to the first met), so that
    /// the hit does not depend on the packet. (Where a triangle test rounds its distance below
    /// its box's by more than the box test's margin, at grazing incidence, either walk can
    /// miss it depending on the order it culls boxes in, as against a brute-force loop.)
    /// obvhs' trees take the rays one by one, with [`Self::closest`].
    #[inline(always)]
    pub fn closest_packet(&self, rays: &[(Vec3, Vec3)], hits: &mut [Option<Hit>]) {
        let Tree::Wide { bvh, packets } = &self.tree else {
            for (&(o, d), hit) in rays.iter().zip(hits.iter_mut()) {
                *hit = self.closest(o, d, f32::INFINITY);
            }
            return;
        };
        for (rays, hits) in rays.chunks(RAYS).zip(hits.chunks_mut(RAYS)) {
            let n = rays.len().min(hits.len());
            let packet = RayPacket::new(rays.get(..n).unwrap_or_default());
            let mut t_max = [f32::INFINITY; RAYS];
            let mut leaf = ClosestForPacket {
                packets,
                rays: &packet,
                packet: [0; RAYS],
                lane: [0; RAYS],
                triangle: [u32::MAX; RAYS],
            };
            bvh.traverse_packet(&packet, &mut t_max, &mut leaf);
            for (r, (hit, &(o, d))) in hits.iter_mut().zip(rays).enumerate() {
                *hit = None;
                if leaf.triangle[r] != u32::MAX
                    && let Some(p) = packets.get(leaf.packet[r] as usize)
                {
                    let (b1, b2) = barycentrics(&p.lane(leaf.lane[r] as usize), o, d);
                    *hit = Some(Hit { triangle: leaf.triangle[r], t: t_max[r], b1, b2 });
                }
            }
        }
    }

    /// True when nothing blocks `origin + t dir` for `t` in `(0, t_max)` (shadow rays). On the
    /// wide tree a ray with a NaN component or an infinite origin hits nothing, so it is
    /// unoccluded (obvhs' trees debug-assert a finite ray).
    #[inline(always)]
    pub fn unoccluded(&self, origin: Vec3, dir: Vec3, t_max: f32) -> bool {
        match &self.tree {
            Tree::Wide { bvh, packets } => {
                // A literal, not `Ray::new`: its clamped reciprocal is never read (the walk
                // takes the exact one), and it debug-asserts a finite ray.
                let ray = Ray { tmax: t_max, ..unbounded_ray(origin, dir) };
                let mut leaf = AnyInPackets { packets, ray: &ray, hit: false };
                bvh.traverse::<false>(&ray, &mut leaf);
                !leaf.hit
            }
            Tree::Cw { bvh, primitives } => {
                let ray = obvhs_ray(origin, dir, t_max);
                bvh.ray_traverse_miss(ray, |r, id| primitives.intersect(r, id))
            }
            Tree::Binary { bvh, primitives } => {
                let ray = obvhs_ray(origin, dir, t_max);
                bvh.ray_traverse_miss(ray, |r, id| primitives.intersect(r, id))
            }
        }
    }
}

/// The ray `origin + t dir`, `t` in `(0, t_max)`, for obvhs' own walks (`Ray::new`: its clamped
/// reciprocal, and a debug assertion that the ray is finite).
#[inline(always)]
fn obvhs_ray(origin: Vec3, dir: Vec3, t_max: f32) -> Ray {
    Ray::new(origin.into(), dir.into(), 0.0, t_max)
}

/// The ray `origin + t dir`, `t` in `(0, inf)`, as the packet tests read it (obvhs'
/// `inv_direction` is left out: the wide walk takes the exact reciprocal itself).
#[inline(always)]
fn unbounded_ray(origin: Vec3, dir: Vec3) -> Ray {
    Ray { origin: origin.into(), direction: dir.into(), inv_direction: Vec3A::ZERO, tmin: 0.0, tmax: f32::INFINITY }
}

/// The closest hit so far of a walk: packet, lane and distance.
#[derive(Clone, Copy)]
struct Best {
    packet: usize,
    lane: usize,
    t: f32,
}

/// The closest hit among the packets of the leaves a walk visits. Lanes are tried in leaf
/// order and a hit must be strictly nearer, so a tie goes to the first triangle the walk meets.
struct ClosestInPackets<'a> {
    packets: &'a [TrianglePacket],
    ray: &'a Ray,
    best: Option<Best>,
}

impl Leaf for &mut ClosestInPackets<'_> {
    #[inline(always)]
    fn visit(&mut self, first: u32, count: u32, t_max: &mut f32) -> bool {
        for k in first as usize..(first as usize).saturating_add(packet_count(count)) {
            let Some(p) = self.packets.get(k) else { break };
            for (i, &t) in p.intersect(self.ray).iter().enumerate() {
                if t < *t_max {
                    *t_max = t;
                    self.best = Some(Best { packet: k, lane: i, t });
                }
            }
        }
        false
    }
}

/// [`ClosestInPackets`] for each ray of a packet walk: each triangle is tested against all the
/// rays at once and each ray keeps its closest hit (packet, lane and scene triangle, `u32::MAX`
/// for none) in vector lanes. A hit replaces the closest so far when it is nearer, or as near
/// and on a lower-numbered scene triangle: the tie rule makes the answer independent of the
/// order the leaves are visited in, so a ray's hit does not depend on the rays it shares a
/// packet with. (The single-ray walk keeps the first triangle it meets instead: the same rule
/// there measured 3-8 % slower.)
struct ClosestForPacket<'a> {
    packets: &'a [TrianglePacket],
    rays: &'a RayPacket,
    packet: [u32; RAYS],
    lane: [u32; RAYS],
    triangle: [u32; RAYS],
}

impl PacketLeaf for &mut ClosestForPacket<'_> {
    #[inline(always)]
    fn visit(&mut self, first: u32, count: u32, lanes: u32, t_max: &mut [f32; RAYS]) {
        let rays = self.rays;
        for k in first as usize..(first as usize).saturating_add(packet_count(count)) {
            let Some(p) = self.packets.get(k) else { break };
            for (i, &triangle) in p.triangle.iter().enumerate() {
                if triangle == u32::MAX {
                    break; // the packet's unused lanes
                }
                let t = p.intersect_rays(i, &rays.origin, &rays.direction, &rays.tmin, f32::INFINITY);
                for r in 0..RAYS {
                    let live = (lanes >> r) & 1 != 0;
                    let tie = t[r] == t_max[r] && t[r] < f32::INFINITY && triangle < self.triangle[r];
                    if live && (t[r] < t_max[r] || tie) {
                        t_max[r] = t[r];
                        self.packet[r] = k as u32;
                        self.lane[r] = i as u32;
                        self.triangle[r] = triangle;
                    }
                }
            }
        }
    }
}

/// Whether any triangle of the leaves a walk visits is hit (shadow rays): stops at the first.
struct AnyInPackets<'a> {
    packets: &'a [TrianglePacket],
    ray: &'a Ray,
    hit: bool,
}

impl Leaf for &mut AnyInPackets<'_> {
    #[inline(always)]
    fn visit(&mut self, first: u32, count: u32, t_max: &mut f32) -> bool {
        // Plain loops: iterator adapters such as `any` stay calls compiled for the baseline ISA.
        for k in first as usize..(first as usize).saturating_add(packet_count(count)) {
            let Some(p) = self.packets.get(k) else { break };
            let mut hit = false;
            for t in p.intersect(self.ray) {
                hit |= t < *t_max;
            }
            if hit {
                self.hit = true;
                return true;
            }
        }
        false
    }
}

/// Packets a leaf of `count` triangles spans.
#[inline(always)]
fn packet_count(count: u32) -> usize {
    (count as usize).div_ceil(PACKET_WIDTH)
}

/// Packs each leaf of `wide` (triangles `first..first + count` of `indices`, the leaf order
/// [`WideBvh::from_bvh2`] returned) into consecutive [`TrianglePacket`]s and points the leaf
/// at its first.
fn pack_leaves(wide: &mut WideBvh, tris: &[BvhTriangle], indices: &[u32]) -> Vec<TrianglePacket> {
    let mut packets = Vec::new();
    wide.remap_leaves(|first, count| {
        let at = packets.len() as u32;
        let range = first as usize..(first as usize).saturating_add(count as usize);
        for chunk in indices.get(range).unwrap_or_default().chunks(PACKET_WIDTH) {
            let lanes = chunk.iter().map(|&i| (tris.get(i as usize).map(RayTriangle::new).unwrap_or_default(), i));
            packets.push(TrianglePacket::new(lanes));
        }
        at
    });
    packets
}

/// Barycentrics `(b1, b2)` of the ray's intersection with the triangle's plane, Moller &
/// Trumbore 1997: `b1 = (s . p) / det`, `b2 = (d . q) / det` with `p = d x e2`, `q = s x e1`.
/// (`v1 - v0` is `-(v0 - v1)` exactly: rounding to nearest is symmetric.)
#[inline(always)]
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
