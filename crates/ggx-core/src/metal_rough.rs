//! The glTF 2.0 metallic-roughness BRDF (glTF 2.0 specification, Appendix B) with the
//! `KHR_materials_specular` and `KHR_materials_ior` extensions, composed from the crate's
//! pieces: the GGX specular lobe of [`GgxConductor`] (Trowbridge-Reitz `D`, height-correlated
//! Smith `G2`) with `F = 1`, [`fresnel_schlick`] and a Lambertian lobe, sampled as a one-sample
//! MIS mixture of the specular sampler and the cosine-weighted hemisphere.

use crate::bxdf::{Bxdf, BxdfFlags, TransportMode};
use crate::conductor::{BsdfSample, GgxConductor};
use crate::dielectric::ETA_MAX;
use crate::distribution::TrowbridgeReitz;
use crate::fresnel::{FresnelParams, fresnel_schlick, kind};
use crate::math::{normalize_or_zero, sanitize_u};
use crate::sampling::Sampling;
use crate::warp;
use core::f32::consts::FRAC_1_PI;
use glam::{Vec2, Vec3};
// Fields and results are clamped to [0, 1], -0.0 and NaN read as +0.0.
use crate::math::saturate as unit;

/// The index of refraction of glTF's core material (`KHR_materials_ior`'s default): `f0 = 0.04`.
pub const DEFAULT_IOR: f32 = 1.5;

/// `2 integral_0^1 (1 - mu)^5 mu dmu = 1 / 21`: the cosine-weighted hemispherical average of
/// Schlick's grazing term, so that a Schlick Fresnel term averages `f0 + (1 - f0) / 21`.
const SCHLICK_GRAZING_AVERAGE: f32 = 1.0 / 21.0;

/// Smallest probability [`GltfMetalRough::new`] gives a lobe that is present.
const P_LOBE_MIN: f32 = 0.1;

/// `x` if finite, else `default`.
#[inline(always)]
fn finite_or(x: f32, default: f32) -> f32 {
    if x.is_finite() { x } else { default }
}

/// `[f32; 3]` as a vector with every component through [`unit`].
#[inline(always)]
fn unit3(v: [f32; 3]) -> Vec3 {
    Vec3::new(unit(v[0]), unit(v[1]), unit(v[2]))
}

/// `(x + y + z) / 3`.
#[inline(always)]
fn mean(v: Vec3) -> f32 {
    (v.x + v.y + v.z) * (1.0 / 3.0)
}

/// The index of refraction [`dielectric_f0`] uses: NaN and infinities -> [`DEFAULT_IOR`], `0`
/// kept (`KHR_materials_ior`'s special value: `f0 = 1`, the Fresnel term is one), anything
/// else clamped to `[1, ETA_MAX]` (below 1 is not a valid glTF `ior`).
#[inline]
pub fn clamp_ior(ior: f32) -> f32 {
    let ior = finite_or(ior, DEFAULT_IOR);
    if ior == 0.0 { 0.0 } else { ior.max(1.0).min(ETA_MAX) }
}

/// The dielectric's normal-incidence reflectance, `KHR_materials_specular`:
/// `f0 = min(((ior - 1) / (ior + 1))^2 specular_color, 1)`, `ior` through [`clamp_ior`], each
/// `specular_color` channel finite or 1 (its default) and at least 0 (not capped: the `min`
/// does that). In `[0, 1]`; `0.04` for the defaults (`ior = 1.5`, `specular_color = 1`).
#[inline]
pub fn dielectric_f0(ior: f32, specular_color: Vec3) -> Vec3 {
    let ior = clamp_ior(ior);
    let r = (ior - 1.0) / (ior + 1.0);
    let r0 = r * r;
    let channel = |c: f32| (r0 * finite_or(c, 1.0).max(0.0)).min(1.0);
    Vec3::new(channel(specular_color.x), channel(specular_color.y), channel(specular_color.z))
}

