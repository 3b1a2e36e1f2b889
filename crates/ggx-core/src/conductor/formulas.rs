//! The conductor BRDF's microfacet factor written once over [`Lanes`]: [`crate::GgxConductor`]'s
//! `eval` is its `f32` instantiation times the Fresnel term, and the tests evaluate it in `f64`.

use crate::distribution::formulas::{Widths, d, stretched_len};
use crate::lanes::{Lanes, Vec3Lanes};

/// `D(wm) G2(wo, wi) / (4 |wo.z|) = D(wm) |wi.z| / (2 (|wi.z| so + |wo.z| si))` (Heitz 2014 eq. 99's G2), `f |wi.z|` before the Fresnel term, with `wo . wm`: inputs normalized, 0 where either is at or below the horizon or `wo . wm <= 0`.
#[inline(always)]
pub fn reflection<L: Lanes>(a: Widths<L>, wo: Vec3Lanes<L>, wi: Vec3Lanes<L>) -> (L, L) {
    let (wo, wi) = (L::normalize_or_zero(wo), L::normalize_or_zero(wi));
    let wm = L::normalize_or_zero(wo + wi);
    let cos_om = wo.dot(wm);
    let f = d(a, wm) * wi.z / g2_denominator(a, wo, wi, stretched_len(a, wo));
    let zero = L::splat(0.0);
    // wo.wm = |wo + wi| / 2 >= 0 exactly; rounding can flip it where wo ~ -wi at grazing angles.
    let ok = wo.z.gt(zero) & wi.z.gt(zero) & cos_om.gt(zero);
    (L::select(ok, f.finite_or_zero(), zero), cos_om)
}

/// `2 (|wi.z| s(wo) + |wo.z| s(wi))`: the shared denominator of `eval` and every weight,
/// from `G2 / (4 zo zi) = 1 / (2 (zi so + zo si))` (for directions above the horizon).
#[inline(always)]
pub(crate) fn g2_denominator<L: Lanes>(a: Widths<L>, wo: Vec3Lanes<L>, wi: Vec3Lanes<L>, so: L) -> L {
    L::splat(2.0) * (wi.z * so + wo.z * stretched_len(a, wi))
}
