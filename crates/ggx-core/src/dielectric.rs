//! GGX reflection and transmission through one rough dielectric interface, Walter et al.
//! 2007, "Microfacet Models for Refraction through Rough Surfaces" (EGSR), in the form of
//! pbrt-v4's `DielectricBxDF` (generalized half vector, exact Fresnel, radiance scaling).
//!
//! Convention: `eta = eta_t / eta_i` is the index of the `-z` side over that of the `+z`
//! side (1.5 for glass in air with the normal pointing into the air). For a pair
//! `(wo, wi)`, `eta' = eta` when `wo.z > 0` and `1 / eta` when `wo.z < 0` (the ray is
//! inside: the geometry is flipped); `eta'` is the index of `wi`'s side over `wo`'s.

use crate::bxdf::{Bxdf, BxdfFlags, TransportMode};
use crate::conductor::BsdfSample;
use crate::fresnel::fresnel_dielectric;
use crate::math::{finite_or_zero, normalize_or_zero, safe_sqrt, sanitize_u};
use crate::sampling::Sampling;
use crate::{TrowbridgeReitz, reflect};
use glam::{Vec2, Vec3};

/// Smallest relative index of refraction used in any formula.
pub const ETA_MIN: f32 = 1e-2;
/// Largest relative index of refraction used in any formula.
pub const ETA_MAX: f32 = 1e2;

/// The relative IOR every formula uses: `eta` clamped to `[ETA_MIN, ETA_MAX]`; NaN, zero
/// and negative values give 1 (an index-matched interface).
#[inline]
pub fn clamp_eta(eta: f32) -> f32 {
    if !(eta > 0.0) { 1.0 } else { eta.max(ETA_MIN).min(ETA_MAX) }
}

/// Snell refraction of `w` through a surface with normal `n` and relative IOR `eta` (index of
/// the side `n` does not point to over that of `w`'s side when `w.n > 0`; pbrt-v4 `Refract`):
/// `wt = -w / eta' + (cos_i / eta' - cos_t) n'`, with `n' = -n`, `eta' = 1 / eta` when `w.n < 0`.
/// `None` under total internal reflection or for a non-finite result; `eta` through
/// [`clamp_eta`]. Unit `w` and `n` give a unit `wt` up to their rounding, which the tangential
/// part amplifies by about `1 / eta'^2`: within `1e-5 + 2e-7 / eta'^2` (tested), so 1e-5 for
/// `eta'` in glass's range and about 1e-3 at `ETA_MIN` (ill-conditioned, even in `f64`).
#[inline]
pub fn refract(w: Vec3, n: Vec3, eta: f32) -> Option<Vec3> {
    let mut eta = clamp_eta(eta);
    let mut n = n;
    let mut cos_i = w.dot(n).max(-1.0).min(1.0);
    if cos_i < 0.0 {
        eta = 1.0 / eta;
        cos_i = -cos_i;
        n = -n;
    }
    // The same test as `fresnel_dielectric`'s total internal reflection, so F < 1 <=> Some.
    let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    if !(sin2_t < 1.0) {
        return None;
    }
    let cos_t = safe_sqrt(1.0 - sin2_t);
    let wt = -w / eta + (cos_i / eta - cos_t) * n;
    if wt.is_finite() { Some(wt) } else { None }
}

/// Jacobian of the generalized half vector for transmission, Walter et al. 2007 eq. 17 with
/// `eta' = eta_i' / eta_o'`: `dwm/dwi = eta'^2 |wi.wm| / (wo.wm + eta' wi.wm)^2`
/// (= `|wi.wm| / (wi.wm + wo.wm / eta')^2`, pbrt-v4's form).
#[inline(always)]
fn jacobian_transmission(etap: f32, cos_om: f32, cos_im: f32) -> f32 {
    let s = cos_om + etap * cos_im;
    etap * etap * cos_im.abs() / (s * s)
}

/// Jacobian of the half vector for reflection, Walter et al. 2007 eq. 14: `1 / (4 |wo.wm|)`.
#[inline(always)]
fn jacobian_reflection(cos_om: f32) -> f32 {
    1.0 / (4.0 * cos_om.abs())
}

