//! Sampling visible normals with Heitz 2018, "Sampling the GGX Distribution of Visible
//! Normals" (JCGT 7(4)); the formula is [`crate::distribution::samplers::sample_wm_vndf`].

use crate::TrowbridgeReitz;
use crate::distribution::samplers;
use glam::{Vec2, Vec3};

impl TrowbridgeReitz {
    /// Heitz 2018 listing 1: stretch `wo` to the alpha = 1 configuration, sample the projected
    /// hemisphere as a warped disk, lift, unstretch. Density of `wm`: `D_wo(wm)`
    /// ([`Self::d_visible`]). Returns zero when `wo.z <= 0`.
    #[inline]
    pub fn sample_wm_vndf(&self, wo: Vec3, u: Vec2) -> Vec3 {
        self.sample_wm_vndf_with::<false>(wo, u)
    }

    /// [`Self::sample_wm_vndf`], the same bits, with the sine and cosine's floors taken as
    /// `ROUND` says; branch-free (both sides computed, then selected), so that `crate::batch`
    /// vectorizes it.
    #[inline(always)]
    pub(crate) fn sample_wm_vndf_with<const ROUND: bool>(&self, wo: Vec3, u: Vec2) -> Vec3 {
        samplers::sample_wm_vndf_with::<f32, ROUND>(self.widths(), wo.into(), u.x, u.y).into()
    }
}
