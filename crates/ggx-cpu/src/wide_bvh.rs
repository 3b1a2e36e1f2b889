//! [`WideBvh`]: obvhs' binary BVH collapsed into 8-wide nodes for the CPU. Each node keeps its
//! children's boxes uncompressed, as `f32` structure-of-arrays, so one ray tests all eight in a
//! loop that LLVM vectorizes (no decoding of quantized boxes, as the CWBVH must do), and the
//! walk visits the nearer children first (Wald et al. 2008, "Getting rid of packets"; Embree's
//! BVH8).

use obvhs::bvh2::Bvh2;
use obvhs::ray::Ray;

/// Children per node.
const WIDTH: usize = 8;

/// Entries of the traversal stack (1.5 KiB, one per thread, reused by every ray: zeroing it per
/// ray cost 5 % of a render). A node pushes at most `WIDTH - 1` entries more than it pops, so
/// trees up to [`MAX_DEPTH`] levels fit; a deeper tree is refused at build time.
const STACK_SIZE: usize = 192;

/// A traversal stack: `(node, distance to its box)`.
type Stack = [(u32, f32); STACK_SIZE];

std::thread_local! {
    static STACK: core::cell::RefCell<Stack> = const { core::cell::RefCell::new([(0, 0.0); STACK_SIZE]) };
    /// The packet walk's stack, reused the same way (2.3 KiB: zeroing one per camera packet was
    /// the `memset` of 0.9 % of a three-spheres profile).
    static PACKET_STACK: core::cell::RefCell<PacketStack> =
        const { core::cell::RefCell::new([(0, 0.0, 0); STACK_SIZE]) };
}

/// Runs `walk` on this thread's stack in `key`, or on a fresh one from `empty` (built only
/// then) when that stack is in use (a walk started from inside another's leaf callback). A walk
/// reads only the entries it wrote, so what an earlier walk left on the thread's stack does not
/// matter.
#[inline(always)]
fn with_stack<S: 'static, R>(
    key: &'static std::thread::LocalKey<core::cell::RefCell<S>>,
    empty: impl FnOnce() -> S,
    walk: impl FnOnce(&mut S) -> R,
) -> R {
    key.with(|cell| match cell.try_borrow_mut() {
        Ok(mut stack) => walk(&mut stack),
        Err(_) => walk(&mut empty()),
    })
}

/// Deepest tree the stack holds: `(WIDTH - 1) * MAX_DEPTH + 1 <= STACK_SIZE`.
const MAX_DEPTH: usize = (STACK_SIZE - 1) / (WIDTH - 1);

/// Rays a packet walk carries ([`WideBvh::traverse_packet`]): one AVX-512 register of `f32`
/// per quantity.
pub(crate) const RAYS: usize = 16;

/// Up to [`RAYS`] rays walked through the tree together, as structure of arrays: the slab test
/// of one child box runs on every ray at once. Lane `r` takes part when bit `r` of `live` is set.
pub(crate) struct RayPacket {
    /// Origins, `origin[axis][lane]`.
    pub(crate) origin: [[f32; RAYS]; 3],
    /// Directions, `direction[axis][lane]` (for the leaf tests).
    pub(crate) direction: [[f32; RAYS]; 3],
    /// Exact reciprocals of the directions (infinite for a zero component), as in [`WideBvh::walk`].
    inv: [[f32; RAYS]; 3],
    /// Sign bits of `inv`: where set, the box's `hi` plane is the near one.
    neg: [[bool; RAYS]; 3],
    /// Each ray's `tmin`.
    pub(crate) tmin: [f32; RAYS],
    /// Lanes that hold a ray the walk can hit something with.
    live: u32,
}

impl RayPacket {
    /// The packet of `rays`, `(origin, direction)` with `tmin = 0` (the first [`RAYS`]; the lanes
    /// past them are dead). A ray with a NaN component or an infinite origin is dead too: it
    /// hits nothing, as in [`WideBvh::traverse`].
    #[inline(always)]
    pub(crate) fn new(rays: &[(glam::Vec3, glam::Vec3)]) -> RayPacket {
        let mut p = RayPacket {
            origin: [[0.0; RAYS]; 3],
            direction: [[0.0; RAYS]; 3],
            inv: [[0.0; RAYS]; 3],
            neg: [[false; RAYS]; 3],
            tmin: [0.0; RAYS],
            live: 0,
        };
        for (r, &(origin, direction)) in rays.iter().take(RAYS).enumerate() {
            if !origin.is_finite() || direction.is_nan() {
                continue;
            }
            let (o, d, inv) = (origin.to_array(), direction.to_array(), direction.recip().to_array());
            for a in 0..3 {
                p.origin[a][r] = o[a];
                p.direction[a][r] = d[a];
                p.inv[a][r] = inv[a];
                p.neg[a][r] = inv[a].is_sign_negative();
            }
            p.live |= 1 << r;
        }
        p
    }
}

/// What a packet walk does at a leaf: `visit(first, count, lanes, t_max)` tests the leaf's
/// primitives for the rays of `lanes` (those whose own slab test entered the leaf's box) and
/// lowers their `t_max[lane]` to nearer hits (closest-hit queries only).
pub(crate) trait PacketLeaf {
    /// Tests the leaf `first` of `count` primitives for the rays `lanes`.
    fn visit(&mut self, first: u32, count: u32, lanes: u32, t_max: &mut [f32; RAYS]);
}

/// A packet walk's stack entry: `(node, nearest entry distance over its rays, rays that entered its box)`.
type PacketStack = [(u32, f32, u32); STACK_SIZE];