/// The glTF 2.0 metallic-roughness BRDF (spec Appendix B, with `KHR_materials_specular` and
/// `KHR_materials_ior`); reflection only, the two-sided convention of [`GgxConductor`]:
///
/// ```text
/// specular_brdf = D(h) G2(wo, wi) / (4 |n.wo| |n.wi|)          (GgxConductor with F = 1)
/// diffuse_brdf  = base_color / pi
/// fr_d          = f0 + (1 - f0) (1 - |wo.h|)^5                  (f0: dielectric_f0)
/// dielectric    = (1 - specular_weight max(fr_d)) diffuse_brdf + specular_weight fr_d specular_brdf
/// metal         = specular_brdf (base_color + (1 - base_color) (1 - |wo.h|)^5)
/// f             = mix(dielectric, metal, metallic)
/// ```
///
/// with `h = normalize(wo + wi)`. The specular lobe has the alphas of the caller (glTF's
/// `alpha = roughness^2`, anisotropic allowed); below [`crate::DELTA_ALPHA`] it is a mirror
/// (`sample` returns it as a delta, `eval` and `pdf` leave it out) while the diffuse lobe stays.
///
/// 48-byte `#[repr(C)]` POD (a multiple of 16, ready for a GPU storage buffer; in WGSL the
/// `[f32; 3]` fields are `vec3<f32>` with the next `f32` in their fourth lane). Any bit pattern
/// in the fields is accepted: every method reads `base_color`, `metallic`, `f0`,
/// `specular_weight` and `p_specular` clamped into `[0, 1]` (NaN -> 0) and the alphas through
/// [`TrowbridgeReitz::alphas`]; [`Self::new`] stores them already in range.
#[repr(C)]
#[derive(Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
#[cfg_attr(not(target_arch = "spirv"), derive(Debug))]
pub struct GltfMetalRough {
    /// `baseColorFactor` (times the texture) RGB, linear, in `[0, 1]`: the diffuse albedo of
    /// the dielectric and the normal-incidence reflectance of the metal.
    pub base_color: [f32; 3],
    /// `metallicFactor` in `[0, 1]`: the mix between the dielectric (0) and the metal (1).
    pub metallic: f32,
    /// The dielectric's normal-incidence reflectance RGB in `[0, 1]` ([`dielectric_f0`] of
    /// `ior` and `specular_color`).
    pub f0: [f32; 3],
    /// `KHR_materials_specular`'s `specularFactor` in `[0, 1]`: the strength of the
    /// dielectric's specular lobe.
    pub specular_weight: f32,
    /// The specular lobe's distribution.
    pub distribution: TrowbridgeReitz,
    /// Probability with which [`Self::sample`] draws the specular lobe (else the diffuse one);
    /// see [`Self::new`].
    pub p_specular: f32,
    /// Padding to 48 bytes.
    pub pad: u32,
}

/// View-independent albedo estimates `(a_s, a_d)` of the specular and diffuse lobes with
/// Schlick's hemispherical average `F_avg(f0) = f0 + (1 - f0) / 21`: `a_s = m mean(F_avg(base))
/// + (1 - m) sw F_avg(f0_max)`, `a_d = (1 - m) max(1 - sw F_avg(f0_max), 0) mean(base)`.
#[inline]
fn lobe_albedos(base: Vec3, metallic: f32, f0_max: f32, specular_weight: f32) -> (f32, f32) {
    let f_avg = |f0: f32| f0 + (1.0 - f0) * SCHLICK_GRAZING_AVERAGE;
    let f_avg_d = f_avg(f0_max);
    let a_s = metallic * mean(Vec3::new(f_avg(base.x), f_avg(base.y), f_avg(base.z)))
        + (1.0 - metallic) * specular_weight * f_avg_d;
    let a_d = (1.0 - metallic) * (1.0 - specular_weight * f_avg_d).max(0.0) * mean(base);
    (a_s, a_d)
}

