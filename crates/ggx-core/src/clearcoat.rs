//! glTF's `KHR_materials_clearcoat` over the metallic-roughness BRDF, composed from the crate's
//! pieces: the base is a [`GltfMetalRough`], the coat lobe is [`GgxConductor`] with `F = 1`
//! (Trowbridge-Reitz `D`, height-correlated Smith `G2`) on the shading normal, and the layers
//! are mixed by [`fresnel_schlick`] at `f0 = 0.04` (the coat's `ior = 1.5`); sampled as a
//! one-sample MIS mixture of the coat lobe and the base's own sampler.

use crate::bxdf::{Bxdf, BxdfFlags, TransportMode};
use crate::conductor::{BsdfSample, GgxConductor};
use crate::distribution::TrowbridgeReitz;
use crate::fresnel::{FresnelParams, fresnel_schlick, kind};
use crate::math::{normalize_or_zero, sanitize_u};
use crate::metal_rough::GltfMetalRough;
use crate::sampling::Sampling;
use glam::{Vec2, Vec3};
// Fields and results are clamped to [0, 1], -0.0 and NaN read as +0.0.
use crate::math::saturate as unit;

/// The coat's normal-incidence reflectance, `((1 - ior) / (1 + ior))^2` at the extension's fixed
/// `ior = 1.5` (`KHR_materials_clearcoat`, `fresnel_coat`).
pub const CLEARCOAT_F0: f32 = 0.04;

/// Smallest probability with which [`GltfClearcoat::sample`] draws a present coat lobe.
pub const P_COAT_MIN: f32 = 0.05;

/// Largest probability with which [`GltfClearcoat::sample`] draws the coat lobe (the base keeps
/// at least `1 - P_COAT_MAX`).
pub const P_COAT_MAX: f32 = 0.95;

/// `fr(mu) = 0.04 + 0.96 (1 - |mu|)^5`, KHR_materials_clearcoat `fresnel_coat` ([`fresnel_schlick`]
/// at [`CLEARCOAT_F0`]); in `[0.04, 1]`, NaN `mu` -> 1.
#[inline]
pub fn clearcoat_fresnel(cos: f32) -> f32 {
    // min: f0 + (1 - f0) x may round one ulp above 1.
    fresnel_schlick(cos.abs(), Vec3::splat(CLEARCOAT_F0), Vec3::ONE).x.min(1.0)
}

/// `m mean(F_avg(base)) + (1 - m) (sw F_avg(max f0) + max(1 - sw F_avg(max f0), 0) mean(base))`
/// with `F_avg(f0) = f0 + (1 - f0) / 21`: the base's view-independent albedo estimate, the
/// `a_s + a_d` of [`GltfMetalRough::new`] ([`GltfMetalRough::albedo_estimate`]); in `[0, 1]`.
#[inline]
pub fn metal_rough_albedo_estimate(base: &GltfMetalRough) -> f32 {
    base.albedo_estimate()
}

/// glTF's `KHR_materials_clearcoat` over the metallic-roughness BRDF; reflection only, `wo` and
/// `wi` above the horizon as in [`GltfMetalRough`]:
///
/// ```text
/// coat_brdf = D_c(h) G2_c(wo, wi) / (4 |wo.z| |wi.z|)        (GgxConductor with F = 1, alpha_c)
/// fr(mu)    = 0.04 + 0.96 (1 - |mu|)^5                        (fresnel_coat, ior = 1.5)
/// f         = mix(base, coat_brdf, weight fr(wo.z))           (clearcoat normal = shading normal)
/// ```
///
/// The coat lobe has the isotropic alpha of the caller (glTF's `clearcoatRoughness^2`); below
/// [`crate::DELTA_ALPHA`] it is a mirror (`sample` returns it as a delta, `eval` and `pdf` leave it
/// out) while the base stays. `weight = 0` is the base bit for bit. The clearcoat normal texture
/// is not supported: the coat shares the base's shading normal, so `fr` depends on `wo.z` only.
///
/// 64-byte `#[repr(C)]` POD (offsets: `base` 0, `coat` 48, `weight` 56, `base_albedo` 60; a
/// multiple of 16, ready for a GPU storage buffer). Any bit pattern in the fields is accepted:
/// `weight` and `base_albedo` are read clamped into `[0, 1]` (NaN -> 0), the coat's alphas
/// through [`TrowbridgeReitz::alphas`] and the base as [`GltfMetalRough`] reads it.
#[repr(C)]
#[derive(Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
#[cfg_attr(not(target_arch = "spirv"), derive(Debug))]
pub struct GltfClearcoat {
    /// The material under the coat.
    pub base: GltfMetalRough,
    /// The coat lobe's distribution (`clearcoatRoughnessFactor^2`, isotropic).
    pub coat: TrowbridgeReitz,
    /// `clearcoatFactor` (times its texture) in `[0, 1]`; 0 is the base alone.
    pub weight: f32,
    /// [`metal_rough_albedo_estimate`] of `base`, in `[0, 1]`: shapes the lobe probability
    /// ([`Self::coat_probability`]).
    pub base_albedo: f32,
}

