//! Validation of `[environment]` into an [`Environment`].

use std::path::Path;

use glam::Vec3;

use super::{EnvMap, Environment, load_image, sky, studio};
use crate::check::{Interval, span_of};
use crate::error::{ErrorKind, SceneError, Source};
use crate::raw::{EnvironmentType, ProceduralPreset, RawEnvironment};

/// Largest procedural map width; the height limit is half of it.
pub const MAX_PROCEDURAL_WIDTH: u32 = 4096;

/// Validates `[environment]`; map files are resolved relative to `base_dir`.
pub(crate) fn build(src: Source<'_>, raw: &RawEnvironment, base_dir: &Path) -> Result<Environment, SceneError> {
    let field = |key: &str| format!("environment.{key}");
    let (type_name, allowed): (_, &[&str]) = match raw.kind.get_ref() {
        EnvironmentType::Constant => ("constant", &["radiance"]),
        EnvironmentType::Map => ("map", &["file", "scale", "rotation"]),
        EnvironmentType::Procedural => ("procedural", &["preset", "resolution", "scale", "rotation"]),
    };
    let present = [
        ("radiance", span_of(&raw.radiance)),
        ("file", span_of(&raw.file)),
        ("preset", span_of(&raw.preset)),
        ("resolution", span_of(&raw.resolution)),
        ("scale", span_of(&raw.scale)),
        ("rotation", span_of(&raw.rotation)),
    ];
    src.only_keys("environment", type_name, &present, allowed)?;
    let missing = |key: &str| {
        let msg = format!("type \"{type_name}\" needs `{key}`");
        src.error(raw.kind.span(), &field("type"), ErrorKind::Conflict, msg)
    };
    let scale = src.number_or(raw.scale.as_ref(), 1.0, &field("scale"), Interval::above(0.0))?;
    let rotation = src.number_or(raw.rotation.as_ref(), 0.0, &field("rotation"), Interval::ANY)?;
    let (width, height, texels, span) = match raw.kind.get_ref() {
        EnvironmentType::Constant => {
            let r = raw.radiance.as_ref().ok_or_else(|| missing("radiance"))?;
            let radiance = src.array(r, &field("radiance"), Interval::at_least(0.0))?;
            return Ok(Environment::Constant(Vec3::from(radiance)));
        }
        EnvironmentType::Map => {
            let file = raw.file.as_ref().ok_or_else(|| missing("file"))?;
            let path = base_dir.join(file.get_ref());
            let file_error = |msg: String| src.error(file.span(), &field("file"), ErrorKind::File, msg);
            if !path.is_file() {
                return Err(file_error(format!("environment map not found: {}", path.display())));
            }
            let (w, h, texels) = load_image(&path).map_err(file_error)?;
            (w, h, texels, file.span())
        }
        EnvironmentType::Procedural => {
            let preset = raw.preset.as_ref().ok_or_else(|| missing("preset"))?;
            let [w, h] = match &raw.resolution {
                None => [512, 256],
                Some(r) => {
                    let [w, h] = *r.get_ref();
                    let max = MAX_PROCEDURAL_WIDTH;
                    if !(1..=max).contains(&w) || !(1..=max / 2).contains(&h) {
                        let msg = format!("width must be in [1, {max}] and height in [1, {}], got [{w}, {h}]", max / 2);
                        return Err(src.error(r.span(), &field("resolution"), ErrorKind::OutOfRange, msg));
                    }
                    [w, h]
                }
            };
            let texels = match preset.get_ref() {
                ProceduralPreset::Sky => sky(w, h),
                ProceduralPreset::Studio => studio(w, h),
            };
            (w, h, texels, preset.span())
        }
    };
    EnvMap::new(width, height, texels, scale, rotation).map(Environment::Map).ok_or_else(|| {
        let msg = "environment map has negative or non-finite texels";
        src.error(span, &field("file"), ErrorKind::File, msg)
    })
}