/// `1 + 2 gamma(3)` (pbrt-v4, 6.8.2): the far distance of a box is scaled by it so that the
/// slab test's own rounding does not cull a box the ray enters (Ize 2013). (A triangle test
/// that rounds its `t` further, at grazing incidence, can still fall outside; obvhs' trees have
/// no margin at all.)
const FAR_SCALE: f32 = 1.0 + 2.0 * (3.0 * f32::EPSILON * 0.5) / (1.0 - 3.0 * f32::EPSILON * 0.5);

/// Eight children: boxes as `lo[axis][lane]`, `hi[axis][lane]`; `count[lane] > 0` marks a leaf
/// of `count` primitives starting at `index[lane]`, `count == 0` an inner node `index[lane]`. An
/// unused lane has the empty box `lo = +inf, hi = -inf`, which no ray enters.
#[derive(Clone, Copy)]
#[repr(C, align(64))]
struct WideNode {
    lo: [[f32; WIDTH]; 3],
    hi: [[f32; WIDTH]; 3],
    index: [u32; WIDTH],
    count: [u32; WIDTH],
}

impl WideNode {
    const EMPTY: WideNode = WideNode {
        lo: [[f32::INFINITY; WIDTH]; 3],
        hi: [[f32::NEG_INFINITY; WIDTH]; 3],
        index: [0; WIDTH],
        count: [0; WIDTH],
    };

    /// Slab test of the eight boxes (Kay & Kajiya 1986, near and far planes chosen by the
    /// direction's signs): bit `i` of the mask is set when `max(t_near, t_min) <= min(t_far,
    /// t_max) * FAR_SCALE` for lane `i`; `t_near[i]` is returned for ordering. A NaN slab distance
    /// (a ray lying in a box's face plane) leaves that axis unconstrained.
    #[inline(always)]
    fn intersect(&self, ray: &Ray, inv: [f32; 3], neg: [bool; 3], t_max: f32) -> (u32, [f32; WIDTH]) {
        let o = ray.origin.to_array();
        let mut t_near = [0.0f32; WIDTH];
        let mut t_far = [0.0f32; WIDTH];
        let plane = |a: usize| if neg[a] { (&self.hi[a], &self.lo[a]) } else { (&self.lo[a], &self.hi[a]) };
        let ((nx, fx), (ny, fy), (nz, fz)) = (plane(0), plane(1), plane(2));
        for i in 0..WIDTH {
            let (near, far) = ([nx[i], ny[i], nz[i]], [fx[i], fy[i], fz[i]]);
            (t_near[i], t_far[i]) = slab_interval(near, far, o, inv, ray.tmin, t_max);
        }
        let mut mask = 0u32;
        for i in 0..WIDTH {
            mask |= u32::from(t_near[i] <= t_far[i]) << i;
        }
        (mask, t_near)
    }

    /// [`Self::intersect`] of each of the eight boxes with every ray of `lanes` at once:
    /// `masks[i]` holds the rays whose slab test enters box `i` (each ray's test the single
    /// walk's, with the same operations and so the same bits), `nearest[i]` the smallest
    /// `t_near` among them (infinite when none), for ordering.
    #[inline(always)]
    fn intersect_packet(&self, p: &RayPacket, t_max: &[f32; RAYS], lanes: u32) -> ([u32; WIDTH], [f32; WIDTH]) {
        let mut masks = [0u32; WIDTH];
        let mut nearest = [f32::INFINITY; WIDTH];
        for i in 0..WIDTH {
            let lo = [self.lo[0][i], self.lo[1][i], self.lo[2][i]];
            let hi = [self.hi[0][i], self.hi[1][i], self.hi[2][i]];
            let mut entry = [f32::INFINITY; RAYS];
            let mut enters = [false; RAYS];
            for r in 0..RAYS {
                // This ray's near and far planes, by its direction's signs.
                let plane = |a: usize| if p.neg[a][r] { (hi[a], lo[a]) } else { (lo[a], hi[a]) };
                let ((nx, fx), (ny, fy), (nz, fz)) = (plane(0), plane(1), plane(2));
                let ray = |m: &[[f32; RAYS]; 3]| [m[0][r], m[1][r], m[2][r]];
                let (o, inv) = (ray(&p.origin), ray(&p.inv));
                let (t_near, t_far) = slab_interval([nx, ny, nz], [fx, fy, fz], o, inv, p.tmin[r], t_max[r]);
                enters[r] = t_near <= t_far && (lanes >> r) & 1 != 0;
                entry[r] = if enters[r] { t_near } else { f32::INFINITY };
            }
            // Reductions by halves, which vectorize: OR of each ray's bit; the smallest entry
            // (never NaN: a ray that enters has a `t_near <= t_far`, the others infinity; so the
            // order does not matter).
            let mut bits = [0u32; RAYS];
            for r in 0..RAYS {
                bits[r] = u32::from(enters[r]) << r;
            }
            let mut width = RAYS / 2;
            while width > 0 {
                for r in 0..width {
                    bits[r] |= bits[r + width];
                    entry[r] = min_or_b(entry[r + width], entry[r]);
                }
                width /= 2;
            }
            masks[i] = bits[0];
            nearest[i] = entry[0];
        }
        (masks, nearest)
    }
}

/// One ray's interval through one box, given the box's `near` and `far` planes on each axis
/// (Kay & Kajiya 1986): `(max(t_near, tmin), min(t_far, t_max) * FAR_SCALE)`, which overlap
/// when the ray enters the box; a NaN slab distance (a ray lying in a face plane) leaves its
/// axis unconstrained. The single and the packet walk both call it: the same bits per ray.
#[inline(always)]
fn slab_interval(near: [f32; 3], far: [f32; 3], o: [f32; 3], inv: [f32; 3], tmin: f32, t_max: f32) -> (f32, f32) {
    let (ax, bx) = ((near[0] - o[0]) * inv[0], (far[0] - o[0]) * inv[0]);
    let (ay, by) = ((near[1] - o[1]) * inv[1], (far[1] - o[1]) * inv[1]);
    let (az, bz) = ((near[2] - o[2]) * inv[2], (far[2] - o[2]) * inv[2]);
    let t_near = max_or_b(ax, max_or_b(ay, max_or_b(az, tmin)));
    let t_far = min_or_b(bx, min_or_b(by, min_or_b(bz, t_max))) * FAR_SCALE;
    (t_near, t_far)
}