impl GltfClearcoat {
    /// The coated material from glTF parameters: `weight` (`clearcoatFactor`) NaN or infinite -> 0
    /// then clamped to `[0, 1]`, `coat_alpha` (`clearcoatRoughnessFactor^2`) through
    /// [`TrowbridgeReitz::isotropic`] as [`GgxConductor::new`] clamps it, `base_albedo` =
    /// [`metal_rough_albedo_estimate`]`(base)`.
    #[inline]
    pub fn new(base: GltfMetalRough, weight: f32, coat_alpha: f32) -> Self {
        let weight = if weight.is_finite() { unit(weight) } else { 0.0 };
        Self {
            base,
            coat: TrowbridgeReitz::isotropic(coat_alpha),
            weight,
            base_albedo: metal_rough_albedo_estimate(&base),
        }
    }

    /// `clamp(weight, 0, 1)`, NaN -> 0: `clearcoatFactor` as every method reads it.
    #[inline]
    pub fn coat_weight(&self) -> f32 {
        unit(self.weight)
    }

    /// `max(alpha_x, alpha_y) < DELTA_ALPHA` of the coat: a mirror coat (a delta in `sample`,
    /// absent from `eval` and `pdf`).
    #[inline]
    pub fn coat_is_delta(&self) -> bool {
        self.coat.is_effectively_smooth()
    }

    /// `D G2 / (4 |wo.z| |wi.z|)`: [`GgxConductor`] of `coat` with `F = 1`, KHR_materials_clearcoat's
    /// `clearcoat_brdf`, whose `eval`, `pdf` and `sample` this BRDF composes.
    #[inline]
    pub fn coat_lobe(&self) -> GgxConductor {
        let one = FresnelParams { kind: kind::ONE, eta: 1.0, pad: [0; 2], a: [0.0; 4], b: [0.0; 4] };
        GgxConductor { distribution: self.coat, pad: [0; 2], fresnel: one }
    }

    /// `c = weight fr(cos)`, `fr = 0.04 + 0.96 (1 - |cos|)^5`: the mix factor of
    /// KHR_materials_clearcoat's `fresnel_coat` at `cos = wo.z`; in `[0, 1]`.
    #[inline]
    pub fn coat_mix(&self, cos: f32) -> f32 {
        self.coat_weight() * clearcoat_fresnel(cos)
    }

    /// `1 - c = (1 - weight) + weight (1 - f0) (1 - (1 - |cos|)^5)`: the base's share in
    /// KHR_materials_clearcoat's `fresnel_coat` mix at `cos = wo.z`, in `[0, 1]`, without the
    /// cancellation of `1 - coat_mix(cos)` at grazing views (`1 - (1 - x)^5` as
    /// `x (5 - 10 x + 10 x^2 - 5 x^3 + x^4)` below `x = 1/2`); NaN `cos` -> `1 - weight`.
    #[inline]
    pub fn base_mix(&self, cos: f32) -> f32 {
        let w = self.coat_weight();
        let x = cos.abs().max(0.0).min(1.0);
        let grazing = if x < 0.5 {
            x * (5.0 + x * (-10.0 + x * (10.0 + x * (-5.0 + x))))
        } else {
            let m = 1.0 - x;
            let m2 = m * m;
            1.0 - m2 * m2 * m
        };
        ((1.0 - w) + w * (1.0 - CLEARCOAT_F0) * grazing).min(1.0)
    }

