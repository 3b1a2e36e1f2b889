//! The distribution's formulas written once over [`Lanes`]: [`crate::TrowbridgeReitz`]'s
//! methods are their `f32` instantiation, and the tests evaluate the same source in `f64` to
//! measure the `f32` rounding error apart from the formula's own.
//!
//! Each takes the alphas as the methods read them ([`Widths`], from
//! [`crate::TrowbridgeReitz::widths`]) and tangent-space directions; branches are selects, so
//! every lane type runs the same IEEE operations in the same order. Any widths and directions
//! are accepted: `d`, `g1`, `g2` and `d_visible` are finite and `lambda` is never NaN (`+inf`
//! where its ratio overflows, as [`crate::TrowbridgeReitz::lambda`]); with the widths
//! `widths()` makes, every value is also non-negative, as the methods promise.

use crate::lanes::{Lanes, Vec3Lanes};

/// The two widths a formula reads, and whether they are equal (the isotropic forms below
/// then group the tangential terms differently, one division or product fewer).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Widths<L> {
    /// Width along the tangent `x` (clamped, as [`crate::TrowbridgeReitz::alphas`] returns it).
    pub x: L,
    /// Width along the tangent `y`.
    pub y: L,
    /// `x == y`: use the isotropic grouping.
    pub isotropic: bool,
}

/// `alpha_x^2 w.x^2 + alpha_y^2 w.y^2`, the squared length of the stretched tangential part.
#[inline(always)]
pub(crate) fn alpha2_xy<L: Lanes>(a: Widths<L>, w: Vec3Lanes<L>) -> L {
    if a.isotropic {
        a.x * a.x * (w.x * w.x + w.y * w.y)
    } else {
        let (x, y) = (a.x * w.x, a.y * w.y);
        x * x + y * y
    }
}

/// `max(|(alpha_x w.x, alpha_y w.y, w.z)|, |w.z|)`, the length of `w` in the stretched
/// (alpha = 1) space, never below `|w.z|` even where `w.z^2` underflows.
#[inline(always)]
pub(crate) fn stretched_len<L: Lanes>(a: Widths<L>, w: Vec3Lanes<L>) -> L {
    (w.z * w.z + alpha2_xy(a, w)).sqrt().max(w.z.abs())
}

/// Walter et al. 2007 eq. 33, quadratic form: `D(wm) = 1 / (pi ax ay (x^2/ax^2 + y^2/ay^2 + z^2)^2)`, 0 for `wm.z <= 0`.
#[inline(always)]
pub fn d<L: Lanes>(a: Widths<L>, wm: Vec3Lanes<L>) -> L {
    let t = if a.isotropic {
        (wm.x * wm.x + wm.y * wm.y) / (a.x * a.x) + wm.z * wm.z
    } else {
        let (x, y) = (wm.x / a.x, wm.y / a.y);
        x * x + y * y + wm.z * wm.z
    };
    let pi = L::from_f64(core::f64::consts::PI);
    let d = (L::splat(1.0) / (pi * a.x * a.y * t * t)).finite_or_zero();
    L::select(wm.z.gt(L::splat(0.0)), d, L::splat(0.0))
}

/// Heitz 2014 eq. 86 without cancellation: `Lambda = q / (2 (1 + sqrt(1 + q)))`, `q = (ax^2 x^2 + ay^2 y^2) / z^2`; 0 where `q` is NaN, `+inf` where it is.
#[inline(always)]
pub fn lambda<L: Lanes>(a: Widths<L>, w: Vec3Lanes<L>) -> L {
    let q = alpha2_xy(a, w) / (w.z * w.z);
    let one = L::splat(1.0);
    let lambda = q / (L::splat(2.0) * (one + (one + q).sqrt()));
    let inf = L::splat(f32::INFINITY);
    L::select(q.is_nan(), L::splat(0.0), L::select(q.eq(inf), inf, lambda))
}

/// Smith masking, `G1 = 1 / (1 + Lambda) = 2|z| / (|z| + s)` with `s = max(|(ax x, ay y, z)|, |z|)`, 0 at `z = 0`.
#[inline(always)]
pub fn g1<L: Lanes>(a: Widths<L>, w: Vec3Lanes<L>) -> L {
    let z = w.z.abs();
    (L::splat(2.0) * z / (z + stretched_len(a, w))).finite_or_zero().min(L::splat(1.0))
}

/// Heitz 2014 eq. 99, height-correlated: `G2 = 1 / (1 + Lambda(wo) + Lambda(wi)) = 2 |zo| |zi| / (|zi| so + |zo| si)`.
#[inline(always)]
pub fn g2<L: Lanes>(a: Widths<L>, wo: Vec3Lanes<L>, wi: Vec3Lanes<L>) -> L {
    let (zo, zi) = (wo.z.abs(), wi.z.abs());
    let g2 = L::splat(2.0) * zo * zi / (zi * stretched_len(a, wo) + zo * stretched_len(a, wi));
    g2.finite_or_zero().min(L::splat(1.0))
}

/// Heitz 2014 eq. 2: `D_w(wm) = G1(w) max(0, w . wm) D(wm) / w.z = 2 D(wm) max(0, w . wm) / (w.z + s)`, 0 for `w.z <= 0`.
#[inline(always)]
pub fn d_visible<L: Lanes>(a: Widths<L>, w: Vec3Lanes<L>, wm: Vec3Lanes<L>) -> L {
    let zero = L::splat(0.0);
    let cos = w.dot(wm).max(zero);
    let dw = (L::splat(2.0) * d(a, wm) * cos / (w.z + stretched_len(a, w))).finite_or_zero();
    L::select(w.z.gt(zero), dw, zero)
}
