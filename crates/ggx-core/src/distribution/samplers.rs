//! The four microfacet-normal samplers and their densities written once over [`Lanes`]:
//! [`crate::TrowbridgeReitz`]'s `sample_wm_*` and `pdf_*` methods are their `f32`
//! instantiation, and the tests run the same source in `f64` (where the sine and cosine are
//! libm's) to check each density against the Jacobian of its sampler and to bound the `f32`
//! rounding.
//!
//! Branches are selects, so every lane type runs the same IEEE operations in the same order.
//! Random numbers are sanitized as [`crate::math::sanitize_u`] does (NaN to 0, clamped into
//! `[0, 1 - 2^-24]`); a sampler returns zero where its view is at or below the horizon.

use super::formulas::{Widths, d, stretched_len};
use crate::lanes::{Lanes, Vec3Lanes};

/// `(ax w.x, ay w.y, w.z)` normalized: `w` in the stretched (alpha = 1) configuration.
#[inline(always)]
fn stretch<L: Lanes>(a: Widths<L>, w: Vec3Lanes<L>) -> Vec3Lanes<L> {
    L::normalize_or_zero(Vec3Lanes::new(a.x * w.x, a.y * w.y, w.z))
}

/// `(ax h.x, ay h.y, max(h.z, 0))` normalized: a stretched-space normal back in the surface's.
#[inline(always)]
fn unstretch<L: Lanes>(a: Widths<L>, h: Vec3Lanes<L>) -> Vec3Lanes<L> {
    L::normalize_or_zero(Vec3Lanes::new(a.x * h.x, a.y * h.y, h.z.max(L::splat(0.0))))
}

/// `v` where `mask` holds, else zero.
#[inline(always)]
fn select3<L: Lanes>(mask: L::Mask, v: Vec3Lanes<L>) -> Vec3Lanes<L> {
    let zero = L::splat(0.0);
    Vec3Lanes::new(L::select(mask, v.x, zero), L::select(mask, v.y, zero), L::select(mask, v.z, zero))
}

/// Walter et al. 2007 eq. 35-36 in slope space: `normalize(ax sqrt(u0) cos phi, ay sqrt(u0) sin phi, sqrt(1 - u0))`, `phi = 2 pi u1`.
#[inline(always)]
pub fn sample_wm_ndf<L: Lanes>(a: Widths<L>, u0: L, u1: L) -> Vec3Lanes<L> {
    let (u0, u1) = (u0.sanitize_u(), u1.sanitize_u());
    let r = u0.safe_sqrt();
    let (sin_phi, cos_phi) = u1.sincos_2pi_with::<false>();
    // sqrt(1 - u0) >= 2^-12 after sanitizing, so the result is never horizontal.
    L::normalize_or_zero(Vec3Lanes::new(a.x * r * cos_phi, a.y * r * sin_phi, (L::splat(1.0) - u0).safe_sqrt()))
}

/// Density of [`sample_wm_ndf`]: `D(wm) max(wm.z, 0)`.
#[inline(always)]
pub fn pdf_wm_ndf<L: Lanes>(a: Widths<L>, wm: Vec3Lanes<L>) -> L {
    (d(a, wm) * wm.z.max(L::splat(0.0))).finite_or_zero()
}

/// Heitz 2018 listing 1: stretch `wo`, sample the projected hemisphere as a warped disk (radius `sqrt(u0)`, angle `2 pi u1`), lift, unstretch; density `D_wo(wm)`.
///
/// The disk's chord half-length `q = sqrt(1 - p1^2)` and the lift `sqrt(1 - p1^2 - p2^2)` are
/// factored so that nothing cancels at the rim (`u0 -> 1`) or near the normal:
/// `q^2 = (1 - u0) + (r sin phi)^2`, `(q - r sin phi)(q + r sin phi) = 1 - u0` (the smaller
/// factor from the larger), and
/// `1 - p1^2 - p2^2 = (q - r sin phi) (|vh.xy|^2 q / 2 + s^2 (q + r sin phi))`
/// (from `1 - vh.z = |vh.xy|^2 / (1 + vh.z)`, `vh` unit).
#[inline(always)]
pub fn sample_wm_vndf<L: Lanes>(a: Widths<L>, wo: Vec3Lanes<L>, u0: L, u1: L) -> Vec3Lanes<L> {
    sample_wm_vndf_with::<L, false>(a, wo, u0, u1)
}

