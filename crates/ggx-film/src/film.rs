//! [`Film`]: the accumulation buffer that renderers add whole passes of samples to.

use glam::Vec3;

use crate::FilmError;

/// Linear RGB accumulation film: per-pixel sums of radiance samples in `f64` plus the number
/// of samples per pixel (every pixel always has the same count: renderers add whole passes).
///
/// Summing in `f64` keeps the mean exact to `f32` precision for any realistic sample count.
/// Non-finite samples are stored as they are (a NaN makes that pixel's mean NaN), so that the
/// film does not hide renderer bugs; the display path ([`crate::tonemap_to_srgb8`]) shows
/// them as black.
#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    width: u32,
    height: u32,
    sum: Vec<[f64; 3]>,
    spp: u32,
}

impl Film {
    /// An empty (all zero, `spp == 0`) film of `width x height` pixels.
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

    /// An empty film, or [`FilmError::TooLarge`] when `width * height` pixels of 24 bytes
    /// exceed the address space.
    pub fn try_new(width: u32, height: u32) -> Result<Self, FilmError> {
        let too_large = FilmError::TooLarge { width, height };
        let len = pixel_count(width, height).ok_or(too_large.clone())?;
        let bytes = len.checked_mul(size_of::<[f64; 3]>()).ok_or(too_large.clone())?;
        if bytes > isize::MAX as usize {
            return Err(too_large);
        }
        let mut sum = Vec::new();
        sum.try_reserve_exact(len).map_err(|_| too_large)?;
        sum.resize(len, [0.0; 3]);
        Ok(Self { width, height, sum, spp: 0 })
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// Samples per pixel accumulated so far.
    pub fn spp(&self) -> u32 {
        self.spp
    }

    /// Number of pixels, `width * height`.
    pub fn len(&self) -> usize {
        self.sum.len()
    }

    /// True when the film has no pixels.
    pub fn is_empty(&self) -> bool {
        self.sum.is_empty()
    }

    /// Adds one pass: `pass[i]` is the SUM of `samples` radiance samples of pixel `i`
    /// (row-major, top row first).
    ///
    /// Errors (leaving the film unchanged) when `pass.len() != width * height`, when
    /// `samples == 0`, or when the samples-per-pixel count would overflow `u32`.
    pub fn add_pass(&mut self, pass: &[Vec3], samples: u32) -> Result<(), FilmError> {
        if pass.len() != self.sum.len() {
            return Err(FilmError::PassLength {
                width: self.width,
                height: self.height,
                expected: self.sum.len(),
                actual: pass.len(),
            });
        }
        if samples == 0 {
            return Err(FilmError::ZeroSamples);
        }
        let spp = self.spp.checked_add(samples).ok_or(FilmError::SampleCountOverflow { spp: self.spp, samples })?;
        for (acc, v) in self.sum.iter_mut().zip(pass) {
            acc[0] += f64::from(v.x);
            acc[1] += f64::from(v.y);
            acc[2] += f64::from(v.z);
        }
        self.spp = spp;
        Ok(())
    }

    /// Mean radiance per pixel, `sum / spp` (zeros when `spp == 0`), row-major, top row first.
    pub fn mean(&self) -> Vec<Vec3> {
        self.sum.iter().map(|s| self.mean_of(s)).collect()
    }

    /// Mean radiance of pixel `(x, y)` (`(0, 0)` is the top-left), or `None` outside the film.
    pub fn pixel(&self, x: u32, y: u32) -> Option<Vec3> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let i = usize::try_from(u64::from(y) * u64::from(self.width) + u64::from(x)).ok()?;
        self.sum.get(i).map(|s| self.mean_of(s))
    }

    /// Forgets every sample: sums and `spp` back to zero.
    pub fn clear(&mut self) {
        self.sum.fill([0.0; 3]);
        self.spp = 0;
    }

    /// `sum / spp` converted to `f32`; zero when `spp == 0`.
    fn mean_of(&self, sum: &[f64; 3]) -> Vec3 {
        if self.spp == 0 {
            return Vec3::ZERO;
        }
        let inv = 1.0 / f64::from(self.spp);
        Vec3::new((sum[0] * inv) as f32, (sum[1] * inv) as f32, (sum[2] * inv) as f32)
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
    fn passes_accumulate_in_f64_and_average() {
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
    fn f64_sums_keep_small_samples_next_to_large_ones() {
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
