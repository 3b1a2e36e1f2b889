//! The energy-compensated GGX conductor: single scattering plus the Kulla & Conty 2017
//! multiple-scattering lobe, sampled as a one-sample MIS mixture.

use crate::conductor::{BsdfSample, GgxConductor};
use crate::energy::{albedo, average_albedo, effective_alpha, multiple_scattering_fresnel};
use crate::math::{finite_or_zero, normalize_or_zero, sanitize_u};
use crate::sampling::Sampling;
use crate::warp;
use core::f32::consts::FRAC_1_PI;
use glam::{Vec2, Vec3};
// Fields and results are clamped to [0, 1], -0.0 and NaN read as +0.0.
use crate::math::saturate as unit;

/// [`GgxConductor`] with the multiple-scattering lobe of Kulla & Conty 2017:
///
/// `f = f_ss + f_ms`, `f_ms(wo, wi) = F_ms (1 - E(mu_o)) (1 - E(mu_i)) / (pi (1 - E_avg))`,
/// `F_ms = F_avg^2 E_avg / (1 - F_avg (1 - E_avg))`, with `E`, `E_avg` from
/// [`crate::energy`] at [`effective_alpha`] and `F_avg = 2 integral F(mu) mu dmu`
/// ([`crate::FresnelParams::average`]). With `F = 1` the albedo `integral f |wi.z| dwi` is 1.
/// `f_ms` is symmetric in `wo`, `wi` (reciprocal) and integrates to `F_ms (1 - E(mu_o))`.
///
/// 80-byte `#[repr(C)]` POD. `compensation == 0` makes every method exactly
/// [`GgxConductor`]'s (a GPU can switch the lobe per material); `f_avg` caches
/// `conductor.fresnel.average()` (set by [`Self::new`]; raw values are clamped into `[0, 1]`,
/// NaN -> 0, where read).
#[repr(C)]
#[derive(Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
#[cfg_attr(not(target_arch = "spirv"), derive(Debug))]
pub struct GgxConductorMs {
    /// The single-scattering lobe.
    pub conductor: GgxConductor,
    /// `F_avg = 2 integral F(mu) mu dmu` of `conductor.fresnel`, RGB.
    pub f_avg: [f32; 3],
    /// Non-zero: add the multiple-scattering lobe; 0: behave exactly as `conductor`.
    pub compensation: u32,
}

impl GgxConductorMs {
    /// The compensated conductor: `f_avg = conductor.fresnel.average()`, `compensation = 1`.
    #[inline]
    pub fn new(conductor: GgxConductor) -> Self {
        let f = conductor.fresnel.average();
        Self { conductor, f_avg: [f.x, f.y, f.z], compensation: 1 }
    }

    /// True when the multiple-scattering lobe is on: `compensation != 0` and the lobe is not a
    /// mirror (a delta lobe keeps all its energy: `E = 1`).
    #[inline]
    pub fn is_compensated(&self) -> bool {
        self.compensation != 0 && !self.conductor.is_delta()
    }

    /// `F_ms` of the material ([`multiple_scattering_fresnel`] of the cached `f_avg` and
    /// `E_avg(effective_alpha)`), in `[0, 1]` per channel.
    #[inline]
    pub fn ms_fresnel(&self) -> Vec3 {
        let f_avg = Vec3::new(unit(self.f_avg[0]), unit(self.f_avg[1]), unit(self.f_avg[2]));
        multiple_scattering_fresnel(f_avg, average_albedo(effective_alpha(&self.conductor.distribution)))
    }

    /// The multiple-scattering lobe alone, times `|wi.z|`:
    /// `F_ms (1 - E(mu_o)) (1 - E(mu_i)) / (pi (1 - E_avg)) wi.z` (Kulla & Conty 2017). Zero
    /// below the horizon, for a mirror, when `compensation == 0`, and where `E_avg` rounds to 1
    /// (`1 - E_avg < 1e-6`, where `1 - E` is 0 too). Inputs need not be normalized.
    #[inline]
    pub fn eval_ms(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        let (wo, wi) = (normalize_or_zero(wo), normalize_or_zero(wi));
        if !(wo.z > 0.0 && wi.z > 0.0 && self.is_compensated()) {
            return Vec3::ZERO;
        }
        let alpha = effective_alpha(&self.conductor.distribution);
        let one_minus_avg = 1.0 - average_albedo(alpha);
        // average_albedo is never NaN.
        if one_minus_avg < 1e-6 {
            return Vec3::ZERO;
        }
        let s = (1.0 - albedo(wo.z, alpha)) * (1.0 - albedo(wi.z, alpha)) * FRAC_1_PI / one_minus_avg;
        self.ms_fresnel() * finite_or_zero(s * wi.z)
    }

