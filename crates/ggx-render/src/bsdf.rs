//! Scene materials as tangent-space BSDFs built on ggx-core. Every `eval` returns
//! `f(wo, wi) |wi.z|`, every `sample` a weight `eval / pdf`, like `ggx_core::GgxConductor`.

use ggx_core::fresnel::fresnel_dielectric;
use ggx_core::warp::{pdf_cosine_hemisphere, sample_cosine_hemisphere};
use ggx_core::{BsdfSample, Fresnel, GgxConductor, Sampling};
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
    /// GGX conductor.
    Conductor {
        /// The BRDF.
        brdf: GgxConductor,
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

impl Bsdf {
    /// Precomputes the BSDF of a scene material.
    pub fn new(material: &Material, strategy: BsdfStrategy) -> Bsdf {
        let sampling = sampling_for(strategy);
        match *material {
            Material::Diffuse { albedo } => Bsdf::Diffuse { albedo },
            Material::Conductor { alpha_x, alpha_y, fresnel } => {
                let fresnel = match fresnel {
                    ConductorFresnel::Schlick { f0 } => Fresnel::Schlick { f0 },
                    ConductorFresnel::Complex { eta, k } => Fresnel::Conductor { eta, k },
                    ConductorFresnel::One => Fresnel::One,
                };
                Bsdf::Conductor { brdf: GgxConductor::new(alpha_x, alpha_y, fresnel), sampling }
            }
            Material::Plastic { alpha, ior, albedo } => Bsdf::Plastic {
                coat: GgxConductor::isotropic(alpha, Fresnel::Dielectric { eta: ior }),
                ior,
                albedo,
                sampling,
            },
            Material::Emissive { .. } => Bsdf::Black,
        }
    }

    /// Probability of sampling the coat of a plastic: `F(wo) / (F(wo) + (1 - F(wo)) lum(albedo))`,
    /// kept in `[0.05, 0.95]` (1 when the base is black) so neither lobe is starved.
    fn coat_probability(fo: f32, albedo: Vec3) -> f32 {
        let base = (1.0 - fo) * luminance(albedo);
        if base <= 0.0 { 1.0 } else { (fo / (fo + base)).clamp(0.05, 0.95) }
    }

    /// `f(wo, wi) |wi.z|`. Plastic: `f = f_coat + (1 - F(wo.z)) (1 - F(wi.z)) albedo / pi`, the
    /// coat's GGX reflection plus a base seen through two Fresnel transmissions
    /// (Ashikhmin & Shirley 2000's coupling without internal reflections, so it never
    /// creates energy).
    #[inline]
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Vec3::ZERO;
        }
        match *self {
            Bsdf::Diffuse { albedo } => albedo * (wi.z * FRAC_1_PI),
            Bsdf::Conductor { brdf, .. } => brdf.eval(wo, wi),
            Bsdf::Plastic { coat, ior, albedo, .. } => {
                let t = (1.0 - fresnel_dielectric(wo.z, ior)) * (1.0 - fresnel_dielectric(wi.z, ior));
                coat.eval(wo, wi) + albedo * (t * wi.z * FRAC_1_PI)
            }
            Bsdf::Black => Vec3::ZERO,
        }
    }

    /// Solid-angle density of [`Bsdf::sample`] returning `wi` (0 for delta lobes).
    #[inline]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        match *self {
            Bsdf::Diffuse { .. } => pdf_cosine_hemisphere(wi),
            Bsdf::Conductor { brdf, sampling } => brdf.pdf(wo, wi, sampling),
            Bsdf::Plastic { coat, ior, albedo, sampling } => {
                let p = Self::coat_probability(fresnel_dielectric(wo.z, ior), albedo);
                p * coat.pdf(wo, wi, sampling) + (1.0 - p) * pdf_cosine_hemisphere(wi)
            }
            Bsdf::Black => 0.0,
        }
    }

    /// Draws `wi`: `u_lobe` picks the lobe of a plastic, `u` the direction. The plastic is a
    /// one-sample mixture whose weight is `eval / pdf` of the whole mixture.
    #[inline]
    pub fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        match *self {
            Bsdf::Diffuse { albedo } => {
                let wi = sample_cosine_hemisphere(u);
                Some(BsdfSample { wi, weight: albedo, pdf: pdf_cosine_hemisphere(wi), is_delta: false })
            }
            Bsdf::Conductor { brdf, sampling } => brdf.sample(wo, u, sampling),
            Bsdf::Plastic { coat, ior, albedo, sampling } => {
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
                let pdf = self.pdf(wo, wi);
                if !(pdf > 0.0) {
                    return None;
                }
                Some(BsdfSample { wi, weight: self.eval(wo, wi) / pdf, pdf, is_delta: false })
            }
            Bsdf::Black => None,
        }
    }

    /// True when every lobe is a delta (a mirror conductor): light sampling cannot help.
    pub fn is_delta(&self) -> bool {
        matches!(self, Bsdf::Conductor { brdf, .. } if brdf.is_delta())
    }

    /// True for materials that reflect light at all.
    pub fn reflects(&self) -> bool {
        !matches!(self, Bsdf::Black)
    }
}
