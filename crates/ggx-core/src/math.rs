//! Scalar helpers shared by every module: square roots that cannot produce NaN, a
//! vectorizable `sin`/`cos` of `2 pi u`, and input sanitizers.
//!
//! With the `std` feature the square root is the hardware instruction from std; without
//! it `libm` provides the same correctly rounded result, so both builds agree bit for bit.

use crate::lanes::Lanes;
use core::f32::consts::TAU;
use glam::{Vec2, Vec3};

/// The largest `f32` below one: `1 - 2^-24`.
pub const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

/// Square root, correctly rounded (IEEE 754). Outside ggx-core's no-NaN contract by design:
/// NaN for a negative or NaN `x`, `+inf` for `+inf`; use [`safe_sqrt`] for anything sanitized.
#[inline(always)]
pub fn sqrt(x: f32) -> f32 {
    #[cfg(feature = "std")]
    {
        x.sqrt()
    }
    #[cfg(not(feature = "std"))]
    {
        libm::sqrtf(x)
    }
}

/// `sqrt(max(x, 0))`: never NaN (0 for NaN and negative `x`); finite except `safe_sqrt(+inf) = +inf`.
#[inline(always)]
pub fn safe_sqrt(x: f32) -> f32 {
    Lanes::safe_sqrt(x)
}

/// `x` clamped to `[0, 1]` (HLSL's `saturate`), NaN and `-0.0` to `+0.0`: a select, so every
/// ISA and vector width returns the same bits (`x.max(0.0)` may keep `-0.0` in scalar code and
/// not in a vectorized loop).
#[inline(always)]
pub fn saturate(x: f32) -> f32 {
    if x > 0.0 { x.min(1.0) } else { 0.0 }
}

/// `x` if it is finite, else 0.
#[inline(always)]
pub fn finite_or_zero(x: f32) -> f32 {
    if x.is_finite() { x } else { 0.0 }
}

/// Clamps a random number into `[0, 1 - 2^-24]`; NaN becomes 0.
#[inline(always)]
pub fn sanitize_u(u: f32) -> f32 {
    // f32::max returns the non-NaN operand, so NaN maps to 0.
    Lanes::sanitize_u(u)
}

/// [`sanitize_u`] on both components.
#[inline(always)]
pub fn sanitize_u2(u: Vec2) -> Vec2 {
    Vec2::new(sanitize_u(u.x), sanitize_u(u.y))
}

/// Unit vector along `v`, or zero when `v` is zero, subnormal, infinite or NaN.
///
/// Idempotent: a vector already unit to within a few ulps (`|len^2 - 1| <= 2e-6`) is returned
/// unchanged, so re-normalizing a direction that `sample` returned cannot move it (which
/// matters where the half vector `wo + wi` cancels at grazing angles).
#[inline(always)]
pub fn normalize_or_zero(v: Vec3) -> Vec3 {
    <f32 as crate::lanes::Lanes>::normalize_or_zero(v.into()).into()
}

/// `floor(x)` for `0 <= x < 2^23`, exact, without an integer conversion (a saturating `as` cast
/// is scalarized by LLVM). `ROUND`: by the rounding instruction (std's `f32::trunc`, equal to the
/// floor there; one instruction where SSE4.1 is on, as in ggx-core's dispatched batch loops, but
/// a library call at the x86-64 baseline), else by float arithmetic alone: `x + 2^23` rounds `x`
/// to an integer (the spacing there is 1), then one step down where it rounded up.
#[inline(always)]
fn floor_small<const ROUND: bool>(x: f32) -> f32 {
    if ROUND {
        #[cfg(feature = "std")]
        {
            x.trunc()
        }
        #[cfg(not(feature = "std"))]
        {
            libm::truncf(x)
        }
    } else {
        let r = (x + TWO_POW_23) - TWO_POW_23;
        if r > x { r - 1.0 } else { r }
    }
}

/// `2^23`: every `f32` at or above it in magnitude is an integer.
const TWO_POW_23: f32 = 8_388_608.0;