/// Radiance scaling of a transmitted path (Veach 1997 eq. 5.16): `1 / eta'^2` for
/// [`TransportMode::Radiance`], 1 for importance and for reflection.
#[inline(always)]
fn transport_scale(reflect: bool, etap: f32, mode: TransportMode) -> f32 {
    if reflect || mode == TransportMode::Importance { 1.0 } else { 1.0 / (etap * etap) }
}

/// The generalized half vector of a pair and what is derived from it.
struct Half {
    /// `normalize(wo + eta' wi)` turned to `+z`.
    wm: Vec3,
    /// Both directions on one side.
    reflect: bool,
    /// 1 for reflection, else `eta` (wo outside) or `1 / eta` (wo inside).
    etap: f32,
    /// `wo . wm`, with the sign of `wo.z`.
    cos_om: f32,
    /// Probability of the lobe: `F(wo . wm)` for reflection, `1 - F` for transmission.
    p_lobe: f32,
    /// Jacobian `dwm / dwi` of the lobe.
    jacobian: f32,
}

/// Rough dielectric BSDF (Walter et al. 2007): with `wm` the generalized half vector,
/// `f_r = F D G2 / (4 |wo.z| |wi.z|)` and
/// `f_t = (1 - F) D G2 eta'^2 |wi.wm| |wo.wm| / (|wi.z| |wo.z| (wo.wm + eta' wi.wm)^2)`, the
/// latter divided by `eta'^2` for [`TransportMode::Radiance`]; `F` is the exact dielectric
/// Fresnel term of `wo . wm`, `G2` the height-correlated Smith term. A smooth (delta)
/// interface below [`crate::DELTA_ALPHA`]. 16-byte `#[repr(C)]` POD, ready to upload to a GPU.
///
/// The fields are public and may hold any bits: alphas are read through
/// [`TrowbridgeReitz::alphas`], `eta` through [`clamp_eta`].
#[repr(C)]
#[derive(Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
#[cfg_attr(not(target_arch = "spirv"), derive(Debug))]
pub struct GgxDielectric {
    /// The microfacet distribution.
    pub distribution: TrowbridgeReitz,
    /// Relative index of refraction `eta_t / eta_i`: the `-z` side over the `+z` side.
    pub eta: f32,
    /// Padding to 16 bytes.
    pub pad: u32,
}

impl GgxDielectric {
    /// BSDF with alphas clamped to `[ALPHA_MIN, ALPHA_MAX]` and `eta` through [`clamp_eta`]; a
    /// lobe with both alphas below [`crate::DELTA_ALPHA`] is a smooth interface.
    #[inline]
    pub fn new(alpha_x: f32, alpha_y: f32, eta: f32) -> Self {
        Self { distribution: TrowbridgeReitz::new(alpha_x, alpha_y), eta: clamp_eta(eta), pad: 0 }
    }

    /// Isotropic BSDF.
    #[inline]
    pub fn isotropic(alpha: f32, eta: f32) -> Self {
        Self::new(alpha, alpha, eta)
    }

    /// The relative IOR every formula uses, [`clamp_eta`] of the field.
    #[inline(always)]
    pub fn eta(&self) -> f32 {
        clamp_eta(self.eta)
    }

    /// True when the interface is smooth: `sample` returns the mirror or the refracted
    /// direction, `eval` and `pdf` are 0.
    #[inline]
    pub fn is_delta(&self) -> bool {
        self.distribution.is_effectively_smooth()
    }

