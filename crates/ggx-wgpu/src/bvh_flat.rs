//! obvhs's [`Bvh2`] flattened into GPU records: 32-byte [`BvhNode`]s and the scene's triangles
//! in leaf order, plus a CPU traversal that does exactly what `path_tracer.wgsl` does.

use bytemuck::{Pod, Zeroable};
use ggx_scene::Triangle;
use glam::{Vec3, Vec3A};
use obvhs::BvhBuildParams;
use obvhs::aabb::Aabb;
use obvhs::bvh2::Bvh2;
use obvhs::ray::Ray;
use obvhs::triangle::Triangle as BvhTriangle;

/// Depth of the traversal stack in `path_tracer.wgsl` (`STACK_SIZE`); deeper trees are refused.
pub const STACK_SIZE: usize = 64;

/// One BVH2 node, WGSL `BvhNode { min: vec3<f32>, prim_count: u32, max: vec3<f32>, first_index: u32 }`.
/// `prim_count == 0`: inner node, children at `first_index` and `first_index + 1`; otherwise a
/// leaf whose triangles are `first_index .. first_index + prim_count` of [`FlatBvh::triangles`].
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct BvhNode {
    /// Bounding box minimum.
    pub min: [f32; 3],
    /// Triangles in the leaf, 0 for an inner node.
    pub prim_count: u32,
    /// Bounding box maximum.
    pub max: [f32; 3],
    /// First child (inner node) or first triangle (leaf).
    pub first_index: u32,
}

/// The node list of a scene without triangles. A real tree's children never start at index 0
/// (the root's slot), so an inner node pointing there cannot occur otherwise: the traversal,
/// here and in `scene.wgsl`, tests for it first and returns "no hit" without reading a box
/// or a child (a box test alone would hit its `[-1, 1]^3` and read `nodes[1]`, past the end).
pub const EMPTY_TREE: BvhNode = BvhNode { min: [1.0; 3], prim_count: 0, max: [-1.0; 3], first_index: 0 };

/// Whether `root` is [`EMPTY_TREE`]'s root (an inner node whose children would be itself).
pub fn is_empty_tree(root: &BvhNode) -> bool {
    root.prim_count == 0 && root.first_index == 0
}

/// A closest hit in the flattened BVH.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlatHit {
    /// Index into [`FlatBvh::triangles`] (leaf order).
    pub primitive: u32,
    /// Ray parameter.
    pub t: f32,
}

/// The flattened tree and the triangles it indexes.
#[derive(Clone, Debug, Default)]
pub struct FlatBvh {
    /// Nodes, root first.
    pub nodes: Vec<BvhNode>,
    /// Scene triangles in leaf order (a triangle split by the builder appears more than once).
    pub triangles: Vec<Triangle>,
    /// Scene index of each entry of `triangles`.
    pub primitive_to_triangle: Vec<u32>,
    /// Longest root-to-leaf path, in edges.
    pub depth: usize,
}

impl FlatBvh {
    /// Builds obvhs's BVH2 with the "medium" preset, the parameters of ggx-cpu's `Accel` (the test
    /// `flat_traversal_finds_the_closest_hits_of_ggx_cpu` holds them equal), and flattens it.
    pub fn build(triangles: &[Triangle]) -> FlatBvh {
        let tris: Vec<BvhTriangle> = triangles
            .iter()
            .map(|t| BvhTriangle { v0: Vec3A::from(t.v0), v1: Vec3A::from(t.v1), v2: Vec3A::from(t.v2) })
            .collect();
        if tris.is_empty() {
            return FlatBvh::default();
        }
        let mut core = std::time::Duration::ZERO;
        let bvh: Bvh2 = obvhs::bvh2::builder::build_bvh2_from_tris(&tris, BvhBuildParams::medium_build(), &mut core);
        let nodes: Vec<BvhNode> = bvh
            .nodes
            .iter()
            .map(|n| BvhNode {
                min: n.aabb().min.to_array(),
                prim_count: n.prim_count,
                max: n.aabb().max.to_array(),
                first_index: n.first_index,
            })
            .collect();
        let ordered =
            bvh.primitive_indices.iter().map(|&i| triangles.get(i as usize).copied().unwrap_or(ZERO_TRIANGLE));
        let depth = tree_depth(&nodes);
        FlatBvh { nodes, triangles: ordered.collect(), primitive_to_triangle: bvh.primitive_indices, depth }
    }