/// `a > b ? a : b` (`maxps`): `b` when `a` is NaN.
#[inline(always)]
fn max_or_b(a: f32, b: f32) -> f32 {
    if a > b { a } else { b }
}

/// `a < b ? a : b` (`minps`): `b` when `a` is NaN.
#[inline(always)]
fn min_or_b(a: f32, b: f32) -> f32 {
    if a < b { a } else { b }
}

/// The 8-wide tree; a leaf `(first, count)` indexes the primitive order that
/// [`WideBvh::from_bvh2`] returns with it (or what [`WideBvh::remap_leaves`] made it).
pub(crate) struct WideBvh {
    /// Root first; empty for a tree without primitives.
    nodes: Vec<WideNode>,
    /// The widest vector ISA of this CPU (`pulp`'s detection, once): the walk and the leaf
    /// tests are compiled for it (AVX2 tests the eight boxes in one register). Every ISA gives
    /// the same bits: Rust never contracts into fused multiply-adds.
    arch: pulp::Arch,
}

/// What a walk does at a leaf: `visit(first, count, t_max)` tests the leaf's primitives
/// (`first` is the leaf's index: the position of its first primitive in the order
/// [`WideBvh::from_bvh2`] returns, or what [`WideBvh::remap_leaves`] made it), lowers `t_max`
/// to a nearer hit and returns true to stop the walk (an any-hit query).
/// A closure is one; a type whose `visit` is `#[inline(always)]` is compiled into the walk
/// for the walk's vector ISA, where a closure's body may stay a call compiled for the
/// baseline one.
pub(crate) trait Leaf {
    /// Tests the leaf `first` of `count` primitives.
    fn visit(&mut self, first: u32, count: u32, t_max: &mut f32) -> bool;
}

impl<F: FnMut(u32, u32, &mut f32) -> bool> Leaf for F {
    #[inline(always)]
    fn visit(&mut self, first: u32, count: u32, t_max: &mut f32) -> bool {
        self(first, count, t_max)
    }
}

/// A walk's arguments, for `pulp`'s dispatch.
struct Walk<'a, const ORDERED: bool, F> {
    bvh: &'a WideBvh,
    ray: &'a Ray,
    stack: &'a mut Stack,
    leaf: F,
}

impl<const ORDERED: bool, F: Leaf> pulp::WithSimd for Walk<'_, ORDERED, F> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) {
        self.bvh.walk::<ORDERED>(self.ray, self.stack, self.leaf)
    }
}

/// A packet walk's arguments, for `pulp`'s dispatch.
struct PacketWalk<'a, F> {
    bvh: &'a WideBvh,
    rays: &'a RayPacket,
    t_max: &'a mut [f32; RAYS],
    stack: &'a mut PacketStack,
    leaf: F,
}

impl<F: PacketLeaf> pulp::WithSimd for PacketWalk<'_, F> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) {
        self.bvh.walk_packet(self.rays, self.t_max, self.stack, self.leaf)
    }
}

impl WideBvh {
    /// Collapses `bvh` (Wald et al. 2008's top-down collapse): each wide node takes its binary
    /// node's two children, then keeps opening the inner child of largest surface area until it
    /// holds eight children or only leaves. A binary subtree of at most [`LEAF_PRIMITIVES`]
    /// primitives counts as a leaf; while a node has lanes to spare, it opens such subtrees too,
    /// largest first, so small leaves fill lanes that would stay empty (obvhs' leaves of about
    /// four primitives left half of each eight-wide triangle packet and half of each node's
    /// lanes unused). Returns the tree and the primitives in leaf order (entries of
    /// `bvh.primitive_indices`): leaf `(first, count)` holds `order[first..first + count]`.
    /// `None` when the result is deeper than [`MAX_DEPTH`] or `bvh` is malformed in a way the
    /// collapse meets (a child index or a leaf's primitive range out of bounds, a cycle): the
    /// caller then keeps `bvh`.
    pub(crate) fn from_bvh2(bvh: &Bvh2) -> Option<(WideBvh, Vec<u32>)> {
        let arch = pulp::Arch::new();
        let mut order = Vec::new();
        let Some(root) = bvh.nodes.first() else { return Some((WideBvh { nodes: Vec::new(), arch }, order)) };
        if bvh.primitive_indices.is_empty() {
            return Some((WideBvh { nodes: Vec::new(), arch }, order));
        }
        // A node that stays a leaf: a binary leaf or a small subtree.
        let is_leaf = |k: usize| bvh.nodes[k].prim_count > 0 || subtree_primitives(bvh, k, None).is_some();
        let mut nodes = vec![WideNode::EMPTY];
        if is_leaf(0) {
            let count = push_leaf(bvh, 0, &mut order)?;
            set_lane(&mut nodes[0], 0, root, 0, count);
            return Some((WideBvh { nodes, arch }, order));
        }
        // (binary node, wide node it becomes, depth); each binary node is opened at most once.
        let mut todo = vec![(0usize, 0usize, 1usize)];
        let mut opened = 0usize;
        while let Some((b, w, depth)) = todo.pop() {
            if depth > MAX_DEPTH {
                return None;
            }
            let mut kids: Vec<usize> = children(bvh, b)?.to_vec();
            opened += 1;
            while kids.len() < WIDTH {
                // The largest child too big for a leaf; else, while lanes are free, the largest
                // small subtree (smaller leaves in lanes that would stay empty: the node's box
                // test is paid anyway, and a ray then tests only the leaves it enters).
                let largest = |open: &dyn Fn(usize) -> bool| {
                    kids.iter()
                        .enumerate()
                        .filter(|&(_, &k)| open(k))
                        .max_by(|a, b| half_area(bvh, *a.1).total_cmp(&half_area(bvh, *b.1)))
                        .map(|(j, &k)| (j, k))
                };
                let inner = largest(&|k| !is_leaf(k)).or_else(|| largest(&|k| bvh.nodes[k].prim_count == 0));
                let Some((j, k)) = inner else { break };
                let [c0, c1] = children(bvh, k)?;
                opened += 1;
                kids[j] = c0;
                kids.push(c1);
            }
            if opened > bvh.nodes.len() {
                return None;
            }
            for (lane, &k) in kids.iter().enumerate() {
                let child = &bvh.nodes[k];
                if is_leaf(k) {
                    let first = u32::try_from(order.len()).ok()?;
                    let count = push_leaf(bvh, k, &mut order)?;
                    set_lane(&mut nodes[w], lane, child, first, count);
                } else {
                    let id = nodes.len();
                    nodes.push(WideNode::EMPTY);
                    set_lane(&mut nodes[w], lane, child, u32::try_from(id).ok()?, 0);
                    todo.push((k, id, depth + 1));
                }
            }
        }
        Some((WideBvh { nodes, arch }, order))
    }

