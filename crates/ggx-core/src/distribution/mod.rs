//! The Trowbridge-Reitz (GGX) microfacet distribution and its Smith masking functions.
//!
//! The formulas live once, over [`crate::lanes::Lanes`], in [`formulas`]; the methods of
//! [`TrowbridgeReitz`] are their `f32` instantiation.

pub mod formulas;
pub mod samplers;

use crate::alpha::{DELTA_ALPHA, clamp_alpha};
use formulas::Widths;
use glam::Vec3;

/// Anisotropic GGX distribution with widths `alpha_x`, `alpha_y` (clamped to
/// `[ALPHA_MIN, ALPHA_MAX]` by [`TrowbridgeReitz::new`]).
///
/// The fields are public and the struct is `Pod`, so they may hold anything (NaN, infinities,
/// negative, zero, subnormal); every method reads them through [`TrowbridgeReitz::alphas`],
/// the constructor's clamp, so any bit pattern behaves as `new(alpha_x, alpha_y)` would.
///
/// All functions take tangent-space unit vectors and return 0 (never NaN or infinity,
/// except [`TrowbridgeReitz::lambda`], which is `+inf` at grazing angles) where the
/// quantity is undefined.
#[repr(C)]
#[derive(Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
#[cfg_attr(not(target_arch = "spirv"), derive(Debug))]
pub struct TrowbridgeReitz {
    /// Width along the tangent `x`.
    pub alpha_x: f32,
    /// Width along the tangent `y`.
    pub alpha_y: f32,
}

impl TrowbridgeReitz {
    /// Distribution with the given alphas, each clamped to `[ALPHA_MIN, ALPHA_MAX]`.
    #[inline]
    pub fn new(alpha_x: f32, alpha_y: f32) -> Self {
        Self { alpha_x: clamp_alpha(alpha_x), alpha_y: clamp_alpha(alpha_y) }
    }

    /// Isotropic distribution (`alpha_x = alpha_y = alpha`).
    #[inline]
    pub fn isotropic(alpha: f32) -> Self {
        let a = clamp_alpha(alpha);
        Self { alpha_x: a, alpha_y: a }
    }

    /// The alphas every formula uses, `(clamp_alpha(alpha_x), clamp_alpha(alpha_y))`: the
    /// identity for constructor-made values, the constructor's clamp for raw field values.
    #[inline(always)]
    pub fn alphas(&self) -> (f32, f32) {
        (clamp_alpha(self.alpha_x), clamp_alpha(self.alpha_y))
    }

    /// The alphas ([`Self::alphas`]) as [`formulas`] read them.
    #[inline(always)]
    pub fn widths(&self) -> Widths<f32> {
        let (x, y) = self.alphas();
        Widths { x, y, isotropic: x == y }
    }

    /// True when both alphas ([`Self::alphas`]) are equal, which enables the isotropic fast paths.
    #[inline]
    pub fn is_isotropic(&self) -> bool {
        self.widths().isotropic
    }

    /// True when the lobe is rendered as a mirror: `max(alpha_x, alpha_y) < DELTA_ALPHA`
    /// (alphas from [`Self::alphas`]).
    #[inline]
    pub fn is_effectively_smooth(&self) -> bool {
        let (ax, ay) = self.alphas();
        ax.max(ay) < DELTA_ALPHA
    }

    /// `|(alpha_x w.x, alpha_y w.y, w.z)|`, the length of `w` in the stretched (alpha = 1) space.
    /// Never below `|w.z|`, even where `w.z^2` underflows, so `G1 <= 1` and weights stay bounded.
    #[inline(always)]
    pub(crate) fn stretched_len(&self, w: Vec3) -> f32 {
        formulas::stretched_len(self.widths(), w.into())
    }

    /// Normal distribution, Walter et al. 2007 eq. 33 in the quadratic form:
    /// `D(wm) = 1 / (pi ax ay (x^2/ax^2 + y^2/ay^2 + z^2)^2)`, 0 for `wm.z <= 0`.
    #[inline]
    pub fn d(&self, wm: Vec3) -> f32 {
        formulas::d(self.widths(), wm.into())
    }

    /// Smith Lambda, Heitz 2014 eq. 86: `(sqrt(1 + q) - 1) / 2` with
    /// `q = (ax^2 x^2 + ay^2 y^2) / z^2`, written as `q / (2 (1 + sqrt(1 + q)))` to avoid
    /// cancellation. Depends on `|w.z|` (pbrt-v4 convention).
    ///
    /// Never NaN or negative (0 where `q` is NaN: a NaN component, `w = 0`). Outside the
    /// finite contract by design: `+inf` exactly where `q` overflows to `+inf`, that is where
    /// `w.z^2` is 0 (`w.z = 0`, or `|w.z| < ~1e-19` so that it underflows) under a non-zero
    /// tangential part, or, for non-unit `w` only, where the tangential part overflows f32
    /// (`|w.x|` or `|w.y|` above about `1.8e19`).
    #[inline]
    pub fn lambda(&self, w: Vec3) -> f32 {
        formulas::lambda(self.widths(), w.into())
    }

    /// Smith masking, `G1 = 1 / (1 + Lambda) = 2|z| / (|z| + sqrt(z^2 + ax^2 x^2 + ay^2 y^2))`
    /// (stable at grazing angles, 0 at `z = 0`).
    #[inline]
    pub fn g1(&self, w: Vec3) -> f32 {
        formulas::g1(self.widths(), w.into())
    }

    /// Height-correlated masking-shadowing, Heitz 2014 eq. 99:
    /// `G2 = 1 / (1 + Lambda(wo) + Lambda(wi)) = 2 |zo| |zi| / (|zi| so + |zo| si)`,
    /// with `s = |(ax x, ay y, z)|`.
    #[inline]
    pub fn g2(&self, wo: Vec3, wi: Vec3) -> f32 {
        formulas::g2(self.widths(), wo.into(), wi.into())
    }

    /// Separable (uncorrelated) masking-shadowing, `G2 = G1(wo) G1(wi)` (Mitsuba 3's form).
    #[inline]
    pub fn g2_separable(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.g1(wo) * self.g1(wi)
    }

    /// Distribution of normals visible from `w`, Heitz 2014 eq. 2:
    /// `D_w(wm) = G1(w) max(0, w . wm) D(wm) / w.z = 2 D(wm) max(0, w . wm) / (w.z + s)`.
    /// Zero for `w.z <= 0`.
    #[inline]
    pub fn d_visible(&self, w: Vec3, wm: Vec3) -> f32 {
        formulas::d_visible(self.widths(), w.into(), wm.into())
    }
}