    /// The generalized half vector `wm = normalize(wo + eta' wi)` turned to `+z`, `None` when a
    /// direction is horizontal or zero, `wm` is degenerate, or the side rules fail
    /// (`wo.wm` must have the sign of `wo.z`, `wi.wm` that of `wi.z`).
    #[inline(always)]
    fn half(&self, wo: Vec3, wi: Vec3) -> Option<Half> {
        let side = wo.z * wi.z;
        if side == 0.0 || side.is_nan() {
            return None;
        }
        let reflect = side > 0.0;
        let eta = self.eta();
        let etap = if reflect {
            1.0
        } else if wo.z > 0.0 {
            eta
        } else {
            1.0 / eta
        };
        let wm = normalize_or_zero(wo + etap * wi);
        if !(wm.z != 0.0) {
            return None;
        }
        let wm = if wm.z < 0.0 { -wm } else { wm };
        let (cos_om, cos_im) = (wo.dot(wm), wi.dot(wm));
        if !(cos_om * wo.z > 0.0 && cos_im * wi.z > 0.0) {
            return None;
        }
        // pbrt-v3 #254: F of the outward-turned wm, negative cosine = from inside (TIR -> 1).
        let f = fresnel_dielectric(cos_om, eta);
        let (p_lobe, jacobian) = if reflect {
            (f, jacobian_reflection(cos_om))
        } else {
            (1.0 - f, jacobian_transmission(etap, cos_om, cos_im))
        };
        Some(Half { wm, reflect, etap, cos_om, p_lobe, jacobian })
    }

    /// Density of `wi` for a half vector: `p_lobe p(wm) dwm/dwi`, `p(wm)` = `D(wm) wm.z` (NDF)
    /// or `D_{wo'}(wm)` with `wo' = sign(wo.z) wo` (visible normals).
    #[inline(always)]
    fn pdf_half(&self, wo: Vec3, h: &Half, sampling: Sampling) -> f32 {
        let d = &self.distribution;
        let p_wm = match sampling {
            Sampling::Ndf => d.pdf_wm_ndf(h.wm),
            Sampling::Vndf | Sampling::SphericalCaps | Sampling::Bounded => d.d_visible(visible_side(wo), h.wm),
            Sampling::Cosine | Sampling::Uniform => 0.0,
        };
        finite_or_zero(h.p_lobe * p_wm * h.jacobian)
    }

