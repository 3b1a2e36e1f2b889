//! The conductor BRDF's microfacet factor written once over [`Lanes`]: [`crate::GgxConductor`]'s
//! `eval` is its `f32` instantiation times the Fresnel term, and the tests evaluate it in `f64`.

use crate::distribution::formulas::{Widths, d, stretched_len};
use crate::lanes::{Lanes, Vec3Lanes};

/// The terms of one pair that `eval` and `pdf` share: the normalized directions, the half
/// vector `wm = normalize(wo + wi)`, `wo . wm`, `D(wm)` and `so = stretched_len(wo)`.
#[derive(Clone, Copy)]
pub(crate) struct HalfTerms<L> {
    /// `wo`, normalized (zero when degenerate).
    pub wo: Vec3Lanes<L>,
    /// `wi`, normalized (zero when degenerate).
    pub wi: Vec3Lanes<L>,
    /// The half vector `normalize(wo + wi)`.
    pub wm: Vec3Lanes<L>,
    /// `wo . wm`, the Fresnel term's argument.
    pub cos_om: L,
    /// `D(wm)`.
    pub d: L,
    /// `so = max(|(ax wo.x, ay wo.y, wo.z)|, |wo.z|)`.
    pub so: L,
}

/// `wm = normalize(wo + wi)` (Walter et al. 2007 eq. 13) with `wo . wm`, `D(wm)` and `so`, from unnormalized inputs.
#[inline(always)]
pub(crate) fn half_terms<L: Lanes>(a: Widths<L>, wo: Vec3Lanes<L>, wi: Vec3Lanes<L>) -> HalfTerms<L> {
    let (wo, wi) = (L::normalize_or_zero(wo), L::normalize_or_zero(wi));
    let wm = L::normalize_or_zero(wo + wi);
    HalfTerms { wo, wi, wm, cos_om: wo.dot(wm), d: d(a, wm), so: stretched_len(a, wo) }
}

/// `D(wm) G2(wo, wi) / (4 |wo.z|) = D(wm) |wi.z| / (2 (|wi.z| so + |wo.z| si))` (Heitz 2014 eq. 99's G2), `f |wi.z|` before the Fresnel term, with `wo . wm`: inputs normalized, 0 where either is at or below the horizon or `wo . wm <= 0`.
#[inline(always)]
pub fn reflection<L: Lanes>(a: Widths<L>, wo: Vec3Lanes<L>, wi: Vec3Lanes<L>) -> (L, L) {
    let t = half_terms(a, wo, wi);
    (reflection_of(a, &t), t.cos_om)
}

/// [`reflection`]'s value from the shared terms: `D(wm) |wi.z| / (2 (|wi.z| so + |wo.z| si))`, 0 below the horizon or for `wo . wm <= 0`.
#[inline(always)]
pub(crate) fn reflection_of<L: Lanes>(a: Widths<L>, t: &HalfTerms<L>) -> L {
    let f = t.d * t.wi.z / g2_denominator(a, t.wo, t.wi, t.so);
    let zero = L::splat(0.0);
    // wo.wm = |wo + wi| / 2 >= 0 exactly; rounding can flip it where wo ~ -wi at grazing angles.
    let ok = t.wo.z.gt(zero) & t.wi.z.gt(zero) & t.cos_om.gt(zero);
    L::select(ok, f.finite_or_zero(), zero)
}

/// The visible-normal density of the pair from its shared terms, `D(wm) / (2 (wo.z + so))`
/// (Heitz 2018 eq. 17 with `G1(wo) = 2 wo.z / (wo.z + so)`), 0 below either horizon or for `wo . wm <= 0`.
#[inline(always)]
pub(crate) fn pdf_vndf_of<L: Lanes>(t: &HalfTerms<L>) -> L {
    let pdf = t.d / (L::splat(2.0) * (t.wo.z + t.so));
    let zero = L::splat(0.0);
    let ok = t.wo.z.gt(zero) & t.wi.z.gt(zero) & t.cos_om.gt(zero);
    L::select(ok, pdf.finite_or_zero(), zero)
}

/// `2 (|wi.z| s(wo) + |wo.z| s(wi))`: the shared denominator of `eval` and every weight,
/// from `G2 / (4 zo zi) = 1 / (2 (zi so + zo si))` (for directions above the horizon).
#[inline(always)]
pub(crate) fn g2_denominator<L: Lanes>(a: Widths<L>, wo: Vec3Lanes<L>, wi: Vec3Lanes<L>, so: L) -> L {
    L::splat(2.0) * (wi.z * so + wo.z * stretched_len(a, wi))
}
