//! Materials: diffuse, GGX conductor, GGX-coated plastic, GGX dielectric and emitter.

use glam::Vec3;
use serde::Deserialize;

use crate::texture::TextureRef;

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

/// Named material presets (`preset = "gold"`, `preset = "glass"`): conductors by their
/// complex index of refraction, dielectrics by their index of refraction.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq, Hash)]
#[serde(rename_all = "kebab-case")]
pub enum MaterialPreset {
    /// Gold (Au), a conductor.
    Gold,
    /// Silver (Ag), a conductor.
    Silver,
    /// Copper (Cu), a conductor.
    Copper,
    /// Aluminium (Al), a conductor.
    Aluminium,
    /// `F = 1` ([`ConductorFresnel::One`]), a conductor.
    Ideal,
    /// Crown glass, dielectric, ior 1.5.
    Glass,
    /// Water, dielectric, ior 1.33.
    Water,
    /// Diamond, dielectric, ior 2.42.
    Diamond,
}

impl MaterialPreset {
    /// The names of the conductor presets, for error messages.
    pub const CONDUCTORS: &'static str = "gold, silver, copper, aluminium, ideal";
    /// The names of the dielectric presets, for error messages.
    pub const DIELECTRICS: &'static str = "glass (1.5), water (1.33), diamond (2.42)";

    /// The Fresnel term of a conductor preset (`None` for a dielectric one). The complex
    /// indices are RGB values (at about 650, 550 and 450 nm) of the measured spectral data
    /// shipped with pbrt-v3 / Mitsuba (Au, Ag, Cu, Al from Palik's Handbook of Optical Constants).
    pub fn conductor(self) -> Option<ConductorFresnel> {
        let c = |eta: [f32; 3], k: [f32; 3]| Some(ConductorFresnel::Complex { eta: eta.into(), k: k.into() });
        match self {
            Self::Gold => c([0.143, 0.374, 1.442], [3.983, 2.385, 1.603]),
            Self::Silver => c([0.155, 0.117, 0.138], [4.828, 3.122, 2.147]),
            Self::Copper => c([0.200, 0.924, 1.102], [3.912, 2.452, 2.142]),
            Self::Aluminium => c([1.657, 0.880, 0.521], [9.224, 6.270, 4.837]),
            Self::Ideal => Some(ConductorFresnel::One),
            Self::Glass | Self::Water | Self::Diamond => None,
        }
    }

    /// The index of refraction of a dielectric preset at about 589 nm (`None` for a
    /// conductor): glass 1.5 (crown glass), water 1.33, diamond 2.42.
    pub fn ior(self) -> Option<f32> {
        match self {
            Self::Glass => Some(1.5),
            Self::Water => Some(1.33),
            Self::Diamond => Some(2.42),
            _ => None,
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
        /// Add the Kulla & Conty 2017 multiple-scattering lobe (`energy_compensation`).
        compensate: bool,
    },
    /// GGX dielectric coat (index `ior`) over a Lambertian base of reflectance `albedo`.
    Plastic {
        /// GGX alpha of the coat, in [0, 1].
        alpha: f32,
        /// Index of refraction of the coat, > 1.
        ior: f32,
        /// Reflectance of the diffuse base, in [0, 1].
        albedo: Vec3,
        /// Couple the base through the coat's `1 - E` albedo (`energy_compensation`) rather than
        /// through two Fresnel transmissions.
        compensate: bool,
    },
    /// GGX rough dielectric interface (Walter et al. 2007): reflection and refraction between
    /// the outside (the side the surface normal points to, index 1) and the inside (`ior`).
    Dielectric {
        /// GGX alpha along the tangent, in [0, 1] (below `ggx_core::DELTA_ALPHA`: smooth).
        alpha_x: f32,
        /// GGX alpha along the bitangent, in [0, 1].
        alpha_y: f32,
        /// Index of refraction of the inside relative to the outside, in `[1/3, 3]`, not 1.
        ior: f32,
        /// Tint applied to every transmission through the surface, in [0, 1].
        transmittance: Vec3,
        /// Beer-Lambert absorption coefficient of the inside, per scene unit, >= 0.
        absorption: Vec3,
        /// A thin sheet: smooth, no interior, light passes straight through.
        thin: bool,
        /// Scale the single-scattering lobe to conserve energy (`energy_compensation`).
        compensate: bool,
    },
    /// The glTF 2.0 metallic-roughness material (`ggx_core::GltfMetalRough`), every parameter
    /// optionally textured, with normal map and emission.
    MetalRough(MetalRough),
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
            Self::MetalRough(m) => m.emission,
            _ => Vec3::ZERO,
        }
    }

    /// `true` for anisotropic conductors and dielectrics.
    pub fn is_anisotropic(&self) -> bool {
        match self {
            Self::Conductor { alpha_x, alpha_y, .. } | Self::Dielectric { alpha_x, alpha_y, .. } => alpha_x != alpha_y,
            _ => false,
        }
    }

    /// The material with its energy-compensation flag set to `on` (no change for materials
    /// without one): the scene-wide `integrator.energy_compensation` override.
    pub fn with_compensation(mut self, on: bool) -> Self {
        match &mut self {
            Self::Conductor { compensate, .. }
            | Self::Plastic { compensate, .. }
            | Self::Dielectric { compensate, .. } => *compensate = on,
            Self::Diffuse { .. } | Self::Emissive { .. } | Self::MetalRough(_) => {}
        }
        self
    }
}