    /// `p_c = clamp(c / (c + (1 - c) a_b), 0.05, 0.95)`, `c` = [`Self::coat_mix`]`(cos)`, `1 - c` =
    /// [`Self::base_mix`]`(cos)`,
    /// `a_b = clamp(base_albedo, 0, 1)` (NaN -> 0.05): the coat's share of the albedo estimate, the
    /// probability of the coat lobe in [`Self::sample`] at `cos = wo.z`; exactly 0 without a coat.
    #[inline]
    pub fn coat_probability(&self, cos: f32) -> f32 {
        if !(self.coat_weight() > 0.0) {
            return 0.0;
        }
        let c = self.coat_mix(cos);
        let p = c / (c + self.base_mix(cos) * unit(self.base_albedo));
        p.max(P_COAT_MIN).min(P_COAT_MAX)
    }

    /// `f |wi.z| = (1 - c) base.eval + c coat_lobe.eval`, `c = weight fr(wo.z)`
    /// (KHR_materials_clearcoat `fresnel_coat`; `1 - c` from [`Self::base_mix`]); zero unless
    /// `wo.z > 0` and `wi.z > 0`; `base.eval` bit for bit when the weight is 0. Inputs need not
    /// be normalized.
    #[inline]
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if !(self.coat_weight() > 0.0) {
            return self.base.eval(wo, wi);
        }
        let (wo, wi) = (normalize_or_zero(wo), normalize_or_zero(wi));
        if !(wo.z > 0.0 && wi.z > 0.0) {
            return Vec3::ZERO;
        }
        self.mix_f(wo.z, self.base.eval(wo, wi), self.coat_lobe().eval(wo, wi))
    }

    /// `(1 - c) f_base + c f_coat` for `wo.z` (the lobes' `f |wi.z|`).
    #[inline(always)]
    fn mix_f(&self, mu_o: f32, f_base: Vec3, f_coat: Vec3) -> Vec3 {
        f_base * self.base_mix(mu_o) + f_coat * self.coat_mix(mu_o)
    }

    /// The mixture density `p_c pdf_coat + (1 - p_c) pdf_base` for `wo.z`.
    #[inline(always)]
    fn mix_pdf(&self, mu_o: f32, pdf_base: f32, pdf_coat: f32) -> f32 {
        let p = self.coat_probability(mu_o);
        // Both terms finite and non-negative (GgxConductor::pdf, GltfMetalRough::pdf).
        p * pdf_coat + (1.0 - p) * pdf_base
    }

    /// [`Self::eval`] and [`Self::pdf`] in one call, equal to both bit for bit (each lobe's
    /// `eval_pdf` shares its half-vector terms).
    #[inline]
    pub fn eval_pdf(&self, wo: Vec3, wi: Vec3, sampling: Sampling) -> (Vec3, f32) {
        if !(self.coat_weight() > 0.0) {
            return self.base.eval_pdf(wo, wi, sampling);
        }
        let (wo, wi) = (normalize_or_zero(wo), normalize_or_zero(wi));
        if !(wo.z > 0.0 && wi.z > 0.0) {
            return (Vec3::ZERO, 0.0);
        }
        let (f_base, pdf_base) = self.base.eval_pdf(wo, wi, sampling);
        let (f_coat, pdf_coat) = self.coat_lobe().eval_pdf(wo, wi, sampling);
        (self.mix_f(wo.z, f_base, f_coat), self.mix_pdf(wo.z, pdf_base, pdf_coat))
    }

    /// `p_c pdf_coat + (1 - p_c) pdf_base`, `p_c` = [`Self::coat_probability`]`(wo.z)`: the density
    /// of the one-sample MIS mixture [`Self::sample`] (mirror lobes left out); zero unless
    /// `wo.z > 0` and `wi.z > 0`; `base.pdf` bit for bit when the weight is 0.
    #[inline]
    pub fn pdf(&self, wo: Vec3, wi: Vec3, sampling: Sampling) -> f32 {
        if !(self.coat_weight() > 0.0) {
            return self.base.pdf(wo, wi, sampling);
        }
        let (wo, wi) = (normalize_or_zero(wo), normalize_or_zero(wi));
        if !(wo.z > 0.0 && wi.z > 0.0) {
            return 0.0;
        }
        self.mix_pdf(wo.z, self.base.pdf(wo, wi, sampling), self.coat_lobe().pdf(wo, wi, sampling))
    }

    /// Draws `wi`: the coat lobe ([`GgxConductor::sample`] from `u`) if `u_lobe < p_c`, else
    /// `base.sample(u, (u_lobe - p_c) / (1 - p_c))`; `pdf` = [`Self::pdf`], `weight = eval / pdf`.
    ///
    /// A mirror coat is returned as a delta sample as [`GltfMetalRough`] returns its mirror: the
    /// mirror direction, `pdf = p_c` (the lobe's probability) and `weight = coat_mix(wo.z) / p_c`;
    /// a mirror lobe of the base keeps the base's delta sample with the probability `(1 - p_c) p_s`
    /// and the weight `(1 - c) specular_fresnel(wo.z) / pdf`. `None` for `wo.z <= 0`, where the
    /// chosen lobe's sampler refuses, and for degenerate input; `base.sample` bit for bit when
    /// the weight is 0.
    #[inline]
    pub fn sample(&self, wo: Vec3, u: Vec2, u_lobe: f32, sampling: Sampling) -> Option<BsdfSample> {
        if !(self.coat_weight() > 0.0) {
            return self.base.sample(wo, u, u_lobe, sampling);
        }
        let wo = normalize_or_zero(wo);
        if !(wo.z > 0.0) {
            return None;
        }
        let p = self.coat_probability(wo.z);
        let u_lobe = sanitize_u(u_lobe);
        let wi = if u_lobe < p {
            let s = self.coat_lobe().sample(wo, u, sampling)?;
            if s.is_delta {
                let weight = Vec3::splat(self.coat_mix(wo.z) / p);
                return Some(BsdfSample { wi: s.wi, weight, pdf: p, is_delta: true });
            }
            s.wi
        } else {
            // Uniform on [0, 1) again (the base's sanitize_u catches a quotient rounded to 1).
            let s = self.base.sample(wo, u, (u_lobe - p) / (1.0 - p), sampling)?;
            if s.is_delta {
                let pdf = (1.0 - p) * s.pdf;
                let weight = self.base.specular_fresnel(wo.z) * self.base_mix(wo.z) / pdf;
                if !(pdf > 0.0 && weight.is_finite()) {
                    return None;
                }
                return Some(BsdfSample { wi: s.wi, weight, pdf, is_delta: true });
            }
            s.wi
        };
        let pdf = self.pdf(wo, wi, sampling);
        let weight = self.eval(wo, wi) / pdf;
        if !(pdf > 0.0 && pdf.is_finite() && weight.is_finite()) {
            return None;
        }
        Some(BsdfSample { wi, weight, pdf, is_delta: false })
    }
}

