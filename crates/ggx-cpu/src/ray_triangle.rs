//! The ray-triangle test, written once over three-component vectors ([`moller_trumbore_t`]) and
//! run on one triangle ([`RayTriangle`], in SSE registers, for obvhs' trees) or on up to eight triangles of a BVH leaf at
//! once ([`TrianglePacket`], structure of arrays, for [`crate::wide_bvh::WideBvh`]): the
//! packet's lane loop is the scalar function inlined once per lane, which LLVM compiles to one
//! AVX operation per step (measured 5-10 % faster than four-wide packets on the peer scenes).
//! The same IEEE operations in the same order, so every lane holds the scalar result bit for
//! bit (Rust never fuses a multiply-add).

use glam::Vec3A;
use obvhs::ray::Ray;
use obvhs::triangle::Triangle as BvhTriangle;

/// Triangles per [`TrianglePacket`].
pub(crate) const PACKET_WIDTH: usize = 8;

/// The three-component arithmetic the test needs, on glam's `Vec3A` (one SSE register: what a
/// single triangle's test runs on) and on `[f32; 3]` (plain components: what a packet's lane
/// loop runs on, vectorized across lanes instead). Both compute every component with the same
/// operations in the same order, so the test gives the same bits on either.
pub(crate) trait Vector3: Copy {
    /// `self - other`.
    fn sub(self, other: Self) -> Self;
    /// `self . other`, summed left to right.
    fn dot(self, other: Self) -> f32;
    /// `self x other`.
    fn cross(self, other: Self) -> Self;
}

impl Vector3 for [f32; 3] {
    #[inline(always)]
    fn sub(self, b: Self) -> Self {
        [self[0] - b[0], self[1] - b[1], self[2] - b[2]]
    }

    #[inline(always)]
    fn dot(self, b: Self) -> f32 {
        self[0] * b[0] + self[1] * b[1] + self[2] * b[2]
    }

    /// Each component as glam's `Vec3A::cross` computes it.
    #[inline(always)]
    fn cross(self, b: Self) -> Self {
        let a = self;
        [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
    }
}

impl Vector3 for Vec3A {
    #[inline(always)]
    fn sub(self, other: Self) -> Self {
        self - other
    }

    #[inline(always)]
    fn dot(self, other: Self) -> f32 {
        Vec3A::dot(self, other)
    }

    #[inline(always)]
    fn cross(self, other: Self) -> Self {
        Vec3A::cross(self, other)
    }
}

/// Möller & Trumbore 1997 in the form of obvhs and `scene.wgsl`: `c = v0 - o`, `r = d x c`,
/// `u = (r . e2) / (n . d)`, `v = (r . e1) / (n . d)`, a hit when `u, v, 1 - u - v` have no sign
/// bit set (`-0.0` misses, as in obvhs) and `t = (n . c) / (n . d)` is in `[tmin, tmax]`; `inf`
/// otherwise (NaN anywhere misses). `EARLY_OUT`: return before computing `t` when the
/// barycentric test fails (one triangle: most tests miss); without it the function has no
/// branch, so a loop over lanes vectorizes. The same bits either way.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(crate) fn moller_trumbore_t<V: Vector3, const EARLY_OUT: bool>(
    v0: V,
    e1: V,
    e2: V,
    n: V,
    o: V,
    d: V,
    tmin: f32,
    tmax: f32,
) -> f32 {
    let c = v0.sub(o);
    let r = d.cross(c);
    let inv_det = 1.0 / n.dot(d);
    let u = r.dot(e2) * inv_det;
    let v = r.dot(e1) * inv_det;
    let w = 1.0 - u - v;
    let signs = u.to_bits() | v.to_bits() | w.to_bits();
    let inside = inv_det != 0.0 && signs & 0x8000_0000 == 0;
    if EARLY_OUT && !inside {
        return f32::INFINITY;
    }
    let t = n.dot(c) * inv_det;
    if inside && t >= tmin && t <= tmax { t } else { f32::INFINITY }
}

/// A triangle as the ray test reads it: `v0`, the edges `e1 = v0 - v1` and `e2 = v2 - v0`,
/// and the unnormalized normal `n = e1 x e2`. These are the terms obvhs'
/// `Triangle::intersect` (and `scene.wgsl`'s `triangle_intersect`) derive on every test;
/// computed once here, with the same operations, they give the same bits. One cache line.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C, align(64))]
pub(crate) struct RayTriangle {
    /// First vertex.
    pub v0: Vec3A,
    /// `v0 - v1`.
    pub e1: Vec3A,
    /// `v2 - v0`.
    pub e2: Vec3A,
    /// `e1 x e2`.
    pub n: Vec3A,
}

impl RayTriangle {
    /// The precomputed terms of `t`.
    pub(crate) fn new(t: &BvhTriangle) -> RayTriangle {
        let e1 = t.v0 - t.v1;
        let e2 = t.v2 - t.v0;
        RayTriangle { v0: t.v0, e1, e2, n: e1.cross(e2) }
    }

