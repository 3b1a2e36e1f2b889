//! Validation of `[materials.NAME]` tables into [`Material`]s.

use glam::Vec3;
use toml::Spanned;

use crate::check::{Interval, span_of};
use crate::error::{ErrorKind, SceneError, Source};
use crate::material::{ConductorFresnel, Material, MaterialPreset, MetalRough};
use crate::radiance::check_radiance;
use crate::raw::{MaterialType, OneOrMany, RawMaterial, Textured};
use crate::texture::TextureRef;
use crate::texture_load::TextureLoader;

const UNIT: Interval = Interval::closed(0.0, 1.0);

/// Validates one material table named `name`; its textures are loaded by `textures`.
pub(crate) fn build(
    src: Source<'_>,
    name: &str,
    raw: &RawMaterial,
    textures: &mut TextureLoader<'_>,
) -> Result<Material, SceneError> {
    let path = format!("materials.{name}");
    let field = |key: &str| format!("{path}.{key}");
    let kind = *raw.kind.get_ref();
    let (type_name, allowed): (_, &[&str]) = match kind {
        MaterialType::Diffuse => ("diffuse", &["albedo", "normal_map", "normal_scale"]),
        MaterialType::MetalRough => (
            "metal-rough",
            &[
                "base_color",
                "metallic",
                "roughness",
                "normal_map",
                "normal_scale",
                "emission",
                "ior",
                "specular",
                "clearcoat",
                "clearcoat_roughness",
            ],
        ),
        MaterialType::Conductor => {
            ("conductor", &["roughness", "alpha", "eta", "k", "f0", "preset", "energy_compensation"])
        }
        MaterialType::Plastic => ("plastic", &["roughness", "alpha", "ior", "albedo", "energy_compensation"]),
        MaterialType::Dielectric => (
            "dielectric",
            &["roughness", "alpha", "ior", "preset", "transmittance", "absorption", "thin", "energy_compensation"],
        ),
        MaterialType::Emissive => ("emissive", &["radiance"]),
    };
    let present = [
        ("albedo", span_of(&raw.albedo)),
        ("roughness", span_of(&raw.roughness)),
        ("alpha", span_of(&raw.alpha)),
        ("eta", span_of(&raw.eta)),
        ("k", span_of(&raw.k)),
        ("f0", span_of(&raw.f0)),
        ("preset", span_of(&raw.preset)),
        ("ior", span_of(&raw.ior)),
        ("radiance", span_of(&raw.radiance)),
        ("transmittance", span_of(&raw.transmittance)),
        ("absorption", span_of(&raw.absorption)),
        ("thin", span_of(&raw.thin)),
        ("energy_compensation", span_of(&raw.energy_compensation)),
        ("base_color", span_of(&raw.base_color)),
        ("metallic", span_of(&raw.metallic)),
        ("normal_map", span_of(&raw.normal_map)),
        ("normal_scale", span_of(&raw.normal_scale)),
        ("emission", span_of(&raw.emission)),
        ("specular", span_of(&raw.specular)),
        ("clearcoat", span_of(&raw.clearcoat)),
        ("clearcoat_roughness", span_of(&raw.clearcoat_roughness)),
    ];
    src.only_keys(&path, type_name, &present, allowed)?;
    let missing = |what: &str| {
        let msg = format!("type \"{type_name}\" needs {what}");
        src.error(raw.kind.span(), &field("type"), ErrorKind::Conflict, msg)
    };
    let albedo = || {
        let a = raw.albedo.as_ref().ok_or_else(|| missing("`albedo`"))?;
        let v = a.get_ref().value().ok_or_else(|| no_texture(src, a.span(), &field("albedo")))?;
        Ok::<_, SceneError>(Vec3::from(src.array(&Spanned::new(a.span(), *v), &field("albedo"), UNIT)?))
    };
    let compensate = raw.energy_compensation.as_ref().is_none_or(|v| *v.get_ref());
    match kind {
        MaterialType::Diffuse => {
            let (normal_texture, normal_scale) = normal_map(src, raw, &path, textures)?;
            let textured =
                raw.albedo.as_ref().is_some_and(|a| a.get_ref().value().is_none()) || normal_texture.is_some();
            if !textured {
                return Ok(Material::Diffuse { albedo: albedo()? });
            }
            // A textured Lambertian: the metal-rough material without its specular lobe
            // (metallic 0, specular 0), whose BRDF is exactly `base_color / pi`.
            let a = raw.albedo.as_ref().ok_or_else(|| missing("`albedo`"))?;
            let (base_color, base_color_texture) = color(src, a, &field("albedo"), textures)?;
            Ok(Material::MetalRough(MetalRough {
                base_color,
                base_color_texture,
                metallic: 0.0,
                specular: 0.0,
                normal_texture,
                normal_scale,
                ..MetalRough::default()
            }))
        }
        MaterialType::MetalRough => metal_rough(src, raw, &path, textures),
        MaterialType::Conductor => {
            let [alpha_x, alpha_y] = alpha(src, raw, &path)?.ok_or_else(|| missing("`roughness` or `alpha`"))?;
            let fresnel =
                conductor_fresnel(src, raw, &path)?.ok_or_else(|| missing("`eta` and `k`, `f0` or `preset`"))?;
            Ok(Material::Conductor { alpha_x, alpha_y, fresnel, compensate })
        }
        MaterialType::Plastic => {
            let [alpha_x, alpha_y] = alpha(src, raw, &path)?.ok_or_else(|| missing("`roughness` or `alpha`"))?;
            if alpha_x != alpha_y {
                let key = if raw.alpha.is_some() { "alpha" } else { "roughness" };
                let span = raw.alpha.as_ref().map(Spanned::span).or(raw.roughness.as_ref().map(Spanned::span));
                let span = span.unwrap_or(raw.kind.span());
                let msg = "plastics are isotropic: give a single number";
                return Err(src.error(span, &field(key), ErrorKind::Conflict, msg));
            }
            let ior = src.number_or(raw.ior.as_ref(), 1.5, &field("ior"), Interval::above(1.0))?;
            Ok(Material::Plastic { alpha: alpha_x, ior, albedo: albedo()?, compensate })
        }
        MaterialType::Dielectric => dielectric(src, raw, &path, compensate),
        MaterialType::Emissive => {
            let r = raw.radiance.as_ref().ok_or_else(|| missing("`radiance`"))?;
            let radiance = Vec3::from(src.array(r, &field("radiance"), Interval::at_least(0.0))?);
            check_radiance(radiance.to_array())
                .map_err(|msg| src.error(r.span(), &field("radiance"), ErrorKind::OutOfRange, msg))?;
            if radiance == Vec3::ZERO {
                let msg = "must be positive in at least one channel (use a black diffuse material for a black surface)";
                return Err(src.error(r.span(), &field("radiance"), ErrorKind::OutOfRange, msg));
            }
            Ok(Material::Emissive { radiance })
        }
    }
}