/// The glTF 2.0 metallic-roughness material (glTF 2.0 spec, Appendix B) with
/// `KHR_materials_ior`, `KHR_materials_specular` and `KHR_materials_emissive_strength`. Each
/// factor multiplies its texture (when set) at the shading point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MetalRough {
    /// Base colour factor (linear RGB, [0, 1]).
    pub base_color: Vec3,
    /// Base colour texture (sRGB, RGB used; alpha is not used: ggx renders opaque surfaces).
    pub base_color_texture: TextureRef,
    /// Metallic factor in [0, 1].
    pub metallic: f32,
    /// Metallic texture (glTF: the B channel of `metallicRoughnessTexture`).
    pub metallic_texture: TextureRef,
    /// Perceptual roughness factor in [0, 1]; GGX alpha = roughness^2.
    pub roughness: f32,
    /// Roughness texture (glTF: the G channel of `metallicRoughnessTexture`).
    pub roughness_texture: TextureRef,
    /// Tangent-space normal map (linear RGB, `n = 2 rgb - 1`, +Y up, glTF convention).
    pub normal_texture: TextureRef,
    /// Scale of the normal map's X and Y.
    pub normal_scale: f32,
    /// Emitted radiance factor (`emissiveFactor * emissive_strength`), >= 0.
    pub emission: Vec3,
    /// Emission texture (sRGB).
    pub emission_texture: TextureRef,
    /// Index of refraction of the dielectric part (`KHR_materials_ior`, default 1.5).
    pub ior: f32,
    /// Specular weight (`KHR_materials_specular`'s `specularFactor`, default 1).
    pub specular: f32,
    /// Specular colour (`specularColorFactor`, default 1).
    pub specular_color: Vec3,
    /// `KHR_materials_anisotropy`'s strength in [0, 1] (0: isotropic): the GGX alpha along the
    /// anisotropy direction is `mix(alpha, 1, strength^2)`.
    pub anisotropy: f32,
    /// The anisotropy direction: radians counter-clockwise from the mesh's tangent (toward the
    /// bitangent).
    pub anisotropy_rotation: f32,
    /// `KHR_materials_clearcoat`'s `clearcoatFactor` in [0, 1] (0: no coat): the weight of a
    /// GGX coat (`ior` 1.5) over the material, ggx-core's `GltfClearcoat`.
    pub clearcoat: f32,
    /// The coat's perceptual roughness (`clearcoatRoughnessFactor`) in [0, 1]; coat alpha =
    /// roughness^2.
    pub clearcoat_roughness: f32,
}

impl Default for MetalRough {
    fn default() -> Self {
        Self {
            base_color: Vec3::ONE,
            base_color_texture: TextureRef::NONE,
            metallic: 1.0,
            metallic_texture: TextureRef::NONE,
            roughness: 1.0,
            roughness_texture: TextureRef::NONE,
            normal_texture: TextureRef::NONE,
            normal_scale: 1.0,
            emission: Vec3::ZERO,
            emission_texture: TextureRef::NONE,
            ior: 1.5,
            specular: 1.0,
            specular_color: Vec3::ONE,
            anisotropy: 0.0,
            anisotropy_rotation: 0.0,
            clearcoat: 0.0,
            clearcoat_roughness: 0.0,
        }
    }
}

impl MetalRough {
    /// True when the BSDF depends on the shading point: some parameter is read from a
    /// texture, or the anisotropy follows the mesh's tangents (the renderers then build the
    /// BSDF and its frame at each shading point).
    pub fn is_textured(&self) -> bool {
        [self.base_color_texture, self.metallic_texture, self.roughness_texture, self.normal_texture]
            .iter()
            .any(TextureRef::is_some)
            || self.anisotropy != 0.0
    }

    /// True when the emission is textured.
    pub fn has_emission_texture(&self) -> bool {
        self.emission_texture.is_some()
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
    fn presets_are_either_conductors_or_dielectrics() {
        use MaterialPreset::*;
        for p in [Gold, Silver, Copper, Aluminium, Ideal, Glass, Water, Diamond] {
            assert!(p.conductor().is_some() != p.ior().is_some(), "{p:?}");
        }
        assert_eq!(Diamond.ior(), Some(2.42));
        let glass = Material::Dielectric {
            alpha_x: 0.1,
            alpha_y: 0.2,
            ior: 1.5,
            transmittance: Vec3::ONE,
            absorption: Vec3::ZERO,
            thin: false,
            compensate: true,
        };
        assert!(glass.is_anisotropic());
        assert!(matches!(glass.with_compensation(false), Material::Dielectric { compensate: false, .. }));
    }

    #[test]
    fn luminance_weights_round_to_the_f32_literals() {
        assert_eq!(LUMINANCE_WEIGHTS.map(|w| w as f32), [0.2126f32, 0.7152, 0.0722]);
    }
}