    /// Replaces the index of every leaf lane (its first primitive's position in the leaf order)
    /// by `f(first, count)`, in node order: lets the caller lay the leaves' primitives out as
    /// it tests them.
    pub(crate) fn remap_leaves(&mut self, mut f: impl FnMut(u32, u32) -> u32) {
        for node in &mut self.nodes {
            for lane in 0..WIDTH {
                if node.count[lane] > 0 {
                    node.index[lane] = f(node.index[lane], node.count[lane]);
                }
            }
        }
    }

    /// Walks the tree for `ray` (`ray.tmax` is the initial limit). `leaf.visit(first, count, t_max)`
    /// tests a leaf's primitives, lowers `t_max` to a nearer hit and returns true to stop the walk
    /// (an any-hit query); `ORDERED`: visit nearer children first (closest-hit queries).
    #[inline(always)]
    pub(crate) fn traverse<const ORDERED: bool>(&self, ray: &Ray, leaf: impl Leaf) {
        // A ray with a NaN component, or an infinite origin, hits nothing.
        if self.nodes.is_empty() || !ray.origin.is_finite() || ray.direction.is_nan() {
            return;
        }
        with_stack(
            &STACK,
            || [(0, 0.0); STACK_SIZE],
            |stack| self.arch.dispatch(Walk::<ORDERED, _> { bvh: self, ray, stack, leaf }),
        )
    }

    /// [`Self::traverse`] with its stack. The slab test uses the exact reciprocal of the
    /// direction (infinite for a zero component), not obvhs' clamped `inv_direction`, which
    /// shortens the slabs of near-axis-parallel rays.
    #[inline(always)]
    fn walk<const ORDERED: bool>(&self, ray: &Ray, stack: &mut Stack, mut leaf: impl Leaf) {
        let inv = ray.direction.recip().to_array();
        // The sign bit, so that -0.0 (reciprocal -inf) takes the mirrored planes.
        let neg = inv.map(|x| x.is_sign_negative());
        let mut t_max = ray.tmax;
        let mut len = 0usize;
        let mut node = 0usize;
        loop {
            let Some(n) = self.nodes.get(node) else { return };
            let (mask, t_near) = n.intersect(ray, inv, neg, t_max);
            let base = len;
            let mut m = mask;
            while m != 0 {
                let i = m.trailing_zeros() as usize;
                m &= m - 1;
                if n.count[i] > 0 {
                    if leaf.visit(n.index[i], n.count[i], &mut t_max) {
                        return;
                    }
                } else if len < STACK_SIZE && n.index[i] as usize > node {
                    // Children come after their parent, so the walk always ends, whatever lane a
                    // degenerate ray enters (an unused lane's index 0 is the root).
                    stack[len] = (n.index[i], t_near[i]);
                    len += 1;
                }
            }
            if ORDERED {
                sort_pushes(&mut stack[..len], base, |e| e.1);
            }
            // Pop the next child that a nearer hit has not culled.
            loop {
                if len == 0 {
                    return;
                }
                len -= 1;
                let (next, t) = stack[len];
                if t <= t_max * FAR_SCALE {
                    node = next as usize;
                    break;
                }
            }
        }
    }

    /// Walks the tree once for all the rays of `rays` (closest-hit queries; `t_max[lane]` is
    /// each ray's initial limit, lowered by `leaf` as it finds hits): a node is opened when any
    /// live ray enters its box, and each leaf is visited with the rays that entered it: every
    /// ray tests the leaves it enters within its limit at the time, as in its own
    /// [`Self::traverse`], in another order (so a leaf culled by a hit found earlier can differ,
    /// which changes nothing but ties and rounding below the box margin). The
    /// children are visited nearest first by their nearest ray's entry. Coherent rays (one
    /// pixel's camera rays) share most of their nodes, so the walk's bookkeeping is paid once
    /// for the packet, and each box test runs on 16 rays in one AVX-512 instruction.
    #[inline(always)]
    pub(crate) fn traverse_packet(&self, rays: &RayPacket, t_max: &mut [f32; RAYS], leaf: impl PacketLeaf) {
        if self.nodes.is_empty() || rays.live == 0 {
            return;
        }
        with_stack(
            &PACKET_STACK,
            || [(0, 0.0, 0); STACK_SIZE],
            |stack| self.arch.dispatch(PacketWalk { bvh: self, rays, t_max, stack, leaf }),
        )
    }

