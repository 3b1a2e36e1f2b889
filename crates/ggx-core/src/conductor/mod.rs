//! The GGX microfacet reflection BRDF (Cook-Torrance with height-correlated Smith G2).
//!
//! Its microfacet factor is written once over [`crate::lanes::Lanes`] in [`formulas`].

pub mod formulas;

use crate::fresnel::{Fresnel, FresnelParams};
use crate::math::{finite_or_zero, normalize_or_zero, sanitize_u2};
use crate::sampling::Sampling;
use crate::warp;
use crate::{TrowbridgeReitz, reflect};
use glam::{Vec2, Vec3};

/// A sampled direction and its Monte Carlo weight.
#[derive(Clone, Copy, PartialEq)]
#[cfg_attr(not(target_arch = "spirv"), derive(Debug))]
pub struct BsdfSample {
    /// Sampled incident direction (unit; `z > 0` from [`GgxConductor`], on either side from
    /// [`crate::GgxDielectric`]: the side of `wo` for reflection, the other for transmission).
    pub wi: Vec3,
    /// `eval(wo, wi) / pdf`, i.e. `f |cos theta_i| / pdf`; for a delta lobe, `F`.
    pub weight: Vec3,
    /// Solid-angle density of `wi` under the chosen technique. For a delta lobe, which has no
    /// density, the discrete probability with which `sample` chose it (1 for a mirror
    /// conductor, `F` or `1 - F` for a smooth dielectric); MIS takes [`Self::mis_pdf`].
    pub pdf: f32,
    /// True when the lobe is a mirror (alpha below [`crate::DELTA_ALPHA`]).
    pub is_delta: bool,
}

impl BsdfSample {
    /// The density MIS helpers take ([`crate::mis`]): `+inf` for a delta lobe, so that it wins
    /// against any light-sampling density (weight 1, as a delta direction can only be found by
    /// the BSDF), otherwise `pdf` (NaN, negative and infinite values as 0).
    #[inline]
    pub fn mis_pdf(&self) -> f32 {
        if self.is_delta { f32::INFINITY } else { finite_or_zero(self.pdf).max(0.0) }
    }

    /// True when the sample crossed the surface (transmission): `wi` and `wo` lie on opposite
    /// sides, `wo.z wi.z < 0`. Reflection keeps the side, so this is exactly which lobe
    /// `sample` took (a method, not a field, so that every existing `BsdfSample { .. }`
    /// literal keeps compiling). False for a zero, horizontal or NaN `wo`.
    #[inline]
    pub fn is_transmission(&self, wo: Vec3) -> bool {
        wo.z * self.wi.z < 0.0
    }

    /// The lobe flag of the sample: [`crate::BxdfFlags::TRANSMISSION`] when
    /// [`Self::is_transmission`], else [`crate::BxdfFlags::REFLECTION`].
    #[inline]
    pub fn lobe(&self, wo: Vec3) -> crate::BxdfFlags {
        if self.is_transmission(wo) { crate::BxdfFlags::TRANSMISSION } else { crate::BxdfFlags::REFLECTION }
    }
}

/// GGX reflection off a conductor (or any interface whose transmission is discarded):
/// `f(wo, wi) = F(wo . wm) D(wm) G2(wo, wi) / (4 |wo.z| |wi.z|)` with the height-correlated
/// `G2`. 64-byte `#[repr(C)]` POD, ready to upload to a GPU.
#[repr(C)]
#[derive(Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
#[cfg_attr(not(target_arch = "spirv"), derive(Debug))]
pub struct GgxConductor {
    /// The microfacet distribution.
    pub distribution: TrowbridgeReitz,
    /// Padding to 16 bytes.
    pub pad: [u32; 2],
    /// The Fresnel model.
    pub fresnel: FresnelParams,
}

/// A direction reflected about a sampled microfacet normal ([`reflect_about`]).
#[derive(Clone, Copy)]
pub(crate) struct Reflected {
    /// The unit reflected direction; zero where the sample is invalid.
    pub wi: Vec3,
    /// Its density under the technique; zero where the sample is invalid.
    pub pdf: f32,
    /// The weight divided by the Fresnel term (for VNDF `G2 / G1(wo) <= 1`).
    pub scale: f32,
    /// `wo . wm` at the half vector of the returned pair: the Fresnel term's argument.
    pub cos_om: f32,
}

