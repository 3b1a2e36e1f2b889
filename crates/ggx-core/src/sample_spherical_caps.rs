//! Sampling visible normals with spherical caps, Dupuy & Benyoub 2023, "Sampling Visible
//! GGX Normals with Spherical Caps" (HPG 2023); the formula is
//! [`crate::distribution::samplers::sample_wm_spherical_caps`].

use crate::TrowbridgeReitz;
use crate::distribution::samplers;
use glam::{Vec2, Vec3};

impl TrowbridgeReitz {
    /// Dupuy & Benyoub 2023 listing 3: in the stretched space, a uniform point `c` on the
    /// spherical cap `z in [-vh.z, 1]` plus `vh` is a visible normal; unstretch.
    /// Same density as [`Self::sample_wm_vndf`]. Returns zero when `wo.z <= 0`.
    #[inline]
    pub fn sample_wm_spherical_caps(&self, wo: Vec3, u: Vec2) -> Vec3 {
        self.sample_wm_spherical_caps_with::<false>(wo, u)
    }

    /// [`Self::sample_wm_spherical_caps`], the same bits, with the sine and cosine's floors
    /// taken as `ROUND` says; branch-free (both sides computed, then selected), so that
    /// `crate::batch` vectorizes it.
    #[inline(always)]
    pub(crate) fn sample_wm_spherical_caps_with<const ROUND: bool>(&self, wo: Vec3, u: Vec2) -> Vec3 {
        samplers::sample_wm_spherical_caps_with::<f32, ROUND>(self.widths(), wo.into(), u.x, u.y).into()
    }
}