    /// [`moller_trumbore_t`] of this triangle, on `Vec3A`, returning early on a miss.
    #[inline(always)]
    pub(crate) fn intersect(&self, ray: &Ray) -> f32 {
        moller_trumbore_t::<_, true>(self.v0, self.e1, self.e2, self.n, ray.origin, ray.direction, ray.tmin, ray.tmax)
    }
}

/// Up to [`PACKET_WIDTH`] consecutive triangles of one BVH leaf as structure of arrays
/// (`v0[axis][lane]`, ...), with the scene triangle each lane stands for. An unused lane has a
/// NaN `v0`, which no ray hits.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(16))]
pub(crate) struct TrianglePacket {
    v0: [[f32; PACKET_WIDTH]; 3],
    e1: [[f32; PACKET_WIDTH]; 3],
    e2: [[f32; PACKET_WIDTH]; 3],
    n: [[f32; PACKET_WIDTH]; 3],
    /// Scene triangle index of each lane (`u32::MAX` for an unused lane).
    pub triangle: [u32; PACKET_WIDTH],
}

impl TrianglePacket {
    /// A packet of no triangles.
    const EMPTY: TrianglePacket = TrianglePacket {
        v0: [[f32::NAN; PACKET_WIDTH]; 3],
        e1: [[0.0; PACKET_WIDTH]; 3],
        e2: [[0.0; PACKET_WIDTH]; 3],
        n: [[0.0; PACKET_WIDTH]; 3],
        triangle: [u32::MAX; PACKET_WIDTH],
    };

    /// Packs `lanes` (at most [`PACKET_WIDTH`]: `(triangle, scene index)`), in order.
    pub(crate) fn new(lanes: impl IntoIterator<Item = (RayTriangle, u32)>) -> TrianglePacket {
        let mut p = TrianglePacket::EMPTY;
        for (i, (t, index)) in lanes.into_iter().take(PACKET_WIDTH).enumerate() {
            let (v0, e1, e2, n) = (t.v0.to_array(), t.e1.to_array(), t.e2.to_array(), t.n.to_array());
            for a in 0..3 {
                p.v0[a][i] = v0[a];
                p.e1[a][i] = e1[a];
                p.e2[a][i] = e2[a];
                p.n[a][i] = n[a];
            }
            p.triangle[i] = index;
        }
        p
    }

    /// Lane `i` as one triangle.
    pub(crate) fn lane(&self, i: usize) -> RayTriangle {
        let i = i % PACKET_WIDTH;
        let at = |m: &[[f32; PACKET_WIDTH]; 3]| Vec3A::new(m[0][i], m[1][i], m[2][i]);
        RayTriangle { v0: at(&self.v0), e1: at(&self.e1), e2: at(&self.e2), n: at(&self.n) }
    }

    /// [`moller_trumbore_t`] of every lane, branch-free.
    #[inline(always)]
    pub(crate) fn intersect(&self, ray: &Ray) -> [f32; PACKET_WIDTH] {
        let (o, d) = (ray.origin.to_array(), ray.direction.to_array());
        let mut t = [f32::INFINITY; PACKET_WIDTH];
        for (i, t) in t.iter_mut().enumerate() {
            let at = |m: &[[f32; PACKET_WIDTH]; 3]| [m[0][i], m[1][i], m[2][i]];
            *t = moller_trumbore_t::<_, false>(
                at(&self.v0),
                at(&self.e1),
                at(&self.e2),
                at(&self.n),
                o,
                d,
                ray.tmin,
                ray.tmax,
            );
        }
        t
    }

