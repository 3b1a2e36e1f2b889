//! Image textures named in scene files (`albedo = { texture = "wood.png" }`): read and
//! decoded once per file, within the limits, into the scene's [`TextureSet`].

use std::collections::HashMap;
use std::ops::Range;
use std::path::{Path, PathBuf};

use crate::error::{ErrorKind, SceneError, Source};
use crate::gltf_asset::decode_image;
use crate::limits::{Limit, Limits, read_regular_file_or};
use crate::raw::{Channel, RawFilter, RawTexture, RawWrap};
use crate::shorten::short_path;
use crate::texture::{TEXTURE_NEAREST, TEXTURE_WRAP_S_SHIFT, TEXTURE_WRAP_T_SHIFT, TextureRef, TextureSet, Wrap};

/// Loads the textures of a scene file's materials.
pub(crate) struct TextureLoader<'a> {
    base_dir: &'a Path,
    limits: &'a Limits,
    /// The textures loaded so far.
    pub set: TextureSet,
    /// By resolved path: the first texture made from the file.
    images: HashMap<PathBuf, u32>,
    /// By (resolved path, flags).
    textures: HashMap<(PathBuf, u32), u32>,
    /// The files read, for [`crate::Scene::inputs`].
    pub inputs: Vec<PathBuf>,
}

impl<'a> TextureLoader<'a> {
    /// A loader resolving files against `base_dir`.
    pub fn new(base_dir: &'a Path, limits: &'a Limits) -> Self {
        Self {
            base_dir,
            limits,
            set: TextureSet::default(),
            images: HashMap::new(),
            textures: HashMap::new(),
            inputs: Vec::new(),
        }
    }

    /// The slot for `raw` at `span` (field `field`): the file decoded once, the sampler's
    /// wrap and filter, the channel (`default_channel` unless given) and the transform;
    /// colour data (`srgb`) decoded from sRGB.
    pub fn load(
        &mut self,
        src: Source<'_>,
        span: Range<usize>,
        field: &str,
        raw: &RawTexture,
        default_channel: u32,
        srgb: bool,
    ) -> Result<TextureRef, SceneError> {
        let at = |kind, msg: String| src.error(span.clone(), field, kind, msg);
        let path = self.base_dir.join(&raw.texture);
        let wrap = match raw.wrap.unwrap_or(RawWrap::Repeat) {
            RawWrap::Repeat => Wrap::Repeat,
            RawWrap::Clamp => Wrap::ClampToEdge,
            RawWrap::Mirror => Wrap::MirroredRepeat,
        } as u32;
        let mut flags = wrap << TEXTURE_WRAP_S_SHIFT | wrap << TEXTURE_WRAP_T_SHIFT;
        if raw.filter == Some(RawFilter::Nearest) {
            flags |= TEXTURE_NEAREST;
        }
        let key = (path.clone(), flags);
        let index = match self.textures.get(&key) {
            Some(&t) => t,
            None => {
                let t = match self.images.get(&path) {
                    Some(&first) => self.set.alias(first, flags),
                    None => {
                        if !path.exists() {
                            return Err(at(ErrorKind::File, format!("texture not found: {}", short_path(&path))));
                        }
                        let bytes = read_regular_file_or(&path, "texture", Limit::MeshBytes, self.limits)
                            .map_err(|e| at(ErrorKind::File, e.to_string()))?;
                        let left = self.limits.max_memory.saturating_sub(self.set.bytes());
                        let (w, h, texels) = decode_image(&bytes, self.limits, left).map_err(|e| {
                            let kind = if e.contains("limit") { ErrorKind::Limit } else { ErrorKind::File };
                            at(kind, format!("{}: {e}", short_path(&path)))
                        })?;
                        self.inputs.push(path.clone());
                        let t = self.set.push(w, h, &texels, flags);
                        if let Some(t) = t {
                            self.images.insert(path.clone(), t);
                        }
                        t
                    }
                };
                let t = t.ok_or_else(|| at(ErrorKind::Limit, "the scene's texture table is full".to_owned()))?;
                self.textures.insert(key, t);
                t
            }
        };
        let channel = match raw.channel {
            None => default_channel,
            Some(Channel::R) => 0,
            Some(Channel::G) => 1,
            Some(Channel::B) => 2,
            Some(Channel::A) => 3,
        };
        let num = |x: f64, what: &str| -> Result<f32, SceneError> {
            let v = x as f32;
            if v.is_finite() {
                Ok(v)
            } else {
                Err(at(ErrorKind::NonFinite, format!("texture {what} must be finite, got {x}")))
            }
        };
        let r = TextureRef::new(index, channel, srgb);
        if raw.scale.is_none() && raw.offset.is_none() && raw.rotation.is_none() {
            return Ok(r);
        }
        let [sx, sy] = raw.scale.unwrap_or([1.0; 2]);
        let [ox, oy] = raw.offset.unwrap_or([0.0; 2]);
        let rotation = num(raw.rotation.unwrap_or(0.0), "rotation")?;
        Ok(r.with_transform([num(ox, "offset")?, num(oy, "offset")?], rotation, [num(sx, "scale")?, num(sy, "scale")?]))
    }
}
