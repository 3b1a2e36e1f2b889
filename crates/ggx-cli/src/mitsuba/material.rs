//! ggx materials as Mitsuba 3 BSDFs, only where the two are the same model; anything else is
//! refused with the reason ([`NoTwin`]).
//!
//! ggx's reflective materials are two-sided (shaded in a frame turned toward the ray), so each
//! is wrapped in Mitsuba's `twosided`. A ggx conductor is Mitsuba's `roughconductor` with
//! `distribution = ggx` and `sample_visible = true` (single scattering, exact complex Fresnel
//! per RGB channel, height-correlated in ggx and separable in Mitsuba's G2; both converge to
//! the same images only where that difference is invisible, which the peer comparison
//! measures); below ggx's delta threshold it is Mitsuba's smooth `conductor`.

use std::fmt;

use ggx_cpu::Bsdf;
use ggx_film::Vec3;
use ggx_scene::{BsdfStrategy, ConductorFresnel, Material};

use super::xml::Xml;

/// ggx-core's smallest alpha (`ggx_core::ALPHA_MIN`): ggx clamps every alpha up to it, so the
/// export does too.
pub const ALPHA_MIN: f32 = 1e-4;

/// A material that has no one-to-one Mitsuba twin.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct NoTwin {
    /// The material's name in the scene file.
    pub material: String,
    /// Its kind, e.g. `plastic`.
    pub kind: &'static str,
    /// Why it has no twin and what to do instead.
    pub reason: &'static str,
}

impl fmt::Display for NoTwin {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "material `{}` ({}) has no one-to-one Mitsuba 3 twin: {}", self.material, self.kind, self.reason)
    }
}

impl std::error::Error for NoTwin {}

/// Why a plastic is refused.
const PLASTIC: &str = "Mitsuba's roughplastic is a different model from ggx's coated plastic (it couples \
    the diffuse base through its own internal-reflection terms; a floor rendered in both came out 23 % darker \
    in Mitsuba), so the images would differ by construction; use a diffuse or conductor material to compare";
/// Why a dielectric is refused.
const DIELECTRIC: &str = "ggx's dielectric tracks the inside by side, with Beer-Lambert absorption, tint and \
    its own thin-sheet and energy-compensation models; the exporter does not write Mitsuba's roughdielectric \
    with an interior medium, which would be needed to match it";
/// Why a Schlick conductor is refused.
const SCHLICK: &str = "Mitsuba's conductors take a complex index of refraction (eta, k), not Schlick's f0; give \
    `eta` and `k` (or a preset) instead of `f0`";
/// Why a compensated conductor is refused.
const COMPENSATED: &str = "energy compensation (Kulla & Conty's multiple-scattering lobe) is on, and Mitsuba's \
    roughconductor is single-scattering; set `energy_compensation = false` in the scene (material or \
    [integrator]) or pass --energy-compensation off";

/// Why the glTF material has no Mitsuba twin.
const METAL_ROUGH: &str = "Mitsuba 3's principled BSDF is Disney's model, not glTF's Appendix B mix of a Lambertian \
    and a GGX lobe with Schlick Fresnel, and its textures and normal maps are not exported";

/// `r, g, b` as Mitsuba's `rgb` value (shortest round-trip decimals).
pub fn rgb(v: Vec3) -> String {
    format!("{}, {}, {}", v.x, v.y, v.z)
}

/// Checks that `material` has a Mitsuba twin, or says why not (`name` names it).
pub fn check(name: &str, material: &Material) -> Result<(), NoTwin> {
    let refuse = |kind, reason| Err(NoTwin { material: name.to_owned(), kind, reason });
    match material {
        Material::Diffuse { .. } | Material::Emissive { .. } => Ok(()),
        Material::Plastic { .. } => refuse("plastic", PLASTIC),
        Material::Dielectric { .. } => refuse("dielectric", DIELECTRIC),
        Material::Conductor { fresnel: ConductorFresnel::Schlick { .. }, .. } => refuse("conductor, f0", SCHLICK),
        Material::Conductor { compensate: true, .. } => refuse("conductor, energy compensation on", COMPENSATED),
        Material::Conductor { .. } => Ok(()),
        Material::MetalRough(_) => refuse("glTF metallic-roughness", METAL_ROUGH),
    }
}

