//! The sRGB transfer function and 8-bit quantisation.

/// sRGB opto-electronic transfer function (IEC 61966-2-1): `12.92 x` for `x <= 0.0031308`,
/// else `1.055 x^(1/2.4) - 0.055`. NaN and negative inputs give 0 (display values cannot be
/// negative); values above 1 are not clamped.
#[inline]
pub fn srgb_encode(linear: f32) -> f32 {
    if !(linear > 0.0031308) {
        // Also NaN and negatives; f32::max ignores a NaN operand.
        12.92 * linear.max(0.0)
    } else {
        1.055 * linear.powf(1.0 / 2.4) - 0.055
    }
}

/// Round-to-nearest quantisation of `[0, 1]` to `0..=255`: `floor(255 v + 0.5)`, with NaN and
/// values below 0 giving 0 and values above 1 giving 255.
#[inline]
pub(crate) fn quantize_u8(v: f32) -> u8 {
    // `as` saturates and maps NaN to 0.
    (v.max(0.0).min(1.0) * 255.0 + 0.5) as u8
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn known_points() {
        assert_eq!(srgb_encode(0.0), 0.0);
        // Both branches meet at the threshold: 12.92 * 0.0031308 = 0.040449936.
        assert!((srgb_encode(0.0031308) - 0.040449936).abs() < 1e-7);
        assert!((srgb_encode(0.0031309) - 0.040449936).abs() < 1e-5);
        assert!((srgb_encode(0.5) - 0.7353569).abs() < 1e-6);
        assert!((srgb_encode(1.0) - 1.0).abs() < 1e-6);
        assert!((srgb_encode(0.18) - 0.46135613).abs() < 1e-6);
    }

    #[test]
    fn monotonic_on_unit_range() {
        let mut prev = srgb_encode(0.0);
        for i in 1..=100_000 {
            let v = srgb_encode(i as f32 / 100_000.0);
            assert!(v >= prev, "not monotonic at {}", i as f32 / 100_000.0);
            prev = v;
        }
    }

    #[test]
    fn invalid_inputs() {
        assert_eq!(srgb_encode(f32::NAN), 0.0);
        assert_eq!(srgb_encode(-1.0), 0.0);
        assert_eq!(srgb_encode(f32::NEG_INFINITY), 0.0);
        assert_eq!(srgb_encode(f32::INFINITY), f32::INFINITY);
    }

    #[test]
    fn quantisation_rounds_to_nearest() {
        assert_eq!([0.0, 0.5 / 255.0 - 1e-6, 0.5 / 255.0 + 1e-6, 0.5, 1.0].map(quantize_u8), [0, 0, 1, 128, 255]);
        assert_eq!([f32::NAN, -1.0, 2.0, f32::INFINITY].map(quantize_u8), [0, 0, 255, 255]);
    }
}
