//! [`Lanes`]: the arithmetic a formula written once needs, implemented for one `f32`, for
//! glam's `Vec3A` (three `f32` lanes in one SSE/NEON register where the target has one) and for
//! one `f64` (the precision references the tests hold the `f32` results to).
//!
//! A formula generic over `Lanes` runs the same IEEE operations in the same order on every
//! lane (add, subtract, multiply, divide and square root are correctly rounded at any width,
//! and Rust never fuses a multiply-add), so each `Vec3A` lane holds the `f32` result bit for
//! bit; branches become [`Lanes::select`]s that compute both sides.

use crate::math::sincos_2pi_with;
use core::ops::{Add, BitAnd, Div, Mul, Neg, Sub};
use glam::{BVec3A, Vec3A};

/// A float or a vector of floats, lane-wise.
pub trait Lanes:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Div<Output = Self> + Neg<Output = Self>
{
    /// Per-lane truth values of a comparison (`&`: both hold).
    type Mask: Copy + BitAnd<Output = Self::Mask>;
    /// `x` in every lane.
    fn splat(x: f32) -> Self;
    /// `x` rounded to the lane type in every lane (constants such as pi: exact for `f64`, the
    /// nearest `f32` otherwise).
    fn from_f64(x: f64) -> Self;
    /// Correctly rounded square root ([`crate::math::sqrt`]: NaN for a negative lane).
    fn sqrt(self) -> Self;
    /// `|self|`.
    fn abs(self) -> Self;
    /// `|self|` with the sign bit of `sign`.
    fn copysign(self, sign: Self) -> Self;
    /// `self == other` (false where either is NaN).
    fn eq(self, other: Self) -> Self::Mask;
    /// `self >= other` (false where either is NaN).
    fn ge(self, other: Self) -> Self::Mask;
    /// `self > other` (false where either is NaN).
    fn gt(self, other: Self) -> Self::Mask;
    /// The larger of the two; the other one where one is NaN (`f32::max`'s rule).
    fn max(self, other: Self) -> Self;
    /// The smaller of the two; the other one where one is NaN (`f32::min`'s rule).
    fn min(self, other: Self) -> Self;
    /// `self` is neither infinite nor NaN.
    fn is_finite(self) -> Self::Mask;
    /// `self` is NaN.
    fn is_nan(self) -> Self::Mask;
    /// `if_true` where `mask` holds, else `if_false`.
    fn select(mask: Self::Mask, if_true: Self, if_false: Self) -> Self;
    /// [`crate::math::normalize_or_zero`]'s rule in every lane: `v` where `|len^2 - 1| <= 2e-6`
    /// (idempotent), `v / len` where `len^2` is finite and above `1e-30`, else zero. Branches
    /// for one lane, so a caller skips the square root of a vector already unit.
    fn normalize_or_zero(v: Vec3Lanes<Self>) -> Vec3Lanes<Self>;
    /// `(sin 2 pi u, cos 2 pi u)` of `u = self`, reduced exactly to the fractional part of `|u|`;
    /// `(+-0, 1)` for NaN and infinities. `f32` lanes: [`crate::math::sincos_2pi`] (`ROUND`
    /// picks how its floors are taken, the same bits either way); `f64`: libm's `sin` and `cos`.
    fn sincos_2pi_with<const ROUND: bool>(self) -> (Self, Self);
    /// `sqrt(max(self, 0))`: never NaN ([`crate::math::safe_sqrt`] is its `f32` instantiation).
    #[inline(always)]
    fn safe_sqrt(self) -> Self {
        self.max(Self::splat(0.0)).sqrt()
    }
    /// A random number clamped into `[0, 1 - 2^-24]`, NaN to 0 ([`crate::math::sanitize_u`] is
    /// its `f32` instantiation).
    #[inline(always)]
    fn sanitize_u(self) -> Self {
        self.max(Self::splat(0.0)).min(Self::splat(crate::math::ONE_MINUS_EPSILON))
    }
    /// `self` where finite, else 0 ([`crate::math::finite_or_zero`] lane-wise).
    #[inline(always)]
    fn finite_or_zero(self) -> Self {
        Self::select(self.is_finite(), self, Self::splat(0.0))
    }
}

/// Three components over [`Lanes`]: one direction (`f32`, `f64`) or one per lane (`Vec3A`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Vec3Lanes<L> {
    /// x component(s).
    pub x: L,
    /// y component(s).
    pub y: L,
    /// z component(s).
    pub z: L,
}

