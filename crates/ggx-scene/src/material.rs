//! Materials: diffuse, GGX conductor, GGX-coated plastic and emitter, plus a flat
//! GPU-uploadable form.

use bytemuck::{Pod, Zeroable};
use glam::Vec3;
use serde::Deserialize;

/// Fresnel reflectance of a conductor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ConductorFresnel {
    /// Schlick's approximation `F = f0 + (1 - f0) (1 - cos)^5` (Schlick 1994).
    Schlick {
        /// Reflectance at normal incidence per RGB channel, in [0, 1].
        f0: Vec3,
    },
    /// Exact conductor Fresnel with complex index of refraction `eta + i k` per RGB channel.
    Complex {
        /// Real part of the index of refraction, > 0.
        eta: Vec3,
        /// Extinction coefficient, >= 0.
        k: Vec3,
    },
    /// `F = 1` for every angle: an ideal, lossless mirror-like conductor for furnace tests.
    One,
}

/// Named conductor presets (`preset = "gold"`).
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq, Hash)]
#[serde(rename_all = "kebab-case")]
pub enum ConductorPreset {
    /// Gold (Au).
    Gold,
    /// Silver (Ag).
    Silver,
    /// Copper (Cu).
    Copper,
    /// Aluminium (Al).
    Aluminium,
    /// `F = 1` ([`ConductorFresnel::One`]).
    Ideal,
}

impl ConductorPreset {
    /// The preset's Fresnel term. The complex indices are RGB values (at about 650, 550 and
    /// 450 nm) of the measured spectral data shipped with pbrt-v3 / Mitsuba
    /// (Au, Ag, Cu, Al from Palik's Handbook of Optical Constants).
    pub fn fresnel(self) -> ConductorFresnel {
        let c = |eta: [f32; 3], k: [f32; 3]| ConductorFresnel::Complex { eta: eta.into(), k: k.into() };
        match self {
            Self::Gold => c([0.143, 0.374, 1.442], [3.983, 2.385, 1.603]),
            Self::Silver => c([0.155, 0.117, 0.138], [4.828, 3.122, 2.147]),
            Self::Copper => c([0.200, 0.924, 1.102], [3.912, 2.452, 2.142]),
            Self::Aluminium => c([1.657, 0.880, 0.521], [9.224, 6.270, 4.837]),
            Self::Ideal => ConductorFresnel::One,
        }
    }
}

/// A validated material. GGX roughness is stored as `alpha` (the distribution's width
/// parameter); scene files may give `roughness` instead, with `alpha = roughness^2`
/// (Burley 2012, "Physically-Based Shading at Disney").
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Material {
    /// Lambertian reflector: `f = albedo / pi`.
    Diffuse {
        /// Reflectance per RGB channel, in [0, 1].
        albedo: Vec3,
    },
    /// GGX microfacet conductor, anisotropic when `alpha_x != alpha_y`.
    Conductor {
        /// GGX alpha along the tangent, in [0, 1].
        alpha_x: f32,
        /// GGX alpha along the bitangent, in [0, 1].
        alpha_y: f32,
        /// Fresnel reflectance.
        fresnel: ConductorFresnel,
    },
    /// GGX dielectric coat (index `ior`) over a Lambertian base of reflectance `albedo`.
    Plastic {
        /// GGX alpha of the coat, in [0, 1].
        alpha: f32,
        /// Index of refraction of the coat, > 1.
        ior: f32,
        /// Reflectance of the diffuse base, in [0, 1].
        albedo: Vec3,
    },
    /// Area-light emitter: radiates `radiance` from its front face, reflects nothing.
    Emissive {
        /// Emitted radiance per RGB channel, >= 0 and not all zero.
        radiance: Vec3,
    },
}

impl Material {
    /// Emitted radiance (zero for non-emitters).
    pub fn emission(&self) -> Vec3 {
        match self {
            Self::Emissive { radiance } => *radiance,
            _ => Vec3::ZERO,
        }
    }

    /// `true` for anisotropic conductors.
    pub fn is_anisotropic(&self) -> bool {
        matches!(self, Self::Conductor { alpha_x, alpha_y, .. } if alpha_x != alpha_y)
    }

