//! `atan2` and `acos` as branch-free polynomials, for the equirectangular mapping
//! ([`super::direction_to_uv`]): inlined into a loop over a batch of directions they run in
//! vector lanes, where libm's are one call per direction. Both are within 5e-7 (two ulps near pi) of the true
//! angle over the whole domain (tested against f64), so a direction finds libm's texel except
//! within that of a texel border, as the GPU's own `atan2` and `acos` do.

use std::f32::consts::{FRAC_PI_2, PI};

/// Coefficients of `atan x = x P(x^2)` on `[0, 1]`, `P` of degree 7 (absolute error 3.8e-8 in
/// exact arithmetic; least-squares fit to the minimax error, the form of Abramowitz & Stegun
/// 4.4.49).
const ATAN: [f32; 8] = [
    0.999_999_34,
    -0.333_298_6,
    0.199_465_75,
    -0.139_086_78,
    0.096_423_276,
    -0.055_914_17,
    0.021_864_277,
    -0.004_054_942,
];

/// Coefficients of `acos x = sqrt(1 - x) Q(x)` on `[0, 1]`, `Q` of degree 7 (absolute error
/// 1.3e-8 in exact arithmetic; Abramowitz & Stegun 4.4.46's form, refitted; the constant term
/// rounds to `pi / 2`).
const ACOS: [f32; 8] = [
    FRAC_PI_2,
    -0.214_599_9,
    0.088_999_22,
    -0.050_312_55,
    0.031_334_82,
    -0.017_808_044,
    0.007_244_765,
    -0.001_441_283_4,
];

/// `c[0] + c[1] x + ... + c[7] x^7` by Horner's rule.
#[inline(always)]
fn horner(c: &[f32; 8], x: f32) -> f32 {
    let mut p = c[7];
    for &k in c[..7].iter().rev() {
        p = p * x + k;
    }
    p
}

/// `atan2(y, x)` in `[-pi, pi]`: `a = min(|x|, |y|) / max(|x|, |y|)`, `atan a` by [`ATAN`], then
/// reflected into the octant of `(x, y)`: `pi/2 - r` when `|y| > |x|`, `pi - r` when `x < 0`,
/// negated when `y` has its sign bit set (so `atan2(-0, -1) = -pi`, as libm). `(0, 0)` gives
/// 0 (or `pi` for `x = -0`), and NaN in gives NaN out.
#[inline(always)]
pub(crate) fn atan2(y: f32, x: f32) -> f32 {
    let (ax, ay) = (x.abs(), y.abs());
    let (lo, hi) = (ax.min(ay), ax.max(ay));
    // `0 / 0` at the origin; NaN stays NaN through min/max only when both are NaN, so the
    // inputs are checked themselves.
    let a = if hi > 0.0 { lo / hi } else { 0.0 };
    let r = a * horner(&ATAN, a * a);
    let r = if ay > ax { FRAC_PI_2 - r } else { r };
    let r = if x.is_sign_negative() { PI - r } else { r };
    let r = if y.is_sign_negative() { -r } else { r };
    if x.is_nan() || y.is_nan() { f32::NAN } else { r }
}

/// `acos x` in `[0, pi]` for `x` in `[-1, 1]` (clamped there; NaN gives NaN): `sqrt(1 - |x|)
/// Q(|x|)` by [`ACOS`], `pi - ` that for `x < 0`.
#[inline(always)]
pub(crate) fn acos(x: f32) -> f32 {
    let ax = x.abs().min(1.0);
    let r = (1.0 - ax).sqrt() * horner(&ACOS, ax);
    let r = if x < 0.0 { PI - r } else { r };
    if x.is_nan() { f32::NAN } else { r }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Largest absolute error over a dense sweep, against f64's functions.
    #[test]
    fn within_half_a_micro_radian_of_f64() {
        let mut worst_acos = 0.0f64;
        for i in 0..=2_000_000 {
            let x = -1.0 + 2.0 * i as f32 / 2_000_000.0;
            worst_acos = worst_acos.max((f64::from(acos(x)) - f64::from(x).acos()).abs());
        }
        let mut worst_atan2 = 0.0f64;
        for i in 0..2_000_000 {
            let phi = -PI + 2.0 * PI * i as f32 / 2_000_000.0;
            for r in [1e-30f32, 1e-3, 1.0, 7.5e3] {
                let (y, x) = (r * phi.sin(), r * phi.cos());
                let exact = f64::from(y).atan2(f64::from(x));
                worst_atan2 = worst_atan2.max((f64::from(atan2(y, x)) - exact).abs());
            }
        }
        assert!(worst_acos < 5e-7, "acos error {worst_acos:e}");
        assert!(worst_atan2 < 5e-7, "atan2 error {worst_atan2:e}");
    }

    /// The axes, signed zeros, infinities and NaN, as libm answers them where the mapping needs it.
    #[test]
    fn edges() {
        let near = |a: f32, b: f32| (a - b).abs() <= 5e-7;
        for (y, x) in [(0.0f32, 1.0f32), (1.0, 0.0), (0.0, -1.0), (-0.0, -1.0), (-1.0, 0.0), (-0.0, 1.0), (1.0, 1.0)] {
            assert!(near(atan2(y, x), y.atan2(x)), "atan2({y}, {x}) = {}", atan2(y, x));
        }
        assert_eq!(atan2(0.0, 0.0), 0.0);
        assert!(atan2(f32::NAN, 1.0).is_nan() && atan2(1.0, f32::NAN).is_nan());
        assert!(near(atan2(f32::INFINITY, 1.0), FRAC_PI_2) && near(atan2(1.0, f32::NEG_INFINITY), PI));
        for x in [-1.0f32, -0.5, 0.0, -0.0, 0.5, 1.0, 1.0 - f32::EPSILON, 1e-30] {
            assert!(near(acos(x), x.acos()), "acos({x}) = {}", acos(x));
        }
        assert_eq!((acos(1.0), acos(2.0), acos(-2.0)), (0.0, 0.0, PI));
        assert!(acos(f32::NAN).is_nan());
    }
}