    /// Closest hit along `origin + t dir`, `t` in `[0, t_max]`: obvhs's `ray_traverse` on the flat nodes.
    pub fn closest(&self, origin: Vec3, dir: Vec3, t_max: f32) -> Option<FlatHit> {
        let mut ray = Ray::new(origin.into(), dir.into(), 0.0, t_max);
        let mut hit = None;
        self.traverse(&mut ray, &mut |prim, t, ray| {
            if t < ray.tmax {
                hit = Some(FlatHit { primitive: prim, t });
                ray.tmax = t;
            }
            true
        });
        hit
    }

    /// True when nothing blocks `origin + t dir` for `t` in `[0, t_max]`.
    pub fn unoccluded(&self, origin: Vec3, dir: Vec3, t_max: f32) -> bool {
        let mut ray = Ray::new(origin.into(), dir.into(), 0.0, t_max);
        let mut miss = true;
        self.traverse(&mut ray, &mut |_, t, ray| {
            if t < ray.tmax {
                miss = false;
            }
            miss
        });
        miss
    }

    fn intersect(&self, prim: u32, ray: &Ray) -> f32 {
        self.triangles.get(prim as usize).map_or(f32::INFINITY, |t| {
            BvhTriangle { v0: Vec3A::from(t.v0), v1: Vec3A::from(t.v1), v2: Vec3A::from(t.v2) }.intersect(ray)
        })
    }

    /// Walks the tree like `Bvh2::ray_traverse_dynamic`: nearer child first, leaves tested as
    /// soon as they are reached; `visit(primitive, t, ray)` returns false to stop.
    fn traverse(&self, ray: &mut Ray, visit: &mut dyn FnMut(u32, f32, &mut Ray) -> bool) {
        let Some(root) = self.nodes.first() else { return };
        if is_empty_tree(root) {
            return;
        }
        let box_t = |n: &BvhNode, ray: &Ray| Aabb { min: n.min.into(), max: n.max.into() }.intersect_ray(ray);
        let mut leaf = |n: &BvhNode, ray: &mut Ray| {
            (n.first_index..n.first_index + n.prim_count).all(|p| visit(p, self.intersect(p, ray), ray))
        };
        if box_t(root, ray) >= ray.tmax {
            return;
        }
        if root.prim_count > 0 {
            leaf(root, ray);
            return;
        }
        let mut stack: Vec<u32> = Vec::with_capacity(STACK_SIZE);
        let mut current = root.first_index;
        loop {
            let (Some(mut left), Some(mut right)) =
                (self.nodes.get(current as usize), self.nodes.get(current as usize + 1))
            else {
                return;
            };
            let (mut left_t, mut right_t) = (box_t(left, ray), box_t(right, ray));
            if left_t > right_t {
                std::mem::swap(&mut left_t, &mut right_t);
                std::mem::swap(&mut left, &mut right);
            }
            let hit_left = left_t < ray.tmax;
            let go_left = if hit_left && left.prim_count > 0 {
                if !leaf(left, ray) {
                    return;
                }
                false
            } else {
                hit_left
            };
            let hit_right = right_t < ray.tmax;
            let go_right = if hit_right && right.prim_count > 0 {
                if !leaf(right, ray) {
                    return;
                }
                false
            } else {
                hit_right
            };
            current = match (go_left, go_right) {
                (true, true) => {
                    stack.push(right.first_index);
                    left.first_index
                }
                (true, false) => left.first_index,
                (false, true) => right.first_index,
                (false, false) => match stack.pop() {
                    Some(next) => next,
                    None => return,
                },
            };
        }
    }
}

const ZERO_TRIANGLE: Triangle =
    Triangle { v0: [0.0; 3], material: 0, v1: [0.0; 3], normals: u32::MAX, v2: [0.0; 3], emitter: u32::MAX };

/// Longest root-to-leaf path of a tree whose inner nodes point at child pairs.
fn tree_depth(nodes: &[BvhNode]) -> usize {
    let mut deepest = 0;
    let mut todo = vec![(0usize, 0usize)];
    while let Some((i, d)) = todo.pop() {
        let Some(n) = nodes.get(i) else { continue };
        deepest = deepest.max(d);
        if n.prim_count == 0 {
            todo.push((n.first_index as usize, d + 1));
            todo.push((n.first_index as usize + 1, d + 1));
        }
    }
    deepest
}