/// `[alpha_x, alpha_y]` from `alpha` or from `roughness` (`alpha = roughness^2`, Burley 2012);
/// `None` when neither is given.
fn alpha(src: Source<'_>, raw: &RawMaterial, path: &str) -> Result<Option<[f32; 2]>, SceneError> {
    let check = |v: &Spanned<OneOrMany<2>>, key: &str| {
        src.components(v.span(), v.get_ref().written(), &format!("{path}.{key}"), UNIT)?;
        Ok::<_, SceneError>(v.get_ref().components())
    };
    match (&raw.roughness, &raw.alpha) {
        (Some(_), Some(a)) => {
            let msg = "give either `roughness` or `alpha`, not both";
            Err(src.error(a.span(), &format!("{path}.alpha"), ErrorKind::Conflict, msg))
        }
        (Some(r), None) => {
            let field = format!("{path}.roughness");
            let v = r.get_ref().value().ok_or_else(|| no_texture(src, r.span(), &field))?;
            Ok(Some(check(&Spanned::new(r.span(), *v), "roughness")?.map(|r| r * r)))
        }
        (None, Some(a)) => Ok(Some(check(a, "alpha")?)),
        (None, None) => Ok(None),
    }
}

/// The conductor's Fresnel term from exactly one of `eta` + `k`, `f0` or `preset`.
fn conductor_fresnel(src: Source<'_>, raw: &RawMaterial, path: &str) -> Result<Option<ConductorFresnel>, SceneError> {
    let eta_k = if raw.eta.is_some() { ("eta", span_of(&raw.eta)) } else { ("k", span_of(&raw.k)) };
    let given = [eta_k, ("f0", span_of(&raw.f0)), ("preset", span_of(&raw.preset))];
    if let Some((key, Some(span))) = given.iter().filter(|(_, s)| s.is_some()).nth(1) {
        let msg = "give only one of `eta` + `k`, `f0` or `preset`";
        return Err(src.error(span.clone(), &format!("{path}.{key}"), ErrorKind::Conflict, msg));
    }
    if let Some(p) = &raw.preset {
        return match p.get_ref().conductor() {
            Some(fresnel) => Ok(Some(fresnel)),
            None => {
                let msg = format!("is a dielectric preset; conductors take {}", MaterialPreset::CONDUCTORS);
                Err(src.error(p.span(), &format!("{path}.preset"), ErrorKind::Conflict, msg))
            }
        };
    }
    if let Some(f0) = &raw.f0 {
        let f0 = src.array(f0, &format!("{path}.f0"), UNIT)?;
        return Ok(Some(ConductorFresnel::Schlick { f0: f0.into() }));
    }
    match (&raw.eta, &raw.k) {
        (None, None) => Ok(None),
        (Some(eta), Some(k)) => Ok(Some(ConductorFresnel::Complex {
            eta: src.array(eta, &format!("{path}.eta"), Interval::above(0.0))?.into(),
            k: src.array(k, &format!("{path}.k"), Interval::at_least(0.0))?.into(),
        })),
        (Some(v), None) | (None, Some(v)) => {
            let (key, other) = if raw.eta.is_some() { ("eta", "k") } else { ("k", "eta") };
            let msg = format!("`{key}` needs `{other}` too");
            Err(src.error(v.span(), &format!("{path}.{key}"), ErrorKind::Conflict, msg))
        }
    }
}

