//! [`compare`]: error metrics between an image and a reference, for tests and the
//! cross-backend diff tool.

use std::fmt;

use glam::Vec3;

use crate::FilmError;

/// `epsilon` in the relative error `|a - b| / sqrt(b^2 + epsilon)`: keeps near-black
/// reference pixels from dominating (the relMSE convention of Rousselle et al. 2011).
pub const REL_EPSILON: f64 = 1e-2;

/// Error statistics of an image against a reference, over all pixels and channels. With the
/// per-channel relative error `e = |a - b| / sqrt(b^2 + REL_EPSILON)`:
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ImageMetrics {
    /// Root mean squared error, `sqrt(mean((a - b)^2))` over all channels.
    pub rmse: f64,
    /// Relative mean squared error, `mean((a - b)^2 / (b^2 + REL_EPSILON)) = mean(e^2)` over
    /// all channels.
    pub rel_mse: f64,
    /// Largest `e` of any channel.
    pub max_rel: f64,
    /// Share (0 to 1) of pixels whose largest channel `e` exceeds the tolerance.
    pub over_tolerance: f64,
}

impl fmt::Display for ImageMetrics {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "rmse {:.6e}, relMSE {:.6e}, max rel {:.6e}, {:.4}% of pixels over tolerance",
            self.rmse,
            self.rel_mse,
            self.max_rel,
            100.0 * self.over_tolerance
        )
    }
}

/// Compares `a` with `reference` (same length, any order as long as both agree) and returns
/// [`ImageMetrics`]; a pixel counts as over tolerance when its largest relative channel error
/// is `> tolerance`.
///
/// Never NaN: a channel where both values are NaN, or both the same infinity, counts as equal;
/// any other non-finite channel counts as an infinite error. Errors on a length mismatch, on
/// empty images and on a negative or NaN tolerance.
pub fn compare(a: &[Vec3], reference: &[Vec3], tolerance: f64) -> Result<ImageMetrics, FilmError> {
    if a.len() != reference.len() {
        return Err(FilmError::CompareLength { image: a.len(), reference: reference.len() });
    }
    if a.is_empty() {
        return Err(FilmError::CompareEmpty);
    }
    if !(tolerance >= 0.0) {
        return Err(FilmError::Tolerance(tolerance));
    }
    let (mut sum_sq, mut sum_rel_sq, mut max_rel, mut over) = (0.0f64, 0.0f64, 0.0f64, 0usize);
    for (p, q) in a.iter().zip(reference) {
        let mut pixel_rel = 0.0f64;
        for (x, y) in p.to_array().into_iter().zip(q.to_array()) {
            let (sq, rel_sq) = channel_errors(f64::from(x), f64::from(y));
            sum_sq += sq;
            sum_rel_sq += rel_sq;
            pixel_rel = pixel_rel.max(rel_sq.sqrt());
        }
        max_rel = max_rel.max(pixel_rel);
        over += usize::from(pixel_rel > tolerance);
    }
    let channels = 3.0 * a.len() as f64;
    Ok(ImageMetrics {
        rmse: (sum_sq / channels).sqrt(),
        rel_mse: sum_rel_sq / channels,
        max_rel,
        over_tolerance: over as f64 / a.len() as f64,
    })
}

/// `(a - b)^2 / (b^2 + REL_EPSILON)`: the relative squared error of one channel against the
/// reference `b`, the term [`compare`]'s relMSE averages; `0` when both are NaN or the same
/// infinity, `+inf` for any other non-finite pair.
#[inline]
pub fn channel_rel_sq(a: f64, b: f64) -> f64 {
    channel_errors(a, b).1
}