#[cfg(test)]
mod tests {
    use super::*;
    use ggx_core::SampleStream;
    use ggx_cpu::{Accel, AccelKind};

    /// Random rays from inside and outside the scene's bounds, through random points of it.
    fn rays(scene: &ggx_scene::Scene, count: u32) -> Vec<(Vec3, Vec3)> {
        let (lo, hi) = scene.mesh.bounds().unwrap_or((Vec3::ZERO, Vec3::ONE));
        let point = |s: &mut SampleStream, scale: f32| {
            let (a, b) = (s.next_2d(), s.next_1d());
            let c = (lo + hi) * 0.5;
            c + (Vec3::new(a.x, a.y, b) - 0.5) * (hi - lo) * scale
        };
        (0..count)
            .map(|i| {
                let mut s = SampleStream::new(ggx_core::SequenceKind::Independent, 7, i, 0);
                let o = point(&mut s, 2.0);
                let dir = (point(&mut s, 1.0) - o).normalize_or(Vec3::Y);
                (o, dir)
            })
            .collect()
    }

    #[test]
    fn the_empty_tree_is_recognised_and_no_real_root_looks_like_it() {
        assert!(is_empty_tree(&EMPTY_TREE));
        let flat = FlatBvh { nodes: vec![EMPTY_TREE], ..FlatBvh::default() };
        // Through the placeholder's [-1, 1]^3 box: no hit, and no read past the one node.
        assert_eq!(flat.closest(Vec3::new(0.0, 0.0, -5.0), Vec3::Z, f32::INFINITY), None);
        assert!(flat.unoccluded(Vec3::ZERO, Vec3::X, 1e3));
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
        for name in ["cornell.toml", "three-spheres.toml"] {
            let scene = ggx_scene::load_scene(&dir.join(name)).unwrap();
            let flat = FlatBvh::build(&scene.mesh.triangles);
            assert!(!is_empty_tree(&flat.nodes[0]), "{name}");
            assert!(flat.nodes.iter().skip(1).all(|n| n.prim_count > 0 || n.first_index > 0), "{name}");
        }
    }

    #[test]
    fn flat_traversal_finds_the_closest_hits_of_ggx_cpu() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
        for name in ["cornell.toml", "three-spheres.toml", "bunny.toml"] {
            let scene = ggx_scene::load_scene(&dir.join(name)).unwrap();
            let flat = FlatBvh::build(&scene.mesh.triangles);
            assert!(flat.depth <= STACK_SIZE, "{name}: depth {}", flat.depth);
            let bvh2 = Accel::build(&scene.mesh.triangles, AccelKind::Bvh2);
            let cw = Accel::build(&scene.mesh.triangles, AccelKind::Cwbvh);
            let (mut hits, mut same_as_cw) = (0, 0);
            for (o, d) in rays(&scene, 4000) {
                let ours = flat.closest(o, d, f32::INFINITY);
                let reference = bvh2.closest(o, d, f32::INFINITY);
                let ours_scene = ours.map(|h| (flat.primitive_to_triangle[h.primitive as usize], h.t));
                assert_eq!(ours_scene, reference.map(|h| (h.triangle, h.t)), "{name}: ray {o} {d}");
                assert_eq!(flat.unoccluded(o, d, 1e3), bvh2.unoccluded(o, d, 1e3), "{name}: shadow ray {o} {d}");
                if let Some((tri, t)) = ours_scene {
                    hits += 1;
                    let c = cw.closest(o, d, f32::INFINITY);
                    same_as_cw +=
                        u32::from(c.is_some_and(|c| c.triangle == tri && (c.t - t).abs() <= 1e-5 * t.max(1.0)));
                }
            }
            assert!(hits > 1000, "{name}: only {hits} rays hit");
            // The CWBVH tests triangles in another order and with its own box slack: equal t on a
            // shared edge may resolve to either triangle, and hits at t ~ 1e-4 of rays starting on
            // a surface may differ.
            assert!(same_as_cw * 100 >= hits * 99, "{name}: {same_as_cw} of {hits} hits agree with the CWBVH");
        }
    }
}