impl<L: Lanes> Vec3Lanes<L> {
    /// The vector `(x, y, z)`.
    #[inline(always)]
    pub fn new(x: L, y: L, z: L) -> Self {
        Self { x, y, z }
    }

    /// `x1 x2 + y1 y2 + z1 z2`, summed left to right (glam's `Vec3::dot` order).
    #[inline(always)]
    pub fn dot(self, other: Self) -> L {
        self.x * other.x + self.y * other.y + self.z * other.z
    }

    /// `self x other`, each component in glam's `Vec3::cross` order (the same bits).
    #[inline(always)]
    pub fn cross(self, other: Self) -> Self {
        Self::new(
            self.y * other.z - other.y * self.z,
            self.z * other.x - other.z * self.x,
            self.x * other.y - other.x * self.y,
        )
    }

    /// Each component times `s`.
    #[inline(always)]
    pub fn scale(self, s: L) -> Self {
        Self::new(self.x * s, self.y * s, self.z * s)
    }
}

impl<L: Lanes> core::ops::Add for Vec3Lanes<L> {
    type Output = Self;
    #[inline(always)]
    fn add(self, other: Self) -> Self {
        Self::new(self.x + other.x, self.y + other.y, self.z + other.z)
    }
}

impl<L: Lanes> core::ops::Sub for Vec3Lanes<L> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, other: Self) -> Self {
        Self::new(self.x - other.x, self.y - other.y, self.z - other.z)
    }
}

impl From<Vec3Lanes<f32>> for glam::Vec3 {
    #[inline(always)]
    fn from(v: Vec3Lanes<f32>) -> Self {
        glam::Vec3::new(v.x, v.y, v.z)
    }
}

impl From<glam::Vec3> for Vec3Lanes<f32> {
    #[inline(always)]
    fn from(v: glam::Vec3) -> Self {
        Self::new(v.x, v.y, v.z)
    }
}

/// Widened exactly, so an `f64` formula sees the very direction its `f32` twin does.
impl From<glam::Vec3> for Vec3Lanes<f64> {
    #[inline(always)]
    fn from(v: glam::Vec3) -> Self {
        Self::new(f64::from(v.x), f64::from(v.y), f64::from(v.z))
    }
}

/// `Lanes` for a scalar float type `$t` (one lane, `bool` masks) whose square root is `$sqrt`.
macro_rules! scalar_lanes {
    ($t:ty, $sqrt:path, $sincos:ident) => {
        impl Lanes for $t {
            type Mask = bool;
            #[inline(always)]
            fn splat(x: f32) -> $t {
                <$t>::from(x)
            }
            #[inline(always)]
            fn from_f64(x: f64) -> $t {
                x as $t
            }
            #[inline(always)]
            fn sqrt(self) -> $t {
                $sqrt(self)
            }
            #[inline(always)]
            fn abs(self) -> $t {
                <$t>::abs(self)
            }
            #[inline(always)]
            fn copysign(self, sign: $t) -> $t {
                <$t>::copysign(self, sign)
            }
            #[inline(always)]
            fn eq(self, other: $t) -> bool {
                self == other
            }
            #[inline(always)]
            fn ge(self, other: $t) -> bool {
                self >= other
            }
            #[inline(always)]
            fn gt(self, other: $t) -> bool {
                self > other
            }
            #[inline(always)]
            fn max(self, other: $t) -> $t {
                <$t>::max(self, other)
            }
            #[inline(always)]
            fn min(self, other: $t) -> $t {
                <$t>::min(self, other)
            }
            #[inline(always)]
            fn is_finite(self) -> bool {
                <$t>::is_finite(self)
            }
            #[inline(always)]
            fn is_nan(self) -> bool {
                <$t>::is_nan(self)
            }
            #[inline(always)]
            fn select(mask: bool, if_true: $t, if_false: $t) -> $t {
                if mask { if_true } else { if_false }
            }
            #[inline(always)]
            fn normalize_or_zero(v: Vec3Lanes<$t>) -> Vec3Lanes<$t> {
                let len2 = v.dot(v);
                if (len2 - 1.0).abs() <= 2e-6 {
                    v
                } else if len2 > 1e-30 && len2.is_finite() {
                    v.scale(1.0 / $sqrt(len2))
                } else {
                    Vec3Lanes::new(0.0, 0.0, 0.0)
                }
            }
            #[inline(always)]
            fn sincos_2pi_with<const ROUND: bool>(self) -> ($t, $t) {
                $sincos::<ROUND>(self)
            }
        }
    };
}