/// `((a - b)^2, (a - b)^2 / (b^2 + REL_EPSILON))` for one channel; `(0, 0)` when both are NaN
/// or equal infinities, `(inf, inf)` for any other non-finite pair.
#[inline]
fn channel_errors(a: f64, b: f64) -> (f64, f64) {
    if a.is_finite() && b.is_finite() {
        let d2 = (a - b) * (a - b);
        (d2, d2 / (b * b + REL_EPSILON))
    } else if a == b || (a.is_nan() && b.is_nan()) {
        (0.0, 0.0)
    } else {
        (f64::INFINITY, f64::INFINITY)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-12 * b.abs().max(1.0)
    }

    #[test]
    fn channel_rel_sq_is_the_relmse_term() {
        assert!(close(channel_rel_sq(1.5, 1.0), 0.25 / (1.0 + REL_EPSILON)));
        assert!(close(channel_rel_sq(0.1, 0.0), 0.01 / REL_EPSILON));
        assert_eq!(channel_rel_sq(f64::NAN, f64::NAN), 0.0);
        assert_eq!(channel_rel_sq(f64::INFINITY, f64::INFINITY), 0.0);
        assert_eq!(channel_rel_sq(f64::INFINITY, f64::NEG_INFINITY), f64::INFINITY);
        assert_eq!(channel_rel_sq(f64::NAN, 1.0), f64::INFINITY);
        assert_eq!(channel_rel_sq(1.0, f64::NAN), f64::INFINITY);
    }

    #[test]
    fn identical_images_give_zeros() {
        let img = [Vec3::new(0.1, 2.0, 0.0), Vec3::new(f32::NAN, f32::INFINITY, -3.0)];
        assert_eq!(compare(&img, &img, 0.0).unwrap(), ImageMetrics::default());
    }

    #[test]
    fn known_offsets() {
        // Reference: pixel 0 = (1, 1, 1), pixel 1 = (0, 0, 0). Image: +0.5 in one channel of
        // each pixel. Squared errors 0.25 twice over 6 channels; relative squared errors
        // 0.25 / 1.01 and 0.25 / 0.01 = 25.
        let reference = [Vec3::ONE, Vec3::ZERO];
        let img = [Vec3::new(1.5, 1.0, 1.0), Vec3::new(0.0, 0.5, 0.0)];
        let m = compare(&img, &reference, 1.0).unwrap();
        assert!(close(m.rmse, (0.5f64 / 6.0).sqrt()), "{m:?}");
        assert!(close(m.rel_mse, (0.25 / 1.01 + 25.0) / 6.0), "{m:?}");
        assert!(close(m.max_rel, 5.0), "{m:?}");
        // Pixel 0: e = 0.5 / sqrt(1.01) = 0.4975 <= 1; pixel 1: e = 5 > 1.
        assert_eq!(m.over_tolerance, 0.5);
        assert_eq!(compare(&img, &reference, 0.4).unwrap().over_tolerance, 1.0);
        assert_eq!(compare(&img, &reference, 5.0).unwrap().over_tolerance, 0.0);
    }

    #[test]
    fn non_finite_mismatch_is_an_infinite_error() {
        let m = compare(&[Vec3::new(f32::NAN, 0.0, 0.0)], &[Vec3::ZERO], 1.0).unwrap();
        assert_eq!(
            (m.rmse, m.rel_mse, m.max_rel, m.over_tolerance),
            (f64::INFINITY, f64::INFINITY, f64::INFINITY, 1.0)
        );
        let m = compare(&[Vec3::ZERO], &[Vec3::new(0.0, f32::INFINITY, 0.0)], 1.0).unwrap();
        assert_eq!(m.max_rel, f64::INFINITY);
    }

    #[test]
    fn invalid_arguments() {
        let one = [Vec3::ONE];
        assert_eq!(compare(&one, &[], 0.1), Err(FilmError::CompareLength { image: 1, reference: 0 }));
        assert_eq!(compare(&[], &[], 0.1), Err(FilmError::CompareEmpty));
        assert!(matches!(compare(&one, &one, f64::NAN), Err(FilmError::Tolerance(t)) if t.is_nan()));
        assert_eq!(compare(&one, &one, -1.0), Err(FilmError::Tolerance(-1.0)));
    }
}
