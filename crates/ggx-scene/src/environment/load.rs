//! Reading `.hdr` (Radiance RGBE, via `image`) and `.exr` (OpenEXR, via `exr`) images as
//! linear RGB texels.

use std::path::Path;

/// Largest accepted map width or height.
pub const MAX_MAP_SIZE: u32 = 16384;

/// Reads an `.hdr` or `.exr` file (chosen by extension) into `(width, height, texels)`,
/// row-major from the top row, `w = 1`.
pub fn load_image(path: &Path) -> Result<(u32, u32, Vec<[f32; 4]>), String> {
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    let (w, h, texels) = match ext.as_deref() {
        Some("hdr") => load_hdr(path)?,
        Some("exr") => load_exr(path)?,
        _ => return Err(format!("{}: unsupported environment map format (use .hdr or .exr)", path.display())),
    };
    if w == 0 || h == 0 || w > MAX_MAP_SIZE || h > MAX_MAP_SIZE {
        return Err(format!("{}: size {w}x{h} is outside 1..={MAX_MAP_SIZE}", path.display()));
    }
    Ok((w, h, texels))
}

fn load_hdr(path: &Path) -> Result<(u32, u32, Vec<[f32; 4]>), String> {
    let err = |e: image::ImageError| format!("{}: {e}", path.display());
    let reader = image::ImageReader::open(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let img = reader.with_guessed_format().map_err(|e| format!("{}: {e}", path.display()))?.decode().map_err(err)?;
    let rgb = img.to_rgb32f();
    let texels = rgb.pixels().map(|p| [p[0], p[1], p[2], 1.0]).collect();
    Ok((rgb.width(), rgb.height(), texels))
}

fn load_exr(path: &Path) -> Result<(u32, u32, Vec<[f32; 4]>), String> {
    use exr::prelude::*;
    let image = read_first_rgba_layer_from_file(
        path,
        |size: Vec2<usize>, _: &RgbaChannels| (size.width(), vec![[0.0f32, 0.0, 0.0, 1.0]; size.area()]),
        |(width, texels): &mut (usize, Vec<[f32; 4]>), pos: Vec2<usize>, (r, g, b, _a): (f32, f32, f32, f32)| {
            texels[pos.y() * *width + pos.x()] = [r, g, b, 1.0];
        },
    )
    .map_err(|e| format!("{}: {e}", path.display()))?;
    let size = image.layer_data.size;
    let (w, h) = (u32::try_from(size.width()), u32::try_from(size.height()));
    match (w, h) {
        (Ok(w), Ok(h)) => Ok((w, h, image.layer_data.channel_data.pixels.1)),
        _ => Err(format!("{}: image too large", path.display())),
    }
}