/// `wi = reflect(wo, wm)` for a normal `wm` sampled by `sampling` at a unit `wo`, with its density and weight / F (closed forms that never divide by `D`: VNDF
/// `G2 / G1(wo)`, bounded `zi (k zo + so) / (zi so + zo si)`, NDF `G2 |wo.wm| / (zo wm.z)`).
/// Invalid (zero `wi` and pdf) where `wm` faces away from `wo` or is zero (what the samplers
/// return for `wo.z <= 0`), `wi` falls at or below the
/// horizon, or the density is not finite and positive. Branch-free but for the uniform
/// `sampling`, so that `crate::batch` runs this very function on each lane.
#[inline(always)]
pub(crate) fn reflect_about(d: &TrowbridgeReitz, wo: Vec3, wm: Vec3, sampling: Sampling) -> Reflected {
    let cos_sampled = wo.dot(wm);
    let wi = normalize_or_zero(reflect(wo, wm));
    // Weight and pdf from the half vector of the returned pair, so that they agree with
    // eval(wo, wi) / pdf(wo, wi) even where reflect() cancels at grazing angles.
    let wm = normalize_or_zero(wo + wi);
    let cos_om = wo.dot(wm);
    let so = d.stretched_len(wo);
    let denom = formulas::g2_denominator(d.widths(), wo.into(), wi.into(), so);
    let (pdf, scale) = match sampling {
        Sampling::Ndf => (d.pdf_wm_ndf(wm) / (4.0 * cos_om), 4.0 * wi.z * cos_om / (wm.z * denom)),
        Sampling::Bounded => {
            let c = d.bounded_k(wo) * wo.z + so;
            // <= 1 analytically (k <= 1, zi <= si); the min guards subnormal rounding.
            (d.d(wm) / (2.0 * c), (2.0 * wi.z * c / denom).min(1.0))
        }
        // G2 / G1(wo) <= 1.
        _ => (d.d(wm) / (2.0 * (wo.z + so)), (2.0 * wi.z * (wo.z + so) / denom).min(1.0)),
    };
    let ok = cos_sampled > 0.0 && wi.z > 0.0 && pdf > 0.0 && pdf.is_finite();
    Reflected { wi: if ok { wi } else { Vec3::ZERO }, pdf: if ok { pdf } else { 0.0 }, scale, cos_om }
}

impl GgxConductor {
    /// BRDF with alphas clamped to `[ALPHA_MIN, ALPHA_MAX]`; a lobe with both alphas below
    /// [`crate::DELTA_ALPHA`] is a mirror.
    #[inline]
    pub fn new(alpha_x: f32, alpha_y: f32, fresnel: Fresnel) -> Self {
        Self { distribution: TrowbridgeReitz::new(alpha_x, alpha_y), pad: [0; 2], fresnel: fresnel.into() }
    }

    /// Isotropic BRDF.
    #[inline]
    pub fn isotropic(alpha: f32, fresnel: Fresnel) -> Self {
        Self::new(alpha, alpha, fresnel)
    }

    /// The Fresnel model as an enum.
    pub fn fresnel(&self) -> Fresnel {
        self.fresnel.to_fresnel()
    }

    /// True when the lobe is a mirror: `sample` returns the reflection, `eval` and `pdf` are 0.
    #[inline]
    pub fn is_delta(&self) -> bool {
        self.distribution.is_effectively_smooth()
    }

