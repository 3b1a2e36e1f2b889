//! Linear `f32` RGB OpenEXR writing and RGB(A) reading, via the `exr` crate.

use std::io::{Seek, Write};
use std::path::Path;

use exr::prelude::{
    Encoding, Image, ReadChannels, ReadLayers, RgbaChannels, SpecificChannels, Vec2, WritableImage, read,
};
use glam::Vec3;

use crate::OutputError;

/// Encodes `pixels` (`width x height`, already validated) as a lossless (ZIP, scan lines)
/// `f32` RGB EXR into `out`; `path` only names the file in errors.
pub(crate) fn write_exr(
    out: impl Write + Seek,
    path: &Path,
    width: usize,
    height: usize,
    pixels: &[Vec3],
) -> Result<(), OutputError> {
    let channels = SpecificChannels::rgb(|pos: Vec2<usize>| {
        let p = pixels.get(pos.y() * width + pos.x()).copied().unwrap_or(Vec3::ZERO);
        (p.x, p.y, p.z)
    });
    Image::from_encoded_channels((width, height), Encoding::SMALL_LOSSLESS, channels)
        .write()
        .to_buffered(out)
        .map_err(|e| OutputError::Encode { path: path.to_owned(), format: "EXR", source: Box::new(e) })
}

/// Reads an RGB(A) float EXR back as linear RGB (for tests and the cross-backend diff tool):
/// `(width, height, pixels)`, row-major, top row first; alpha is ignored and `f16`/`u32`
/// channels are converted to `f32`. Reads the first layer with R, G and B channels.
pub fn read_exr(path: &Path) -> Result<(u32, u32, Vec<Vec3>), OutputError> {
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .rgba_channels(
            |size: Vec2<usize>, _: &RgbaChannels| (size.width(), vec![Vec3::ZERO; size.area()]),
            |(width, px): &mut (usize, Vec<Vec3>), pos: Vec2<usize>, (r, g, b, _a): (f32, f32, f32, f32)| {
                if let Some(p) = px.get_mut(pos.y() * *width + pos.x()) {
                    *p = Vec3::new(r, g, b);
                }
            },
        )
        .first_valid_layer()
        .all_attributes()
        .from_file(path)
        .map_err(|source| OutputError::Decode { path: path.to_owned(), source })?;
    let size = image.layer_data.size;
    match (u32::try_from(size.width()), u32::try_from(size.height())) {
        (Ok(w), Ok(h)) => Ok((w, h, image.layer_data.channel_data.pixels.1)),
        _ => Err(OutputError::TooLarge { path: path.to_owned(), width: size.width(), height: size.height() }),
    }
}
