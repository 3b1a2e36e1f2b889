//! Scene materials as tangent-space BSDFs built on ggx-core. Every `eval` returns
//! `f(wo, wi) |wi.z|`, every `sample` a weight `eval / pdf`, like `ggx_core::GgxConductor`.
//! Camera paths carry radiance ([`TransportMode::Radiance`]).
//!
//! Sides: reflective materials are two-sided and shade in a frame turned toward `wo`
//! (`wo.z > 0`, else nothing). A dielectric has an inside: its frame keeps the surface's
//! outward normal, `wo.z < 0` means the ray arrives from inside, and `wi` may lie on
//! either side ([`Bsdf::has_inside`]).

use ggx_core::energy_dielectric::plastic_base_weight;
use ggx_core::fresnel::fresnel_dielectric;
use ggx_core::warp::{pdf_cosine_hemisphere, sample_cosine_hemisphere};
use ggx_core::{
    BsdfSample, Fresnel, GgxConductor, GgxConductorMs, GgxDielectric, GgxDielectricMs, GltfClearcoat, GltfMetalRough,
    Sampling, ThinDielectric, TransportMode,
};
use ggx_scene::{BsdfStrategy, ConductorFresnel, Material, luminance};
use glam::{Vec2, Vec3};
use std::f32::consts::FRAC_1_PI;

/// A material ready to shade: ggx-core objects precomputed once per scene.
#[derive(Clone, Copy, Debug)]
pub enum Bsdf {
    /// Lambertian, `f = albedo / pi`.
    Diffuse {
        /// Reflectance.
        albedo: Vec3,
    },
    /// GGX conductor, with the Kulla & Conty lobe when `brdf.compensation != 0`.
    Conductor {
        /// The BRDF.
        brdf: GgxConductorMs,
        /// The technique `sample` uses.
        sampling: Sampling,
    },
    /// GGX dielectric coat over a Lambertian base (see [`Bsdf::eval`]).
    Plastic {
        /// Coat reflection with the exact dielectric Fresnel term.
        coat: GgxConductor,
        /// Coat index of refraction.
        ior: f32,
        /// Base reflectance.
        albedo: Vec3,
        /// The technique used for the coat lobe.
        sampling: Sampling,
        /// Couple the base through the coat's `1 - E` (energy compensation).
        compensate: bool,
    },
    /// GGX rough (or smooth) dielectric interface with an inside.
    Dielectric {
        /// The BSDF, energy-compensated when `bsdf.compensation != 0`.
        bsdf: GgxDielectricMs,
        /// Tint of every transmission.
        transmittance: Vec3,
        /// Beer-Lambert absorption coefficient of the inside.
        absorption: Vec3,
        /// The technique `sample` uses (cosine and uniform fall back to VNDF).
        sampling: Sampling,
    },
    /// Smooth thin sheet: no inside, transmission straight through.
    Thin {
        /// The sheet.
        sheet: ThinDielectric,
        /// Tint of the transmission.
        transmittance: Vec3,
    },
    /// The glTF metallic-roughness BRDF (diffuse + GGX specular, Schlick Fresnel).
    MetalRough {
        /// The BRDF.
        brdf: GltfMetalRough,
        /// The technique its specular lobe uses.
        sampling: Sampling,
    },
    /// The glTF metallic-roughness BRDF under `KHR_materials_clearcoat`'s GGX coat.
    Clearcoat {
        /// The coated BRDF.
        brdf: GltfClearcoat,
        /// The technique its specular and coat lobes use.
        sampling: Sampling,
    },
    /// Emitters and anything else that reflects nothing.
    Black,
}

/// The ggx-core technique for a scene's BSDF strategy.
pub fn sampling_for(strategy: BsdfStrategy) -> Sampling {
    match strategy {
        BsdfStrategy::Cosine => Sampling::Cosine,
        BsdfStrategy::Ndf => Sampling::Ndf,
        BsdfStrategy::Vndf => Sampling::Vndf,
        BsdfStrategy::SphericalCaps => Sampling::SphericalCaps,
        BsdfStrategy::Bounded => Sampling::Bounded,
    }
}

