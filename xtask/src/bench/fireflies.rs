//! Firefly counting: a pixel is a firefly when its luminance exceeds [`FACTOR`] times the
//! reference's luminance at that pixel, with an absolute floor of [`FLOOR`] on the reference
//! so that near-black pixels need a visible outlier to count. Non-finite pixels count too.

use ggx_film::Vec3;
use ggx_scene::luminance;

/// A pixel brighter than this many times the reference is a firefly.
pub const FACTOR: f32 = 10.0;
/// Floor on the reference luminance: the threshold is `FACTOR * max(reference, FLOOR)`.
pub const FLOOR: f32 = 1e-3;

/// True when `pixel` is a firefly against `reference` (Rec. 709 luminance).
pub fn is_firefly(pixel: Vec3, reference: Vec3) -> bool {
    let threshold = FACTOR * luminance(reference).max(FLOOR);
    // Written so that a NaN luminance counts as a firefly.
    !(luminance(pixel) <= threshold)
}

/// Number of fireflies of `image` against `reference` (same size).
pub fn count(image: &[Vec3], reference: &[Vec3]) -> Result<usize, String> {
    if image.len() != reference.len() {
        return Err(format!("firefly count: image has {} pixels, reference {}", image.len(), reference.len()));
    }
    Ok(image.iter().zip(reference).filter(|&(&p, &r)| is_firefly(p, r)).count())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn threshold_with_floor() {
        let grey = |v: f32| Vec3::splat(v);
        assert!(!is_firefly(grey(1.0), grey(0.5)));
        assert!(!is_firefly(grey(5.0), grey(0.5)), "exactly 10x is not a firefly");
        assert!(is_firefly(grey(5.01), grey(0.5)));
        // Black reference: the floor makes the threshold 0.01.
        assert!(!is_firefly(grey(0.009), Vec3::ZERO));
        assert!(is_firefly(grey(0.011), Vec3::ZERO));
        assert!(is_firefly(grey(0.011), grey(-1.0)), "negative reference uses the floor");
        assert!(is_firefly(Vec3::new(f32::NAN, 0.0, 0.0), grey(1.0)));
        assert!(is_firefly(Vec3::INFINITY, grey(1.0)));
        // Luminance, not the max channel: pure blue 20 against grey 1 has Y = 1.44.
        assert!(!is_firefly(Vec3::new(0.0, 0.0, 20.0), grey(1.0)));
    }

    #[test]
    fn counts() {
        let reference = vec![Vec3::splat(0.1); 4];
        let image = [Vec3::splat(0.1), Vec3::splat(2.0), Vec3::ZERO, Vec3::splat(1.5)];
        assert_eq!(count(&image, &reference), Ok(2));
        assert!(count(&image[..3], &reference).is_err());
    }
}
