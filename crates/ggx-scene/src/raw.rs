//! The scene file as written: serde structures mirroring the TOML, every user-facing value
//! wrapped in [`Spanned`] so that validation can point at it. Numbers stay `f64` (TOML's
//! own type) until validation converts them to `f32`, so that `1e39` is reported as too
//! large instead of silently becoming infinity. Validation lives in the
//! modules that own each part (camera, materials, shapes, environment).

use std::collections::BTreeMap;
use std::fmt;
use std::marker::PhantomData;

use serde::Deserialize;
use serde::de::{self, Deserializer, SeqAccess, Visitor};
use toml::Spanned;

use crate::camera_path::Interpolation;
use crate::integrator::{BsdfStrategy, LightStrategy, SamplerKind};
use crate::material::MaterialPreset;

/// Shorthand for an optional spanned value.
pub(crate) type Opt<T> = Option<Spanned<T>>;

/// The whole scene file.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawScene {
    /// Spanned so that a missing `position` can point at the `[camera]` header.
    pub camera: Spanned<RawCamera>,
    pub integrator: Option<RawIntegrator>,
    #[serde(default)]
    pub materials: BTreeMap<String, RawMaterial>,
    #[serde(default)]
    pub shapes: Vec<RawShape>,
    pub environment: Option<RawEnvironment>,
}

/// `[camera]`: `position` and `look_at` for a still camera, or `keys` for an animated one
/// (whose `up` and `fov_y` are then the keys' defaults).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawCamera {
    pub position: Opt<[f64; 3]>,
    pub look_at: Opt<[f64; 3]>,
    pub up: Opt<[f64; 3]>,
    pub fov_y: Opt<f64>,
    pub resolution: Opt<[u32; 2]>,
    pub fps: Opt<f64>,
    pub interpolation: Opt<Interpolation>,
    pub keys: Opt<Vec<Spanned<RawCameraKey>>>,
}

/// `[[camera.keys]]`: one key of an animated camera.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawCameraKey {
    pub time: Spanned<f64>,
    pub position: Spanned<[f64; 3]>,
    pub look_at: Spanned<[f64; 3]>,
    pub up: Opt<[f64; 3]>,
    pub fov_y: Opt<f64>,
}

/// `[integrator]`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawIntegrator {
    pub spp: Opt<u32>,
    pub max_depth: Opt<u32>,
    pub russian_roulette: Opt<u32>,
    pub time: Opt<f64>,
    pub seed: Opt<i64>,
    pub sampler: Option<SamplerKind>,
    pub bsdf_sampling: Option<BsdfStrategy>,
    pub light_strategy: Option<LightStrategy>,
    pub energy_compensation: Option<bool>,
    pub mis_compensation: Option<bool>,
}

/// Material `type` strings.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub(crate) enum MaterialType {
    Diffuse,
    Conductor,
    Plastic,
    Dielectric,
    Emissive,
    MetalRough,
}

/// `[materials.NAME]`: one flat table, the keys allowed depend on `type`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawMaterial {
    #[serde(rename = "type")]
    pub kind: Spanned<MaterialType>,
    pub albedo: Opt<Textured<[f64; 3]>>,
    pub roughness: Opt<Textured<OneOrMany<2>>>,
    pub base_color: Opt<Textured<[f64; 3]>>,
    pub metallic: Opt<Textured<f64>>,
    pub normal_map: Opt<RawTexture>,
    pub normal_scale: Opt<f64>,
    pub emission: Opt<Textured<[f64; 3]>>,
    pub specular: Opt<f64>,
    pub clearcoat: Opt<f64>,
    pub clearcoat_roughness: Opt<f64>,
    pub alpha: Opt<OneOrMany<2>>,
    pub eta: Opt<[f64; 3]>,
    pub k: Opt<[f64; 3]>,
    pub f0: Opt<[f64; 3]>,
    pub preset: Opt<MaterialPreset>,
    pub ior: Opt<f64>,
    pub radiance: Opt<[f64; 3]>,
    pub transmittance: Opt<[f64; 3]>,
    pub absorption: Opt<[f64; 3]>,
    pub thin: Opt<bool>,
    pub energy_compensation: Opt<bool>,
}

/// Shape `type` strings.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub(crate) enum ShapeType {
    Sphere,
    Rectangle,
    Box,
    Disk,
    Mesh,
    Gltf,
}

/// `[[shapes]]`: one flat table, the keys allowed depend on `type`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawShape {
    #[serde(rename = "type")]
    pub kind: Spanned<ShapeType>,
    /// Required for every type but `gltf`, whose materials come from the file (a `material`
    /// there replaces them all).
    pub material: Opt<String>,
    pub center: Opt<[f64; 3]>,
    pub radius: Opt<f64>,
    pub subdivisions: Opt<u32>,
    pub smooth: Opt<bool>,
    pub segments: Opt<u32>,
    pub file: Opt<String>,
    pub transform: Option<RawTransform>,
}

/// `transform = { translate, rotate, scale }`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawTransform {
    pub translate: Opt<[f64; 3]>,
    pub rotate: Opt<[f64; 3]>,
    pub scale: Opt<OneOrMany<3>>,
}

/// Environment `type` strings.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub(crate) enum EnvironmentType {
    Constant,
    Map,
    Procedural,
}

