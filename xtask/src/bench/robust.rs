//! An outlier-robust error: the relMSE of the image after dropping the pixels with the largest
//! errors. A heavy-tailed estimator (NEE alone on a caustic, cosine sampling of a sharp lobe)
//! puts most of its squared error into a few rare, huge samples; while the ladder has not yet
//! seen them, plain relMSE jumps up and down by orders of magnitude from rung to rung, so a
//! convergence check on it would judge luck. Dropping the worst pixels keeps the bulk of the
//! image, where a correct estimator converges as 1/spp and a biased one stalls.

use ggx_film::{Vec3, channel_rel_sq};

/// Share of pixels dropped by [`trimmed_rel_mse`] in the bench (the largest errors).
pub const TRIM: f64 = 0.01;

/// `mean(e^2)` over the pixels left after dropping the `trim` share (0 to 1) with the largest
/// `e^2`, where a pixel's `e^2` is the mean of [`channel_rel_sq`] over its channels (so with no
/// trim this is `ggx_film::compare`'s relMSE). A channel that is non-finite on one side only is
/// an infinite error (it survives the trim only if too many pixels have one); `+inf` for empty
/// or unequal-length images.
pub fn trimmed_rel_mse(image: &[Vec3], reference: &[Vec3], trim: f64) -> f64 {
    if image.len() != reference.len() || image.is_empty() {
        return f64::INFINITY;
    }
    let mut errors: Vec<f64> = image
        .iter()
        .zip(reference)
        .map(|(a, b)| {
            let channels = a.to_array().into_iter().zip(b.to_array());
            channels.map(|(x, y)| channel_rel_sq(x.into(), y.into())).sum::<f64>() / 3.0
        })
        .collect();
    let trim = if trim.is_finite() { trim.clamp(0.0, 1.0) } else { 0.0 };
    let keep = ((1.0 - trim) * errors.len() as f64).ceil().max(1.0) as usize;
    let keep = keep.min(errors.len());
    if keep < errors.len() {
        errors.select_nth_unstable_by(keep, f64::total_cmp);
    }
    errors[..keep].iter().sum::<f64>() / keep as f64
}

#[cfg(test)]
mod tests {
    use super::*;
    use ggx_film::REL_EPSILON;

    fn image(values: &[f32]) -> Vec<Vec3> {
        values.iter().map(|&v| Vec3::splat(v)).collect()
    }

    #[test]
    fn untrimmed_equals_compare() {
        let a = image(&[0.5, 1.0, 2.0, 0.0]);
        let b = image(&[0.4, 1.5, 2.0, 0.1]);
        let plain = ggx_film::compare(&a, &b, 1.0).unwrap().rel_mse;
        assert!((trimmed_rel_mse(&a, &b, 0.0) - plain).abs() <= 1e-12 * plain);
    }

    #[test]
    fn drops_the_largest_errors() {
        // 20 pixels: 19 with e^2 = 0.01 / 1.01, one firefly; a 5 % trim drops exactly the firefly.
        let reference = image(&[1.0; 20]);
        let mut a = image(&[1.1; 20]);
        a[7] = Vec3::splat(1e6);
        let small = 0.1f64 * 0.1 / (1.0 + REL_EPSILON);
        let got = trimmed_rel_mse(&a, &reference, 0.05);
        assert!((got - small).abs() < 1e-6 * small, "{got}");
        assert!(trimmed_rel_mse(&a, &reference, 0.0) > 1e9);
    }

    #[test]
    fn non_finite_pixels_count_as_infinite() {
        let reference = image(&[1.0; 4]);
        let a = vec![Vec3::ONE, Vec3::new(f32::NAN, 1.0, 1.0), Vec3::ONE, Vec3::ONE];
        assert_eq!(trimmed_rel_mse(&a, &reference, 0.25), 0.0);
        assert_eq!(trimmed_rel_mse(&a, &reference, 0.1), f64::INFINITY);
    }

    #[test]
    fn bad_inputs() {
        assert_eq!(trimmed_rel_mse(&[], &[], 0.1), f64::INFINITY);
        assert_eq!(trimmed_rel_mse(&image(&[1.0]), &image(&[1.0, 2.0]), 0.1), f64::INFINITY);
        // A trim of 1 (or more, or NaN) still keeps one pixel / trims nothing.
        assert_eq!(trimmed_rel_mse(&image(&[1.0, 3.0]), &image(&[1.0, 1.0]), 1.0), 0.0);
        assert!(trimmed_rel_mse(&image(&[1.0, 3.0]), &image(&[1.0, 1.0]), f64::NAN) > 1.0);
    }
}
