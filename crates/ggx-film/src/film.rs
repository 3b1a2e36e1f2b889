//! [`Film`]: the accumulation buffer that renderers add passes, tiles and other films to.

use glam::Vec3;

use crate::FilmError;
use crate::sample_sum::SampleSum;

/// Linear RGB accumulation film: per pixel, the radiance samples summed in 128-bit fixed
/// point ([`SampleSum`]) and their count.
///
/// Fixed-point sums are exact under any grouping, so the film of a render equals, bit for
/// bit, the merge of films that rendered disjoint parts of its samples (`ggx merge`), and a
/// pixel may hold more samples than another (a render interrupted mid-pass keeps its finished
/// tiles). Non-finite samples are counted, not hidden: such a pixel's mean is NaN (the display
/// path, [`crate::tonemap_to_srgb8`], shows it as black).
#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    width: u32,
    height: u32,
    pixels: Vec<SampleSum>,
}

/// A pixel window `[x0, y0, x1, y1)` of a film.
pub type Window = [u32; 4];

impl Film {
    /// An empty (all zero, no samples) film of `width x height` pixels.
    ///
    /// # Panics
    ///
    /// If the film cannot be allocated (see [`Film::try_new`], which returns an error instead).
    pub fn new(width: u32, height: u32) -> Self {
        match Self::try_new(width, height) {
            Ok(film) => film,
            Err(e) => panic!("{e}"),
        }
    }

    /// An empty film, or [`FilmError::TooLarge`] when `width * height` pixels of
    /// [`Film::BYTES_PER_PIXEL`] bytes exceed the address space or cannot be allocated.
    pub fn try_new(width: u32, height: u32) -> Result<Self, FilmError> {
        let too_large = FilmError::TooLarge { width, height };
        let len = pixel_count(width, height).ok_or(too_large.clone())?;
        let bytes = len.checked_mul(Self::BYTES_PER_PIXEL).ok_or(too_large.clone())?;
        if bytes > isize::MAX as usize {
            return Err(too_large);
        }
        let mut pixels = Vec::new();
        pixels.try_reserve_exact(len).map_err(|_| too_large)?;
        pixels.resize(len, SampleSum::default());
        Ok(Self { width, height, pixels })
    }

    /// Memory of one pixel.
    pub const BYTES_PER_PIXEL: usize = size_of::<SampleSum>();

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The whole film as a window, `[0, 0, width, height]`.
    pub fn full_window(&self) -> Window {
        [0, 0, self.width, self.height]
    }

    /// Samples that every pixel has (the smallest per-pixel count; 0 for an empty film).
    pub fn spp(&self) -> u32 {
        self.pixels.iter().map(|p| p.samples).min().unwrap_or(0)
    }

    /// Number of pixels, `width * height`.
    pub fn len(&self) -> usize {
        self.pixels.len()
    }

    /// True when the film has no pixels.
    pub fn is_empty(&self) -> bool {
        self.pixels.is_empty()
    }

    /// Every pixel's samples, row-major, top row first.
    pub fn pixels(&self) -> &[SampleSum] {
        &self.pixels
    }

    /// Mutable access to every pixel's samples (for readers of saved films).
    pub fn pixels_mut(&mut self) -> &mut [SampleSum] {
        &mut self.pixels
    }

    /// Adds one pass over the whole film: `pass[i]` is the SUM of `samples` radiance samples of
    /// pixel `i` (row-major, top row first).
    ///
    /// Errors (leaving the film unchanged) when `pass.len() != width * height`, when
    /// `samples == 0`, or when a pixel's sample count would overflow `u32`.
    pub fn add_pass(&mut self, pass: &[Vec3], samples: u32) -> Result<(), FilmError> {
        self.add_pass_window(pass, samples, self.full_window())
    }

