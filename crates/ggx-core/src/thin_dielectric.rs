//! A thin dielectric sheet (a window pane, a soap film without interference): two parallel
//! smooth interfaces so close that the light bouncing between them leaves where it entered
//! (pbrt-v4's `ThinDielectricBxDF`).

use crate::bxdf::{Bxdf, BxdfFlags, TransportMode};
use crate::conductor::BsdfSample;
use crate::dielectric::clamp_eta;
use crate::fresnel::fresnel_dielectric;
use crate::math::{normalize_or_zero, sanitize_u};
use crate::sampling::Sampling;
use glam::{Vec2, Vec3};

/// Smooth thin sheet of relative index `eta`: reflection `R' = R + T^2 R / (1 - R^2)` (the
/// geometric series of the internal bounces, pbrt-v4 `ThinDielectricBxDF`; `R` the dielectric
/// Fresnel term of `|wo.z|`, `T = 1 - R`) into the mirror direction, transmission `1 - R'`
/// straight through (`wi = -wo`: the two refractions cancel). Both lobes are deltas, the sheet
/// has no inside (it looks the same from both sides) and radiance is not rescaled (the ray
/// leaves into the medium it came from). 8-byte `#[repr(C)]` POD; `eta` is read through
/// [`clamp_eta`].
#[repr(C)]
#[derive(Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
#[cfg_attr(not(target_arch = "spirv"), derive(Debug))]
pub struct ThinDielectric {
    /// Index of refraction of the sheet relative to its surroundings.
    pub eta: f32,
    /// Padding.
    pub pad: u32,
}

impl ThinDielectric {
    /// The sheet with index `eta` ([`clamp_eta`]).
    #[inline]
    pub fn new(eta: f32) -> Self {
        Self { eta: clamp_eta(eta), pad: 0 }
    }

    /// `R' = R + T^2 R / (1 - R^2)` with `R = F(|cos_theta|, eta)`, `T = 1 - R`: the
    /// reflectance of the sheet, in `[0, 1]` (1 at grazing incidence, where `R = 1`).
    #[inline]
    pub fn reflectance(&self, cos_theta: f32) -> f32 {
        let r = fresnel_dielectric(cos_theta.abs(), clamp_eta(self.eta));
        if !(r < 1.0) {
            return 1.0;
        }
        let t = 1.0 - r;
        (r + t * t * r / (1.0 - r * r)).max(0.0).min(1.0)
    }

    /// Draws the mirror direction with probability `R'` ([`Self::reflectance`]) decided by
    /// `u_lobe`, else `-wo`; the weight is 1 and `pdf` the lobe's probability. `None` for a
    /// horizontal or degenerate `wo`.
    #[inline]
    pub fn sample(&self, wo: Vec3, u_lobe: f32) -> Option<BsdfSample> {
        let wo = normalize_or_zero(wo);
        if !(wo.z != 0.0) {
            return None;
        }
        let r = self.reflectance(wo.z);
        let (wi, pdf) = if sanitize_u(u_lobe) < r { (Vec3::new(-wo.x, -wo.y, wo.z), r) } else { (-wo, 1.0 - r) };
        if !(pdf > 0.0) {
            return None;
        }
        Some(BsdfSample { wi, weight: Vec3::ONE, pdf, is_delta: true })
    }
}

/// The sheet through the interface: `eval` and `pdf` are 0 (deltas only), `u` and
/// `sampling` are unused, `mode` changes nothing (no radiance scaling through a sheet).
impl Bxdf for ThinDielectric {
    #[inline]
    fn eval(&self, _wo: Vec3, _wi: Vec3, _mode: TransportMode) -> Vec3 {
        Vec3::ZERO
    }

    #[inline]
    fn pdf(&self, _wo: Vec3, _wi: Vec3, _sampling: Sampling, _mode: TransportMode) -> f32 {
        0.0
    }

    #[inline]
    fn sample(&self, wo: Vec3, _u: Vec2, u_lobe: f32, _sampling: Sampling, _mode: TransportMode) -> Option<BsdfSample> {
        ThinDielectric::sample(self, wo, u_lobe)
    }

    #[inline]
    fn flags(&self) -> BxdfFlags {
        BxdfFlags::REFLECTION.union(BxdfFlags::TRANSMISSION).union(BxdfFlags::SPECULAR)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reflectance_sums_the_internal_bounces() {
        let sheet = ThinDielectric::new(1.5);
        // Normal incidence: R = 0.04, R' = 2R / (1 + R) = 0.0769.
        assert!((sheet.reflectance(1.0) - 0.08 / 1.04).abs() < 1e-6);
        assert_eq!(sheet.reflectance(0.0), 1.0);
        assert_eq!(sheet.reflectance(-1.0), sheet.reflectance(1.0), "both sides alike");
        for eta in [f32::NAN, 0.0, -1.0, f32::INFINITY, 1e-30, 1.0] {
            let r = ThinDielectric::new(eta).reflectance(0.5);
            assert!((0.0..=1.0).contains(&r), "{eta} -> {r}");
        }
    }

    #[test]
    fn sample_picks_each_lobe_with_its_probability() {
        let sheet = ThinDielectric::new(1.5);
        let wo = Vec3::new(0.6, 0.0, 0.8);
        let r = sheet.reflectance(0.8);
        let s = sheet.sample(wo, r * 0.5).unwrap();
        assert_eq!((s.wi, s.pdf, s.is_delta), (Vec3::new(-0.6, 0.0, 0.8), r, true));
        let s = sheet.sample(-wo, r + (1.0 - r) * 0.5).unwrap();
        assert_eq!((s.wi, s.weight), (wo, Vec3::ONE));
        assert!((s.pdf - (1.0 - r)).abs() < 1e-7);
        assert!(sheet.sample(Vec3::new(1.0, 0.0, 0.0), 0.5).is_none());
        assert!(sheet.sample(Vec3::splat(f32::NAN), f32::NAN).is_none());
    }
}
