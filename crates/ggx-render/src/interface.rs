//! The interface every backend implements: options and hooks in, progress during, a result
//! or an error out.

use std::sync::atomic::AtomicBool;
use std::time::Duration;

use ggx_film::{Film, FilmError, Window};
use thiserror::Error;

/// How to run a render (the scene file decides what to render).
#[derive(Clone, Copy, Debug)]
pub struct RenderOptions {
    /// Worker threads; 0 = one per core (ignored by the GPU backend).
    pub threads: usize,
    /// Run the kernel specialized to the scene's features (default) or the generic one.
    pub specialize: bool,
    /// The samples `[start, end)` of every pixel to render; `None`: `[0, spp)` of the scene.
    pub samples: Option<[u32; 2]>,
    /// The pixel window `[x0, y0, x1, y1)` to render; `None`: the whole image.
    pub window: Option<Window>,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions { threads: 0, specialize: true, samples: None, window: None }
    }
}

/// What one render call covers: the sample range and the pixel window, checked.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Job {
    /// Samples `[start, end)` of every window pixel.
    pub samples: [u32; 2],
    /// Pixels `[x0, y0, x1, y1)`.
    pub window: Window,
}

impl Job {
    /// The job of `options` for a scene of `spp` samples and `resolution` pixels; an error when
    /// the range is empty or reversed or the window empty or outside the image.
    pub fn new(options: &RenderOptions, spp: u32, [width, height]: [u32; 2]) -> Result<Job, RenderError> {
        let samples = options.samples.unwrap_or([0, spp.max(1)]);
        if samples[0] >= samples[1] {
            return Err(RenderError::Job(format!("the sample range {}..{} is empty", samples[0], samples[1])));
        }
        let window = options.window.unwrap_or([0, 0, width, height]);
        let [x0, y0, x1, y1] = window;
        if x0 >= x1 || y0 >= y1 || x1 > width || y1 > height {
            return Err(RenderError::Job(format!(
                "the pixel window {x0},{y0},{x1},{y1} is empty or leaves the {width}x{height} image"
            )));
        }
        Ok(Job { samples, window })
    }

    /// Pixels in the window.
    pub fn pixels(&self) -> u64 {
        let [x0, y0, x1, y1] = self.window;
        u64::from(x1 - x0) * u64::from(y1 - y0)
    }

    /// Samples per pixel asked for.
    pub fn spp(&self) -> u32 {
        self.samples[1] - self.samples[0]
    }

    /// Checks that `film` (a resumed render's) fits: same size, no pixel holding more than the
    /// range. Returns the camera samples it already holds inside the window.
    pub fn check_film(&self, film: &Film, resolution: [u32; 2]) -> Result<u64, RenderError> {
        if [film.width(), film.height()] != resolution {
            return Err(RenderError::Job(format!(
                "the film to continue is {}x{}, the image {}x{}",
                film.width(),
                film.height(),
                resolution[0],
                resolution[1]
            )));
        }
        let (mut held, width) = (0u64, resolution[0] as usize);
        for (i, p) in film.pixels().iter().enumerate() {
            let (x, y) = ((i % width) as u32, (i / width) as u32);
            let inside = x >= self.window[0] && x < self.window[2] && y >= self.window[1] && y < self.window[3];
            if p.samples > self.spp() || (!inside && p.samples > 0) {
                return Err(RenderError::Job(format!(
                    "pixel ({x}, {y}) of the film to continue holds {} samples, which the range {}..{} and window do not allow",
                    p.samples, self.samples[0], self.samples[1]
                )));
            }
            held += u64::from(p.samples);
        }
        Ok(held)
    }
}

/// Progress, reported as tiles (CPU) or row bands (GPU) finish.
#[derive(Clone, Copy, Debug)]
pub struct Progress {
    /// Samples per pixel every window pixel holds (passes complete).
    pub spp_done: u32,
    /// Samples per pixel requested.
    pub spp_target: u32,
    /// Camera samples held so far, finished tiles of the pass in flight included.
    pub samples_done: u64,
    /// Camera samples requested (`spp_target` times the window's pixels).
    pub samples_target: u64,
    /// True at the end of a pass.
    pub pass_end: bool,
    /// Time since the render started.
    pub elapsed: Duration,
}

/// Optional hooks into a running render.
#[derive(Clone, Copy, Default)]
pub struct RenderControl<'a> {
    /// Set it to stop after the work in flight; the image keeps every completed pass.
    pub cancel: Option<&'a AtomicBool>,
    /// Called as work finishes (from worker threads).
    pub progress: Option<&'a (dyn Fn(Progress) + Sync)>,
    /// Called with the film after every pass (on the render's thread), e.g. to write a
    /// checkpoint.
    pub pass_film: Option<&'a dyn Fn(&Film)>,
}

/// A finished (or interrupted) render.
pub struct RenderResult {
    /// Accumulated radiance.
    pub film: Film,
    /// Samples per pixel every window pixel of `film` holds (some may hold more: a cancelled
    /// pass keeps its finished tiles).
    pub spp: u32,
    /// Wall time of the render (BVH build and shader compilation excluded).
    pub elapsed: Duration,
    /// Camera samples traced by this call (a resumed film's are not counted).
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
    /// The sample range, window or film to continue does not fit the scene.
    #[error("{0}")]
    Job(String),
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
    fn jobs_are_checked() {
        let options = |samples, window| RenderOptions { samples, window, ..Default::default() };
        let job = Job::new(&options(None, None), 64, [8, 4]).unwrap();
        assert_eq!((job.samples, job.window, job.pixels(), job.spp()), ([0, 64], [0, 0, 8, 4], 32, 64));
        let job = Job::new(&options(Some([16, 48]), Some([2, 1, 4, 4])), 64, [8, 4]).unwrap();
        assert_eq!((job.pixels(), job.spp()), (6, 32));
        let msg = Job::new(&options(Some([5, 5]), None), 64, [8, 4]).unwrap_err().to_string();
        assert_eq!(msg, "the sample range 5..5 is empty");
        let msg = Job::new(&options(None, Some([0, 0, 9, 4])), 64, [8, 4]).unwrap_err().to_string();
        assert_eq!(msg, "the pixel window 0,0,9,4 is empty or leaves the 8x4 image");
        let mut film = Film::new(8, 4);
        assert_eq!(job.check_film(&film, [8, 4]).unwrap(), 0);
        film.add_pass_window(&[glam::Vec3::ONE; 32], 3, [2, 1, 4, 4]).unwrap();
        assert_eq!(job.check_film(&film, [8, 4]).unwrap(), 18);
        film.add_pass(&[glam::Vec3::ONE; 32], 1).unwrap();
        assert!(job.check_film(&film, [8, 4]).unwrap_err().to_string().contains("pixel (0, 0)"));
        assert!(job.check_film(&Film::new(4, 8), [8, 4]).is_err());
    }

    #[test]
    fn an_impossible_film_is_an_error() {
        assert_eq!(new_film(4, 3).unwrap().len(), 12);
        // 2^32 x 2^32 pixels cannot be addressed: an error, not an abort.
        let msg = new_film(u32::MAX, u32::MAX).err().map(|e| e.to_string()).unwrap_or_default();
        assert!(msg.contains("cannot allocate the 4294967295x4294967295 image"), "{msg}");
    }
}