    /// [`Film::add_pass`] for the pixels of `window` only (`pass` still covers the whole film;
    /// the window is clipped to it).
    pub fn add_pass_window(&mut self, pass: &[Vec3], samples: u32, window: Window) -> Result<(), FilmError> {
        if pass.len() != self.pixels.len() {
            return Err(FilmError::PassLength {
                width: self.width,
                height: self.height,
                expected: self.pixels.len(),
                actual: pass.len(),
            });
        }
        if samples == 0 {
            return Err(FilmError::ZeroSamples);
        }
        let rows = self.window_rows(window);
        for range in rows.clone() {
            if let Some(p) = self.pixels[range].iter().find(|p| p.samples.checked_add(samples).is_none()) {
                return Err(FilmError::SampleCountOverflow { spp: p.samples, samples });
            }
        }
        for range in rows {
            for (acc, v) in self.pixels[range.clone()].iter_mut().zip(&pass[range]) {
                acc.add_summed(*v, samples);
            }
        }
        Ok(())
    }

    /// Adds per-pixel sums for the pixels of `window` (row-major within the window, as a tile
    /// renderer produces them). Errors, leaving the film unchanged, when `sums` does not have
    /// one entry per window pixel, the window leaves the film, or a count would overflow.
    pub fn add_window(&mut self, window: Window, sums: &[SampleSum]) -> Result<(), FilmError> {
        let [x0, y0, x1, y1] = window;
        let inside = x0 <= x1 && y0 <= y1 && x1 <= self.width && y1 <= self.height;
        let expected = (x1.saturating_sub(x0) as usize) * (y1.saturating_sub(y0) as usize);
        if !inside || sums.len() != expected {
            return Err(FilmError::WindowLength { window, width: self.width, height: self.height, actual: sums.len() });
        }
        let w = (x1 - x0) as usize;
        let rows = self.window_rows(window);
        for (range, chunk) in rows.clone().zip(sums.chunks(w.max(1))) {
            for (acc, s) in self.pixels[range].iter().zip(chunk) {
                if acc.samples.checked_add(s.samples).is_none() {
                    return Err(FilmError::SampleCountOverflow { spp: acc.samples, samples: s.samples });
                }
            }
        }
        for (range, chunk) in rows.zip(sums.chunks(w.max(1))) {
            for (acc, s) in self.pixels[range].iter_mut().zip(chunk) {
                // Checked above.
                let _ = acc.merge(s);
            }
        }
        Ok(())
    }

    /// Adds every pixel of `other` (same size) to this film: the exact merge of two renders of
    /// disjoint samples. Errors, leaving the film unchanged, on a size mismatch or overflow.
    pub fn merge(&mut self, other: &Film) -> Result<(), FilmError> {
        if (other.width, other.height) != (self.width, self.height) {
            return Err(FilmError::MergeSize { this: [self.width, self.height], other: [other.width, other.height] });
        }
        self.add_window(self.full_window(), &other.pixels)
    }

    /// Mean radiance per pixel ([`SampleSum::mean`]), row-major, top row first.
    pub fn mean(&self) -> Vec<Vec3> {
        self.pixels.iter().map(SampleSum::mean).collect()
    }

    /// Mean radiance of pixel `(x, y)` (`(0, 0)` is the top-left), or `None` outside the film.
    pub fn pixel(&self, x: u32, y: u32) -> Option<Vec3> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let i = usize::try_from(u64::from(y) * u64::from(self.width) + u64::from(x)).ok()?;
        self.pixels.get(i).map(SampleSum::mean)
    }

    /// Forgets every sample.
    pub fn clear(&mut self) {
        self.pixels.fill(SampleSum::default());
    }

    /// The index ranges of the rows of `window` clipped to the film.
    fn window_rows(&self, [x0, y0, x1, y1]: Window) -> impl Iterator<Item = std::ops::Range<usize>> + Clone + use<> {
        let (x0, x1) = (x0.min(self.width) as usize, x1.min(self.width) as usize);
        let (y0, y1) = (y0.min(self.height), y1.min(self.height));
        let width = self.width as usize;
        (y0..y1).map(move |y| y as usize * width + x0..y as usize * width + x1.max(x0))
    }
}