impl GltfMetalRough {
    /// The BRDF from glTF material parameters, every one sanitized: `base_color` channels,
    /// `metallic` and `specular_weight` NaN or infinite -> 1 (glTF's defaults), then clamped
    /// to `[0, 1]`; the alphas clamped by [`TrowbridgeReitz::new`] (as [`GgxConductor::new`]
    /// does: NaN -> `ALPHA_MIN`, a mirror); `ior` and `specular_color` through
    /// [`dielectric_f0`] (the glTF defaults are `ior = 1.5`, `specular_color = 1`,
    /// `specular_weight = 1`).
    ///
    /// Precomputes the lobe selection probability `p_specular = a_s / (a_s + a_d)` from
    /// view-independent albedo estimates with Schlick's hemispherical average
    /// `F_avg(f0) = f0 + (1 - f0) / 21`: `a_s = metallic mean(F_avg(base)) + (1 - metallic)
    /// specular_weight F_avg(max(f0))`, `a_d = (1 - metallic) (1 - specular_weight
    /// F_avg(max(f0))) mean(base)`, clamped to `[0.1, 0.9]` when both lobes are present; exactly
    /// 0 without a specular lobe (`metallic = specular_weight = 0`) and exactly 1 without a
    /// diffuse one (`metallic = 1`, a black base or `specular_weight max(f0) = 1`). Any value in
    /// `(0, 1)` keeps the sampler unbiased; this one only shapes its variance.
    #[inline]
    pub fn new(
        base_color: Vec3,
        metallic: f32,
        alpha_x: f32,
        alpha_y: f32,
        ior: f32,
        specular_color: Vec3,
        specular_weight: f32,
    ) -> Self {
        let unit_or_one = |x: f32| unit(finite_or(x, 1.0));
        let base = Vec3::new(unit_or_one(base_color.x), unit_or_one(base_color.y), unit_or_one(base_color.z));
        let metallic = unit_or_one(metallic);
        let specular_weight = unit_or_one(specular_weight);
        let f0 = dielectric_f0(ior, specular_color);
        let (a_s, a_d) = lobe_albedos(base, metallic, f0.max_element(), specular_weight);
        let p_specular = if !(a_s > 0.0) {
            0.0
        } else if !(a_d > 0.0) {
            1.0
        } else {
            (a_s / (a_s + a_d)).max(P_LOBE_MIN).min(1.0 - P_LOBE_MIN)
        };
        Self {
            base_color: base.to_array(),
            metallic,
            f0: f0.to_array(),
            specular_weight,
            distribution: TrowbridgeReitz::new(alpha_x, alpha_y),
            p_specular,
            pad: 0,
        }
    }

    /// `a_s + a_d` of the lobes' albedo estimates (see [`Self::new`]) from the stored fields
    /// (each read clamped to `[0, 1]`): the BRDF's view-independent albedo estimate, in `[0, 1]`.
    #[inline]
    pub fn albedo_estimate(&self) -> f32 {
        let [r, g, b] = self.base_color.map(unit);
        let [x, y, z] = self.f0.map(unit);
        let (a_s, a_d) =
            lobe_albedos(Vec3::new(r, g, b), unit(self.metallic), x.max(y).max(z), unit(self.specular_weight));
        unit(a_s + a_d)
    }

    /// glTF's core material without extensions: `ior = 1.5`, `specular_color = 1`,
    /// `specular_weight = 1` (so `f0 = 0.04`), isotropic `alpha` (glTF's `roughness^2`).
    #[inline]
    pub fn core(base_color: Vec3, metallic: f32, alpha: f32) -> Self {
        Self::new(base_color, metallic, alpha, alpha, DEFAULT_IOR, Vec3::ONE, 1.0)
    }

    /// True when the specular lobe is a mirror (both alphas below [`crate::DELTA_ALPHA`]):
    /// `sample` returns it as a delta, `eval` and `pdf` hold only the diffuse lobe.
    #[inline]
    pub fn is_delta(&self) -> bool {
        self.distribution.is_effectively_smooth()
    }

    /// The specular lobe without Fresnel: `GgxConductor` of `distribution` with `F = 1`
    /// (`D G2 / (4 |wo.z| |wi.z|)`), whose `eval`, `pdf` and `sample` this BRDF composes.
    #[inline]
    pub fn specular(&self) -> GgxConductor {
        let one = FresnelParams { kind: kind::ONE, eta: 1.0, pad: [0; 2], a: [0.0; 4], b: [0.0; 4] };
        GgxConductor { distribution: self.distribution, pad: [0; 2], fresnel: one }
    }

    /// `p_specular` clamped to `[0, 1]` (NaN -> 0): the probability with which [`Self::sample`]
    /// draws the specular lobe.
    #[inline]
    pub fn specular_probability(&self) -> f32 {
        unit(self.p_specular)
    }

