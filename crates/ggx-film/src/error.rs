//! [`FilmError`], [`OutputError`] and [`ParseToneMapError`]: every message says what is wrong
//! and, for file errors, names the path.

use std::io;
use std::path::PathBuf;

use thiserror::Error;

/// An error from the in-memory film and image operations.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum FilmError {
    /// A pass does not have one value per film pixel.
    #[error("pass has {actual} pixels, but the {width}x{height} film has {expected}")]
    PassLength {
        /// Film width.
        width: u32,
        /// Film height.
        height: u32,
        /// `width * height`.
        expected: usize,
        /// Length of the pass.
        actual: usize,
    },
    /// A pass claims to hold zero samples per pixel.
    #[error("a pass must hold at least one sample per pixel")]
    ZeroSamples,
    /// The samples-per-pixel count would exceed `u32::MAX`.
    #[error("samples per pixel overflow: {spp} + {samples} exceeds {}", u32::MAX)]
    SampleCountOverflow {
        /// Samples per pixel already in the film.
        spp: u32,
        /// Samples in the rejected pass.
        samples: u32,
    },
    /// Per-pixel sums that do not match their window, or a window outside the film.
    #[error("{actual} pixel sums do not fit the window {window:?} of the {width}x{height} film")]
    WindowLength {
        /// The window `[x0, y0, x1, y1)`.
        window: [u32; 4],
        /// Film width.
        width: u32,
        /// Film height.
        height: u32,
        /// Number of sums given.
        actual: usize,
    },
    /// Two films of different sizes cannot be merged.
    #[error("cannot merge a {}x{} film into a {}x{} film", other[0], other[1], this[0], this[1])]
    MergeSize {
        /// This film's size.
        this: [u32; 2],
        /// The other film's size.
        other: [u32; 2],
    },
    /// `width * height` pixels cannot be allocated on this platform.
    #[error("film size {width}x{height} is too large")]
    TooLarge {
        /// Requested width.
        width: u32,
        /// Requested height.
        height: u32,
    },
    /// The two images given to [`crate::compare`] have different pixel counts.
    #[error("cannot compare an image of {image} pixels with a reference of {reference} pixels")]
    CompareLength {
        /// Pixels in the image.
        image: usize,
        /// Pixels in the reference.
        reference: usize,
    },
    /// [`crate::compare`] was given two empty images.
    #[error("cannot compare empty images")]
    CompareEmpty,
    /// The tolerance given to [`crate::compare`] is negative or NaN.
    #[error("comparison tolerance must be a non-negative number, got {0}")]
    Tolerance(f64),
}

/// An error while writing or reading an image file. Every variant names the file.
#[derive(Debug, Error)]
pub enum OutputError {
    /// A file that `ggx merge` or `--resume` cannot use as a film.
    #[error("{}: not a ggx film file: {reason}", path.display())]
    NotAFilm {
        /// The file.
        path: PathBuf,
        /// Why.
        reason: String,
    },
    /// The extension is not one of [`crate::SUPPORTED_EXTENSIONS`].
    #[error("{}: unsupported image format (supported extensions: {})", .path.display(), crate::SUPPORTED_EXTENSIONS.join(", "))]
    UnsupportedFormat {
        /// The path as given.
        path: PathBuf,
    },
    /// The pixel slice does not hold `width * height` pixels.
    #[error("{}: a {width}x{height} image needs {expected} pixels, got {actual}", .path.display())]
    PixelCount {
        /// The path as given.
        path: PathBuf,
        /// Image width.
        width: u32,
        /// Image height.
        height: u32,
        /// `width * height` (saturated at `usize::MAX`).
        expected: usize,
        /// Length of the pixel slice.
        actual: usize,
    },
    /// Width or height is zero.
    #[error("{}: cannot write an empty {width}x{height} image", .path.display())]
    Empty {
        /// The path as given.
        path: PathBuf,
        /// Image width.
        width: u32,
        /// Image height.
        height: u32,
    },
    /// A file-system operation failed (missing directory, permission denied, disk full, ...).
    #[error("{}: {action}: {source}", .path.display())]
    Io {
        /// The path as given.
        path: PathBuf,
        /// What was being done, e.g. `cannot create temporary file in "out"`.
        action: String,
        /// The underlying I/O error.
        #[source]
        source: io::Error,
    },
    /// The encoder failed (this includes I/O errors it met while writing).
    #[error("{}: cannot encode {format}: {source}", .path.display())]
    Encode {
        /// The path as given.
        path: PathBuf,
        /// `"EXR"` or `"PNG"`.
        format: &'static str,
        /// The encoder's error.
        #[source]
        source: Box<dyn std::error::Error + Send + Sync + 'static>,
    },
    /// The file could not be read or decoded as an RGB(A) OpenEXR image.
    #[error("{}: cannot read EXR: {source}", .path.display())]
    Decode {
        /// The path as given.
        path: PathBuf,
        /// The decoder's error.
        #[source]
        source: exr::error::Error,
    },
    /// The decoded image is wider or taller than `u32::MAX` pixels.
    #[error("{}: image size {width}x{height} does not fit in 32 bits", .path.display())]
    TooLarge {
        /// The path as given.
        path: PathBuf,
        /// Width in the file.
        width: usize,
        /// Height in the file.
        height: usize,
    },
}

/// An unknown tone-map name given to `ToneMap::from_str`.
#[derive(Debug, Error, Clone, PartialEq, Eq)]
#[error("unknown tone map {input:?} (expected one of: aces, reinhard, clamp)")]
pub struct ParseToneMapError {
    /// The rejected input.
    pub input: String,
}