    /// [`Self::traverse_packet`] with its stack (12 bytes an entry; see [`with_stack`]).
    #[inline(always)]
    fn walk_packet(&self, p: &RayPacket, t_max: &mut [f32; RAYS], stack: &mut PacketStack, mut leaf: impl PacketLeaf) {
        let mut len = 0usize;
        let (mut node, mut lanes) = (0usize, p.live);
        loop {
            let Some(n) = self.nodes.get(node) else { return };
            let (masks, nearest) = n.intersect_packet(p, t_max, lanes);
            let base = len;
            for i in 0..WIDTH {
                let m = masks[i];
                if m == 0 {
                    continue;
                }
                if n.count[i] > 0 {
                    leaf.visit(n.index[i], n.count[i], m, t_max);
                } else if len < STACK_SIZE && n.index[i] as usize > node {
                    // Children come after their parent (see `walk`).
                    stack[len] = (n.index[i], nearest[i], m);
                    len += 1;
                }
            }
            sort_pushes(&mut stack[..len], base, |e| e.1);
            // Pop the next child that some ray still needs: one whose nearest entry is within
            // that ray's (lowered) limit.
            loop {
                if len == 0 {
                    return;
                }
                len -= 1;
                let (next, t, m) = stack[len];
                let mut need = 0u32;
                for (r, &limit) in t_max.iter().enumerate() {
                    need |= u32::from(t <= limit * FAR_SCALE) << r;
                }
                if m & need != 0 {
                    (node, lanes) = (next as usize, m & need);
                    break;
                }
            }
        }
    }

    /// Depth of the tree (1 for a root of leaves; 0 when empty), for tests.
    #[cfg(test)]
    fn depth(&self) -> usize {
        fn walk(nodes: &[WideNode], n: usize) -> usize {
            let node = &nodes[n];
            1 + (0..WIDTH)
                .filter(|&i| node.count[i] == 0 && node.lo[0][i] <= node.hi[0][i])
                .map(|i| walk(nodes, node.index[i] as usize))
                .max()
                .unwrap_or(0)
        }
        if self.nodes.is_empty() { 0 } else { walk(&self.nodes, 0) }
    }
}

/// Insertion sort of the entries a node pushed (`stack[base..]`) by `distance`, farthest at the
/// bottom, so the nearest pops first.
#[inline(always)]
fn sort_pushes<T>(stack: &mut [T], base: usize, distance: impl Fn(&T) -> f32) {
    for i in base + 1..stack.len() {
        let mut j = i;
        while j > base && distance(&stack[j - 1]) < distance(&stack[j]) {
            stack.swap(j - 1, j);
            j -= 1;
        }
    }
}

/// The two children of inner binary node `b`, checked to be in range.
fn children(bvh: &Bvh2, b: usize) -> Option<[usize; 2]> {
    let first = bvh.nodes.get(b)?.first_index as usize;
    (first + 1 < bvh.nodes.len()).then_some([first, first + 1])
}

/// Primitives of the largest binary subtree that [`WideBvh::from_bvh2`] may make one leaf: two
/// [`crate::ray_triangle::TrianglePacket`]s (measured on the peer scenes' ray-query bench: 16
/// beat 8, 12 and 32, with the spare lanes filled as `from_bvh2` does).
const LEAF_PRIMITIVES: u32 = 2 * crate::ray_triangle::PACKET_WIDTH as u32;

/// The number of primitives under binary node `k` when it is an inner node with at most
/// [`LEAF_PRIMITIVES`] of them (`None` for more, for a leaf, or for a child index out of
/// bounds: the walk visits at most `2 LEAF_PRIMITIVES` nodes, so a cycle ends it); with
/// `order`, appends them to it, left child first, and is also `None` for a leaf's primitive
/// range out of bounds (nothing is appended on `None`).
fn subtree_primitives(bvh: &Bvh2, k: usize, order: Option<&mut Vec<u32>>) -> Option<u32> {
    if bvh.nodes.get(k)?.prim_count > 0 {
        return None;
    }
    // The subtree's leaves, left to right, checked before anything is appended.
    let mut leaves = [0usize; LEAF_PRIMITIVES as usize];
    let mut stack = [0usize; 2 * LEAF_PRIMITIVES as usize];
    let (mut len, mut found, mut count, mut visits) = (1usize, 0usize, 0u32, 0u32);
    stack[0] = k;
    while len > 0 {
        len -= 1;
        visits += 1;
        if visits > 2 * LEAF_PRIMITIVES {
            return None;
        }
        let node = bvh.nodes.get(stack[len])?;
        if node.prim_count > 0 {
            count = count.checked_add(node.prim_count).filter(|&c| c <= LEAF_PRIMITIVES)?;
            *leaves.get_mut(found)? = stack[len];
            found += 1;
        } else {
            let [c0, c1] = children(bvh, stack[len])?;
            // The left child on top, so it is taken first.
            stack[len] = c1;
            *stack.get_mut(len + 1)? = c0;
            len += 2;
        }
    }
    if let Some(order) = order {
        let start = order.len();
        for &leaf in &leaves[..found] {
            let Some(prims) = leaf_primitives(bvh, leaf) else {
                order.truncate(start);
                return None;
            };
            order.extend_from_slice(prims);
        }
    }
    Some(count)
}

/// The primitives of binary leaf `k` (`None` when its range is out of bounds).
fn leaf_primitives(bvh: &Bvh2, k: usize) -> Option<&[u32]> {
    let node = bvh.nodes.get(k)?;
    let first = node.first_index as usize;
    bvh.primitive_indices.get(first..first.checked_add(node.prim_count as usize)?)
}

