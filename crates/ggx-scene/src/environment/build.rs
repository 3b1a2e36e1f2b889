//! Validation of `[environment]` into an [`Environment`].

use std::path::Path;

use glam::Vec3;

use super::load::check_size;
use super::map::TexelError;
use super::{EnvMap, Environment, load_image, sky, studio};
use crate::check::{Interval, span_of};
use crate::error::{ErrorKind, SceneError, Source};
use crate::limits::{Limit, LimitError, Limits, format_bytes};
use crate::memory::{MemoryEstimate, triangle_bytes};
use crate::radiance::{MAX_RADIANCE, check_radiance};
use crate::raw::{EnvironmentType, ProceduralPreset, RawEnvironment};
use crate::shorten::short_path;

/// Largest procedural map width; the height limit is half of it.
pub const MAX_PROCEDURAL_WIDTH: u32 = 4096;

/// Checks the memory of `triangles` triangles and a `width x height` environment map
/// together against `limits.max_memory` ([`MemoryEstimate`] without the film).
pub(crate) fn check_with_triangles(limits: &Limits, triangles: u64, width: u32, height: u32) -> Result<(), LimitError> {
    let bytes = MemoryEstimate::new(triangles, u64::from(width) * u64::from(height), [0, 0]).total();
    limits.check(Limit::Memory, format!("{triangles} triangles and a {width}x{height} environment map"), bytes)
}

/// Validates `[environment]` of a scene with `triangles` triangles (already allocated); map
/// files are resolved relative to `base_dir` and read within `limits`, less the memory of the
/// triangles. Radiance, after `scale`, must be at most [`MAX_RADIANCE`] per channel.
pub(crate) fn build(
    src: Source<'_>,
    raw: &RawEnvironment,
    base_dir: &Path,
    limits: &Limits,
    triangles: u64,
) -> Result<Environment, SceneError> {
    let taken = triangle_bytes(triangles);
    let left = Limits { max_memory: limits.max_memory.saturating_sub(taken), ..*limits };
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
    let (width, height, texels, span, key) = match raw.kind.get_ref() {
        EnvironmentType::Constant => {
            let r = raw.radiance.as_ref().ok_or_else(|| missing("radiance"))?;
            let radiance = src.array(r, &field("radiance"), Interval::at_least(0.0))?;
            check_radiance(radiance)
                .map_err(|msg| src.error(r.span(), &field("radiance"), ErrorKind::OutOfRange, msg))?;
            return Ok(Environment::Constant(Vec3::from(radiance)));
        }
        EnvironmentType::Map => {
            let file = raw.file.as_ref().ok_or_else(|| missing("file"))?;
            let path = base_dir.join(file.get_ref());
            let file_error = |msg: String| src.error(file.span(), &field("file"), ErrorKind::File, msg);
            if !path.exists() {
                return Err(file_error(format!("environment map not found: {}", short_path(&path))));
            }
            let (w, h, texels) = load_image(&path, &left).map_err(|msg| {
                // The limit in the message is what the triangles leave of max_memory: say so.
                if taken > 0 && msg.contains(Limit::Memory.field()) {
                    let max = format_bytes(limits.max_memory);
                    file_error(format!(
                        "{msg}: what the {triangles} triangles ({}) leave of {max}",
                        format_bytes(taken)
                    ))
                } else {
                    file_error(msg)
                }
            })?;
            (w, h, texels, file.span(), "file")
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
            let msg = |e: String| src.error(preset.span(), &field("preset"), ErrorKind::OutOfRange, e);
            check_size(u64::from(w), u64::from(h), 0, limits).map_err(msg)?;
            check_with_triangles(limits, triangles, w, h)
                .map_err(|e| src.error(raw.kind.span(), "environment", ErrorKind::Limit, e.to_string()))?;
            let texels = match preset.get_ref() {
                ProceduralPreset::Sky => sky(w, h),
                ProceduralPreset::Studio => studio(w, h),
            };
            (w, h, texels, preset.span(), "preset")
        }
    };
    EnvMap::try_new(width, height, texels, scale, rotation).map(Environment::Map).map_err(|e| {
        let msg = match &raw.file {
            Some(f) => format!("{}: {e}", short_path(&base_dir.join(f.get_ref()))),
            None => format!("procedural map: {e}"),
        };
        match (&e, &raw.scale) {
            // Blame `scale` when it, not the texel alone, takes the radiance over the bound.
            (TexelError::TooBright { value, .. }, Some(s)) if *value <= MAX_RADIANCE => {
                src.error(s.span(), &field("scale"), ErrorKind::OutOfRange, msg)
            }
            _ => src.error(span, &field(key), ErrorKind::File, msg),
        }
    })
}