    /// `f(wo, wi) |wi.z|`: `F D G2 / (4 |wo.z|)` for reflection,
    /// `(1 - F) D G2 |wo.wm| dwm/dwi / |wo.z|` (`/ eta'^2` for radiance) for transmission, with
    /// `dwm/dwi = eta'^2 |wi.wm| / (wo.wm + eta' wi.wm)^2`. Zero for a delta interface, a
    /// horizontal direction, a pair that breaks the side rules and degenerate input. Inputs need
    /// not be normalized.
    #[inline]
    pub fn eval(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> Vec3 {
        let (wo, wi) = (normalize_or_zero(wo), normalize_or_zero(wi));
        if self.is_delta() {
            return Vec3::ZERO;
        }
        let Some(h) = self.half(wo, wi) else { return Vec3::ZERO };
        self.eval_half(wo, wi, &h, mode)
    }

    /// `f(wo, wi) |wi.z|` for a half vector of normalized `wo`, `wi`:
    /// `p_lobe D G2 |wo.wm| dwm/dwi / |wo.z|` (`/ eta'^2` for transmitted radiance).
    #[inline(always)]
    fn eval_half(&self, wo: Vec3, wi: Vec3, h: &Half, mode: TransportMode) -> Vec3 {
        let d = &self.distribution;
        let dg = d.d(h.wm) * d.g2(wo, wi);
        let f = h.p_lobe * dg * (h.cos_om / wo.z).abs() * h.jacobian * transport_scale(h.reflect, h.etap, mode);
        Vec3::splat(finite_or_zero(f))
    }

    /// [`Self::eval`] and [`Self::pdf`] of one pair in one call, equal to both bit for bit: the
    /// generalized half vector, its Fresnel term and Jacobian are computed once (Mitsuba 3's
    /// `eval_pdf`). For light sampling with MIS, which needs both.
    #[inline]
    pub fn eval_pdf(&self, wo: Vec3, wi: Vec3, sampling: Sampling, mode: TransportMode) -> (Vec3, f32) {
        let (wo, wi) = (normalize_or_zero(wo), normalize_or_zero(wi));
        if self.is_delta() {
            return (Vec3::ZERO, 0.0);
        }
        match self.half(wo, wi) {
            Some(h) => (self.eval_half(wo, wi, &h, mode), self.pdf_half(wo, &h, sampling)),
            None => (Vec3::ZERO, 0.0),
        }
    }

    /// Solid-angle density with which [`Self::sample`] returns `wi`:
    /// `F D_wo'(wm) / (4 |wo.wm|)` (reflection) or `(1 - F) D_wo'(wm) dwm/dwi` (transmission),
    /// `D_wo'` the visible normals of `wo' = sign(wo.z) wo` (VNDF, spherical caps and bounded,
    /// which falls back to spherical caps), or `D(wm) wm.z` (NDF). Zero for cosine and uniform
    /// (refused: they cover one hemisphere), a delta interface and degenerate input. `mode`
    /// does not change the density.
    #[inline]
    pub fn pdf(&self, wo: Vec3, wi: Vec3, sampling: Sampling, mode: TransportMode) -> f32 {
        let _ = mode;
        let (wo, wi) = (normalize_or_zero(wo), normalize_or_zero(wi));
        if self.is_delta() {
            return 0.0;
        }
        match self.half(wo, wi) {
            Some(h) => self.pdf_half(wo, &h, sampling),
            None => 0.0,
        }
    }

    /// Draws `wi` for `wo` (either side): a microfacet normal from `u` (visible normals of
    /// `sign(wo.z) wo`, or the NDF), then reflection with probability `F(wo . wm)` (1 under total
    /// internal reflection) decided by `u_lobe`, else refraction. `Sampling::Bounded` (a bound
    /// for reflection only, Eto & Tokuyoshi 2023) samples spherical caps: its cap would drop
    /// normals whose transmission is valid. `Cosine` and `Uniform` are refused (`None`).
    /// Weights never divide by `D`: visible normals `G2 / G1(wo)`, NDF `G2 |wo.wm| / (|wo.z| wm.z)`,
    /// times `1 / eta'^2` for transmitted radiance. A delta interface returns the mirror
    /// direction with `pdf = F`, weight 1, or the refracted one with `pdf = 1 - F`, weight
    /// `1 / eta'^2` (radiance) or 1. `None` for `wo.z = 0`, degenerate input, and a sample that
    /// leaves its lobe's hemisphere or breaks the side rules.
    #[inline]
    pub fn sample(
        &self,
        wo: Vec3,
        u: Vec2,
        u_lobe: f32,
        sampling: Sampling,
        mode: TransportMode,
    ) -> Option<BsdfSample> {
        let wo = normalize_or_zero(wo);
        if !(wo.z != 0.0) || matches!(sampling, Sampling::Cosine | Sampling::Uniform) {
            return None;
        }
        let eta = self.eta();
        let u_lobe = sanitize_u(u_lobe);
        if self.is_delta() {
            let f = fresnel_dielectric(wo.z, eta);
            if u_lobe < f {
                return Some(BsdfSample {
                    wi: Vec3::new(-wo.x, -wo.y, wo.z),
                    weight: Vec3::ONE,
                    pdf: f,
                    is_delta: true,
                });
            }
            let wi = normalize_or_zero(refract(wo, Vec3::Z, eta)?);
            let etap = if wo.z > 0.0 { eta } else { 1.0 / eta };
            let (pdf, weight) = (1.0 - f, transport_scale(false, etap, mode));
            if !(wi.z * wo.z < 0.0 && pdf > 0.0 && weight.is_finite()) {
                return None;
            }
            return Some(BsdfSample { wi, weight: Vec3::splat(weight), pdf, is_delta: true });
        }
        let d = &self.distribution;
        let wv = visible_side(wo);
        let wm = match sampling {
            Sampling::Ndf => d.sample_wm_ndf(u),
            Sampling::Vndf => d.sample_wm_vndf(wv, u),
            _ => d.sample_wm_spherical_caps(wv, u),
        };
        let cos_om = wo.dot(wm);
        if !(cos_om * wo.z > 0.0) {
            return None;
        }
        let reflected = u_lobe < fresnel_dielectric(cos_om, eta);
        let wi = if reflected { reflect(wo, wm) } else { refract(wo, wm, eta)? };
        let wi = normalize_or_zero(wi);
        // Weight and pdf from the half vector of the returned pair (as GgxConductor does), so
        // that they agree with eval(wo, wi) / pdf(wo, wi) to rounding.
        let h = self.half(wo, wi)?;
        if h.reflect != reflected {
            return None;
        }
        let pdf = self.pdf_half(wo, &h, sampling);
        let g2 = d.g2(wo, wi);
        let ratio = match sampling {
            Sampling::Ndf => g2 * (h.cos_om / wo.z).abs() / h.wm.z,
            // G2 / G1(wo) <= 1.
            _ => (g2 / d.g1(wo)).min(1.0),
        };
        let weight = ratio * transport_scale(h.reflect, h.etap, mode);
        if !(pdf > 0.0 && pdf.is_finite() && weight.is_finite()) {
            return None;
        }
        Some(BsdfSample { wi, weight: Vec3::splat(weight), pdf, is_delta: false })
    }
}

/// `wo` turned to the `+z` side, whose visible normals the samplers draw: `sign(wo.z) wo`.
#[inline(always)]
fn visible_side(wo: Vec3) -> Vec3 {
    if wo.z < 0.0 { -wo } else { wo }
}

/// The dielectric through the interface (the inherent methods, same arguments).
impl Bxdf for GgxDielectric {
    #[inline]
    fn eval(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> Vec3 {
        GgxDielectric::eval(self, wo, wi, mode)
    }

    #[inline]
    fn pdf(&self, wo: Vec3, wi: Vec3, sampling: Sampling, mode: TransportMode) -> f32 {
        GgxDielectric::pdf(self, wo, wi, sampling, mode)
    }

    #[inline]
    fn eval_pdf(&self, wo: Vec3, wi: Vec3, sampling: Sampling, mode: TransportMode) -> (Vec3, f32) {
        GgxDielectric::eval_pdf(self, wo, wi, sampling, mode)
    }

    #[inline]
    fn sample(&self, wo: Vec3, u: Vec2, u_lobe: f32, sampling: Sampling, mode: TransportMode) -> Option<BsdfSample> {
        GgxDielectric::sample(self, wo, u, u_lobe, sampling, mode)
    }

    #[inline]
    fn flags(&self) -> BxdfFlags {
        let lobe = if self.is_delta() { BxdfFlags::SPECULAR } else { BxdfFlags::GLOSSY };
        BxdfFlags::REFLECTION.union(BxdfFlags::TRANSMISSION).union(lobe)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layout_is_16_bytes_of_u32_words() {
        assert_eq!(core::mem::size_of::<GgxDielectric>(), 16);
        assert_eq!(core::mem::size_of::<GgxDielectric>() % 16, 0);
        assert_eq!(core::mem::align_of::<GgxDielectric>(), 4);
        let b = GgxDielectric::new(0.2, 0.3, 1.5);
        let words: [u32; 4] = bytemuck::cast(b);
        assert_eq!(words, [0.2f32.to_bits(), 0.3f32.to_bits(), 1.5f32.to_bits(), 0]);
        assert_eq!(core::mem::size_of::<TransportMode>(), 4);
    }

    #[test]
    fn refract_obeys_snell_and_round_trips() {
        let w = Vec3::new(0.6, 0.0, 0.8);
        let t = refract(w, Vec3::Z, 1.5).unwrap();
        assert!((t.length() - 1.0).abs() < 1e-6 && t.z < 0.0);
        assert!((0.6 - 1.5 * (-t.x)).abs() < 1e-6, "sin_i = eta sin_t");
        let back = refract(t, Vec3::Z, 1.5).unwrap();
        assert!((back - w).length() < 1e-6);
        // Total internal reflection from inside beyond the critical angle (41.8 deg).
        assert!(refract(Vec3::new(0.8, 0.0, -0.6), Vec3::Z, 1.5).is_none());
    }
}
