//! Tone-mapped 8-bit sRGB PNG writing, via the `image` crate.

use std::io::Write;
use std::path::Path;

use glam::Vec3;
use image::codecs::png::PngEncoder;
use image::{ExtendedColorType, ImageEncoder};

use crate::{OutputError, OutputOptions, tonemap_to_srgb8};

/// Encodes `pixels` (`width x height`, already validated) as an RGB8 PNG after exposure, tone
/// mapping and sRGB encoding ([`tonemap_to_srgb8`]); `path` only names the file in errors.
pub(crate) fn write_png(
    out: impl Write,
    path: &Path,
    width: u32,
    height: u32,
    pixels: &[Vec3],
    options: &OutputOptions,
) -> Result<(), OutputError> {
    let bytes = tonemap_to_srgb8(pixels, options);
    PngEncoder::new(out).write_image(&bytes, width, height, ExtendedColorType::Rgb8).map_err(|e| OutputError::Encode {
        path: path.to_owned(),
        format: "PNG",
        source: Box::new(e),
    })
}
