//! glTF materials to [`MetalRough`]: factors, textures (decoded once per image, one
//! [`TextureSet`] entry per image and sampler), `KHR_texture_transform`, and the extensions
//! ggx reads; what it cannot render becomes a warning.

use std::collections::HashMap;
use std::path::Path;

use glam::Vec3;
use gltf::texture::{MagFilter, WrappingMode};

use super::sources::{decode_image, read_uri};
use crate::limits::Limits;
use crate::material::{Material, MetalRough};
use crate::texture::{TEXTURE_NEAREST, TEXTURE_WRAP_S_SHIFT, TEXTURE_WRAP_T_SHIFT, TextureRef, TextureSet, Wrap};

/// Textures already added to the set: by image (first sampler) and by (image, flags).
#[derive(Default)]
pub(crate) struct ImageCache {
    by_image: HashMap<usize, u32>,
    by_sampler: HashMap<(usize, u32), u32>,
    /// Some material has an occlusion texture (ignored, said once).
    pub occlusion: bool,
}

fn wrap(mode: WrappingMode) -> Wrap {
    match mode {
        WrappingMode::ClampToEdge => Wrap::ClampToEdge,
        WrappingMode::MirroredRepeat => Wrap::MirroredRepeat,
        WrappingMode::Repeat => Wrap::Repeat,
    }
}

/// The scene texture of glTF texture `tex`: its image decoded (once), with its sampler's
/// filter and wrap modes.
fn texture(
    src: &Sources<'_>,
    tex: &gltf::Texture<'_>,
    set: &mut TextureSet,
    cache: &mut ImageCache,
) -> Result<u32, String> {
    let Sources { root, buffers, base_dir, limits, memory } = *src;
    let sampler = tex.sampler();
    let mut flags = (wrap(sampler.wrap_s()) as u32) << TEXTURE_WRAP_S_SHIFT
        | (wrap(sampler.wrap_t()) as u32) << TEXTURE_WRAP_T_SHIFT;
    if sampler.mag_filter() == Some(MagFilter::Nearest) {
        flags |= TEXTURE_NEAREST;
    }
    let image = tex.source();
    let key = (image.index(), flags);
    if let Some(&t) = cache.by_sampler.get(&key) {
        return Ok(t);
    }
    let at = |e: String| format!("textures[{}] (images[{}]): {e}", tex.index(), image.index());
    let t = match cache.by_image.get(&image.index()) {
        Some(&first) => set.alias(first, flags).ok_or_else(|| at("too many textures".to_owned()))?,
        None => {
            let left = memory.saturating_sub(set.bytes());
            // From the JSON: `Image::source` unwraps a missing `mimeType` or `uri` (gltf 1.4.1).
            let json = root.images.get(image.index()).ok_or_else(|| at("missing".to_owned()))?;
            let bytes: std::borrow::Cow<[u8]> = match (&json.buffer_view, &json.uri) {
                (Some(v), _) => {
                    let view =
                        root.buffer_views.get(v.value()).ok_or_else(|| at("its bufferView is missing".to_owned()))?;
                    let buffer =
                        buffers.get(view.buffer.value()).ok_or_else(|| at("its buffer is missing".to_owned()))?;
                    let start = view.byte_offset.map_or(0, |o| o.0) as usize;
                    let end = start.checked_add(view.byte_length.0 as usize).filter(|&e| e <= buffer.len());
                    let end = end.ok_or_else(|| at(format!("bufferViews[{}] lies outside its buffer", v.value())))?;
                    std::borrow::Cow::Borrowed(&buffer[start..end])
                }
                (None, Some(uri)) => {
                    std::borrow::Cow::Owned(read_uri(uri, base_dir, limits, limits.max_mesh_bytes).map_err(at)?)
                }
                (None, None) => return Err(at("has neither a uri nor a bufferView".to_owned())),
            };
            let (w, h, texels) = decode_image(&bytes, limits, left).map_err(at)?;
            let t = set.push(w, h, &texels, flags).ok_or_else(|| at("the texture table is full".to_owned()))?;
            cache.by_image.insert(image.index(), t);
            t
        }
    };
    cache.by_sampler.insert(key, t);
    Ok(t)
}

/// A texture slot from a glTF `textureInfo`: the texture, channel, colour space, transform.
#[allow(clippy::too_many_arguments)]
fn slot(
    info: Option<InfoParts<'_>>,
    what: &str,
    channel: u32,
    srgb: bool,
    ctx: &mut Ctx<'_, '_>,
) -> Result<TextureRef, String> {
    let Some((tex, tex_coord, transform)) = info else { return Ok(TextureRef::NONE) };
    let index = texture(ctx.src, &tex, ctx.set, ctx.cache).map_err(|e| format!("{what}: {e}"))?;
    let coord = transform.as_ref().and_then(|t| t.tex_coord()).unwrap_or(tex_coord);
    if coord != 0 {
        ctx.warnings.push(format!("{what} reads TEXCOORD_{coord}: ggx reads TEXCOORD_0 instead"));
    }
    let r = TextureRef::new(index, channel, srgb);
    Ok(match transform {
        Some(t) => r.with_transform(t.offset(), t.rotation(), t.scale()),
        None => r,
    })
}

