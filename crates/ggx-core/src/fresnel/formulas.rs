//! The scalar Fresnel formulas.

use super::complex::Complex;
use crate::lanes::Lanes;
use crate::math::{finite_or_zero, safe_sqrt};
use glam::{Vec3, Vec3A};

/// Schlick 1994 with Burley's `f90`: `F = f0 + (f90 - f0) (1 - cos)^5`, cos clamped to `[0, 1]`.
#[inline]
pub fn fresnel_schlick(cos_theta: f32, f0: Vec3, f90: Vec3) -> Vec3 {
    let m = 1.0 - cos_theta.max(0.0).min(1.0);
    let m2 = m * m;
    let f = f0 + (f90 - f0) * (m2 * m2 * m);
    // NaN or infinite parameters give 0 rather than propagating.
    Vec3::new(finite_or_zero(f.x), finite_or_zero(f.y), finite_or_zero(f.z))
}

/// Exact unpolarised dielectric reflectance (Fresnel equations, pbrt-v4 `FrDielectric`):
/// `(r_par^2 + r_perp^2) / 2`; negative cosines flip to the inside (`eta -> 1/eta`),
/// total internal reflection returns 1. A non-positive or NaN `eta` returns 1.
#[inline]
pub fn fresnel_dielectric(cos_theta_i: f32, eta: f32) -> f32 {
    if !(eta > 0.0) || !eta.is_finite() {
        return 1.0;
    }
    let mut cos_i = cos_theta_i.max(-1.0).min(1.0);
    let mut eta = eta;
    if cos_i < 0.0 {
        eta = 1.0 / eta;
        cos_i = -cos_i;
    }
    let sin2_i = 1.0 - cos_i * cos_i;
    let sin2_t = sin2_i / (eta * eta);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = safe_sqrt(1.0 - sin2_t);
    let r_par = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    let f = 0.5 * (r_par * r_par + r_perp * r_perp);
    if f.is_nan() { 1.0 } else { f }
}

/// Conductor reflectance for complex IOR `eta + i k` (pbrt-v4 `FrComplex`): Snell's law and
/// the Fresnel equations in complex arithmetic, `(|r_par|^2 + |r_perp|^2) / 2`, cos clamped
/// to `[0, 1]`. Returns 1 where the result is not a reflectance: NaN parameters, or an
/// unphysical `eta + i k` near `-1 + 0i`, whose denominators cancel to rounding noise (infinite,
/// or finite and huge). For `eta, k >= 0` the value is in `[0, 1]` (a rounding above 1 reads 1).
#[inline]
pub fn fresnel_complex(cos_theta_i: f32, eta: f32, k: f32) -> f32 {
    fresnel_complex_lanes(cos_theta_i.max(0.0).min(1.0), eta, k)
}

/// [`fresnel_complex`] of the three channels of `eta + i k` at once, each lane bit for bit the
/// scalar function's value.
#[inline(always)]
pub(crate) fn fresnel_complex_rgb(cos_theta_i: f32, eta: Vec3, k: Vec3) -> Vec3 {
    let c = Vec3A::splat(cos_theta_i.max(0.0).min(1.0));
    Vec3::from(fresnel_complex_lanes(c, Vec3A::from(eta), Vec3A::from(k)))
}

/// The body of [`fresnel_complex`] over any [`Lanes`], `cos_i` already clamped to `[0, 1]`.
#[inline(always)]
fn fresnel_complex_lanes<L: Lanes>(cos_i: L, eta: L, k: L) -> L {
    let eta = Complex::new(eta, k);
    let sin2_i = L::splat(1.0) - cos_i * cos_i;
    let sin2_t = Complex::real(sin2_i).div(eta.mul(eta));
    let cos_t = Complex::real(L::splat(1.0)).sub(sin2_t).sqrt();
    let ci = Complex::real(cos_i);
    let r_par = eta.mul(ci).sub(cos_t).div(eta.mul(ci).add(cos_t));
    let r_perp = ci.sub(eta.mul(cos_t)).div(ci.add(eta.mul(cos_t)));
    let f = L::splat(0.5) * (r_par.norm() + r_perp.norm());
    // `f <= 1` is false for NaN and +inf.
    L::select(L::splat(1.0).ge(f), f, L::splat(1.0))
}
