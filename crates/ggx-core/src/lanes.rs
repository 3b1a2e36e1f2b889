//! [`Lanes`]: the arithmetic a formula written once needs, implemented for one `f32` and for
//! glam's `Vec3A` (three `f32` lanes in one SSE/NEON register where the target has one).
//!
//! A formula generic over `Lanes` runs the same IEEE operations in the same order on every
//! lane (add, subtract, multiply, divide and square root are correctly rounded at any width,
//! and Rust never fuses a multiply-add), so each `Vec3A` lane holds the `f32` result bit for
//! bit; branches become [`Lanes::select`]s that compute both sides.

use core::ops::{Add, Div, Mul, Sub};
use glam::{BVec3A, Vec3A};

/// A float or a vector of floats, lane-wise.
pub trait Lanes: Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Div<Output = Self> {
    /// Per-lane truth values of a comparison.
    type Mask: Copy;
    /// `x` in every lane.
    fn splat(x: f32) -> Self;
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
    /// `self` is NaN.
    fn is_nan(self) -> Self::Mask;
    /// `if_true` where `mask` holds, else `if_false`.
    fn select(mask: Self::Mask, if_true: Self, if_false: Self) -> Self;
}

impl Lanes for f32 {
    type Mask = bool;
    #[inline(always)]
    fn splat(x: f32) -> f32 {
        x
    }
    #[inline(always)]
    fn sqrt(self) -> f32 {
        crate::math::sqrt(self)
    }
    #[inline(always)]
    fn abs(self) -> f32 {
        f32::abs(self)
    }
    #[inline(always)]
    fn copysign(self, sign: f32) -> f32 {
        f32::copysign(self, sign)
    }
    #[inline(always)]
    fn eq(self, other: f32) -> bool {
        self == other
    }
    #[inline(always)]
    fn ge(self, other: f32) -> bool {
        self >= other
    }
    #[inline(always)]
    fn is_nan(self) -> bool {
        f32::is_nan(self)
    }
    #[inline(always)]
    fn select(mask: bool, if_true: f32, if_false: f32) -> f32 {
        if mask { if_true } else { if_false }
    }
}

impl Lanes for Vec3A {
    type Mask = BVec3A;
    #[inline(always)]
    fn splat(x: f32) -> Vec3A {
        Vec3A::splat(x)
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
    fn is_nan(self) -> BVec3A {
        self.is_nan_mask()
    }
    #[inline(always)]
    fn select(mask: BVec3A, if_true: Vec3A, if_false: Vec3A) -> Vec3A {
        Vec3A::select(mask, if_true, if_false)
    }
}