/// The clearcoat through the interface: `u_lobe` picks the coat or the base (and, rescaled, the
/// base's lobe), `mode` is ignored (reflection only). Flags: the base's, plus `GLOSSY` for a
/// rough coat or `SPECULAR` for a mirror coat when the weight is above 0.
impl Bxdf for GltfClearcoat {
    #[inline]
    fn eval(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> Vec3 {
        GltfClearcoat::eval(self, wo, wi)
    }

    #[inline]
    fn pdf(&self, wo: Vec3, wi: Vec3, sampling: Sampling, _mode: TransportMode) -> f32 {
        GltfClearcoat::pdf(self, wo, wi, sampling)
    }

    #[inline]
    fn eval_pdf(&self, wo: Vec3, wi: Vec3, sampling: Sampling, _mode: TransportMode) -> (Vec3, f32) {
        GltfClearcoat::eval_pdf(self, wo, wi, sampling)
    }

    #[inline]
    fn sample(&self, wo: Vec3, u: Vec2, u_lobe: f32, sampling: Sampling, _mode: TransportMode) -> Option<BsdfSample> {
        GltfClearcoat::sample(self, wo, u, u_lobe, sampling)
    }

    #[inline]
    fn flags(&self) -> BxdfFlags {
        let flags = Bxdf::flags(&self.base);
        if !(self.coat_weight() > 0.0) {
            return flags;
        }
        flags.union(if self.coat_is_delta() { BxdfFlags::SPECULAR } else { BxdfFlags::GLOSSY })
    }
}
