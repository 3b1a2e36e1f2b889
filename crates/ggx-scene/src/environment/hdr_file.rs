//! `.hdr` (Radiance RGBE) environment maps via `image`'s `HdrDecoder`: the header is read
//! and checked against [`Limits`] first, then the scan lines are decoded straight into the
//! memory of the final texels.

use std::fs::File;
use std::io::{BufReader, Cursor, Read as _};

use image::ImageDecoder as _;
use image::codecs::hdr::HdrDecoder;

use super::MAX_MAP_SIZE;
use super::load::{Texels, alloc_texels, check_size};
use crate::limits::Limits;

/// Longest accepted header (signature, attribute lines, blank line and dimension line).
/// Real headers are a few hundred bytes; the bound stops a file without line breaks from
/// being read into memory line by line.
pub(crate) const MAX_HDR_HEADER_BYTES: usize = 64 * 1024;

/// Reads the Radiance RGBE `file`.
///
/// The header must end within [`MAX_HDR_HEADER_BYTES`]; the size it declares is checked
/// against [`MAX_MAP_SIZE`], `limits.max_map_pixels` and `limits.max_memory` before the
/// texels are allocated, and `image`'s own limits are set from `limits` (instead of its
/// 512 MiB default). Decoding needs one full-size buffer, the returned texels: the `Rgb32F`
/// scan lines are decoded into the front three quarters of its memory and expanded to RGBA
/// in place from the back.
pub(super) fn read_hdr(mut file: File, limits: &Limits) -> Result<Texels, String> {
    let mut head = Vec::new();
    (&mut file).take(MAX_HDR_HEADER_BYTES as u64).read_to_end(&mut head).map_err(|e| format!("cannot read: {e}"))?;
    if header_len(&head).is_none() {
        return Err(if head.len() < MAX_HDR_HEADER_BYTES {
            "invalid Radiance HDR file: the header or its dimension line is missing or truncated".into()
        } else {
            format!("invalid Radiance HDR file: no end of header in its first {MAX_HDR_HEADER_BYTES} bytes")
        });
    }
    let reader = Cursor::new(head).chain(BufReader::new(file));
    let mut decoder = HdrDecoder::new(reader).map_err(|e| format!("invalid Radiance HDR file: {e}"))?;
    let (width, height) = decoder.dimensions();
    // The decoder keeps one RGBE scan line (4 bytes per pixel) beside the output.
    let (width, height, pixels) = check_size(u64::from(width), u64::from(height), 4 * u64::from(width), limits)?;
    let mut image_limits = image::Limits::default();
    image_limits.max_image_width = Some(MAX_MAP_SIZE);
    image_limits.max_image_height = Some(MAX_MAP_SIZE);
    image_limits.max_alloc = Some(limits.max_memory);
    decoder.set_limits(image_limits).map_err(|e| format!("invalid Radiance HDR file: {e}"))?;
    let mut texels = alloc_texels(pixels, [0.0; 4])?;
    let rgb_bytes = decoder.total_bytes();
    let bytes: &mut [u8] = bytemuck::cast_slice_mut(&mut texels);
    let rgb = usize::try_from(rgb_bytes).ok().and_then(|n| bytes.get_mut(..n)).ok_or("decoded size mismatch")?;
    decoder.read_image(rgb).map_err(|e| format!("invalid Radiance HDR file: {e}"))?;
    expand_rgb_in_place(&mut texels);
    Ok((width, height, texels))
}

/// Length of the header of `head` up to and including the dimension line (the line after
/// the first blank line), or `None` when it does not end within `head`.
fn header_len(head: &[u8]) -> Option<usize> {
    let blank = head.windows(2).position(|w| w == b"\n\n")? + 2;
    let dims_end = head[blank..].iter().position(|&b| b == b'\n')?;
    Some(blank + dims_end + 1)
}

/// Turns texels whose memory holds packed RGB `f32` triples in its first three quarters
/// (the layout of an `Rgb32F` image) into RGBA texels with `w = 1`. Texel `i` reads floats
/// `3i..3i + 3` and writes `4i..4i + 4`; going from the last texel to the first never
/// overwrites a float that is still to be read, since `4i >= 3i` and all texels `j < i`
/// read below `3i`.
fn expand_rgb_in_place(texels: &mut [[f32; 4]]) {
    let flat: &mut [f32] = bytemuck::cast_slice_mut(texels);
    for i in (0..flat.len() / 4).rev() {
        let (r, g, b) = (flat[3 * i], flat[3 * i + 1], flat[3 * i + 2]);
        flat[4 * i..4 * i + 4].copy_from_slice(&[r, g, b, 1.0]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rgb_expands_to_rgba_in_place() {
        let n = 5;
        let mut texels = vec![[0.0f32; 4]; n];
        let flat: &mut [f32] = bytemuck::cast_slice_mut(&mut texels);
        for (i, v) in flat[..3 * n].iter_mut().enumerate() {
            *v = i as f32;
        }
        expand_rgb_in_place(&mut texels);
        for (i, t) in texels.iter().enumerate() {
            let c = 3.0 * i as f32;
            assert_eq!(*t, [c, c + 1.0, c + 2.0, 1.0]);
        }
    }

    #[test]
    fn header_ends_after_the_dimension_line() {
        assert_eq!(header_len(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 3\nxx"), Some(45));
        assert_eq!(header_len(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 3"), None);
        assert_eq!(header_len(b"#?RADIANCE\n"), None);
    }
}