/// Appends the primitives of binary node `k` (a leaf, or a subtree [`subtree_primitives`]
/// accepts) to `order`; returns how many (`None` if malformed or too large for a leaf).
fn push_leaf(bvh: &Bvh2, k: usize, order: &mut Vec<u32>) -> Option<u32> {
    if bvh.nodes.get(k)?.prim_count == 0 {
        return subtree_primitives(bvh, k, Some(order));
    }
    let prims = leaf_primitives(bvh, k)?;
    order.extend_from_slice(prims);
    u32::try_from(prims.len()).ok()
}

/// Half the surface area of binary node `k`'s box.
fn half_area(bvh: &Bvh2, k: usize) -> f32 {
    let a = &bvh.nodes[k].aabb;
    let d = (a.max - a.min).max(glam::Vec3A::ZERO);
    d.x * d.y + d.y * d.z + d.z * d.x
}

/// Stores `child`'s box with `index` and `count` in `lane` of `node`.
fn set_lane(node: &mut WideNode, lane: usize, child: &obvhs::bvh2::node::Bvh2Node, index: u32, count: u32) {
    let (lo, hi) = (child.aabb.min.to_array(), child.aabb.max.to_array());
    for a in 0..3 {
        node.lo[a][lane] = lo[a];
        node.hi[a][lane] = hi[a];
    }
    node.index[lane] = index;
    node.count[lane] = count;
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A closure as a [`Leaf`] (fixes its argument types).
    fn leaf(f: impl FnMut(u32, u32, &mut f32) -> bool) -> impl Leaf {
        f
    }
    use glam::Vec3A;
    use obvhs::BvhBuildParams;
    use obvhs::triangle::Triangle;

    fn bvh2(tris: &[Triangle]) -> Bvh2 {
        obvhs::bvh2::builder::build_bvh2_from_tris(tris, BvhBuildParams::medium_build(), &mut Default::default())
    }

    /// Every box test and leaf the walk skips is one the answer does not need: the closest `t`
    /// over random rays equals a brute-force loop over all triangles, bit for bit, from a
    /// single triangle to a grid of thousands, for rays from inside and outside the grid and
    /// axis-parallel ones (zero components: infinite reciprocals, and NaN slab distances where
    /// the origin lies on a face plane, which the grid's shared coordinates make common).
    #[test]
    fn closest_and_any_hit_match_brute_force() {
        let mut seed = 0x2545_f491u32;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            seed as f32 / u32::MAX as f32
        };
        for count in [1usize, 2, 9, 100, 3000] {
            let tris: Vec<Triangle> = (0..count)
                .map(|i| {
                    let c = Vec3A::new((i % 17) as f32, ((i / 17) % 13) as f32, (i / 221) as f32) * 0.5;
                    let j = |s: &mut dyn FnMut() -> f32| Vec3A::new(s(), s(), s()) * 0.6;
                    Triangle { v0: c + j(&mut next), v1: c + j(&mut next), v2: c + j(&mut next) }
                })
                .collect();
            let tree = bvh2(&tris);
            let (wide, order) = WideBvh::from_bvh2(&tree).unwrap();
            assert!(wide.depth() <= MAX_DEPTH);
            let mut hits = 0;
            for r in 0..3000 {
                // Towards a point near a random triangle's centroid, from anywhere around the
                // grid, or along an axis through it.
                let t = &tris[(next() * count as f32) as usize % count];
                let mut aim = (t.v0 + t.v1 + t.v2) / 3.0 + Vec3A::new(next(), next(), next()) * 0.2 - 0.1;
                let mut o = Vec3A::new(next() * 10.0 - 1.0, next() * 8.0 - 1.0, next() * 8.0 - 1.0);
                if r % 5 == 0 {
                    o = aim - Vec3A::AXES[r % 3] * if r % 2 == 0 { 3.0 } else { -3.0 };
                }
                if r % 7 == 0 && r % 5 != 0 {
                    // On the plane of a triangle vertex's coordinate, moving parallel to it.
                    (o, aim) = (Vec3A::new(o.x, t.v0.y, o.z), Vec3A::new(aim.x, t.v0.y, aim.z));
                }
                let d = (aim - o).normalize();
                // (The walk ignores obvhs' clamped `inv_direction`: it takes the exact reciprocal.)
                let ray = Ray::new(o, d, 0.0, f32::INFINITY);
                let brute = tris.iter().map(|t| t.intersect(&ray)).fold(f32::INFINITY, f32::min);
                let mut hit = None;
                wide.traverse::<true>(
                    &ray,
                    leaf(|first, n, t_max| {
                        for p in first..first + n {
                            let t = tris[order[p as usize] as usize].intersect(&ray);
                            if t < *t_max {
                                *t_max = t;
                                hit = Some(t);
                            }
                        }
                        false
                    }),
                );
                assert_eq!(hit.unwrap_or(f32::INFINITY).to_bits(), brute.to_bits(), "{count} triangles, ray {r}");
                hits += usize::from(hit.is_some());
                for limit in [brute * 0.999, brute * 1.001, 1e30] {
                    let shadow = Ray { tmax: limit, ..ray };
                    let mut blocked = false;
                    wide.traverse::<false>(
                        &shadow,
                        leaf(|first, n, t_max| {
                            blocked = (first..first + n)
                                .any(|p| tris[order[p as usize] as usize].intersect(&shadow) < *t_max);
                            blocked
                        }),
                    );
                    assert_eq!(blocked, brute < limit, "{count} triangles, ray {r}, limit {limit}");
                }
            }
            // Enough rays hit for the comparison to mean something.
            assert!(hits >= 1000, "{count} triangles: {hits} of 3000 rays hit");
        }
    }

    /// A walk started from inside another's leaf callback (the thread's stack is in use) gets a
    /// stack of its own and the same answer.
    #[test]
    fn a_nested_walk_uses_its_own_stack() {
        let tris: Vec<Triangle> = (0..50)
            .map(|i| {
                let c = Vec3A::new(i as f32, 0.0, 0.0);
                Triangle { v0: c, v1: c + Vec3A::new(0.5, 0.0, 0.0), v2: c + Vec3A::new(0.0, 1.0, 0.0) }
            })
            .collect();
        let tree = bvh2(&tris);
        let (wide, order) = WideBvh::from_bvh2(&tree).unwrap();
        let closest = |ray: &Ray| {
            let mut best = None;
            wide.traverse::<true>(
                ray,
                leaf(|first, n, t_max| {
                    for p in first..first + n {
                        let t = tris[order[p as usize] as usize].intersect(ray);
                        if t < *t_max {
                            (*t_max, best) = (t, Some(t));
                        }
                    }
                    false
                }),
            );
            best
        };
        let ray = Ray::new(Vec3A::new(7.2, 0.3, 5.0), -Vec3A::Z, 0.0, f32::INFINITY);
        let mut inner = Vec::new();
        wide.traverse::<false>(
            &ray,
            leaf(|_, _, _| {
                inner.push(closest(&ray));
                false
            }),
        );
        assert!(!inner.is_empty());
        assert!(inner.iter().all(|&t| t == Some(5.0)), "{inner:?}");
        assert_eq!(closest(&ray), Some(5.0));
    }

    /// A packet walk started from inside another's leaf callback (the thread's packet stack is in
    /// use) gets a stack of its own and the same hits; one after the other, a walk reads nothing
    /// the previous one left on the shared stack.
    #[test]
    fn a_nested_packet_walk_uses_its_own_stack() {
        /// Closest hits of a packet, lowering `t_max`; with `nested`, each leaf first walks a
        /// packet of its own and records its hits.
        struct Closest<'a> {
            tris: &'a [Triangle],
            order: &'a [u32],
            rays: &'a [(glam::Vec3, glam::Vec3)],
            nested: Option<(&'a WideBvh, Vec<[f32; RAYS]>)>,
        }
        impl PacketLeaf for &mut Closest<'_> {
            fn visit(&mut self, first: u32, count: u32, lanes: u32, t_max: &mut [f32; RAYS]) {
                if let Some((wide, found)) = &mut self.nested {
                    let mut inner = Closest { tris: self.tris, order: self.order, rays: self.rays, nested: None };
                    found.push(inner.walk(wide));
                }
                for r in (0..RAYS).filter(|r| (lanes >> r) & 1 != 0) {
                    let (o, d) = self.rays[r];
                    let ray = Ray::new(o.into(), d.into(), 0.0, f32::INFINITY);
                    for p in first..first + count {
                        t_max[r] = t_max[r].min(self.tris[self.order[p as usize] as usize].intersect(&ray));
                    }
                }
            }
        }
        impl Closest<'_> {
            fn walk(&mut self, wide: &WideBvh) -> [f32; RAYS] {
                let mut t_max = [f32::INFINITY; RAYS];
                wide.traverse_packet(&RayPacket::new(self.rays), &mut t_max, &mut *self);
                t_max
            }
        }
        let tris: Vec<Triangle> = (0..50)
            .map(|i| {
                let c = Vec3A::new(i as f32, 0.0, 0.0);
                Triangle { v0: c, v1: c + Vec3A::new(0.5, 0.0, 0.0), v2: c + Vec3A::new(0.0, 1.0, 0.0) }
            })
            .collect();
        let (wide, order) = WideBvh::from_bvh2(&bvh2(&tris)).unwrap();
        // Rays down onto triangles 0, 3, 6, ..., 42 from distance 5, and one that misses between
        // triangles 45 and 46 (past 45's hypotenuse).
        let rays: Vec<(glam::Vec3, glam::Vec3)> = (0..RAYS)
            .map(|r| if r < 15 { (3.0 * r as f32 + 0.1, 0.3) } else { (45.4, 0.7) })
            .map(|(x, y)| (glam::Vec3::new(x, y, 5.0), -glam::Vec3::Z))
            .collect();
        let want: [f32; RAYS] = core::array::from_fn(|r| if r < 15 { 5.0 } else { f32::INFINITY });
        let alone = Closest { tris: &tris, order: &order, rays: &rays, nested: None }.walk(&wide);
        assert_eq!(alone, want);
        let mut outer = Closest { tris: &tris, order: &order, rays: &rays, nested: Some((&wide, Vec::new())) };
        assert_eq!(outer.walk(&wide), want);
        let found = outer.nested.map(|(_, found)| found).unwrap_or_default();
        assert!(!found.is_empty());
        assert!(found.iter().all(|t| *t == want), "{found:?}");
        // Again on the thread's stack, after the walks above filled it.
        assert_eq!(Closest { tris: &tris, order: &order, rays: &rays, nested: None }.walk(&wide), want);
    }

    /// The collapse lays every primitive out once, each leaf's slice of the order inside its
    /// box; merges binary leaves into leaves of up to [`LEAF_PRIMITIVES`] primitives; fills
    /// nodes (the old collapse, which kept obvhs' leaves of about four, left half of each
    /// node's lanes empty); and refuses a cyclic tree and a leaf range out of bounds.
    #[test]
    fn small_subtrees_become_leaves_in_full_nodes() {
        let tris: Vec<Triangle> = (0..3000)
            .map(|i| {
                let c = Vec3A::new((i % 17) as f32, ((i / 17) % 13) as f32, (i / 221) as f32) * 0.5;
                Triangle { v0: c, v1: c + Vec3A::new(0.4, 0.1, 0.0), v2: c + Vec3A::new(0.0, 0.3, 0.2) }
            })
            .collect();
        let tree = bvh2(&tris);
        let (wide, order) = WideBvh::from_bvh2(&tree).unwrap();
        let mut laid_out = order.clone();
        let mut primitives = tree.primitive_indices.clone();
        laid_out.sort_unstable();
        primitives.sort_unstable();
        assert_eq!(laid_out, primitives, "every primitive once, in some leaf");
        let largest_binary_leaf = tree.nodes.iter().map(|n| n.prim_count).max().unwrap();
        let (mut lanes, mut covered, mut largest_leaf) = (0usize, vec![false; order.len()], 0);
        for node in &wide.nodes {
            for lane in 0..WIDTH {
                if node.lo[0][lane] > node.hi[0][lane] {
                    continue; // unused
                }
                lanes += 1;
                let (first, count) = (node.index[lane] as usize, node.count[lane]);
                if count > 0 {
                    assert!(count <= LEAF_PRIMITIVES.max(largest_binary_leaf), "a leaf of {count}");
                    largest_leaf = largest_leaf.max(count);
                    for (c, &p) in covered[first..first + count as usize].iter_mut().zip(&order[first..]) {
                        assert!(!*c, "two leaves share a primitive slot");
                        *c = true;
                        // The slice belongs to this lane: its triangles meet the lane's box (a
                        // triangle split by the builder's pre-splitting need not lie inside it).
                        let t = &tris[p as usize];
                        let (lo, hi) = (t.v0.min(t.v1).min(t.v2).to_array(), t.v0.max(t.v1).max(t.v2).to_array());
                        assert!((0..3).all(|a| node.lo[a][lane] <= hi[a] && lo[a] <= node.hi[a][lane]));
                    }
                }
            }
        }
        assert!(covered.iter().all(|&c| c));
        assert!(largest_leaf > largest_binary_leaf, "no binary leaves merged ({largest_leaf})");
        let fill = lanes as f64 / wide.nodes.len() as f64;
        assert!(fill >= 6.0, "{fill:.2} lanes used per node");
        // An inner node whose child is itself: refused, not walked forever.
        let mut cyclic = tree.clone();
        let first = cyclic.nodes[0].first_index;
        cyclic.nodes[first as usize].prim_count = 0;
        cyclic.nodes[first as usize].first_index = first;
        assert!(WideBvh::from_bvh2(&cyclic).is_none());
        // A leaf whose primitives lie past the index list.
        let mut out_of_range = tree.clone();
        let leaf = out_of_range.nodes.iter().position(|n| n.prim_count > 0).unwrap();
        out_of_range.nodes[leaf].first_index = out_of_range.primitive_indices.len() as u32;
        assert!(WideBvh::from_bvh2(&out_of_range).is_none());
    }

    #[test]
    fn an_empty_tree_hits_nothing_and_a_deep_one_is_refused() {
        let (empty, _) = WideBvh::from_bvh2(&Bvh2::default()).unwrap();
        let mut called = false;
        empty.traverse::<true>(
            &Ray::new(Vec3A::ZERO, Vec3A::X, 0.0, f32::INFINITY),
            leaf(|_, _, _| {
                called = true;
                false
            }),
        );
        assert!(!called);
        // Rays with a NaN component or an infinite origin end without a hit (and without
        // visiting a leaf); the same rays with finite components reach the triangle.
        let tris = [Triangle { v0: Vec3A::ZERO, v1: Vec3A::X, v2: Vec3A::Y }];
        let (wide, _) = WideBvh::from_bvh2(&bvh2(&tris)).unwrap();
        let ray =
            |o: Vec3A, d: Vec3A| Ray { origin: o, direction: d, inv_direction: Vec3A::ONE, tmin: 0.0, tmax: 1e30 };
        let (nan, inf) = (f32::NAN, f32::INFINITY);
        for (o, d) in [
            (Vec3A::new(0.2, 0.2, 1.0), Vec3A::new(nan, 0.0, -1.0)),
            (Vec3A::new(nan, 0.2, 1.0), -Vec3A::Z),
            (Vec3A::new(0.2, 0.2, inf), -Vec3A::Z),
        ] {
            wide.traverse::<true>(&ray(o, d), leaf(|_, _, _| panic!("{o} {d} reached a leaf")));
        }
        for (o, d) in
            [(Vec3A::new(0.2, 0.2, 1.0), -Vec3A::Z), (Vec3A::new(0.2, 0.2, 1.0), Vec3A::new(-0.0, -0.0, -1.0))]
        {
            let mut reached = false;
            wide.traverse::<true>(
                &ray(o, d),
                leaf(|_, _, _| {
                    reached = true;
                    false
                }),
            );
            assert!(reached, "{o} {d}");
        }
        // A chain: every inner node has a leaf and an inner child, so each wide level opens
        // only seven binary levels.
        let mut chain = Bvh2::default();
        let levels = 8 * MAX_DEPTH;
        for i in 0..levels {
            let inner = obvhs::bvh2::node::Bvh2Node {
                aabb: obvhs::aabb::Aabb { min: Vec3A::ZERO, max: Vec3A::ONE },
                prim_count: 0,
                first_index: (2 * i + 1) as u32,
                ..Default::default()
            };
            chain.nodes.push(inner);
            chain.nodes.push(obvhs::bvh2::node::Bvh2Node { prim_count: 1, first_index: i as u32, ..inner });
        }
        chain.nodes.push(obvhs::bvh2::node::Bvh2Node { prim_count: 1, first_index: levels as u32, ..chain.nodes[0] });
        chain.primitive_indices = (0..=levels as u32).collect();
        assert!(WideBvh::from_bvh2(&chain).is_none());
    }
}
