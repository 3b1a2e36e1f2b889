//! Sampling microfacet normals proportionally to `D(wm) wm.z` (Walter et al. 2007).

use crate::TrowbridgeReitz;
use crate::math::{normalize_or_zero, safe_sqrt, sanitize_u2, sincos_2pi};
use glam::{Vec2, Vec3};

impl TrowbridgeReitz {
    /// Walter et al. 2007 eq. 35-36 in slope space: `tan^2 theta = u0 / (1 - u0)` for
    /// alpha = 1, slopes stretched by `(ax, ay)`; returns
    /// `normalize(ax sqrt(u0) cos phi, ay sqrt(u0) sin phi, sqrt(1 - u0))`, `phi = 2 pi u1`.
    /// Density of `wm`: `D(wm) wm.z`.
    #[inline]
    pub fn sample_wm_ndf(&self, u: Vec2) -> Vec3 {
        let u = sanitize_u2(u);
        let (ax, ay) = self.alphas();
        let r = safe_sqrt(u.x);
        let (sin_phi, cos_phi) = sincos_2pi(u.y);
        // sqrt(1 - u0) >= 2^-12 after sanitizing, so the result is never horizontal.
        normalize_or_zero(Vec3::new(ax * r * cos_phi, ay * r * sin_phi, safe_sqrt(1.0 - u.x)))
    }

    /// Density of [`Self::sample_wm_ndf`]: `D(wm) wm.z`.
    #[inline]
    pub fn pdf_wm_ndf(&self, wm: Vec3) -> f32 {
        crate::math::finite_or_zero(self.d(wm) * wm.z.max(0.0))
    }
}