/// Procedural environment presets.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub(crate) enum ProceduralPreset {
    Sky,
    Studio,
}

/// `[environment]`: one flat table, the keys allowed depend on `type`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawEnvironment {
    #[serde(rename = "type")]
    pub kind: Spanned<EnvironmentType>,
    pub radiance: Opt<[f64; 3]>,
    pub file: Opt<String>,
    pub preset: Opt<ProceduralPreset>,
    pub resolution: Opt<[u32; 2]>,
    pub scale: Opt<f64>,
    pub rotation: Opt<f64>,
}

/// A value as written, or a texture (`albedo = [0.8, 0.8, 0.8]` or `albedo = { texture =
/// "wood.png" }`).
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Textured<T> {
    Value(T),
    Texture(RawTexture),
}

impl<T> Textured<T> {
    /// The value, `None` for a texture.
    pub fn value(&self) -> Option<&T> {
        match self {
            Self::Value(v) => Some(v),
            Self::Texture(_) => None,
        }
    }
}

impl<'de, T: Deserialize<'de>> Deserialize<'de> for Textured<T> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let v = toml::Value::deserialize(deserializer)?;
        if v.is_table() {
            RawTexture::deserialize(v).map(Self::Texture).map_err(de::Error::custom)
        } else {
            T::deserialize(v).map(Self::Value).map_err(de::Error::custom)
        }
    }
}

/// Texture `channel` names.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub(crate) enum Channel {
    R,
    G,
    B,
    A,
}

/// Texture `wrap` modes.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub(crate) enum RawWrap {
    Repeat,
    Clamp,
    Mirror,
}

/// Texture `filter` modes.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub(crate) enum RawFilter {
    Bilinear,
    Nearest,
}

/// `{ texture = "file.png", channel, wrap, filter, scale, offset, rotation }`, or just the
/// file name where only a texture makes sense (`normal_map = "n.png"`).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct RawTexture {
    pub texture: String,
    pub channel: Option<Channel>,
    pub wrap: Option<RawWrap>,
    pub filter: Option<RawFilter>,
    pub scale: Option<[f64; 2]>,
    pub offset: Option<[f64; 2]>,
    pub rotation: Option<f64>,
}

/// The table form of [`RawTexture`].
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawTextureTable {
    texture: String,
    channel: Option<Channel>,
    wrap: Option<RawWrap>,
    filter: Option<RawFilter>,
    scale: Option<[f64; 2]>,
    offset: Option<[f64; 2]>,
    rotation: Option<f64>,
}

impl<'de> Deserialize<'de> for RawTexture {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let v = toml::Value::deserialize(deserializer)?;
        if let toml::Value::String(texture) = v {
            return Ok(RawTexture {
                texture,
                channel: None,
                wrap: None,
                filter: None,
                scale: None,
                offset: None,
                rotation: None,
            });
        }
        let t = RawTextureTable::deserialize(v).map_err(de::Error::custom)?;
        Ok(RawTexture {
            texture: t.texture,
            channel: t.channel,
            wrap: t.wrap,
            filter: t.filter,
            scale: t.scale,
            offset: t.offset,
            rotation: t.rotation,
        })
    }
}

/// A number, or an array of exactly `N` numbers (`alpha = 0.1` or `alpha = [0.1, 0.4]`),
/// kept in `f64` as written so that validation can tell a value too large for `f32`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum OneOrMany<const N: usize> {
    One(f64),
    Many([f64; N]),
}

impl<const N: usize> OneOrMany<N> {
    /// The numbers as written (one or `N`), for validation.
    pub fn written(&self) -> &[f64] {
        match self {
            Self::One(x) => std::slice::from_ref(x),
            Self::Many(v) => v,
        }
    }

    /// All `N` components in `f32` (a single number is repeated); call after validating
    /// [`Self::written`].
    pub fn components(self) -> [f32; N] {
        match self {
            Self::One(x) => [x as f32; N],
            Self::Many(v) => v.map(|x| x as f32),
        }
    }
}

impl<'de, const N: usize> Deserialize<'de> for OneOrMany<N> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        deserializer.deserialize_any(OneOrManyVisitor::<N>(PhantomData))
    }
}

struct OneOrManyVisitor<const N: usize>(PhantomData<[f32; N]>);

impl<'de, const N: usize> Visitor<'de> for OneOrManyVisitor<N> {
    type Value = OneOrMany<N>;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "a number or an array of {N} numbers")
    }

    fn visit_f64<E: de::Error>(self, v: f64) -> Result<Self::Value, E> {
        Ok(OneOrMany::One(v))
    }

    fn visit_i64<E: de::Error>(self, v: i64) -> Result<Self::Value, E> {
        Ok(OneOrMany::One(v as f64))
    }

    fn visit_u64<E: de::Error>(self, v: u64) -> Result<Self::Value, E> {
        Ok(OneOrMany::One(v as f64))
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
        let mut out = [0.0f64; N];
        for (i, slot) in out.iter_mut().enumerate() {
            *slot = seq.next_element()?.ok_or_else(|| de::Error::invalid_length(i, &self))?;
        }
        if seq.next_element::<de::IgnoredAny>()?.is_some() {
            return Err(de::Error::invalid_length(N + 1, &self));
        }
        Ok(OneOrMany::Many(out))
    }
}