/// `|u| - trunc(|u|)`, the fractional part of `|u|` in `[0, 1)`, exact (Sterbenz); 0 for
/// `|u| >= 2^23` (integers), infinities and NaN. Identity on `[0, 1)`.
#[inline(always)]
fn fract_abs<const ROUND: bool>(u: f32) -> f32 {
    let a = u.abs();
    // NaN fails the comparison.
    if a < TWO_POW_23 { a - floor_small::<ROUND>(a) } else { 0.0 }
}

/// `(sin 2 pi u, cos 2 pi u)` for any `f32`: exact reduction `u -> sign(u) fract_abs(u)` (sine
/// is odd, cosine even), nearest quarter turn, then Taylor polynomials of degree 9 and 8 on
/// `[-pi/4, pi/4]` (absolute error below 2e-7 for every finite `u`, branch-free).
///
/// Both outputs are finite and in `[-1, 1]` for every input. NaN and infinities are treated as
/// 0 (`(+-0, 1)`), and so is every `|u| >= 2^23` (an integer, where the true value is `(0, 1)`).
/// On `[0, 1)` the reduction is the identity, so the result there is that of the polynomial alone.
#[inline(always)]
pub fn sincos_2pi(u: f32) -> (f32, f32) {
    sincos_2pi_with::<false>(u)
}