/// What [`slot`] needs besides the texture info.
struct Ctx<'a, 'b> {
    src: &'a Sources<'a>,
    set: &'b mut TextureSet,
    cache: &'b mut ImageCache,
    warnings: &'b mut Vec<String>,
}

/// Where a glTF file's images come from and what they may take.
#[derive(Clone, Copy)]
pub(crate) struct Sources<'a> {
    /// The file's JSON.
    pub root: &'a gltf::json::Root,
    /// Its buffers, read.
    pub buffers: &'a [Vec<u8>],
    /// The directory its relative URIs resolve against.
    pub base_dir: &'a Path,
    /// The limits images are read within.
    pub limits: &'a Limits,
    /// Bytes of memory the textures may still take.
    pub memory: u64,
}

/// `[0, 1]`, NaN as `default`.
fn unit(x: f32, default: f32) -> f32 {
    if x.is_nan() { default } else { x.max(0.0).min(1.0) }
}

/// The parts of a `textureInfo` a slot reads.
type InfoParts<'a> = (gltf::Texture<'a>, u32, Option<gltf::texture::TextureTransform<'a>>);

fn info(i: Option<gltf::texture::Info<'_>>) -> Option<InfoParts<'_>> {
    i.map(|i| (i.texture(), i.tex_coord(), i.texture_transform()))
}

/// Converts glTF material `m`: Appendix B's metallic-roughness model, or ggx's dielectric for
/// a transmissive one ([`transmissive`]).
pub(crate) fn convert(
    m: &gltf::Material<'_>,
    src: &Sources<'_>,
    set: &mut TextureSet,
    cache: &mut ImageCache,
    warnings: &mut Vec<String>,
) -> Result<Material, String> {
    let name = m.name().map_or_else(|| format!("materials[{}]", m.index().map_or(0, |i| i)), str::to_owned);
    let mut notes = Vec::new();
    let mut ctx = Ctx { src, set, cache, warnings: &mut notes };
    let pbr = m.pbr_metallic_roughness();
    let [r, g, b, _] = pbr.base_color_factor();
    let base_color_texture = slot(info(pbr.base_color_texture()), "baseColorTexture", 0, true, &mut ctx)?;
    let roughness_texture =
        slot(info(pbr.metallic_roughness_texture()), "metallicRoughnessTexture", 1, false, &mut ctx)?;
    let metallic_texture =
        slot(info(pbr.metallic_roughness_texture()), "metallicRoughnessTexture", 2, false, &mut ctx)?;
    let (normal_texture, normal_scale) = match m.normal_texture() {
        Some(n) => {
            let t = slot(Some((n.texture(), n.tex_coord(), None)), "normalTexture", 0, false, &mut ctx)?;
            (t, if n.scale().is_finite() { n.scale() } else { 1.0 })
        }
        None => (TextureRef::NONE, 1.0),
    };
    let emission_texture = slot(info(m.emissive_texture()), "emissiveTexture", 0, true, &mut ctx)?;
    let strength = m.emissive_strength().unwrap_or(1.0);
    let emission = Vec3::from(m.emissive_factor()) * strength;
    let emission =
        if emission.is_finite() { emission.max(Vec3::ZERO).min(Vec3::splat(crate::MAX_RADIANCE)) } else { Vec3::ZERO };
    let ior = m.ior().filter(|x| x.is_finite() && *x >= 1.0).unwrap_or(1.5).min(3.0);
    let (specular, specular_color) = match m.specular() {
        Some(s) => {
            if s.specular_texture().is_some() || s.specular_color_texture().is_some() {
                ctx.warnings.push("KHR_materials_specular textures are ignored (the factors are used)".to_owned());
            }
            let c = Vec3::from(s.specular_color_factor());
            (unit(s.specular_factor(), 1.0), if c.is_finite() { c.max(Vec3::ZERO) } else { Vec3::ONE })
        }
        None => (1.0, Vec3::ONE),
    };
    if m.occlusion_texture().is_some() {
        ctx.cache.occlusion = true;
    }
    if m.alpha_mode() != gltf::material::AlphaMode::Opaque {
        ctx.warnings.push(format!("alphaMode {:?} is rendered opaque", m.alpha_mode()));
    }
    let transmission = m.transmission().map(|t| {
        if t.transmission_texture().is_some() {
            ctx.warnings.push("the transmission texture is ignored (the factor is used)".to_owned());
        }
        unit(t.transmission_factor(), 0.0)
    });
    let roughness = unit(pbr.roughness_factor(), 1.0);
    let (anisotropy, anisotropy_rotation) = anisotropy(m, &mut notes);
    let (clearcoat, clearcoat_roughness) = clearcoat(m, &mut notes);
    if let Some(t) = transmission.filter(|t| *t > 0.0) {
        let base = Vec3::new(unit(r, 1.0), unit(g, 1.0), unit(b, 1.0));
        let material = transmissive(m, t, base, roughness, ior, &mut notes);
        warnings.extend(notes.into_iter().map(|n| format!("material \"{}\": {n}", crate::shorten::short(&name))));
        return Ok(material);
    }
    warnings.extend(notes.into_iter().map(|n| format!("material \"{}\": {n}", crate::shorten::short(&name))));
    Ok(Material::MetalRough(MetalRough {
        base_color: Vec3::new(unit(r, 1.0), unit(g, 1.0), unit(b, 1.0)),
        base_color_texture,
        metallic: unit(pbr.metallic_factor(), 1.0),
        metallic_texture,
        roughness,
        roughness_texture,
        normal_texture,
        normal_scale,
        emission,
        emission_texture,
        ior,
        specular,
        specular_color,
        anisotropy,
        anisotropy_rotation,
        clearcoat,
        clearcoat_roughness,
    }))
}

/// `KHR_materials_clearcoat` (`clearcoatFactor`, `clearcoatRoughnessFactor`, both default 0)
/// from the material's extension JSON (the gltf crate 1.4 has no typed accessor for it); its
/// textures are not read (a note says so).
fn clearcoat(m: &gltf::Material<'_>, notes: &mut Vec<String>) -> (f32, f32) {
    let Some(ext) = m.extensions().and_then(|e| e.get("KHR_materials_clearcoat")) else { return (0.0, 0.0) };
    let number = |key: &str| ext.get(key).and_then(|v| v.as_f64()).map(|v| v as f32).filter(|v| v.is_finite());
    let textures = ["clearcoatTexture", "clearcoatRoughnessTexture", "clearcoatNormalTexture"];
    if textures.iter().any(|t| ext.get(*t).is_some()) {
        notes.push("the clearcoat textures are ignored (the factors are used, the coat follows the normal)".to_owned());
    }
    (unit(number("clearcoatFactor").unwrap_or(0.0), 0.0), unit(number("clearcoatRoughnessFactor").unwrap_or(0.0), 0.0))
}

/// `KHR_materials_anisotropy` (strength, rotation) from the material's extension JSON (the
/// gltf crate 1.4 has no typed accessor for it); its texture is not read (a note says so).
fn anisotropy(m: &gltf::Material<'_>, notes: &mut Vec<String>) -> (f32, f32) {
    let Some(ext) = m.extensions().and_then(|e| e.get("KHR_materials_anisotropy")) else { return (0.0, 0.0) };
    let number = |key: &str| ext.get(key).and_then(|v| v.as_f64()).map(|v| v as f32).filter(|v| v.is_finite());
    if ext.get("anisotropyTexture").is_some() {
        notes.push("the anisotropy texture is ignored (strength and rotation are used)".to_owned());
    }
    (unit(number("anisotropyStrength").unwrap_or(0.0), 0.0), number("anisotropyRotation").unwrap_or(0.0))
}

/// A material with `KHR_materials_transmission` (factor `t > 0`) as ggx's dielectric: with
/// `KHR_materials_volume` (a non-zero thickness) a rough interface around an absorbing inside
/// (`alpha = roughness^2`, Beer-Lambert `sigma = -ln(attenuationColor) / attenuationDistance`),
/// else glTF's thin-walled transmission as a smooth thin sheet; the transmission is tinted by
/// the base colour. What cannot be carried over (a partial factor, roughness on a thin wall,
/// textures) is said in `notes`.
fn transmissive(
    m: &gltf::Material<'_>,
    t: f32,
    base: Vec3,
    roughness: f32,
    ior: f32,
    notes: &mut Vec<String>,
) -> Material {
    if t < 1.0 {
        notes.push(format!("transmission factor {t} rendered as 1 (fully transmissive)"));
    }
    let ior = if ior > 1.0 { ior } else { 1.5 };
    let volume = m.volume().filter(|v| v.thickness_factor() > 0.0);
    let Some(v) = volume else {
        if roughness > 0.0 {
            notes.push("thin-walled rough transmission rendered as a smooth thin sheet".to_owned());
        }
        return Material::Dielectric {
            alpha_x: 0.0,
            alpha_y: 0.0,
            ior,
            transmittance: base,
            absorption: Vec3::ZERO,
            thin: true,
            compensate: true,
        };
    };
    let distance = v.attenuation_distance();
    let color = Vec3::from(v.attenuation_color());
    let absorption = if distance.is_finite() && distance > 0.0 && color.is_finite() {
        let sigma = |c: f32| if c > 0.0 { (-c.min(1.0).ln() / distance).max(0.0) } else { 1e6 / distance };
        Vec3::new(sigma(color.x), sigma(color.y), sigma(color.z))
    } else {
        Vec3::ZERO
    };
    let alpha = roughness * roughness;
    Material::Dielectric {
        alpha_x: alpha,
        alpha_y: alpha,
        ior,
        transmittance: base,
        absorption: if absorption.is_finite() { absorption } else { Vec3::ZERO },
        thin: false,
        compensate: true,
    }
}
