//! Bounded visible-normal sampling for reflection, Eto & Tokuyoshi 2023, "Bounded VNDF
//! Sampling for Smith-GGX Reflections" (SIGGRAPH Asia 2023 technical communications).

use crate::TrowbridgeReitz;
use crate::math::{finite_or_zero, normalize_or_zero, sqrt};
use glam::{Vec2, Vec3};

impl TrowbridgeReitz {
    /// Eto & Tokuyoshi 2023 eq. 5: the cap shrink factor
    /// `k = (1 - a^2) s^2 / (s^2 + a^2 wo.z^2)`, `a = min(ax, ay)`, `s = 1 + |wo.xy|`.
    #[inline(always)]
    pub fn bounded_k(&self, wo: Vec3) -> f32 {
        let (ax, ay) = self.alphas();
        let a = ax.min(ay);
        let a2 = a * a;
        let s = 1.0 + sqrt(wo.x * wo.x + wo.y * wo.y);
        let s2 = s * s;
        finite_or_zero((1.0 - a2) * s2 / (s2 + a2 * wo.z * wo.z))
    }

    /// Eto & Tokuyoshi 2023 listing 1: the spherical-cap sampler with the lower cap bound
    /// `-k vh.z` instead of `-vh.z`, which removes most normals whose reflection would fall
    /// below the horizon. Density of the *reflected direction*: [`Self::pdf_wi_bounded`].
    /// Returns zero when `wo.z <= 0`.
    #[inline]
    pub fn sample_wm_bounded(&self, wo: Vec3, u: Vec2) -> Vec3 {
        if !(wo.z > 0.0) {
            return Vec3::ZERO;
        }
        let (ax, ay) = self.alphas();
        let vh = normalize_or_zero(Vec3::new(ax * wo.x, ay * wo.y, wo.z));
        self.sample_cap::<false>(vh, self.bounded_k(wo) * vh.z, u)
    }

    /// Eto & Tokuyoshi 2023 eq. 8, density of the reflected direction for `wo.z > 0`:
    /// `p(wi) = D(wm) / (2 (k wo.z + |(ax wo.x, ay wo.y, wo.z)|))`; 0 for `wo.z <= 0`.
    #[inline]
    pub fn pdf_wi_bounded(&self, wo: Vec3, wm: Vec3) -> f32 {
        if !(wo.z > 0.0) {
            return 0.0;
        }
        finite_or_zero(self.d(wm) / (2.0 * (self.bounded_k(wo) * wo.z + self.stretched_len(wo))))
    }
}
