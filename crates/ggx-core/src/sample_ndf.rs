//! Sampling microfacet normals proportionally to `D(wm) wm.z` (Walter et al. 2007); the
//! formulas are in [`crate::distribution::samplers`].

use crate::TrowbridgeReitz;
use crate::distribution::samplers;
use glam::{Vec2, Vec3};

impl TrowbridgeReitz {
    /// Walter et al. 2007 eq. 35-36 in slope space: `tan^2 theta = u0 / (1 - u0)` for
    /// alpha = 1, slopes stretched by `(ax, ay)`; returns
    /// `normalize(ax sqrt(u0) cos phi, ay sqrt(u0) sin phi, sqrt(1 - u0))`, `phi = 2 pi u1`.
    /// Density of `wm`: `D(wm) wm.z`.
    #[inline]
    pub fn sample_wm_ndf(&self, u: Vec2) -> Vec3 {
        samplers::sample_wm_ndf(self.widths(), u.x, u.y).into()
    }

    /// Density of [`Self::sample_wm_ndf`]: `D(wm) wm.z`.
    #[inline]
    pub fn pdf_wm_ndf(&self, wm: Vec3) -> f32 {
        samplers::pdf_wm_ndf(self.widths(), wm.into())
    }
}