/// Writes the `<bsdf id="id">` of a reflective material (diffuse or conductor, as [`check`]
/// accepts); emitters get their black BSDF inline in their shape ([`emitter_bsdf`]).
pub fn write_bsdf(xml: &mut Xml, id: &str, material: &Material) {
    match *material {
        Material::Diffuse { albedo } => {
            xml.open("bsdf", &[("type", "twosided"), ("id", id)]);
            xml.open("bsdf", &[("type", "diffuse")]);
            xml.leaf("rgb", &[("name", "reflectance"), ("value", &rgb(albedo))]);
            xml.close();
            xml.close();
        }
        Material::Conductor { alpha_x, alpha_y, fresnel, .. } => {
            let delta = Bsdf::new(material, BsdfStrategy::Vndf).is_delta();
            xml.open("bsdf", &[("type", "twosided"), ("id", id)]);
            if delta {
                xml.comment("both alphas below ggx's delta threshold 1e-3: a smooth (mirror) conductor");
                xml.open("bsdf", &[("type", "conductor")]);
            } else {
                xml.open("bsdf", &[("type", "roughconductor")]);
                xml.leaf("string", &[("name", "distribution"), ("value", "ggx")]);
                xml.leaf("boolean", &[("name", "sample_visible"), ("value", "true")]);
                let (ax, ay) = (alpha_x.max(ALPHA_MIN), alpha_y.max(ALPHA_MIN));
                if ax == ay {
                    xml.leaf("float", &[("name", "alpha"), ("value", &ax.to_string())]);
                } else {
                    xml.comment("anisotropic: u is ggx's tangent (the mesh's texture coordinates follow it)");
                    xml.leaf("float", &[("name", "alpha_u"), ("value", &ax.to_string())]);
                    xml.leaf("float", &[("name", "alpha_v"), ("value", &ay.to_string())]);
                }
            }
            match fresnel {
                ConductorFresnel::Complex { eta, k } => {
                    xml.leaf("rgb", &[("name", "eta"), ("value", &rgb(eta))]);
                    xml.leaf("rgb", &[("name", "k"), ("value", &rgb(k))]);
                }
                // "none": eta = 0, k = 1, a Fresnel of exactly 1 (ggx's F = 1 conductor).
                ConductorFresnel::One => xml.leaf("string", &[("name", "material"), ("value", "none")]),
                // Refused by `check`; written as the closest thing should a caller skip it.
                ConductorFresnel::Schlick { .. } => xml.comment("Schlick f0 has no twin (refused by check)"),
            }
            xml.close();
            xml.close();
        }
        Material::Plastic { .. }
        | Material::Dielectric { .. }
        | Material::Emissive { .. }
        | Material::MetalRough(_) => {}
    }
}

/// An emitter's inline BSDF (black: ggx's emitters reflect nothing) and `area` emitter of
/// `radiance` (one-sided, front face, as in ggx).
pub fn emitter_bsdf(xml: &mut Xml, radiance: Vec3) {
    xml.open("bsdf", &[("type", "diffuse")]);
    xml.leaf("rgb", &[("name", "reflectance"), ("value", "0, 0, 0")]);
    xml.close();
    xml.open("emitter", &[("type", "area")]);
    xml.leaf("rgb", &[("name", "radiance"), ("value", &rgb(radiance))]);
    xml.close();
}

#[cfg(test)]
mod tests {
    use super::*;

    fn conductor(ax: f32, ay: f32, fresnel: ConductorFresnel, compensate: bool) -> Material {
        Material::Conductor { alpha_x: ax, alpha_y: ay, fresnel, compensate }
    }

    const GOLD: ConductorFresnel =
        ConductorFresnel::Complex { eta: Vec3::new(0.143, 0.374, 1.442), k: Vec3::new(3.983, 2.385, 1.603) };

    #[test]
    fn refuses_materials_without_a_twin_by_name() {
        let plastic = Material::Plastic { alpha: 0.1, ior: 1.5, albedo: Vec3::ONE, compensate: false };
        let e = check("floor", &plastic).unwrap_err();
        assert_eq!((e.material.as_str(), e.kind), ("floor", "plastic"));
        let text = e.to_string();
        assert!(text.starts_with("material `floor` (plastic) has no one-to-one Mitsuba 3 twin"), "{text}");
        assert!(text.contains("roughplastic"), "{text}");
        let schlick = conductor(0.1, 0.1, ConductorFresnel::Schlick { f0: Vec3::ONE }, false);
        assert!(check("chrome", &schlick).unwrap_err().to_string().contains("eta"));
        let compensated = conductor(0.1, 0.1, GOLD, true);
        assert!(check("gold", &compensated).unwrap_err().to_string().contains("--energy-compensation off"));
        assert!(check("gold", &conductor(0.1, 0.1, GOLD, false)).is_ok());
        assert!(check("w", &Material::Diffuse { albedo: Vec3::ONE }).is_ok());
    }

    #[test]
    fn conductors_become_rough_smooth_or_anisotropic() {
        let xml_of = |m: Material| {
            let mut x = Xml::new();
            write_bsdf(&mut x, "m", &m);
            x.finish()
        };
        let rough = xml_of(conductor(0.05, 0.05, GOLD, false));
        for part in [
            "type=\"twosided\" id=\"m\"",
            "type=\"roughconductor\"",
            "value=\"ggx\"",
            "name=\"sample_visible\" value=\"true\"",
            "name=\"alpha\" value=\"0.05\"",
            "name=\"eta\" value=\"0.143, 0.374, 1.442\"",
            "name=\"k\" value=\"3.983, 2.385, 1.603\"",
        ] {
            assert!(rough.contains(part), "missing {part}: {rough}");
        }
        let aniso = xml_of(conductor(0.05, 0.5, ConductorFresnel::One, false));
        assert!(aniso.contains("\"alpha_u\" value=\"0.05\"") && aniso.contains("\"alpha_v\" value=\"0.5\""), "{aniso}");
        assert!(aniso.contains("name=\"material\" value=\"none\""), "{aniso}");
        let mirror = xml_of(conductor(5e-4, 1e-4, GOLD, false));
        assert!(mirror.contains("type=\"conductor\"") && !mirror.contains("name=\"alpha"), "{mirror}");
        let tiny = xml_of(conductor(0.0, 0.5, GOLD, false));
        assert!(tiny.contains("\"alpha_u\" value=\"0.0001\""), "clamped as ggx clamps: {tiny}");
    }
}
