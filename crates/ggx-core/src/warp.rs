//! Hemisphere sampling baselines (cosine-weighted and uniform) with their densities.

use crate::math::{safe_sqrt, sanitize_u2, sincos_2pi};
use core::f32::consts::{FRAC_1_PI, PI};
use glam::{Vec2, Vec3};

/// Cosine-weighted hemisphere by Malley's method: a uniform disk point
/// `(sqrt(u0) cos 2 pi u1, sqrt(u0) sin 2 pi u1)` lifted to `z = sqrt(1 - u0)`.
/// Density [`pdf_cosine_hemisphere`]. Never returns a horizontal direction.
#[inline]
pub fn sample_cosine_hemisphere(u: Vec2) -> Vec3 {
    let u = sanitize_u2(u);
    let r = safe_sqrt(u.x);
    let (sin_phi, cos_phi) = sincos_2pi(u.y);
    Vec3::new(r * cos_phi, r * sin_phi, safe_sqrt(1.0 - u.x))
}

/// Density of [`sample_cosine_hemisphere`]: `max(0, w.z) / pi`; never NaN, finite except
/// `+inf` for `w.z = +inf` (IEEE, outside the finite contract).
#[inline]
pub fn pdf_cosine_hemisphere(w: Vec3) -> f32 {
    if w.z > 0.0 { w.z * FRAC_1_PI } else { 0.0 }
}

/// Uniform hemisphere: `z = 1 - u0`, `phi = 2 pi u1`. Density [`pdf_uniform_hemisphere`].
#[inline]
pub fn sample_uniform_hemisphere(u: Vec2) -> Vec3 {
    let u = sanitize_u2(u);
    let z = 1.0 - u.x;
    let r = safe_sqrt(1.0 - z * z);
    let (sin_phi, cos_phi) = sincos_2pi(u.y);
    Vec3::new(r * cos_phi, r * sin_phi, z)
}

/// Density of [`sample_uniform_hemisphere`]: `1 / (2 pi)` on the upper hemisphere.
#[inline]
pub fn pdf_uniform_hemisphere(w: Vec3) -> f32 {
    if w.z > 0.0 { 0.5 / PI } else { 0.0 }
}