/// `v` where `transmitted`, else 1: the tint of a dielectric's transmission.
#[inline(always)]
fn tint(transmitted: bool, transmittance: Vec3) -> Vec3 {
    if transmitted { transmittance } else { Vec3::ONE }
}

impl Bsdf {
    /// Precomputes the BSDF of a scene material.
    pub fn new(material: &Material, strategy: BsdfStrategy) -> Bsdf {
        let sampling = sampling_for(strategy);
        match *material {
            Material::Diffuse { albedo } => Bsdf::Diffuse { albedo },
            Material::Conductor { alpha_x, alpha_y, fresnel, compensate } => {
                let fresnel = match fresnel {
                    ConductorFresnel::Schlick { f0 } => Fresnel::Schlick { f0 },
                    ConductorFresnel::Complex { eta, k } => Fresnel::Conductor { eta, k },
                    ConductorFresnel::One => Fresnel::One,
                };
                let mut brdf = GgxConductorMs::new(GgxConductor::new(alpha_x, alpha_y, fresnel));
                brdf.compensation = u32::from(compensate);
                Bsdf::Conductor { brdf, sampling }
            }
            Material::Plastic { alpha, ior, albedo, compensate } => Bsdf::Plastic {
                coat: GgxConductor::isotropic(alpha, Fresnel::Dielectric { eta: ior }),
                ior,
                albedo,
                sampling,
                compensate,
            },
            Material::Dielectric { thin: true, ior, transmittance, .. } => {
                Bsdf::Thin { sheet: ThinDielectric::new(ior), transmittance }
            }
            Material::Dielectric { alpha_x, alpha_y, ior, transmittance, absorption, compensate, .. } => {
                let mut bsdf = GgxDielectricMs::new(GgxDielectric::new(alpha_x, alpha_y, ior));
                bsdf.compensation = u32::from(compensate);
                // The hemisphere-only techniques cannot reach the other side: VNDF instead.
                let sampling = match sampling {
                    Sampling::Cosine | Sampling::Uniform => Sampling::Vndf,
                    s => s,
                };
                Bsdf::Dielectric { bsdf, transmittance, absorption, sampling }
            }
            Material::Emissive { .. } => Bsdf::Black,
            Material::MetalRough(m) => {
                let a = m.roughness * m.roughness;
                let a_t = a + (1.0 - a) * m.anisotropy * m.anisotropy;
                let brdf = GltfMetalRough::new(m.base_color, m.metallic, a_t, a, m.ior, m.specular_color, m.specular);
                Bsdf::metal_rough(brdf, m.clearcoat, m.clearcoat_roughness, Self::metal_rough_sampling(sampling))
            }
        }
    }

    /// The technique of a metal-rough material's specular (and coat) lobe for the scene's
    /// `sampling`: the hemisphere-only ones would sample the diffuse shape twice, VNDF instead.
    pub fn metal_rough_sampling(sampling: Sampling) -> Sampling {
        match sampling {
            Sampling::Cosine | Sampling::Uniform => Sampling::Vndf,
            s => s,
        }
    }

    /// `brdf` as a [`Bsdf`]: [`Bsdf::MetalRough`], or [`Bsdf::Clearcoat`] under a coat of weight
    /// `clearcoat > 0` and perceptual roughness `clearcoat_roughness` (coat alpha =
    /// roughness^2, `KHR_materials_clearcoat`).
    #[inline]
    pub fn metal_rough(brdf: GltfMetalRough, clearcoat: f32, clearcoat_roughness: f32, sampling: Sampling) -> Bsdf {
        if clearcoat > 0.0 {
            let coat = GltfClearcoat::new(brdf, clearcoat, clearcoat_roughness * clearcoat_roughness);
            Bsdf::Clearcoat { brdf: coat, sampling }
        } else {
            Bsdf::MetalRough { brdf, sampling }
        }
    }

