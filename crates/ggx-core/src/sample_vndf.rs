//! Sampling visible normals with Heitz 2018, "Sampling the GGX Distribution of Visible
//! Normals" (JCGT 7(4)).

use crate::TrowbridgeReitz;
use crate::math::{normalize_or_zero, safe_sqrt, sanitize_u2, sincos_2pi, sqrt};
use glam::{Vec2, Vec3};

impl TrowbridgeReitz {
    /// Heitz 2018 listing 1: stretch `wo` to the alpha = 1 configuration, sample the projected
    /// hemisphere as a warped disk, lift, unstretch. Density of `wm`: `D_wo(wm)`
    /// ([`Self::d_visible`]). Returns zero when `wo.z <= 0`.
    #[inline]
    pub fn sample_wm_vndf(&self, wo: Vec3, u: Vec2) -> Vec3 {
        if !(wo.z > 0.0) {
            return Vec3::ZERO;
        }
        let u = sanitize_u2(u);
        let (ax, ay) = self.alphas();
        let vh = normalize_or_zero(Vec3::new(ax * wo.x, ay * wo.y, wo.z));
        // Basis around vh, Heitz 2018's rule: X only when vh is exactly the normal. (pbrt-v4's
        // shortcut "vh.z >= 0.99999 -> X" tilts the sampled hemisphere by up to 4.5e-3 rad,
        // which tiny alphas magnify into back-facing normals; found by `cargo xtask stress`.)
        let lensq = vh.x * vh.x + vh.y * vh.y;
        let t1 = if lensq > 0.0 { Vec3::new(-vh.y, vh.x, 0.0) * (1.0 / sqrt(lensq)) } else { Vec3::X };
        let t2 = vh.cross(t1);
        // Uniform point on the unit disk (polar map), then warp to the projected hemisphere.
        let r = safe_sqrt(u.x);
        let (sin_phi, cos_phi) = sincos_2pi(u.y);
        let p1 = r * cos_phi;
        let s = 0.5 * (1.0 + vh.z);
        let p2 = (1.0 - s) * safe_sqrt(1.0 - p1 * p1) + s * (r * sin_phi);
        let nh = p1 * t1 + p2 * t2 + safe_sqrt(1.0 - p1 * p1 - p2 * p2) * vh;
        normalize_or_zero(Vec3::new(ax * nh.x, ay * nh.y, nh.z.max(0.0)))
    }
}
