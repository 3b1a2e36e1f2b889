//! The interface every backend implements: options and hooks in, progress during, a result
//! or an error out.

use std::sync::atomic::AtomicBool;
use std::time::Duration;

use ggx_film::{Film, FilmError};
use thiserror::Error;

/// How to run a render (the scene file decides what to render).
#[derive(Clone, Copy, Debug)]
pub struct RenderOptions {
    /// Worker threads; 0 = one per core (ignored by the GPU backend).
    pub threads: usize,
    /// Run the kernel specialized to the scene's features (default) or the generic one.
    pub specialize: bool,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions { threads: 0, specialize: true }
    }
}

/// Progress reported after each pass.
#[derive(Clone, Copy, Debug)]
pub struct Progress {
    /// Samples per pixel accumulated so far.
    pub spp_done: u32,
    /// Samples per pixel requested.
    pub spp_target: u32,
    /// Time since the render started.
    pub elapsed: Duration,
}

/// Optional hooks into a running render.
#[derive(Clone, Copy, Default)]
pub struct RenderControl<'a> {
    /// Set it to stop after the work in flight; the image keeps every completed pass.
    pub cancel: Option<&'a AtomicBool>,
    /// Called after every pass.
    pub progress: Option<&'a (dyn Fn(Progress) + Sync)>,
}

/// A finished (or interrupted) render.
pub struct RenderResult {
    /// Accumulated radiance.
    pub film: Film,
    /// Samples per pixel in `film`.
    pub spp: u32,
    /// Wall time of the render (BVH build and shader compilation excluded).
    pub elapsed: Duration,
    /// Camera samples traced (`spp * pixels`).
    pub camera_samples: u64,
    /// Rays traced (closest-hit and shadow rays).
    pub rays: u64,
    /// True when the cancel flag stopped the render before its target.
    pub interrupted: bool,
    /// The kernel variant that ran (e.g. `"area+env"`).
    pub kernel: &'static str,
}

/// Why a render could not run.
#[derive(Debug, Error)]
pub enum RenderError {
    /// The film, or a buffer of the render loop, could not be allocated.
    #[error("cannot allocate the {width}x{height} image: {source}")]
    Film {
        /// Image width.
        width: u32,
        /// Image height.
        height: u32,
        /// What failed.
        #[source]
        source: FilmError,
    },
}

/// An empty film, or [`RenderError::Film`] when it cannot be allocated.
pub fn new_film(width: u32, height: u32) -> Result<Film, RenderError> {
    Film::try_new(width, height).map_err(|source| RenderError::Film { width, height, source })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_impossible_film_is_an_error() {
        assert_eq!(new_film(4, 3).unwrap().len(), 12);
        // 2^32 x 2^32 pixels cannot be addressed: an error, not an abort.
        let msg = new_film(u32::MAX, u32::MAX).err().map(|e| e.to_string()).unwrap_or_default();
        assert!(msg.contains("cannot allocate the 4294967295x4294967295 image"), "{msg}");
    }
}
