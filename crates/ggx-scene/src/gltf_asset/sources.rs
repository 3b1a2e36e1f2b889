//! The bytes a glTF file points to: the GLB binary chunk, `data:` URIs (base64) and files
//! beside the asset, each read within the limits; and images decoded to [`Texels`].

use std::io::Cursor;
use std::path::Path;

use base64::Engine as _;

use crate::limits::{Limit, Limits, read_regular_file_or};
use crate::texture::Texels;

/// Largest side of a texture image.
pub(crate) const MAX_TEXTURE_SIZE: u32 = 16384;

/// The bytes of `uri`: a `data:` URI's base64 payload, or a file relative to `base_dir`
/// (percent-escapes decoded), read within `limit` bytes.
pub(crate) fn read_uri(uri: &str, base_dir: &Path, limits: &Limits, max_bytes: u64) -> Result<Vec<u8>, String> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let (_, payload) = rest.split_once(";base64,").ok_or("a data: URI that is not base64")?;
        // Base64 decodes to 3/4 of its length: check before decoding.
        let decoded = payload.len() as u64 / 4 * 3;
        if decoded > max_bytes {
            return Err(format!("a data: URI of {decoded} bytes, over the limit of {max_bytes} (max_mesh_bytes)"));
        }
        return base64::engine::general_purpose::STANDARD
            .decode(payload.trim_end())
            .map_err(|e| format!("invalid base64 in a data: URI: {e}"));
    }
    if uri.contains("://") {
        return Err(format!("\"{}\": only relative file paths and data: URIs are read", crate::shorten::short(uri)));
    }
    let path = base_dir.join(percent_decode(uri)?);
    let limits = Limits { max_mesh_bytes: max_bytes, ..*limits };
    read_regular_file_or(&path, "glTF resource", Limit::MeshBytes, &limits).map_err(|e| e.to_string())
}

/// `%XX` escapes of a URI path decoded (UTF-8).
fn percent_decode(uri: &str) -> Result<String, String> {
    let bytes = uri.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = uri.get(i + 1..i + 3).and_then(|h| u8::from_str_radix(h, 16).ok());
            out.push(hex.ok_or_else(|| format!("bad percent escape in \"{}\"", crate::shorten::short(uri)))?);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    String::from_utf8(out).map_err(|_| "a URI that is not UTF-8 once unescaped".to_owned())
}

/// Decodes an encoded image (PNG, JPEG, HDR, EXR) into texels: 8-bit images stay packed
/// RGBA8, deeper ones become RGBA `f32`. The declared size is checked against
/// [`MAX_TEXTURE_SIZE`], `limits.max_map_pixels` and `max_bytes` before decoding.
pub(crate) fn decode_image(bytes: &[u8], limits: &Limits, max_bytes: u64) -> Result<(u32, u32, Texels), String> {
    let reader = image::ImageReader::new(Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| format!("cannot read the image: {e}"))?;
    if reader.format().is_none() {
        return Err("unknown image format (PNG, JPEG, HDR or EXR are read)".to_owned());
    }
    let (w, h) = reader.into_dimensions().map_err(|e| format!("cannot read the image: {e}"))?;
    if !(1..=MAX_TEXTURE_SIZE).contains(&w) || !(1..=MAX_TEXTURE_SIZE).contains(&h) {
        return Err(format!("image size {w}x{h} is outside 1..={MAX_TEXTURE_SIZE} per side"));
    }
    let pixels = u64::from(w) * u64::from(h);
    limits.check(Limit::MapPixels, format!("texture {w}x{h}"), pixels).map_err(|e| e.to_string())?;
    // Decoded at up to 16 bytes per pixel, plus the decoder's copy.
    let bytes_needed = pixels * 32;
    if bytes_needed > max_bytes {
        return Err(format!(
            "texture {w}x{h} needs about {}, over what the memory limit leaves ({})",
            crate::format_bytes(bytes_needed),
            crate::format_bytes(max_bytes)
        ));
    }
    let mut reader = image::ImageReader::new(Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| format!("cannot read the image: {e}"))?;
    let mut l = image::Limits::default();
    l.max_image_width = Some(MAX_TEXTURE_SIZE);
    l.max_image_height = Some(MAX_TEXTURE_SIZE);
    l.max_alloc = Some(bytes_needed);
    reader.limits(l);
    let img = reader.decode().map_err(|e| format!("cannot decode the image: {e}"))?;
    use image::DynamicImage as D;
    let texels = match img {
        D::ImageLuma8(_) | D::ImageLumaA8(_) | D::ImageRgb8(_) | D::ImageRgba8(_) => {
            let rgba = img.into_rgba8();
            Texels::Rgba8(rgba.pixels().map(|p| u32::from_le_bytes(p.0)).collect())
        }
        other => {
            let rgba = other.into_rgba32f();
            Texels::RgbaF32(rgba.pixels().map(|p| p.0.map(|c| if c.is_finite() { c } else { 0.0 })).collect())
        }
    };
    Ok((w, h, texels))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn data_uris_and_escapes() {
        let l = Limits::default();
        assert_eq!(read_uri("data:application/octet-stream;base64,AAEC", Path::new("."), &l, 100).unwrap(), [0, 1, 2]);
        assert!(read_uri("data:application/octet-stream;base64,AAEC", Path::new("."), &l, 2).is_err());
        assert!(read_uri("data:text/plain,abc", Path::new("."), &l, 100).is_err());
        assert!(read_uri("https://example.com/a.bin", Path::new("."), &l, 100).unwrap_err().contains("only relative"));
        assert_eq!(percent_decode("a%20b.bin").unwrap(), "a b.bin");
        assert!(percent_decode("a%2").is_err());
    }

    #[test]
    fn images_decode_within_limits() {
        let mut png = Vec::new();
        let img = image::RgbaImage::from_raw(2, 1, vec![255, 0, 0, 255, 0, 255, 0, 128]).unwrap();
        img.write_to(&mut Cursor::new(&mut png), image::ImageFormat::Png).unwrap();
        let (w, h, t) = decode_image(&png, &Limits::default(), 1 << 20).unwrap();
        assert_eq!((w, h), (2, 1));
        assert_eq!(t, Texels::Rgba8(vec![0xff00_00ff, 0x8000_ff00]));
        assert!(decode_image(&png, &Limits::default(), 10).unwrap_err().contains("memory limit"));
        assert!(decode_image(b"not an image", &Limits::default(), 1 << 20).is_err());
    }
}