/// [`sample_wm_vndf`], with the sine and cosine's floors taken as `ROUND` says (the same bits
/// either way): `crate::batch`'s dispatched loops take the rounding instruction.
#[inline(always)]
pub(crate) fn sample_wm_vndf_with<L: Lanes, const ROUND: bool>(
    a: Widths<L>,
    wo: Vec3Lanes<L>,
    u0: L,
    u1: L,
) -> Vec3Lanes<L> {
    let (zero, one, half) = (L::splat(0.0), L::splat(1.0), L::splat(0.5));
    let (u0, u1) = (u0.sanitize_u(), u1.sanitize_u());
    let vh = stretch(a, wo);
    // Basis around vh, Heitz 2018's rule: X only when vh is exactly the normal. (pbrt-v4's
    // shortcut "vh.z >= 0.99999 -> X" tilts the sampled hemisphere by up to 4.5e-3 rad,
    // which tiny alphas magnify into back-facing normals; found by `cargo xtask stress`.)
    let lensq = vh.x * vh.x + vh.y * vh.y;
    let tilted = lensq.gt(zero);
    let inv_len = one / lensq.sqrt();
    let t1 = Vec3Lanes::new(L::select(tilted, -vh.y * inv_len, one), L::select(tilted, vh.x * inv_len, zero), zero);
    let t2 = vh.cross(t1);
    // Uniform point (p1, r sin phi) on the unit disk (polar map), warped to the projected
    // hemisphere: p2 = (1 - s) q + s r sin phi, s = (1 + vh.z) / 2.
    let r = u0.safe_sqrt();
    let (sin_phi, cos_phi) = u1.sincos_2pi_with::<ROUND>();
    let (p1, rs) = (r * cos_phi, r * sin_phi);
    let rim = one - u0; // exact: 1 - r^2
    let q = (rim + rs * rs).safe_sqrt();
    let far = q + rs.abs();
    let near = rim / far;
    let (q_minus, q_plus) = (L::select(rs.ge(zero), near, far), L::select(rs.ge(zero), far, near));
    let s = half * (one + vh.z);
    let p2 = (one - s) * q + s * rs;
    let lift = (q_minus * (half * lensq * q + s * s * q_plus)).safe_sqrt();
    let nh = t1.scale(p1) + t2.scale(p2) + vh.scale(lift);
    select3(wo.z.gt(zero), unstretch(a, nh))
}

/// Dupuy & Benyoub 2023 listing 3: in the stretched space a uniform point on the spherical cap `z in [-vh.z, 1]`, plus `vh`, is a visible normal; density `D_wo(wm)`.
#[inline(always)]
pub fn sample_wm_spherical_caps<L: Lanes>(a: Widths<L>, wo: Vec3Lanes<L>, u0: L, u1: L) -> Vec3Lanes<L> {
    sample_wm_spherical_caps_with::<L, false>(a, wo, u0, u1)
}

/// [`sample_wm_spherical_caps`], with the sine and cosine's floors taken as `ROUND` says (the
/// same bits either way): `crate::batch`'s dispatched loops take the rounding instruction.
#[inline(always)]
pub(crate) fn sample_wm_spherical_caps_with<L: Lanes, const ROUND: bool>(
    a: Widths<L>,
    wo: Vec3Lanes<L>,
    u0: L,
    u1: L,
) -> Vec3Lanes<L> {
    let vh = stretch(a, wo);
    let cap = sample_cap::<L, ROUND>(a, vh, L::splat(1.0), L::splat(0.0), u0, u1);
    select3(wo.z.gt(L::splat(0.0)), cap)
}