/// Smallest and largest accepted dielectric `ior`: the range of ggx-core's dielectric
/// energy tables (water 1.33, glass 1.5, diamond 2.42 and their inverses lie inside).
const IOR_RANGE: Interval = Interval::closed(1.0 / 3.0, 3.0);

/// `type = "dielectric"`: `ior` or `preset` (default glass, 1.5), optional `roughness` or
/// `alpha` (default 0: smooth), `transmittance` (default 1), `absorption` (default 0) and
/// `thin` (a smooth sheet without interior, so neither roughness nor absorption applies).
fn dielectric(src: Source<'_>, raw: &RawMaterial, path: &str, compensate: bool) -> Result<Material, SceneError> {
    let field = |key: &str| format!("{path}.{key}");
    let ior = match (&raw.ior, &raw.preset) {
        (Some(_), Some(p)) => {
            let msg = "give either `ior` or `preset`, not both";
            return Err(src.error(p.span(), &field("preset"), ErrorKind::Conflict, msg));
        }
        (Some(v), None) => {
            let ior = src.number(v, &field("ior"), IOR_RANGE)?;
            if ior == 1.0 {
                let msg = "1 is the outside's index: the surface would be invisible (give a tint with `transmittance` on a thin sheet instead)";
                return Err(src.error(v.span(), &field("ior"), ErrorKind::OutOfRange, msg));
            }
            ior
        }
        (None, Some(p)) => p.get_ref().ior().ok_or_else(|| {
            let msg = format!("is a conductor preset; dielectrics take {}", MaterialPreset::DIELECTRICS);
            src.error(p.span(), &field("preset"), ErrorKind::Conflict, msg)
        })?,
        (None, None) => 1.5,
    };
    let [alpha_x, alpha_y] = alpha(src, raw, path)?.unwrap_or([0.0; 2]);
    let transmittance = match &raw.transmittance {
        Some(t) => Vec3::from(src.array(t, &field("transmittance"), UNIT)?),
        None => Vec3::ONE,
    };
    let absorption = match &raw.absorption {
        Some(a) => Vec3::from(src.array(a, &field("absorption"), Interval::at_least(0.0))?),
        None => Vec3::ZERO,
    };
    let thin = raw.thin.as_ref().is_some_and(|t| *t.get_ref());
    if thin {
        let rough = raw.alpha.as_ref().map(Spanned::span).or(raw.roughness.as_ref().map(Spanned::span));
        if let Some(r) = rough.filter(|_| alpha_x > 0.0 || alpha_y > 0.0) {
            let key = if raw.alpha.is_some() { "alpha" } else { "roughness" };
            let msg = "a thin sheet is smooth: remove it or set `thin = false`";
            return Err(src.error(r, &field(key), ErrorKind::Conflict, msg));
        }
        if let Some(a) = raw.absorption.as_ref().filter(|_| absorption != Vec3::ZERO) {
            let msg = "a thin sheet has no interior to absorb in: tint it with `transmittance`";
            return Err(src.error(a.span(), &field("absorption"), ErrorKind::Conflict, msg));
        }
    }
    Ok(Material::Dielectric { alpha_x, alpha_y, ior, transmittance, absorption, thin, compensate })
}