scalar_lanes!(f32, crate::math::sqrt, sincos_2pi_with);
scalar_lanes!(f64, sqrt_f64, sincos_2pi_f64);

/// `(sin 2 pi u, cos 2 pi u)` in `f64`: `u` reduced exactly to `v = |u| - floor(|u|)` (0 for
/// `|u| >= 2^52`, infinities and NaN), then libm's `sin(2 pi v)`, `cos(2 pi v)`, the sign of `u`
/// on the sine. `ROUND` has no meaning here (it is [`Lanes::sincos_2pi_with`]'s `f32` knob).
#[inline(always)]
fn sincos_2pi_f64<const ROUND: bool>(u: f64) -> (f64, f64) {
    let a = u.abs();
    // NaN fails the comparison.
    let v = if a < 4_503_599_627_370_496.0 { a - libm::floor(a) } else { 0.0 };
    let x = core::f64::consts::TAU * v;
    let (s, c) = (libm::sin(x), libm::cos(x));
    (if u.is_sign_negative() { -s } else { s }, c)
}

/// Correctly rounded `f64` square root: the hardware instruction with `std`, `libm::sqrt` without.
#[inline(always)]
fn sqrt_f64(x: f64) -> f64 {
    #[cfg(feature = "std")]
    {
        x.sqrt()
    }
    #[cfg(not(feature = "std"))]
    {
        libm::sqrt(x)
    }
}

impl Lanes for Vec3A {
    type Mask = BVec3A;
    #[inline(always)]
    fn splat(x: f32) -> Vec3A {
        Vec3A::splat(x)
    }
    #[inline(always)]
    fn from_f64(x: f64) -> Vec3A {
        Vec3A::splat(x as f32)
    }
    #[inline(always)]
    fn sqrt(self) -> Vec3A {
        let s = crate::math::sqrt;
        Vec3A::new(s(self.x), s(self.y), s(self.z))
    }
    #[inline(always)]
    fn abs(self) -> Vec3A {
        Vec3A::abs(self)
    }
    #[inline(always)]
    fn copysign(self, sign: Vec3A) -> Vec3A {
        Vec3A::copysign(self, sign)
    }
    #[inline(always)]
    fn eq(self, other: Vec3A) -> BVec3A {
        self.cmpeq(other)
    }
    #[inline(always)]
    fn ge(self, other: Vec3A) -> BVec3A {
        self.cmpge(other)
    }
    #[inline(always)]
    fn gt(self, other: Vec3A) -> BVec3A {
        self.cmpgt(other)
    }
    /// Lane by lane with `f32::max`: the SSE instruction's NaN rule differs.
    #[inline(always)]
    fn max(self, other: Vec3A) -> Vec3A {
        Vec3A::new(self.x.max(other.x), self.y.max(other.y), self.z.max(other.z))
    }
    /// Lane by lane with `f32::min`: the SSE instruction's NaN rule differs.
    #[inline(always)]
    fn min(self, other: Vec3A) -> Vec3A {
        Vec3A::new(self.x.min(other.x), self.y.min(other.y), self.z.min(other.z))
    }
    #[inline(always)]
    fn is_finite(self) -> BVec3A {
        self.is_finite_mask()
    }
    #[inline(always)]
    fn is_nan(self) -> BVec3A {
        self.is_nan_mask()
    }
    #[inline(always)]
    fn select(mask: BVec3A, if_true: Vec3A, if_false: Vec3A) -> Vec3A {
        Vec3A::select(mask, if_true, if_false)
    }
    /// The `f32` rule lane by lane.
    #[inline(always)]
    fn normalize_or_zero(v: Vec3Lanes<Vec3A>) -> Vec3Lanes<Vec3A> {
        let lane = |i: usize| <f32 as Lanes>::normalize_or_zero(Vec3Lanes::new(v.x[i], v.y[i], v.z[i]));
        let (a, b, c) = (lane(0), lane(1), lane(2));
        Vec3Lanes::new(Vec3A::new(a.x, b.x, c.x), Vec3A::new(a.y, b.y, c.y), Vec3A::new(a.z, b.z, c.z))
    }
    /// The `f32` function lane by lane.
    #[inline(always)]
    fn sincos_2pi_with<const ROUND: bool>(self) -> (Vec3A, Vec3A) {
        let f = sincos_2pi_with::<ROUND>;
        let (a, b, c) = (f(self.x), f(self.y), f(self.z));
        (Vec3A::new(a.0, b.0, c.0), Vec3A::new(a.1, b.1, c.1))
    }
}
