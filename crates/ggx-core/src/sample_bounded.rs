//! Bounded visible-normal sampling for reflection, Eto & Tokuyoshi 2023, "Bounded VNDF
//! Sampling for Smith-GGX Reflections" (SIGGRAPH Asia 2023 technical communications); the
//! formulas are in [`crate::distribution::samplers`].

use crate::TrowbridgeReitz;
use crate::distribution::samplers;
use glam::{Vec2, Vec3};

impl TrowbridgeReitz {
    /// Eto & Tokuyoshi 2023 eq. 5: the cap shrink factor
    /// `k = (1 - a^2) s^2 / (s^2 + a^2 wo.z^2)`, `a = min(ax, ay)`, `s = 1 + |wo.xy|`.
    #[inline(always)]
    pub fn bounded_k(&self, wo: Vec3) -> f32 {
        samplers::bounded_k(self.widths(), wo.into())
    }

    /// Eto & Tokuyoshi 2023 listing 1: the spherical-cap sampler with the lower cap bound
    /// `-k vh.z` instead of `-vh.z`, which removes most normals whose reflection would fall
    /// below the horizon. Density of the *reflected direction*: [`Self::pdf_wi_bounded`].
    /// Returns zero when `wo.z <= 0`.
    #[inline]
    pub fn sample_wm_bounded(&self, wo: Vec3, u: Vec2) -> Vec3 {
        samplers::sample_wm_bounded(self.widths(), wo.into(), u.x, u.y).into()
    }

    /// Eto & Tokuyoshi 2023 eq. 8, density of the reflected direction for `wo.z > 0`:
    /// `p(wi) = D(wm) / (2 (k wo.z + |(ax wo.x, ay wo.y, wo.z)|))`; 0 for `wo.z <= 0`.
    #[inline]
    pub fn pdf_wi_bounded(&self, wo: Vec3, wm: Vec3) -> f32 {
        samplers::pdf_wi_bounded(self.widths(), wo.into(), wm.into())
    }
}