    /// `f(wo, wi) |wi.z| = F D G2 / (4 |wo.z|) = F D |wi.z| / (2 (|wi.z| so + |wo.z| si))`;
    /// zero when either direction is at or below the horizon, for a delta lobe, and for
    /// degenerate input. Inputs need not be normalized.
    #[inline(always)]
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        self.eval_with(wo, wi, |cos| self.fresnel.eval(cos))
    }

    /// [`Self::eval`] with the Fresnel term `fresnel(wo . wm)`, branch-free (every guard is a
    /// select on values computed for every input), so that `crate::batch` runs this very
    /// function on each lane with the Fresnel kind chosen once per batch.
    #[inline(always)]
    pub(crate) fn eval_with(&self, wo: Vec3, wi: Vec3, fresnel: impl Fn(f32) -> Vec3) -> Vec3 {
        let (f, cos_om) = formulas::reflection(self.distribution.widths(), wo.into(), wi.into());
        let value = fresnel(cos_om) * f;
        if self.is_delta() { Vec3::ZERO } else { value }
    }

    /// Solid-angle density with which [`Self::sample`] returns `wi` for the technique:
    /// NDF `D(wm) wm.z / (4 wo.wm)`, VNDF and spherical caps `D_wo(wm) / (4 wo.wm) =
    /// D(wm) / (2 (wo.z + so))`, bounded `D(wm) / (2 (k wo.z + so))`, cosine `wi.z / pi`,
    /// uniform `1 / (2 pi)`. Zero below the horizon and for a delta lobe.
    #[inline]
    pub fn pdf(&self, wo: Vec3, wi: Vec3, sampling: Sampling) -> f32 {
        self.pdf_of(&formulas::half_terms(self.distribution.widths(), wo.into(), wi.into()), sampling)
    }

    /// [`Self::eval`] and [`Self::pdf`] of one pair in one call, equal to both bit for bit: the
    /// half vector, `D(wm)` and `so` are computed once (Mitsuba 3's `eval_pdf`). For light
    /// sampling with MIS, which needs both.
    #[inline(always)]
    pub fn eval_pdf(&self, wo: Vec3, wi: Vec3, sampling: Sampling) -> (Vec3, f32) {
        let a = self.distribution.widths();
        let t = formulas::half_terms(a, wo.into(), wi.into());
        let value = self.fresnel.eval(t.cos_om) * formulas::reflection_of(a, &t);
        (if self.is_delta() { Vec3::ZERO } else { value }, self.pdf_of(&t, sampling))
    }

    /// [`Self::pdf`] from the shared terms of the pair.
    #[inline(always)]
    fn pdf_of(&self, t: &formulas::HalfTerms<f32>, sampling: Sampling) -> f32 {
        let (wo, wi, wm, cos_om): (Vec3, Vec3, Vec3, f32) = (t.wo.into(), t.wi.into(), t.wm.into(), t.cos_om);
        if !(wo.z > 0.0 && wi.z > 0.0) || self.is_delta() {
            return 0.0;
        }
        let d = &self.distribution;
        // A back-facing half vector (rounding where wo ~ -wi) is never sampled; eval is 0 there too.
        if !(cos_om > 0.0) && !matches!(sampling, Sampling::Cosine | Sampling::Uniform) {
            return 0.0;
        }
        let pdf = match sampling {
            Sampling::Ndf => d.pdf_wm_ndf(wm) / (4.0 * cos_om),
            Sampling::Vndf | Sampling::SphericalCaps => formulas::pdf_vndf_of(t),
            Sampling::Bounded => d.pdf_wi_bounded(wo, wm),
            Sampling::Cosine => warp::pdf_cosine_hemisphere(wi),
            Sampling::Uniform => warp::pdf_uniform_hemisphere(wi),
        };
        finite_or_zero(pdf)
    }

    /// Draws `wi` for `wo` with the technique. `None` when `wo.z <= 0`, when the sample falls
    /// at or below the horizon or on a back-facing microfacet, or for degenerate input.
    /// Weights are closed forms that never divide by `D`: VNDF `F G2 / G1(wo)`, bounded
    /// `F zi (k zo + so) / (zi so + zo si)`, NDF `F G2 |wo.wm| / (zo wm.z)`.
    #[inline(always)]
    pub fn sample(&self, wo: Vec3, u: Vec2, sampling: Sampling) -> Option<BsdfSample> {
        let wo = normalize_or_zero(wo);
        if !(wo.z > 0.0) {
            return None;
        }
        let u = sanitize_u2(u);
        if self.is_delta() {
            let weight = self.fresnel.eval(wo.z);
            return Some(BsdfSample { wi: Vec3::new(-wo.x, -wo.y, wo.z), weight, pdf: 1.0, is_delta: true });
        }
        let d = &self.distribution;
        let (wi, pdf, weight) = match sampling {
            Sampling::Cosine | Sampling::Uniform => {
                let wi = if sampling == Sampling::Cosine {
                    warp::sample_cosine_hemisphere(u)
                } else {
                    warp::sample_uniform_hemisphere(u)
                };
                let pdf = self.pdf(wo, wi, sampling);
                let f = self.eval(wo, wi);
                (wi, pdf, f / pdf)
            }
            _ => {
                let wm = match sampling {
                    Sampling::Ndf => d.sample_wm_ndf(u),
                    Sampling::SphericalCaps => d.sample_wm_spherical_caps(wo, u),
                    Sampling::Bounded => d.sample_wm_bounded(wo, u),
                    _ => d.sample_wm_vndf(wo, u),
                };
                let r = reflect_about(d, wo, wm, sampling);
                (r.wi, r.pdf, self.fresnel.eval(r.cos_om) * r.scale)
            }
        };
        if !(pdf > 0.0 && pdf.is_finite() && weight.is_finite()) {
            return None;
        }
        Some(BsdfSample { wi, weight, pdf, is_delta: false })
    }
}