    /// Probability of sampling the coat of a plastic: `F(wo) / (F(wo) + (1 - F(wo)) lum(albedo))`,
    /// kept in `[0.05, 0.95]` (1 when the base is black) so neither lobe is starved.
    fn coat_probability(fo: f32, albedo: Vec3) -> f32 {
        let base = (1.0 - fo) * luminance(albedo);
        if base <= 0.0 { 1.0 } else { (fo / (fo + base)).clamp(0.05, 0.95) }
    }

    /// The plastic base's coupling through the coat: with compensation
    /// `(1 - E_R(mu_o)) (1 - E_R(mu_i)) / (1 - E_R_avg)` (ggx-core's `plastic_base_weight`,
    /// white furnace exactly 1), else `(1 - F(mu_o)) (1 - F(mu_i))` (Ashikhmin & Shirley 2000's
    /// two Fresnel transmissions without internal reflections, which loses energy).
    #[inline(always)]
    fn base_weight(coat: &GgxConductor, ior: f32, compensate: bool, mu_o: f32, mu_i: f32) -> f32 {
        if compensate {
            plastic_base_weight(mu_o, mu_i, coat.distribution.alpha_x, ior)
        } else {
            (1.0 - fresnel_dielectric(mu_o, ior)) * (1.0 - fresnel_dielectric(mu_i, ior))
        }
    }