    /// The flat GPU form.
    pub fn to_gpu(&self) -> GpuMaterial {
        let v4 = |v: Vec3, w: f32| [v.x, v.y, v.z, w];
        let zero = [0.0; 4];
        match *self {
            Self::Diffuse { albedo } => GpuMaterial::new(GpuMaterial::DIFFUSE, 0, [0.0; 2], v4(albedo, 0.0), zero),
            Self::Conductor { alpha_x, alpha_y, fresnel } => {
                let (kind, a, b) = match fresnel {
                    ConductorFresnel::Schlick { f0 } => (GpuMaterial::FRESNEL_SCHLICK, v4(f0, 0.0), zero),
                    ConductorFresnel::Complex { eta, k } => (GpuMaterial::FRESNEL_COMPLEX, v4(eta, 0.0), v4(k, 0.0)),
                    ConductorFresnel::One => (GpuMaterial::FRESNEL_ONE, [1.0; 4], zero),
                };
                GpuMaterial::new(GpuMaterial::CONDUCTOR, kind, [alpha_x, alpha_y], a, b)
            }
            Self::Plastic { alpha, ior, albedo } => {
                GpuMaterial::new(GpuMaterial::PLASTIC, 0, [alpha, alpha], v4(albedo, ior), zero)
            }
            Self::Emissive { radiance } => {
                GpuMaterial::new(GpuMaterial::EMISSIVE, 0, [0.0; 2], v4(radiance, 0.0), zero)
            }
        }
    }
}

/// A material as one 48-byte, std430-compatible record.
///
/// | `kind` | `color` (rgb, w) | `extra` |
/// |---|---|---|
/// | `DIFFUSE` | albedo | - |
/// | `CONDUCTOR` | f0 (Schlick), eta (complex), 1 (one) | k (complex) |
/// | `PLASTIC` | albedo, w = ior | - |
/// | `EMISSIVE` | radiance | - |
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuMaterial {
    /// One of the `DIFFUSE`, `CONDUCTOR`, `PLASTIC`, `EMISSIVE` constants.
    pub kind: u32,
    /// For conductors one of the `FRESNEL_*` constants, else 0.
    pub fresnel: u32,
    /// GGX `[alpha_x, alpha_y]` (equal for plastics, zero for others).
    pub alpha: [f32; 2],
    /// Main colour, see the table.
    pub color: [f32; 4],
    /// Second parameter, see the table.
    pub extra: [f32; 4],
}

impl GpuMaterial {
    /// [`Material::Diffuse`].
    pub const DIFFUSE: u32 = 0;
    /// [`Material::Conductor`].
    pub const CONDUCTOR: u32 = 1;
    /// [`Material::Plastic`].
    pub const PLASTIC: u32 = 2;
    /// [`Material::Emissive`].
    pub const EMISSIVE: u32 = 3;
    /// [`ConductorFresnel::Schlick`].
    pub const FRESNEL_SCHLICK: u32 = 0;
    /// [`ConductorFresnel::Complex`].
    pub const FRESNEL_COMPLEX: u32 = 1;
    /// [`ConductorFresnel::One`].
    pub const FRESNEL_ONE: u32 = 2;

    const fn new(kind: u32, fresnel: u32, alpha: [f32; 2], color: [f32; 4], extra: [f32; 4]) -> Self {
        Self { kind, fresnel, alpha, color, extra }
    }
}

/// Rec. 709 / sRGB relative luminance weights of R, G and B, in `f64` for the callers that
/// compute in `f64` (environment map sampling weights); [`luminance`] rounds them to `f32`.
pub const LUMINANCE_WEIGHTS: [f64; 3] = [0.2126, 0.7152, 0.0722];

/// Rec. 709 / sRGB relative luminance `Y = 0.2126 R + 0.7152 G + 0.0722 B`
/// ([`LUMINANCE_WEIGHTS`]).
pub fn luminance(rgb: Vec3) -> f32 {
    let [r, g, b] = LUMINANCE_WEIGHTS;
    rgb.dot(Vec3::new(r as f32, g as f32, b as f32))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gpu_material_is_48_bytes() {
        assert_eq!(size_of::<GpuMaterial>(), 48);
        let m = Material::Plastic { alpha: 0.1, ior: 1.5, albedo: Vec3::splat(0.5) }.to_gpu();
        assert_eq!((m.kind, m.color[3], m.alpha), (GpuMaterial::PLASTIC, 1.5, [0.1, 0.1]));
    }

    #[test]
    fn luminance_weights_round_to_the_f32_literals() {
        assert_eq!(LUMINANCE_WEIGHTS.map(|w| w as f32), [0.2126f32, 0.7152, 0.0722]);
    }
}
