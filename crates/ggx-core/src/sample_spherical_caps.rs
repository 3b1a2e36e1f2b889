//! Sampling visible normals with spherical caps, Dupuy & Benyoub 2023, "Sampling Visible
//! GGX Normals with Spherical Caps" (HPG 2023).

use crate::TrowbridgeReitz;
use crate::math::{normalize_or_zero, safe_sqrt, sanitize_u2, sincos_2pi_with};
use glam::{Vec2, Vec3};

impl TrowbridgeReitz {
    /// Dupuy & Benyoub 2023 listing 3: in the stretched space, a uniform point `c` on the
    /// spherical cap `z in [-vh.z, 1]` plus `vh` is a visible normal; unstretch.
    /// Same density as [`Self::sample_wm_vndf`]. Returns zero when `wo.z <= 0`.
    #[inline]
    pub fn sample_wm_spherical_caps(&self, wo: Vec3, u: Vec2) -> Vec3 {
        self.sample_wm_spherical_caps_with::<false>(wo, u)
    }

    /// [`Self::sample_wm_spherical_caps`], the same bits, with `sincos_2pi_with::<ROUND>`;
    /// branch-free (both sides computed, then selected), so that `crate::batch` vectorizes it.
    #[inline(always)]
    pub(crate) fn sample_wm_spherical_caps_with<const ROUND: bool>(&self, wo: Vec3, u: Vec2) -> Vec3 {
        let (ax, ay) = self.alphas();
        let vh = normalize_or_zero(Vec3::new(ax * wo.x, ay * wo.y, wo.z));
        let wm = self.sample_cap::<ROUND>(vh, vh.z, u);
        if wo.z > 0.0 { wm } else { Vec3::ZERO }
    }

    /// Uniform point on the cap `z in [-lower, 1]` of the unit sphere, offset by `vh` and
    /// unstretched: shared by the spherical-cap and bounded samplers. `ROUND`: floors for
    /// `sincos_2pi_with` (the same bits either way).
    #[inline(always)]
    pub(crate) fn sample_cap<const ROUND: bool>(&self, vh: Vec3, lower: f32, u: Vec2) -> Vec3 {
        let u = sanitize_u2(u);
        let (ax, ay) = self.alphas();
        let (sin_phi, cos_phi) = sincos_2pi_with::<ROUND>(u.x);
        let t = (1.0 - u.y) * (1.0 + lower);
        let z = t - lower;
        let sin_theta = safe_sqrt(1.0 - z * z);
        // h.z = z + vh.z written as t + (vh.z - lower): no cancellation as u1 -> 1 (for spherical
        // caps it is exactly t), which GPU compilers would otherwise fold differently.
        let h = Vec3::new(sin_theta * cos_phi + vh.x, sin_theta * sin_phi + vh.y, t + (vh.z - lower));
        normalize_or_zero(Vec3::new(ax * h.x, ay * h.y, h.z.max(0.0)))
    }
}