    /// [`moller_trumbore_t`] of lane `i`'s triangle against `N` rays (origins `o[axis][ray]`,
    /// directions `d`, each ray's `tmin`, and `tmax` for all), branch-free: the rays are the
    /// vector lanes here, each the scalar result bit for bit.
    #[inline(always)]
    pub(crate) fn intersect_rays<const N: usize>(
        &self,
        i: usize,
        o: &[[f32; N]; 3],
        d: &[[f32; N]; 3],
        tmin: &[f32; N],
        tmax: f32,
    ) -> [f32; N] {
        let i = i % PACKET_WIDTH;
        let at = |m: &[[f32; PACKET_WIDTH]; 3]| [m[0][i], m[1][i], m[2][i]];
        let (v0, e1, e2, n) = (at(&self.v0), at(&self.e1), at(&self.e2), at(&self.n));
        let mut t = [f32::INFINITY; N];
        for (r, t) in t.iter_mut().enumerate() {
            let ray = |m: &[[f32; N]; 3]| [m[0][r], m[1][r], m[2][r]];
            *t = moller_trumbore_t::<_, false>(v0, e1, e2, n, ray(o), ray(d), tmin[r], tmax);
        }
        t
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The bits of every term (NaN included, which `==` would call unequal to itself).
    fn bits(t: &RayTriangle) -> Vec<u32> {
        [t.v0, t.e1, t.e2, t.n].iter().flat_map(|v| v.to_array()).map(|x| x.to_bits()).collect()
    }

    /// Every lane of a packet, and the one-triangle test, give obvhs' `Triangle::intersect`
    /// bit for bit: random triangles and rays, rays along axes (infinite reciprocals), rays in
    /// a triangle's plane, degenerate triangles (a point, a line), huge and tiny coordinates,
    /// NaN and infinite vertices, and `tmin`/`tmax` limits around the hit; unused lanes miss.
    /// And the transposed test (one triangle against a packet of rays) likewise, per ray.
    #[test]
    fn packet_lanes_are_obvhs_triangle_test_bit_for_bit() {
        let mut seed = 0x9e37_79b9u32;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            seed as f32 / u32::MAX as f32 * 2.0 - 1.0
        };
        let mut v = |s: f32| Vec3A::new(next(), next(), next()) * s;
        let (mut hits, mut cases) = (0, 0);
        for round in 0..4000 {
            let scale = [1.0, 1e-20, 1e20, 3.0][round % 4];
            let mut tris: Vec<BvhTriangle> =
                (0..PACKET_WIDTH).map(|_| BvhTriangle { v0: v(scale), v1: v(scale), v2: v(scale) }).collect();
            match round % 9 {
                0 => tris[1].v1 = tris[1].v0,
                1 => tris[2] = BvhTriangle { v0: tris[2].v0, v1: tris[2].v0, v2: tris[2].v0 },
                2 => tris[3].v2 = Vec3A::new(f32::NAN, 0.0, 0.0),
                3 => tris[0].v1 = Vec3A::splat(f32::INFINITY),
                _ => {}
            }
            let used = 1 + round % PACKET_WIDTH;
            let aim = (tris[0].v0 + tris[0].v1 + tris[0].v2) / 3.0 + v(0.3 * scale);
            let mut o = v(4.0 * scale);
            if round % 5 == 0 {
                o = aim + Vec3A::AXES[round % 3] * 2.0 * scale;
            }
            if round % 7 == 0 {
                // In the plane of the first triangle.
                o = tris[0].v0 + (tris[0].v1 - tris[0].v0) * 3.0;
            }
            let d = (aim - o).normalize_or(Vec3A::X);
            // A literal: `Ray::new` debug-asserts a finite origin, which the hostile rounds break.
            let mut ray = Ray { origin: o, direction: d, inv_direction: d.recip(), tmin: 0.0, tmax: f32::INFINITY };
            let exact = tris[0].intersect(&ray);
            if exact.is_finite() && round % 3 == 0 {
                ray.tmax = exact * if round % 2 == 0 { 0.999 } else { 1.001 };
                ray.tmin = exact * 0.5;
            }
            let lanes: Vec<(RayTriangle, u32)> =
                tris.iter().take(used).enumerate().map(|(i, t)| (RayTriangle::new(t), i as u32)).collect();
            let packet = TrianglePacket::new(lanes);
            let t = packet.intersect(&ray);
            // The same ray in every lane of a ray packet but one, which holds another ray.
            let other = Ray { origin: v(4.0 * scale), ..ray };
            let (mut o4, mut d4, mut tmin4) = ([[0.0f32; 4]; 3], [[0.0f32; 4]; 3], [ray.tmin; 4]);
            for r in 0..4 {
                let this = if r == round % 4 { other } else { ray };
                for a in 0..3 {
                    (o4[a][r], d4[a][r]) = (this.origin[a], this.direction[a]);
                }
                tmin4[r] = this.tmin;
            }
            for (i, tri) in tris.iter().enumerate() {
                let want = if i < used { tri.intersect(&ray) } else { f32::INFINITY };
                assert_eq!(t[i].to_bits(), want.to_bits(), "round {round}, lane {i}");
                // The transposed test: triangle `i` against the four rays.
                let across = packet.intersect_rays(i, &o4, &d4, &tmin4, ray.tmax);
                for (r, t) in across.iter().enumerate() {
                    let this = if r == round % 4 { other } else { ray };
                    let want = if i < used { tri.intersect(&this) } else { f32::INFINITY };
                    assert_eq!(t.to_bits(), want.to_bits(), "round {round}, lane {i}, ray {r}");
                }
                if i < used {
                    assert_eq!(RayTriangle::new(tri).intersect(&ray).to_bits(), want.to_bits(), "round {round}");
                    assert_eq!(bits(&packet.lane(i)), bits(&RayTriangle::new(tri)), "round {round}, lane {i}");
                    assert_eq!(packet.triangle[i], i as u32);
                    hits += usize::from(want.is_finite());
                    cases += 1;
                } else {
                    assert_eq!(packet.triangle[i], u32::MAX);
                }
            }
        }
        // Enough lanes hit for the comparison to mean something.
        assert!(hits >= 1000, "{hits} hits of {cases}");
    }
}