    /// `f(wo, wi) |wi.z| = (f_ss + f_ms) |wi.z|`: [`GgxConductor::eval`] plus [`Self::eval_ms`].
    #[inline(always)]
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        self.conductor.eval(wo, wi) + self.eval_ms(wo, wi)
    }

    /// Probability with which [`Self::sample`] picks the multiple-scattering lobe for `wo`:
    /// its albedo over the total, `P_ms = a_ms / (a_ss + a_ms)`, `a_ms = mean(F_ms) (1 -
    /// E(mu_o))`, `a_ss = mean(F_avg) E(mu_o)` (an estimate; any value in `[0, 1)` keeps the
    /// sampler exact). In `[0, 1]`; 0 when the lobe is off or `wo.z <= 0`.
    #[inline]
    pub fn ms_probability(&self, wo: Vec3) -> f32 {
        let wo = normalize_or_zero(wo);
        if !(wo.z > 0.0) || !self.is_compensated() {
            return 0.0;
        }
        let e = albedo(wo.z, effective_alpha(&self.conductor.distribution));
        let f_ms = self.ms_fresnel();
        let a_ms = (f_ms.x + f_ms.y + f_ms.z) * (1.0 / 3.0) * (1.0 - e);
        let a_ss = (unit(self.f_avg[0]) + unit(self.f_avg[1]) + unit(self.f_avg[2])) * (1.0 / 3.0) * e;
        let p = a_ms / (a_ss + a_ms);
        // 0 / 0 (black Fresnel) -> 0; never 1, so the single-scattering lobe is always sampled.
        finite_or_zero(p).max(0.0).min(0.999)
    }

    /// Solid-angle density of [`Self::sample`]: the one-sample MIS mixture
    /// `(1 - P_ms) pdf_ss(wi) + P_ms wi.z / pi`, with `pdf_ss` = [`GgxConductor::pdf`] for the
    /// technique and `P_ms` = [`Self::ms_probability`]. Zero below the horizon and for a mirror.
    #[inline]
    pub fn pdf(&self, wo: Vec3, wi: Vec3, sampling: Sampling) -> f32 {
        self.mix_pdf(wo, wi, self.conductor.pdf(wo, wi, sampling))
    }

    /// [`Self::eval`] and [`Self::pdf`] in one call, equal to both bit for bit (the conductor's
    /// [`GgxConductor::eval_pdf`] shares its half-vector terms).
    #[inline(always)]
    pub fn eval_pdf(&self, wo: Vec3, wi: Vec3, sampling: Sampling) -> (Vec3, f32) {
        let (f_ss, pdf_ss) = self.conductor.eval_pdf(wo, wi, sampling);
        (f_ss + self.eval_ms(wo, wi), self.mix_pdf(wo, wi, pdf_ss))
    }

    /// The one-sample mixture's density `(1 - P_ms) pdf_ss + P_ms wi.z / pi` from the
    /// single-scattering lobe's `pdf_ss` (that alone without compensation).
    #[inline(always)]
    fn mix_pdf(&self, wo: Vec3, wi: Vec3, pdf_ss: f32) -> f32 {
        if !self.is_compensated() {
            return pdf_ss;
        }
        let p = self.ms_probability(wo);
        let pdf_ms = warp::pdf_cosine_hemisphere(normalize_or_zero(wi));
        finite_or_zero((1.0 - p) * pdf_ss + p * pdf_ms)
    }

    /// Draws `wi`: the multiple-scattering lobe (cosine-weighted, [`warp::sample_cosine_hemisphere`]
    /// of `u`) when `u_lobe < P_ms`, else [`GgxConductor::sample`] with the technique. The
    /// returned `pdf` is [`Self::pdf`] and `weight = eval / pdf` of the returned pair (one-sample
    /// MIS over both lobes). `None` where the conductor's sampler refuses, and for degenerate
    /// input. Without compensation (or for a mirror) exactly [`GgxConductor::sample`].
    #[inline(always)]
    pub fn sample(&self, wo: Vec3, u: Vec2, u_lobe: f32, sampling: Sampling) -> Option<BsdfSample> {
        if !self.is_compensated() {
            return self.conductor.sample(wo, u, sampling);
        }
        let wo = normalize_or_zero(wo);
        if !(wo.z > 0.0) {
            return None;
        }
        let wi = if sanitize_u(u_lobe) < self.ms_probability(wo) {
            warp::sample_cosine_hemisphere(u)
        } else {
            self.conductor.sample(wo, u, sampling)?.wi
        };
        let pdf = self.pdf(wo, wi, sampling);
        let weight = self.eval(wo, wi) / pdf;
        if !(pdf > 0.0 && pdf.is_finite() && weight.is_finite()) {
            return None;
        }
        Some(BsdfSample { wi, weight, pdf, is_delta: false })
    }
}