/// A texture where only a value is accepted.
fn no_texture(src: Source<'_>, span: std::ops::Range<usize>, field: &str) -> SceneError {
    let msg = "textures apply to `metal-rough` materials and a diffuse `albedo`: give a value here";
    src.error(span, field, ErrorKind::Schema, msg)
}

/// An RGB in [0, 1] or an sRGB colour texture (factor 1).
fn color(
    src: Source<'_>,
    v: &Spanned<Textured<[f64; 3]>>,
    field: &str,
    textures: &mut TextureLoader<'_>,
) -> Result<(Vec3, TextureRef), SceneError> {
    match v.get_ref() {
        Textured::Value(c) => Ok((Vec3::from(src.array(&Spanned::new(v.span(), *c), field, UNIT)?), TextureRef::NONE)),
        Textured::Texture(t) => Ok((Vec3::ONE, textures.load(src, v.span(), field, t, 0, true)?)),
    }
}

/// `normal_map` (linear, tangent space, +Y up) and `normal_scale` (default 1).
fn normal_map(
    src: Source<'_>,
    raw: &RawMaterial,
    path: &str,
    textures: &mut TextureLoader<'_>,
) -> Result<(TextureRef, f32), SceneError> {
    let scale = src.number_or(raw.normal_scale.as_ref(), 1.0, &format!("{path}.normal_scale"), Interval::ANY)?;
    let Some(n) = &raw.normal_map else {
        if let Some(s) = &raw.normal_scale {
            let msg = "`normal_scale` needs `normal_map`";
            return Err(src.error(s.span(), &format!("{path}.normal_scale"), ErrorKind::Conflict, msg));
        }
        return Ok((TextureRef::NONE, 1.0));
    };
    Ok((textures.load(src, n.span(), &format!("{path}.normal_map"), n.get_ref(), 0, false)?, scale))
}