/// [`sincos_2pi`] with its floors taken as `floor_small::<ROUND>` does: the same bits either way;
/// `ROUND = true` for loops compiled with SSE4.1 or later (ggx-core's dispatched batch loops).
#[inline(always)]
pub(crate) fn sincos_2pi_with<const ROUND: bool>(u: f32) -> (f32, f32) {
    let v = fract_abs::<ROUND>(u);
    // Nearest quarter turn of v in [0, 1): q in 0..=4, an integer-valued f32.
    let q = floor_small::<ROUND>(v * 4.0 + 0.5);
    let r = v - q * 0.25; // exact (Sterbenz), in [-1/8, 1/8]
    let x = r * TAU;
    let x2 = x * x;
    let s = x * (1.0 + x2 * (-1.0 / 6.0 + x2 * (1.0 / 120.0 + x2 * (-1.0 / 5040.0 + x2 * (1.0 / 362_880.0)))));
    let c = 1.0 + x2 * (-0.5 + x2 * (1.0 / 24.0 + x2 * (-1.0 / 720.0 + x2 * (1.0 / 40_320.0))));
    // Quadrant q mod 4 (4 is 0), by float comparisons that vectorize: odd quadrants swap,
    // quadrants 2 and 3 negate the sine, quadrants 1 and 2 the cosine.
    let (a, b) = if q == 1.0 || q == 3.0 { (c, s) } else { (s, c) };
    let sin = if q == 2.0 || q == 3.0 { -a } else { a };
    let cos = if q == 1.0 || q == 2.0 { -b } else { b };
    // sin(-x) = -sin(x): the sign bit of u (so -0.0 keeps the old -0.0).
    (if u.is_sign_negative() { -sin } else { sin }, cos)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sincos_matches_f64_everywhere_on_the_unit_interval() {
        let mut worst = 0.0f64;
        for i in 0..=1_000_000u32 {
            let u = i as f32 / 1_000_000.0;
            let (s, c) = sincos_2pi(u);
            let a = core::f64::consts::TAU * u as f64;
            worst = worst.max((s as f64 - a.sin()).abs()).max((c as f64 - a.cos()).abs());
        }
        assert!(worst < 2e-7, "worst abs error {worst}");
        let (s, c) = sincos_2pi(ONE_MINUS_EPSILON);
        assert!(s <= 0.0 && s > -1e-6 && c == 1.0);
    }

    /// The reduction by `floor_small` (both ways) and float quadrant tests is the integer-cast formulation (what
    /// `ggx_core.wgsl` writes) bit for bit, over every 61st f32 bit pattern and the edges.
    #[test]
    fn sincos_by_float_floor_is_the_integer_cast_formulation() {
        fn by_casts(u: f32) -> (f32, f32) {
            let a = u.abs();
            let v = if a < TWO_POW_23 { a - (a as u32) as f32 } else { 0.0 };
            let q = (v * 4.0 + 0.5) as i32;
            let x = (v - q as f32 * 0.25) * TAU;
            let x2 = x * x;
            let s = x * (1.0 + x2 * (-1.0 / 6.0 + x2 * (1.0 / 120.0 + x2 * (-1.0 / 5040.0 + x2 * (1.0 / 362_880.0)))));
            let c = 1.0 + x2 * (-0.5 + x2 * (1.0 / 24.0 + x2 * (-1.0 / 720.0 + x2 * (1.0 / 40_320.0))));
            let quadrant = q & 3;
            let (a, b) = if quadrant & 1 != 0 { (c, s) } else { (s, c) };
            let sin = if quadrant & 2 != 0 { -a } else { a };
            let cos = if (quadrant + 1) & 2 != 0 { -b } else { b };
            (if u.is_sign_negative() { -sin } else { sin }, cos)
        }
        let edges =
            [0.0f32, -0.0, 0.125, 0.375, 0.625, 0.875, ONE_MINUS_EPSILON, 1.0, TWO_POW_23, f32::NAN, f32::INFINITY];
        let patterns = (0..=u32::MAX / 61).map(|i| f32::from_bits(i * 61));
        for u in patterns.chain(edges).chain(edges.map(|e| -e)) {
            let want = by_casts(u);
            for got in [sincos_2pi(u), sincos_2pi_with::<true>(u)] {
                assert_eq!((got.0.to_bits(), got.1.to_bits()), (want.0.to_bits(), want.1.to_bits()), "u = {u:e}");
            }
        }
    }

    #[test]
    fn sincos_reduces_any_f32_exactly() {
        // Negative and large u against f64 at the f32 value of u: same accuracy as on [0, 1].
        let mut worst = 0.0f64;
        for i in 0..=200_000u32 {
            for u in [-(i as f32) / 200_000.0, i as f32 * 0.7313 - 70_000.0, -(i as f32) * 41.93] {
                let (s, c) = sincos_2pi(u);
                let a = core::f64::consts::TAU * (u as f64).rem_euclid(1.0);
                worst = worst.max((s as f64 - a.sin()).abs()).max((c as f64 - a.cos()).abs());
            }
        }
        assert!(worst < 2e-7, "worst abs error {worst}");
        // Symmetric about 0, identity of the reduction on [0, 1).
        for u in [0.1f32, 0.3, 0.5, 0.77, ONE_MINUS_EPSILON, 1e-30, 1e-45] {
            let ((s, c), (t, d)) = (sincos_2pi(u), sincos_2pi(-u));
            assert!(s == -t && c == d, "{u}");
            assert_eq!((fract_abs::<false>(u), fract_abs::<true>(u)), (u, u));
        }
        // Integers (every |u| >= 2^23), NaN and infinities: (0, 1).
        for u in [f32::NAN, -f32::NAN, f32::INFINITY, f32::NEG_INFINITY, f32::MAX, -f32::MAX, 8_388_608.0, -1e30, 5.0] {
            let (s, c) = sincos_2pi(u);
            assert!(s == 0.0 && c == 1.0, "{u} -> {s} {c}");
        }
        // 2^23 - 0.5 is a half turn.
        let (s, c) = sincos_2pi(8_388_607.5);
        assert!(s.abs() < 1e-7 && c == -1.0);
    }

    #[test]
    fn sanitizers_clamp_every_special_value() {
        for u in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY, -0.0, 1.0, 2.0, -1e-45] {
            let s = sanitize_u(u);
            assert!((0.0..1.0).contains(&s), "{u} -> {s}");
        }
        assert_eq!(sanitize_u(0.25), 0.25);
        assert_eq!(safe_sqrt(-1.0), 0.0);
        assert_eq!(safe_sqrt(f32::NAN), 0.0);
        assert_eq!(normalize_or_zero(Vec3::new(f32::INFINITY, 0.0, 0.0)), Vec3::ZERO);
        assert_eq!(normalize_or_zero(Vec3::new(1e-30, 0.0, 0.0)), Vec3::ZERO);
        assert_eq!(normalize_or_zero(Vec3::new(0.0, 3.0, 4.0)), Vec3::new(0.0, 0.6, 0.8));
    }
}