/// Dupuy & Benyoub 2023 listing 3's core: `vh` plus a uniform point on the cap `z in [-lower, 1]` of the unit sphere, `lower = k vh.z` (`phi = 2 pi u0`, `z = t - lower`, `t = (1 - u1)(1 + lower)`), unstretched.
///
/// Written without cancellation for any `k` (1 for spherical caps, [`bounded_k`] for the
/// bounded sampler; `one_minus_k` is `1 - k` computed without cancelling): `1 - z^2` as
/// `u1 ((1 - lower^2) + (1 + lower) t)` (from `1 - z = u1 (1 + lower)`), `1 - lower^2` as
/// `|vh.xy|^2 + vh.z^2 (1 - k)(1 + k)` (`vh` unit), and `h.z = z + vh.z` as
/// `t + (1 - k) vh.z` (exactly `t` for caps, as u1 -> 1 too).
#[inline(always)]
fn sample_cap<L: Lanes, const ROUND: bool>(
    a: Widths<L>,
    vh: Vec3Lanes<L>,
    k: L,
    one_minus_k: L,
    u0: L,
    u1: L,
) -> Vec3Lanes<L> {
    let one = L::splat(1.0);
    let (u0, u1) = (u0.sanitize_u(), u1.sanitize_u());
    let (sin_phi, cos_phi) = u0.sincos_2pi_with::<ROUND>();
    let lower = k * vh.z;
    let one_minus_lower2 = (vh.x * vh.x + vh.y * vh.y) + vh.z * vh.z * (one_minus_k * (one + k));
    let t = (one - u1) * (one + lower);
    let sin_theta = (u1 * (one_minus_lower2 + (one + lower) * t)).safe_sqrt();
    let h = Vec3Lanes::new(sin_theta * cos_phi + vh.x, sin_theta * sin_phi + vh.y, t + one_minus_k * vh.z);
    unstretch(a, h)
}

/// Eto & Tokuyoshi 2023 eq. 5, the cap shrink factor: `k = (1 - a^2) s^2 / (s^2 + a^2 wo.z^2)`, `a = min(ax, ay)`, `s = 1 + |wo.xy|`.
#[inline(always)]
pub fn bounded_k<L: Lanes>(a: Widths<L>, wo: Vec3Lanes<L>) -> L {
    bounded_k_and_complement(a, wo).0
}

/// `(k, 1 - k)` of [`bounded_k`], `1 - k = a^2 (s^2 + wo.z^2) / (s^2 + a^2 wo.z^2)` without
/// the cancellation of `1 - k` for small `a`; `(0, 1)` where `k` is not finite.
#[inline(always)]
fn bounded_k_and_complement<L: Lanes>(a: Widths<L>, wo: Vec3Lanes<L>) -> (L, L) {
    let one = L::splat(1.0);
    let m = a.x.min(a.y);
    let a2 = m * m;
    let s = one + (wo.x * wo.x + wo.y * wo.y).sqrt();
    let s2 = s * s;
    let z2 = wo.z * wo.z;
    let den = s2 + a2 * z2;
    let k = (one - a2) * s2 / den;
    let ok = k.is_finite();
    (L::select(ok, k, L::splat(0.0)), L::select(ok, a2 * (s2 + z2) / den, one))
}

/// Eto & Tokuyoshi 2023 listing 1: [`sample_wm_spherical_caps`] with the lower cap bound `-k vh.z` ([`bounded_k`]) instead of `-vh.z`; density of the reflected direction [`pdf_wi_bounded`].
#[inline(always)]
pub fn sample_wm_bounded<L: Lanes>(a: Widths<L>, wo: Vec3Lanes<L>, u0: L, u1: L) -> Vec3Lanes<L> {
    let vh = stretch(a, wo);
    let (k, one_minus_k) = bounded_k_and_complement(a, wo);
    select3(wo.z.gt(L::splat(0.0)), sample_cap::<L, false>(a, vh, k, one_minus_k, u0, u1))
}

/// Eto & Tokuyoshi 2023 eq. 8, density of the reflected direction: `D(wm) / (2 (k wo.z + |(ax wo.x, ay wo.y, wo.z)|))`, 0 for `wo.z <= 0`.
#[inline(always)]
pub fn pdf_wi_bounded<L: Lanes>(a: Widths<L>, wo: Vec3Lanes<L>, wm: Vec3Lanes<L>) -> L {
    let zero = L::splat(0.0);
    let pdf = d(a, wm) / (L::splat(2.0) * (bounded_k(a, wo) * wo.z + stretched_len(a, wo)));
    L::select(wo.z.gt(zero), pdf.finite_or_zero(), zero)
}