/// `type = "metal-rough"`: glTF's metallic-roughness material. `base_color` (default 1),
/// `metallic` (default 0), `roughness` (perceptual, default 0.5), each a value or a texture
/// (`channel` defaults: metallic B, roughness G, as glTF packs them), `normal_map`,
/// `emission` (RGB radiance or an sRGB texture), `ior` (default 1.5), `specular` (default 1),
/// `clearcoat` (`KHR_materials_clearcoat`'s weight, default 0) and `clearcoat_roughness`
/// (perceptual, default 0; only with a `clearcoat`).
fn metal_rough(
    src: Source<'_>,
    raw: &RawMaterial,
    path: &str,
    textures: &mut TextureLoader<'_>,
) -> Result<Material, SceneError> {
    let field = |key: &str| format!("{path}.{key}");
    let (base_color, base_color_texture) = match &raw.base_color {
        Some(c) => color(src, c, &field("base_color"), textures)?,
        None => (Vec3::ONE, TextureRef::NONE),
    };
    let scalar = |v: Option<&Spanned<Textured<f64>>>,
                  key: &str,
                  default: f32,
                  channel: u32,
                  textures: &mut TextureLoader<'_>| {
        match v {
            None => Ok((default, TextureRef::NONE)),
            Some(s) => match s.get_ref() {
                Textured::Value(x) => {
                    Ok((src.number(&Spanned::new(s.span(), *x), &field(key), UNIT)?, TextureRef::NONE))
                }
                Textured::Texture(t) => Ok((1.0, textures.load(src, s.span(), &field(key), t, channel, false)?)),
            },
        }
    };
    let (metallic, metallic_texture) = scalar(raw.metallic.as_ref(), "metallic", 0.0, 2, textures)?;
    let (roughness, roughness_texture) = match &raw.roughness {
        None => (0.5, TextureRef::NONE),
        Some(r) => match r.get_ref() {
            Textured::Texture(t) => (1.0, textures.load(src, r.span(), &field("roughness"), t, 1, false)?),
            Textured::Value(v) => {
                src.components(r.span(), v.written(), &field("roughness"), UNIT)?;
                if v.written().len() != 1 {
                    let msg = "metal-rough materials are isotropic: give a single number";
                    return Err(src.error(r.span(), &field("roughness"), ErrorKind::Conflict, msg));
                }
                (v.components()[0], TextureRef::NONE)
            }
        },
    };
    let (normal_texture, normal_scale) = normal_map(src, raw, path, textures)?;
    let (emission, emission_texture) = match &raw.emission {
        None => (Vec3::ZERO, TextureRef::NONE),
        Some(e) => match e.get_ref() {
            Textured::Texture(t) => (Vec3::ONE, textures.load(src, e.span(), &field("emission"), t, 0, true)?),
            Textured::Value(v) => {
                let radiance =
                    Vec3::from(src.array(&Spanned::new(e.span(), *v), &field("emission"), Interval::at_least(0.0))?);
                check_radiance(radiance.to_array())
                    .map_err(|msg| src.error(e.span(), &field("emission"), ErrorKind::OutOfRange, msg))?;
                (radiance, TextureRef::NONE)
            }
        },
    };
    let ior = src.number_or(raw.ior.as_ref(), 1.5, &field("ior"), Interval::closed(1.0, 3.0))?;
    let specular = src.number_or(raw.specular.as_ref(), 1.0, &field("specular"), UNIT)?;
    let clearcoat = src.number_or(raw.clearcoat.as_ref(), 0.0, &field("clearcoat"), UNIT)?;
    let clearcoat_roughness =
        src.number_or(raw.clearcoat_roughness.as_ref(), 0.0, &field("clearcoat_roughness"), UNIT)?;
    if let Some(r) = raw.clearcoat_roughness.as_ref().filter(|_| raw.clearcoat.is_none()) {
        let msg = "`clearcoat_roughness` needs `clearcoat`";
        return Err(src.error(r.span(), &field("clearcoat_roughness"), ErrorKind::Conflict, msg));
    }
    Ok(Material::MetalRough(MetalRough {
        base_color,
        base_color_texture,
        metallic,
        metallic_texture,
        roughness,
        roughness_texture,
        normal_texture,
        normal_scale,
        emission,
        emission_texture,
        ior,
        specular,
        specular_color: Vec3::ONE,
        anisotropy: 0.0,
        anisotropy_rotation: 0.0,
        clearcoat,
        clearcoat_roughness,
    }))
}