/// `width * height` as a `usize`, `None` on overflow.
pub(crate) fn pixel_count(width: u32, height: u32) -> Option<usize> {
    usize::try_from(width).ok()?.checked_mul(usize::try_from(height).ok()?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn passes_accumulate_and_average() {
        let mut film = Film::new(2, 1);
        assert_eq!(film.mean(), vec![Vec3::ZERO; 2]);
        film.add_pass(&[Vec3::new(1.0, 2.0, 3.0), Vec3::splat(4.0)], 1).unwrap();
        film.add_pass(&[Vec3::new(3.0, 4.0, 5.0), Vec3::splat(2.0)], 3).unwrap();
        assert_eq!(film.spp(), 4);
        assert_eq!(film.mean(), vec![Vec3::new(1.0, 1.5, 2.0), Vec3::splat(1.5)]);
        assert_eq!(film.pixel(1, 0), Some(Vec3::splat(1.5)));
        assert_eq!(film.pixel(2, 0), None);
        assert_eq!(film.pixel(0, 1), None);
    }

    #[test]
    fn fixed_point_keeps_small_samples_next_to_large_ones() {
        // In f32, 1e8 + 1 == 1e8: the small samples would vanish.
        let mut film = Film::new(1, 1);
        film.add_pass(&[Vec3::splat(1e8)], 1).unwrap();
        for _ in 0..1000 {
            film.add_pass(&[Vec3::ONE], 1).unwrap();
        }
        film.add_pass(&[Vec3::splat(-1e8)], 1).unwrap();
        assert_eq!(film.spp(), 1002);
        assert_eq!(film.pixel(0, 0), Some(Vec3::splat((1000.0f64 / 1002.0) as f32)));
    }

    #[test]
    fn windows_and_merges_add_per_pixel() {
        let mut a = Film::new(3, 2);
        a.add_pass_window(&[Vec3::ONE; 6], 2, [1, 0, 3, 1]).unwrap();
        let counts = |f: &Film| f.pixels().iter().map(|p| p.samples).collect::<Vec<_>>();
        assert_eq!(counts(&a), [0, 2, 2, 0, 0, 0]);
        let tile = [SampleSum { rgb: [1 << 57, 0, 0], samples: 1, invalid: 0 }; 2];
        a.add_window([0, 1, 2, 2], &tile).unwrap();
        assert_eq!(counts(&a), [0, 2, 2, 1, 1, 0]);
        assert_eq!(a.pixel(0, 1), Some(Vec3::new(2.0, 0.0, 0.0)));
        assert_eq!(a.spp(), 0);
        let mut b = a.clone();
        b.merge(&a).unwrap();
        assert_eq!(counts(&b), [0, 4, 4, 2, 2, 0]);
        assert_eq!(b.mean(), a.mean());
        let err = a.add_window([0, 1, 2, 2], &tile[..1]).unwrap_err();
        assert_eq!(err.to_string(), "1 pixel sums do not fit the window [0, 1, 2, 2] of the 3x2 film");
        assert!(a.add_window([2, 1, 4, 2], &tile).is_err());
        assert!(matches!(a.merge(&Film::new(2, 3)), Err(FilmError::MergeSize { .. })));
    }

    #[test]
    fn rejected_passes_leave_the_film_unchanged() {
        let mut film = Film::new(3, 2);
        film.add_pass(&[Vec3::ONE; 6], 2).unwrap();
        let before = film.clone();
        let err = film.add_pass(&[Vec3::ONE; 5], 1).unwrap_err();
        assert_eq!(err, FilmError::PassLength { width: 3, height: 2, expected: 6, actual: 5 });
        assert_eq!(err.to_string(), "pass has 5 pixels, but the 3x2 film has 6");
        assert_eq!(film.add_pass(&[Vec3::ONE; 6], 0), Err(FilmError::ZeroSamples));
        assert!(matches!(film.add_pass(&[Vec3::ONE; 6], u32::MAX), Err(FilmError::SampleCountOverflow { .. })));
        assert_eq!(film, before);
        film.clear();
        assert_eq!((film.spp(), film.mean()), (0, vec![Vec3::ZERO; 6]));
    }

    #[test]
    fn empty_and_oversized_films() {
        let film = Film::new(0, 7);
        assert!(film.is_empty() && film.mean().is_empty() && film.pixel(0, 0).is_none());
        if usize::BITS == 64 {
            assert_eq!(
                Film::try_new(u32::MAX, u32::MAX),
                Err(FilmError::TooLarge { width: u32::MAX, height: u32::MAX })
            );
        }
    }
}