    /// `f(wo, wi) |wi.z|`. Plastic: `f = f_coat + w(wo, wi) albedo / pi`, the coat's GGX
    /// reflection plus a base weighted by `Self::base_weight`. Dielectric: both sides,
    /// transmission tinted by `transmittance`.
    #[inline(always)]
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if let Bsdf::Dielectric { bsdf, transmittance, .. } = self {
            return bsdf.eval(wo, wi, TransportMode::Radiance) * tint(wo.z * wi.z < 0.0, *transmittance);
        }
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Vec3::ZERO;
        }
        match *self {
            Bsdf::Diffuse { albedo } => albedo * (wi.z * FRAC_1_PI),
            Bsdf::Conductor { brdf, .. } => brdf.eval(wo, wi),
            Bsdf::Plastic { coat, ior, albedo, compensate, .. } => {
                Self::plastic_f(coat.eval(wo, wi), &coat, ior, albedo, compensate, wo, wi)
            }
            Bsdf::MetalRough { brdf, .. } => brdf.eval(wo, wi),
            Bsdf::Clearcoat { brdf, .. } => brdf.eval(wo, wi),
            Bsdf::Dielectric { .. } | Bsdf::Thin { .. } | Bsdf::Black => Vec3::ZERO,
        }
    }

    /// Solid-angle density of [`Bsdf::sample`] returning `wi` (0 for delta lobes).
    #[inline]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if let Bsdf::Dielectric { bsdf, sampling, .. } = self {
            return bsdf.pdf(wo, wi, *sampling, TransportMode::Radiance);
        }
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        match *self {
            Bsdf::Diffuse { .. } => pdf_cosine_hemisphere(wi),
            Bsdf::Conductor { brdf, sampling } => brdf.pdf(wo, wi, sampling),
            Bsdf::Plastic { coat, ior, albedo, sampling, .. } => {
                Self::plastic_pdf(coat.pdf(wo, wi, sampling), ior, albedo, wo, wi)
            }
            Bsdf::MetalRough { brdf, sampling } => brdf.pdf(wo, wi, sampling),
            Bsdf::Clearcoat { brdf, sampling } => brdf.pdf(wo, wi, sampling),
            Bsdf::Dielectric { .. } | Bsdf::Thin { .. } | Bsdf::Black => 0.0,
        }
    }

    /// [`Self::eval`] and [`Self::pdf`] of one pair in one call, equal to both bit for bit:
    /// each microfacet lobe computes its half vector, `D` and Smith terms once
    /// (`ggx_core::Bxdf::eval_pdf`). What light sampling with MIS needs.
    #[inline(always)]
    pub fn eval_pdf(&self, wo: Vec3, wi: Vec3) -> (Vec3, f32) {
        if let Bsdf::Dielectric { bsdf, transmittance, sampling, .. } = self {
            let (f, pdf) = bsdf.eval_pdf(wo, wi, *sampling, TransportMode::Radiance);
            return (f * tint(wo.z * wi.z < 0.0, *transmittance), pdf);
        }
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return (Vec3::ZERO, 0.0);
        }
        match *self {
            Bsdf::Diffuse { albedo } => (albedo * (wi.z * FRAC_1_PI), pdf_cosine_hemisphere(wi)),
            Bsdf::Conductor { brdf, sampling } => brdf.eval_pdf(wo, wi, sampling),
            Bsdf::Plastic { coat, ior, albedo, sampling, compensate } => {
                let (f_coat, pdf_coat) = coat.eval_pdf(wo, wi, sampling);
                (
                    Self::plastic_f(f_coat, &coat, ior, albedo, compensate, wo, wi),
                    Self::plastic_pdf(pdf_coat, ior, albedo, wo, wi),
                )
            }
            Bsdf::MetalRough { brdf, sampling } => brdf.eval_pdf(wo, wi, sampling),
            Bsdf::Clearcoat { brdf, sampling } => brdf.eval_pdf(wo, wi, sampling),
            Bsdf::Dielectric { .. } | Bsdf::Thin { .. } | Bsdf::Black => (Vec3::ZERO, 0.0),
        }
    }

    /// The plastic's `f |wi.z| = f_coat |wi.z| + w(wo, wi) albedo wi.z / pi` from the coat's value.
    #[inline(always)]
    fn plastic_f(
        f_coat: Vec3,
        coat: &GgxConductor,
        ior: f32,
        albedo: Vec3,
        compensate: bool,
        wo: Vec3,
        wi: Vec3,
    ) -> Vec3 {
        let t = Self::base_weight(coat, ior, compensate, wo.z, wi.z);
        f_coat + albedo * (t * wi.z * FRAC_1_PI)
    }

    /// The plastic's one-sample mixture density `p pdf_coat + (1 - p) wi.z / pi`, `p` the coat's
    /// [`Self::coat_probability`], from the coat's density.
    #[inline(always)]
    fn plastic_pdf(pdf_coat: f32, ior: f32, albedo: Vec3, wo: Vec3, wi: Vec3) -> f32 {
        let p = Self::coat_probability(fresnel_dielectric(wo.z, ior), albedo);
        p * pdf_coat + (1.0 - p) * pdf_cosine_hemisphere(wi)
    }

    /// Draws `wi`: `u_lobe` picks the lobe (a plastic's coat or base, a compensated
    /// conductor's single- or multiple-scattering lobe, a dielectric's reflection or
    /// transmission), `u` the direction. The plastic is a one-sample mixture whose weight is
    /// `eval / pdf` of the whole mixture.
    #[inline(always)]
    pub fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        match *self {
            Bsdf::Dielectric { bsdf, transmittance, sampling, .. } => {
                let s = bsdf.sample(wo, u, u_lobe, sampling, TransportMode::Radiance)?;
                let weight = s.weight * tint(wo.z * s.wi.z < 0.0, transmittance);
                return Some(BsdfSample { weight, ..s });
            }
            Bsdf::Thin { sheet, transmittance } => {
                let s = sheet.sample(wo, u_lobe)?;
                let weight = s.weight * tint(wo.z * s.wi.z < 0.0, transmittance);
                return Some(BsdfSample { weight, ..s });
            }
            _ => {}
        }
        if wo.z <= 0.0 {
            return None;
        }
        match *self {
            Bsdf::Diffuse { albedo } => {
                let wi = sample_cosine_hemisphere(u);
                Some(BsdfSample { wi, weight: albedo, pdf: pdf_cosine_hemisphere(wi), is_delta: false })
            }
            Bsdf::Conductor { brdf, sampling } => brdf.sample(wo, u, u_lobe, sampling),
            Bsdf::Plastic { coat, ior, albedo, sampling, .. } => {
                let p = Self::coat_probability(fresnel_dielectric(wo.z, ior), albedo);
                let wi = if u_lobe < p {
                    let s = coat.sample(wo, u, sampling)?;
                    if s.is_delta {
                        return Some(BsdfSample { weight: s.weight / p, pdf: p, ..s });
                    }
                    s.wi
                } else {
                    sample_cosine_hemisphere(u)
                };
                let (f, pdf) = self.eval_pdf(wo, wi);
                if !(pdf > 0.0) {
                    return None;
                }
                Some(BsdfSample { wi, weight: f / pdf, pdf, is_delta: false })
            }
            Bsdf::MetalRough { brdf, sampling } => brdf.sample(wo, u, u_lobe, sampling),
            Bsdf::Clearcoat { brdf, sampling } => brdf.sample(wo, u, u_lobe, sampling),
            Bsdf::Dielectric { .. } | Bsdf::Thin { .. } | Bsdf::Black => None,
        }
    }

    /// True when every lobe is a delta (a mirror conductor, a smooth dielectric, a thin
    /// sheet): light sampling cannot help.
    pub fn is_delta(&self) -> bool {
        match self {
            Bsdf::Conductor { brdf, .. } => brdf.conductor.is_delta(),
            Bsdf::Dielectric { bsdf, .. } => bsdf.dielectric.is_delta(),
            Bsdf::Thin { .. } => true,
            _ => false,
        }
    }

    /// True for materials that reflect or transmit light at all.
    pub fn reflects(&self) -> bool {
        !matches!(self, Bsdf::Black)
    }

    /// True for a dielectric with an inside: shade it in the frame of the outward normal
    /// (`wo.z < 0` from inside) and let `wi` cross to the other side.
    pub fn has_inside(&self) -> bool {
        matches!(self, Bsdf::Dielectric { .. })
    }

    /// True when `wi` may lie on the other side of the surface from `wo` (dielectrics and
    /// thin sheets).
    pub fn transmits(&self) -> bool {
        matches!(self, Bsdf::Dielectric { .. } | Bsdf::Thin { .. })
    }

    /// `eta'^2` for a transmission through a dielectric with an inside (`wo.z * wi.z < 0`,
    /// `eta' = eta` from outside, `1 / eta` from inside): the inverse of the `1 / eta'^2`
    /// radiance scaling in its weight (Veach 1997 sec. 5.2), for Russian roulette. 1 otherwise.
    pub fn radiance_scale_inverse(&self, wo: Vec3, wi: Vec3) -> f32 {
        match self {
            Bsdf::Dielectric { bsdf, .. } if wo.z * wi.z < 0.0 => {
                let eta = bsdf.dielectric.eta();
                if wo.z > 0.0 { eta * eta } else { 1.0 / (eta * eta) }
            }
            _ => 1.0,
        }
    }

    /// The absorption coefficient of the inside (zero outside dielectrics).
    pub fn absorption(&self) -> Vec3 {
        match self {
            Bsdf::Dielectric { absorption, .. } => *absorption,
            _ => Vec3::ZERO,
        }
    }

    /// True when energy compensation changes this BSDF (a compensated rough conductor or
    /// dielectric, a compensated plastic): it reads ggx-core's energy tables.
    pub fn is_compensated(&self) -> bool {
        match self {
            Bsdf::Conductor { brdf, .. } => brdf.is_compensated(),
            Bsdf::Plastic { compensate, .. } => *compensate,
            Bsdf::Dielectric { bsdf, .. } => bsdf.is_compensated(),
            _ => false,
        }
    }

    /// True when `sample` reads `u_lobe`: plastics, compensated rough conductors, dielectrics,
    /// metal-rough materials (coated or not).
    pub fn uses_lobe_sample(&self) -> bool {
        match self {
            Bsdf::Conductor { brdf, .. } => brdf.is_compensated(),
            Bsdf::Plastic { .. }
            | Bsdf::Dielectric { .. }
            | Bsdf::Thin { .. }
            | Bsdf::MetalRough { .. }
            | Bsdf::Clearcoat { .. } => true,
            Bsdf::Diffuse { .. } | Bsdf::Black => false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bits((f, pdf): (Vec3, f32)) -> ([u32; 3], u32) {
        (f.to_array().map(f32::to_bits), pdf.to_bits())
    }

    /// Every material kind under every strategy: rough, anisotropic and smooth lobes, with and
    /// without energy compensation, the glTF BRDF with and without its clearcoat.
    fn bsdfs() -> Vec<Bsdf> {
        let gold = ConductorFresnel::Complex { eta: Vec3::new(0.143, 0.374, 1.442), k: Vec3::new(3.983, 2.385, 1.603) };
        let albedo = Vec3::new(0.6, 0.4, 0.2);
        let strategies = [
            BsdfStrategy::Cosine,
            BsdfStrategy::Ndf,
            BsdfStrategy::Vndf,
            BsdfStrategy::SphericalCaps,
            BsdfStrategy::Bounded,
        ];
        let mut out = Vec::new();
        for strategy in strategies {
            for compensate in [false, true] {
                for (ax, ay) in [(1e-4, 1e-4), (0.05, 0.05), (0.3, 0.08), (0.9, 0.9)] {
                    let materials = [
                        Material::Diffuse { albedo },
                        Material::Conductor { alpha_x: ax, alpha_y: ay, fresnel: gold, compensate },
                        Material::Conductor { alpha_x: ax, alpha_y: ay, fresnel: ConductorFresnel::One, compensate },
                        Material::Plastic { alpha: ax, ior: 1.5, albedo, compensate },
                        Material::Dielectric {
                            alpha_x: ax,
                            alpha_y: ay,
                            ior: 1.5,
                            transmittance: Vec3::new(0.9, 0.8, 0.7),
                            absorption: Vec3::ZERO,
                            thin: false,
                            compensate,
                        },
                        Material::Dielectric {
                            alpha_x: ax,
                            alpha_y: ay,
                            ior: 1.33,
                            transmittance: Vec3::ONE,
                            absorption: Vec3::ZERO,
                            thin: true,
                            compensate,
                        },
                        Material::Emissive { radiance: Vec3::ONE },
                    ];
                    out.extend(materials.iter().map(|m| Bsdf::new(m, strategy)));
                    let sampling = Bsdf::metal_rough_sampling(sampling_for(strategy));
                    let brdf = GltfMetalRough::new(albedo, 0.3, ax, ay, 1.5, Vec3::ONE, 1.0);
                    out.push(Bsdf::metal_rough(brdf, 0.0, 0.0, sampling));
                    out.push(Bsdf::metal_rough(brdf, 0.7, 0.2, sampling));
                }
            }
        }
        out
    }

    /// `eval_pdf` returns `eval` and `pdf` bit for bit for every material, on both sides of the
    /// surface and for hostile directions (zero, horizontal, unnormalized, NaN, infinite).
    #[test]
    fn eval_pdf_is_eval_and_pdf_bit_for_bit() {
        let mut dirs: Vec<Vec3> = Vec::new();
        for (theta, phi) in [(0.0f32, 0.0f32), (0.4, 1.0), (1.0, 2.5), (1.4, -0.7), (1.5702, 4.0)] {
            let w = Vec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos());
            dirs.extend([w, Vec3::new(w.x, w.y, -w.z), -w, w * 3.0]);
        }
        dirs.extend([Vec3::ZERO, Vec3::X, Vec3::new(f32::NAN, 0.0, 1.0), Vec3::new(0.0, f32::INFINITY, 1.0)]);
        let (mut pairs, mut both_positive) = (0, 0);
        for b in bsdfs() {
            for &wo in &dirs {
                for &wi in &dirs {
                    let fused = b.eval_pdf(wo, wi);
                    assert_eq!(bits(fused), bits((b.eval(wo, wi), b.pdf(wo, wi))), "{b:?} wo {wo} wi {wi}");
                    pairs += 1;
                    both_positive += usize::from(fused.0.max_element() > 0.0 && fused.1 > 0.0);
                }
            }
        }
        // The grid reaches the lobes, not only their zero cases (32 960 of 207 360 pairs).
        assert!(both_positive * 10 > pairs, "{both_positive} of {pairs} pairs have f > 0 and pdf > 0");
    }
}
