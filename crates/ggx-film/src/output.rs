//! [`write_image`]: format dispatch by extension, size validation and atomic writing.

use std::path::Path;

use glam::Vec3;

use crate::atomic::write_atomically;
use crate::film::pixel_count;
use crate::{OutputError, OutputOptions, exr_io, png_io};

/// File extensions [`write_image`] understands (matched case-insensitively).
pub const SUPPORTED_EXTENSIONS: [&str; 2] = ["exr", "png"];

/// An output file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Format {
    Exr,
    Png,
}

/// Writes `pixels` (`width x height`, linear RGB, row-major, top row first) to `path`:
/// `.exr` = linear `f32` RGB (exposure and tone map NOT applied), `.png` = tone-mapped 8-bit
/// sRGB. Chosen by extension (case-insensitive); other extensions are an error naming the
/// path and the supported list.
///
/// Atomic: the image goes to a temporary file in the same directory
/// (`.<name>.tmp-<pid>-<counter>`), which is then renamed over `path`, so a crash never
/// leaves a half-written image and an existing file is replaced only on success; the
/// temporary file is removed on error. Errors name the path and the cause (unsupported
/// extension, wrong pixel count, missing directory, permission denied, ...).
pub fn write_image(
    path: &Path,
    width: u32,
    height: u32,
    pixels: &[Vec3],
    options: &OutputOptions,
) -> Result<(), OutputError> {
    let format = format_of(path)?;
    if width == 0 || height == 0 {
        return Err(OutputError::Empty { path: path.to_owned(), width, height });
    }
    let expected = pixel_count(width, height);
    if expected != Some(pixels.len()) {
        return Err(OutputError::PixelCount {
            path: path.to_owned(),
            width,
            height,
            expected: expected.unwrap_or(usize::MAX),
            actual: pixels.len(),
        });
    }
    write_atomically(path, |out| match format {
        // Both fit in usize: their product does.
        Format::Exr => exr_io::write_exr(out, path, width as usize, height as usize, pixels),
        Format::Png => png_io::write_png(out, path, width, height, pixels, options),
    })
}

/// The format for `path`'s extension, or [`OutputError::UnsupportedFormat`].
fn format_of(path: &Path) -> Result<Format, OutputError> {
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("exr") => Ok(Format::Exr),
        Some("png") => Ok(Format::Png),
        _ => Err(OutputError::UnsupportedFormat { path: path.to_owned() }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn extensions_are_case_insensitive() {
        assert_eq!(format_of(Path::new("a/b.EXR")).unwrap(), Format::Exr);
        assert_eq!(format_of(Path::new("b.Png")).unwrap(), Format::Png);
        for bad in ["b.jpg", "b", "png", "b.png.tmp", ".exr"] {
            let err = format_of(Path::new(bad)).unwrap_err();
            assert_eq!(err.to_string(), format!("{bad}: unsupported image format (supported extensions: exr, png)"));
        }
    }
}
