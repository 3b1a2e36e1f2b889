//! Reading environment map files, `.hdr` (Radiance RGBE, [`super::hdr_file`]) and `.exr`
//! (OpenEXR, [`super::exr_file`]), as linear RGB texels. Each reader checks the size its
//! file declares against [`Limits`] before it allocates pixels.

use std::fs::File;
use std::path::Path;

use super::exr_file::read_exr;
use super::hdr_file::read_hdr;
use crate::limits::{Limit, Limits, open_regular};
use crate::shorten::short_path;

/// Largest accepted map width or height.
pub const MAX_MAP_SIZE: u32 = 16384;

/// `(width, height, texels)`: row-major RGBA texels from the top row, `w = 1`.
pub(crate) type Texels = (u32, u32, Vec<[f32; 4]>);

/// Reads an `.hdr` or `.exr` file (chosen by extension) into `(width, height, texels)`,
/// row-major from the top row, `w = 1`.
///
/// Only regular files are read (a directory, FIFO or device is refused). The size the file
/// declares is checked before any pixel is allocated: each side in `1..=`[`MAX_MAP_SIZE`],
/// `width * height` at most `limits.max_map_pixels`, and the texels, the sampling tables
/// ([`crate::BYTES_PER_TEXEL`] per pixel) and the decoder's buffers at most
/// `limits.max_memory`. Errors start with the path.
pub fn load_image(path: &Path, limits: &Limits) -> Result<(u32, u32, Vec<[f32; 4]>), String> {
    let shown = short_path(path);
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    let read: fn(File, &Limits) -> Result<Texels, String> = match ext.as_deref() {
        Some("hdr") => read_hdr,
        Some("exr") => read_exr,
        _ => return Err(format!("{shown}: unsupported environment map format (use .hdr or .exr)")),
    };
    let (file, _) = open_regular(path).map_err(|e| format!("{shown}: cannot read environment map: {e}"))?;
    let (w, h, texels) = read(file, limits).map_err(|e| format!("{shown}: {e}"))?;
    if texels.len() as u64 != u64::from(w) * u64::from(h) {
        return Err(format!("{shown}: decoded {} texels for a {w}x{h} map", texels.len()));
    }
    Ok((w, h, texels))
}

/// Checks a declared map size before its pixels are allocated: each side in
/// `1..=`[`MAX_MAP_SIZE`], `width * height` within `limits.max_map_pixels`, and
/// [`crate::BYTES_PER_TEXEL`] per pixel plus `decoder_bytes` within `limits.max_memory`.
/// Returns the size and the pixel count.
pub(crate) fn check_size(
    width: u64,
    height: u64,
    decoder_bytes: u64,
    limits: &Limits,
) -> Result<(u32, u32, usize), String> {
    let max = u64::from(MAX_MAP_SIZE);
    if !(1..=max).contains(&width) || !(1..=max).contains(&height) {
        return Err(format!("size {width}x{height} is outside 1..={MAX_MAP_SIZE} per side"));
    }
    let what = format!("environment map {width}x{height}");
    let pixels = width * height;
    limits.check(Limit::MapPixels, &what, pixels).map_err(|e| e.to_string())?;
    let bytes = crate::map_bytes(pixels).saturating_add(decoder_bytes);
    limits.check(Limit::Memory, what, bytes).map_err(|e| e.to_string())?;
    let pixels = usize::try_from(pixels).map_err(|_| format!("size {width}x{height} does not fit in memory"))?;
    // Both sides are at most MAX_MAP_SIZE, so they fit in u32.
    Ok((width as u32, height as u32, pixels))
}

/// `pixels` texels of value `fill`, allocated without aborting: when the memory cannot be
/// reserved (`--max-memory` raised past what the machine has), an error names the size.
pub(crate) fn alloc_texels(pixels: usize, fill: [f32; 4]) -> Result<Vec<[f32; 4]>, String> {
    let mut texels = Vec::new();
    texels.try_reserve_exact(pixels).map_err(|_| {
        let bytes = (pixels as u64).saturating_mul(size_of::<[f32; 4]>() as u64);
        format!("cannot allocate {} for {pixels} texels", crate::format_bytes(bytes))
    })?;
    texels.resize(pixels, fill);
    Ok(texels)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn texels_that_cannot_be_allocated_are_an_error() {
        assert_eq!(alloc_texels(2, [0.0, 0.0, 0.0, 1.0]).unwrap(), vec![[0.0, 0.0, 0.0, 1.0]; 2]);
        let msg = alloc_texels(usize::MAX / 16, [0.0; 4]).unwrap_err();
        assert!(msg.starts_with("cannot allocate ") && msg.contains(" texels"), "{msg}");
    }
}
