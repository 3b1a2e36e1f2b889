//! Film and image output shared by the ggx CPU and GPU path tracers.
//!
//! * [`Film`]: per-pixel sums of radiance samples in 128-bit fixed point ([`SampleSum`]), exact
//!   under any grouping, filled by passes, tiles ([`Film::add_window`]) or other films
//!   ([`Film::merge`]), read back as the mean radiance ([`Film::mean`]).
//! * [`ToneMap`], [`OutputOptions`], [`srgb_encode`] and [`tonemap_to_srgb8`]: exposure, tone
//!   mapping (fitted ACES, luminance Reinhard, clamp) and sRGB encoding to 8 bits. Every `f32`
//!   is accepted: NaN and negative values become black, `+inf` becomes full intensity.
//! * [`write_image`]: linear `f32` OpenEXR (`.exr`) or tone-mapped sRGB PNG (`.png`), written
//!   to a temporary file in the target directory and renamed over the target, so a crash
//!   never leaves a half-written image; links are followed, the replaced file's mode kept.
//!   [`check_output`] proves before a render that the write can happen;
//!   [`remove_pending_temp_files`] cleans up for a signal handler that exits at once.
//!   [`read_exr`] reads an EXR back.
//! * [`compare`]: RMSE, relative MSE and relative-error statistics between two images, for
//!   tests and the cross-backend diff tool.
//!
//! Pixels are linear RGB, row-major with the top row first. Nothing here panics on user data:
//! mismatched sizes, bad paths and I/O failures are returned as [`FilmError`] or
//! [`OutputError`].
#![deny(missing_docs)]

mod atomic;
mod display;
mod error;
mod exr_io;
mod film;
mod film_file;
mod merge;
mod metrics;
mod output;
mod png_io;
mod sample_sum;
mod srgb;
mod tonemap;

pub use atomic::remove_pending_temp_files;
pub use display::{OutputOptions, tonemap_to_srgb8};
pub use error::{FilmError, OutputError, ParseToneMapError};
pub use exr_io::read_exr;
pub use film::{Film, Window};
pub use film_file::{FilmInfo, read_film, read_film_info, write_film};
pub use merge::{Merged, Merger, Part, merge_films};
pub use metrics::{ImageMetrics, REL_EPSILON, channel_rel_sq, compare};
pub use output::{SUPPORTED_EXTENSIONS, check_file, check_output, write_file, write_image};
pub use sample_sum::{FRACTION_BITS, MAX_SAMPLE, SampleSum};
pub use srgb::srgb_encode;
pub use tonemap::ToneMap;

/// Re-exported so users of the public API need not depend on glam themselves.
pub use glam::Vec3;
