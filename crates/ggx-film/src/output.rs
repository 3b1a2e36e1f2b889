//! [`write_image`]: format dispatch by extension, size validation and atomic writing.

use std::path::Path;

use glam::Vec3;

use crate::atomic::{check_replaceable, write_atomically};
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
/// `.exr` = linear `f32` RGB scaled by the exposure `2^stops` (no tone map; values the
/// scale takes past `f32::MAX` saturate there), `.png` = exposed, tone-mapped 8-bit sRGB. Chosen by extension (case-insensitive); other extensions are an error naming the
/// path and the supported list.
///
/// Atomic: the image goes to a temporary file in the same directory
/// (`.<name>.tmp-<pid>-<counter>`), which is then renamed over `path`, so a crash never
/// leaves a half-written image and an existing file is replaced only on success; the
/// temporary file is removed on error. A symbolic link is followed (the file it points to is
/// replaced, the link stays); the replaced file's mode (and owner, where allowed) is kept;
/// a directory, FIFO or device at `path` is refused. Errors name the path and the cause
/// (unsupported extension, wrong pixel count, missing directory, permission denied, ...).
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
        Format::Exr => {
            let scale = options.exposure_scale();
            if scale == 1.0 {
                exr_io::write_exr(out, path, width as usize, height as usize, pixels)
            } else {
                let exposed: Vec<Vec3> = pixels.iter().map(|&p| expose(p, scale)).collect();
                exr_io::write_exr(out, path, width as usize, height as usize, &exposed)
            }
        }
        Format::Png => png_io::write_png(out, path, width, height, pixels, options),
    })
}

/// Checks, before a render starts, that [`write_image`] will be able to write `path`: a
/// supported extension, an existing directory in which a file can be created (the check
/// creates and removes one), and nothing but a regular file to replace. Symbolic links are
/// followed as [`write_image`] follows them.
pub fn check_output(path: &Path) -> Result<(), OutputError> {
    format_of(path)?;
    check_replaceable(path)
}

/// Writes `bytes` to `path` the way [`write_image`] writes images: to a temporary file in the
/// same directory, synced, then renamed over `path` (links followed, the replaced file's mode
/// kept, only a regular file replaced). For files that go with an image, such as render
/// statistics.
pub fn write_file(path: &Path, bytes: &[u8]) -> Result<(), OutputError> {
    write_atomically(path, |out| {
        use std::io::Write as _;
        out.write_all(bytes).map_err(|source| OutputError::Io {
            path: path.to_owned(),
            action: "cannot write".into(),
            source,
        })
    })
}

/// Checks, before any work is done, that [`write_file`] will be able to write `path` (an
/// existing directory in which a file can be created, nothing but a regular file to replace).
pub fn check_file(path: &Path) -> Result<(), OutputError> {
    check_replaceable(path)
}

/// `p * scale` in f64, finite values saturated to `±f32::MAX` (NaN and inf stay as they are).
pub(crate) fn expose(p: Vec3, scale: f64) -> Vec3 {
    let one = |c: f32| {
        if !c.is_finite() {
            return c;
        }
        let v = f64::from(c) * scale;
        if v.is_nan() { 0.0 } else { v.clamp(-f64::from(f32::MAX), f64::from(f32::MAX)) as f32 }
    };
    Vec3::new(one(p.x), one(p.y), one(p.z))
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
    fn exposure_scales_and_saturates() {
        assert_eq!(expose(Vec3::new(1.0, -2.0, 0.25), 4.0), Vec3::new(4.0, -8.0, 1.0));
        assert_eq!(expose(Vec3::new(1e30, -1e30, 0.0), 1e20), Vec3::new(f32::MAX, -f32::MAX, 0.0));
        let odd = expose(Vec3::new(f32::NAN, f32::INFINITY, 1.0), 0.0);
        assert!(odd.x.is_nan() && odd.y == f32::INFINITY && odd.z == 0.0);
    }

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
