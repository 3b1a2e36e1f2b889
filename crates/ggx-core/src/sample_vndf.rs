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
        samplers::sample_wm_vndf(self.widths(), wo.into(), u.x, u.y).into()
    }
}