    /// The specular lobe's and the diffuse lobe's weights for `cos = |wo.h|`:
    /// `((1 - metallic) specular_weight fr_d + metallic F_m, (1 - metallic) (1 - specular_weight
    /// max(fr_d)))` with `fr_d = fresnel_schlick(cos, f0, 1)`, `F_m = fresnel_schlick(cos,
    /// base_color, 1)` (glTF 2.0 Appendix B `fresnel_mix`, `conductor_fresnel`, `mix`).
    #[inline(always)]
    fn weights(&self, cos: f32) -> (Vec3, f32) {
        let metallic = unit(self.metallic);
        let specular_weight = unit(self.specular_weight);
        let fr_d = fresnel_schlick(cos, unit3(self.f0), Vec3::ONE);
        let fr_m = fresnel_schlick(cos, unit3(self.base_color), Vec3::ONE);
        let specular = fr_d * ((1.0 - metallic) * specular_weight) + fr_m * metallic;
        // max(0): f0 + (1 - f0) x may round one ulp above 1.
        let diffuse = (1.0 - metallic) * (1.0 - specular_weight * fr_d.max_element()).max(0.0);
        (specular, diffuse)
    }

    /// The specular lobe's Fresnel weight for `cos = |wo.h|`: `(1 - metallic) specular_weight
    /// fr_d + metallic (base + (1 - base) (1 - cos)^5)`, `fr_d = f0 + (1 - f0) (1 - cos)^5`
    /// (glTF 2.0 Appendix B with `KHR_materials_specular`); `cos` clamped to `[0, 1]`. Also the
    /// reflectance of the mirror lobe at `cos = wo.z`. In `[0, 1]` up to rounding.
    #[inline]
    pub fn specular_fresnel(&self, cos: f32) -> Vec3 {
        self.weights(cos).0
    }

    /// The diffuse lobe's weight for `cos = |wo.h|`: `(1 - metallic) (1 - specular_weight
    /// max(fr_d))`, `fr_d = f0 + (1 - f0) (1 - cos)^5` (glTF 2.0 Appendix B `fresnel_mix` with
    /// `KHR_materials_specular`), at least 0; `cos` clamped to `[0, 1]`.
    #[inline]
    pub fn diffuse_weight(&self, cos: f32) -> f32 {
        self.weights(cos).1
    }

    /// `f(wo, wi) |wi.z|` with `f = specular_fresnel(|wo.h|) specular_brdf + diffuse_weight(|wo.h|)
    /// base_color / pi` (glTF 2.0 Appendix B; `specular_brdf |wi.z|` is [`GgxConductor::eval`]
    /// with `F = 1`, 0 for a mirror). Zero unless `wo.z > 0` and `wi.z > 0` (after
    /// normalization), and for degenerate input. Inputs need not be normalized.
    #[inline]
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        let (wo, wi) = (normalize_or_zero(wo), normalize_or_zero(wi));
        if !(wo.z > 0.0 && wi.z > 0.0) {
            return Vec3::ZERO;
        }
        self.mix_f(wo, wi, self.specular().eval(wo, wi).x)
    }

    /// `specular_fresnel(|wo.h|) s + diffuse_weight(|wo.h|) base_color wi.z / pi` for normalized
    /// directions above the horizon, from the specular lobe's `s = specular_brdf |wi.z|`.
    #[inline(always)]
    fn mix_f(&self, wo: Vec3, wi: Vec3, s: f32) -> Vec3 {
        // |wo.h|; rounding can make it 0 or negative where wo ~ -wi (fresnel_schlick clamps).
        let cos = wo.dot(normalize_or_zero(wo + wi));
        let (specular, diffuse) = self.weights(cos);
        specular * s + unit3(self.base_color) * (diffuse * wi.z * FRAC_1_PI)
    }

    /// The mixture density `p_s pdf_s + (1 - p_s) wi.z / pi` from the specular lobe's `pdf_s`.
    #[inline(always)]
    fn mix_pdf(&self, wi: Vec3, pdf_s: f32) -> f32 {
        let p = self.specular_probability();
        // Both terms finite and non-negative: GgxConductor::pdf is finite_or_zero, wi.z <= 1.
        p * pdf_s + (1.0 - p) * warp::pdf_cosine_hemisphere(wi)
    }

    /// [`Self::eval`] and [`Self::pdf`] in one call, equal to both bit for bit (the specular
    /// lobe's [`GgxConductor::eval_pdf`] shares its half-vector terms).
    #[inline]
    pub fn eval_pdf(&self, wo: Vec3, wi: Vec3, sampling: Sampling) -> (Vec3, f32) {
        let (wo, wi) = (normalize_or_zero(wo), normalize_or_zero(wi));
        if !(wo.z > 0.0 && wi.z > 0.0) {
            return (Vec3::ZERO, 0.0);
        }
        let (s, pdf_s) = self.specular().eval_pdf(wo, wi, sampling);
        (self.mix_f(wo, wi, s.x), self.mix_pdf(wi, pdf_s))
    }

    /// Solid-angle density of [`Self::sample`], the one-sample MIS mixture
    /// `p_s pdf_s(wi) + (1 - p_s) wi.z / pi` with `pdf_s` = [`GgxConductor::pdf`] of the
    /// specular lobe for the technique (0 for a mirror) and `p_s` = [`Self::specular_probability`].
    /// Zero unless `wo.z > 0` and `wi.z > 0`.
    #[inline]
    pub fn pdf(&self, wo: Vec3, wi: Vec3, sampling: Sampling) -> f32 {
        let (wo, wi) = (normalize_or_zero(wo), normalize_or_zero(wi));
        if !(wo.z > 0.0 && wi.z > 0.0) {
            return 0.0;
        }
        self.mix_pdf(wi, self.specular().pdf(wo, wi, sampling))
    }

    /// Draws `wi`: the specular lobe ([`GgxConductor::sample`] with the technique, from `u`)
    /// when `u_lobe < p_s`, else the cosine-weighted hemisphere ([`warp::sample_cosine_hemisphere`]
    /// of `u`); `pdf` is [`Self::pdf`] and `weight = eval / pdf` of the returned pair (one-sample
    /// MIS over both lobes). A mirror specular lobe is returned as a delta sample (as the plastic
    /// coat of ggx-render does): the mirror direction, `pdf = p_s` (the probability of the lobe)
    /// and `weight = specular_fresnel(wo.z) / p_s`. `None` for `wo.z <= 0`, where the specular
    /// sampler refuses, and for degenerate input.
    #[inline]
    pub fn sample(&self, wo: Vec3, u: Vec2, u_lobe: f32, sampling: Sampling) -> Option<BsdfSample> {
        let wo = normalize_or_zero(wo);
        if !(wo.z > 0.0) {
            return None;
        }
        let p = self.specular_probability();
        let wi = if sanitize_u(u_lobe) < p {
            let s = self.specular().sample(wo, u, sampling)?;
            if s.is_delta {
                let weight = self.specular_fresnel(wo.z) / p;
                if !weight.is_finite() {
                    return None;
                }
                return Some(BsdfSample { wi: s.wi, weight, pdf: p, is_delta: true });
            }
            s.wi
        } else {
            warp::sample_cosine_hemisphere(u)
        };
        let pdf = self.pdf(wo, wi, sampling);
        let weight = self.eval(wo, wi) / pdf;
        if !(pdf > 0.0 && pdf.is_finite() && weight.is_finite()) {
            return None;
        }
        Some(BsdfSample { wi, weight, pdf, is_delta: false })
    }
}

/// The glTF BRDF through the interface: `u_lobe` picks the specular or the diffuse lobe, `mode`
/// is ignored (reflection only). Flags: `REFLECTION`, `GLOSSY` when a lobe has densities (the
/// diffuse lobe, `p_s < 1`, or a rough specular lobe), `SPECULAR` when the specular lobe is a
/// present mirror (`p_s > 0`); a mirror over a diffuse base sets both.
impl Bxdf for GltfMetalRough {
    #[inline]
    fn eval(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> Vec3 {
        GltfMetalRough::eval(self, wo, wi)
    }

    #[inline]
    fn pdf(&self, wo: Vec3, wi: Vec3, sampling: Sampling, _mode: TransportMode) -> f32 {
        GltfMetalRough::pdf(self, wo, wi, sampling)
    }

    #[inline]
    fn eval_pdf(&self, wo: Vec3, wi: Vec3, sampling: Sampling, _mode: TransportMode) -> (Vec3, f32) {
        GltfMetalRough::eval_pdf(self, wo, wi, sampling)
    }

    #[inline]
    fn sample(&self, wo: Vec3, u: Vec2, u_lobe: f32, sampling: Sampling, _mode: TransportMode) -> Option<BsdfSample> {
        GltfMetalRough::sample(self, wo, u, u_lobe, sampling)
    }

    #[inline]
    fn flags(&self) -> BxdfFlags {
        let p = self.specular_probability();
        let delta = self.is_delta();
        let mut flags = BxdfFlags::REFLECTION;
        if p < 1.0 || !delta {
            flags = flags.union(BxdfFlags::GLOSSY);
        }
        if p > 0.0 && delta {
            flags = flags.union(BxdfFlags::SPECULAR);
        }
        flags
    }
}
