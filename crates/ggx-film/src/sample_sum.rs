//! [`SampleSum`]: one pixel's radiance samples summed in 128-bit fixed point, so that sums
//! of any split of the samples add up to the same bits (integer addition is associative;
//! floating-point addition is not).

use glam::Vec3;

/// Fractional bits of the fixed-point sums: a resolution of `2^-56` (1.4e-17).
pub const FRACTION_BITS: u32 = 56;

/// Largest magnitude of one sample, `2^39` (5.5e11); larger values are clamped to it. With at
/// most `u32::MAX` samples per pixel, `2^39 * 2^32 * 2^56 < 2^127`: a sum never overflows.
pub const MAX_SAMPLE: f32 = 549_755_813_888.0;

/// One pixel's samples: per-channel sums in fixed point (`value * 2^56`, rounded to the
/// nearest integer), the number of samples, and how many of them were not finite.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SampleSum {
    /// Fixed-point sums of the red, green and blue samples.
    pub rgb: [i128; 3],
    /// Samples added (finite or not).
    pub samples: u32,
    /// Samples that had a NaN or infinite channel (left out of `rgb`).
    pub invalid: u32,
}

impl SampleSum {
    /// Adds one radiance sample.
    #[inline(always)]
    pub fn add(&mut self, sample: Vec3) {
        self.add_summed(sample, 1);
    }

    /// Adds `n` samples given by their (floating-point) sum, as the GPU returns them: each
    /// channel is clamped to `n * MAX_SAMPLE`; a non-finite sum counts as `n` invalid samples.
    #[inline(always)]
    pub fn add_summed(&mut self, sum: Vec3, n: u32) {
        let channels = sum.to_array();
        if channels.iter().all(|c| c.is_finite()) {
            for (acc, c) in self.rgb.iter_mut().zip(channels) {
                *acc = acc.wrapping_add(to_fixed(c, n));
            }
        } else {
            self.invalid = self.invalid.saturating_add(n);
        }
        self.samples = self.samples.saturating_add(n);
    }

    /// Adds another pixel's samples; `None` (and `self` unchanged) when the count would
    /// exceed `u32::MAX`.
    pub fn merge(&mut self, other: &SampleSum) -> Option<()> {
        let samples = self.samples.checked_add(other.samples)?;
        for (acc, c) in self.rgb.iter_mut().zip(other.rgb) {
            *acc = acc.wrapping_add(c);
        }
        self.samples = samples;
        self.invalid = self.invalid.saturating_add(other.invalid);
        Some(())
    }

    /// The mean radiance `sum * 2^-56 / samples` in `f64`, rounded once to `f32`: zero without
    /// samples, NaN when any sample was not finite (the film does not hide renderer bugs).
    pub fn mean(&self) -> Vec3 {
        if self.invalid > 0 {
            return Vec3::NAN;
        }
        if self.samples == 0 {
            return Vec3::ZERO;
        }
        let scale = f64::from(self.samples).recip() * (-f64::from(FRACTION_BITS)).exp2();
        let [r, g, b] = self.rgb.map(|c| (c as f64 * scale) as f32);
        Vec3::new(r, g, b)
    }
}

/// `trunc(clamp(v, ±n MAX_SAMPLE) * 2^56)` for a finite `v`: the product is exact in `f64` (a
/// 24-bit mantissa scaled by a power of two) and at most `2^127 / 2^32 * n` in magnitude.
/// Truncation, not rounding: `round` is a library call without SSE4.1, and either is exact
/// to 2^-56. Magnitudes below 2^63 (radiance below 128) convert through one `i64`
/// instruction; the `i128` conversion gives the same value for them.
#[inline]
fn to_fixed(v: f32, n: u32) -> i128 {
    const SCALE: f64 = (1u64 << FRACTION_BITS) as f64;
    const I64_RANGE: f64 = 9_223_372_036_854_775_808.0;
    let limit = f64::from(MAX_SAMPLE) * f64::from(n);
    let scaled = f64::from(v).clamp(-limit, limit) * SCALE;
    if scaled.abs() < I64_RANGE { i128::from(scaled as i64) } else { scaled as i128 }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sums_of_any_split_are_the_same_bits() {
        let samples: Vec<Vec3> =
            (0..200).map(|i| Vec3::new(1e-9 * i as f32, 1e6 / (i + 1) as f32, (i as f32).sin())).collect();
        let mut whole = SampleSum::default();
        samples.iter().for_each(|&s| whole.add(s));
        for split in [1, 7, 100, 199] {
            let (mut a, mut b) = (SampleSum::default(), SampleSum::default());
            samples[..split].iter().for_each(|&s| a.add(s));
            samples[split..].iter().rev().for_each(|&s| b.add(s));
            b.merge(&a).unwrap();
            assert_eq!(b, whole, "split at {split}");
        }
        assert_eq!(whole.samples, 200);
    }

    #[test]
    fn the_fast_conversion_is_the_wide_one() {
        for v in [0.0f32, 1e-30, -1e-17, 0.1, 1.0, 127.99, -128.0, 128.0, 4096.5, -3e9, 5.4e11, f32::MAX] {
            let scaled = f64::from(v).clamp(-f64::from(MAX_SAMPLE), f64::from(MAX_SAMPLE)) * 2f64.powi(56);
            assert_eq!(to_fixed(v, 1), scaled as i128, "{v}");
        }
    }

    #[test]
    fn the_mean_keeps_f32_precision() {
        let mut s = SampleSum::default();
        for v in [0.1f32, 0.2, 0.3, 1e-12] {
            s.add(Vec3::splat(v));
        }
        let exact = (0.1f32 as f64 + 0.2f32 as f64 + 0.3f32 as f64 + 1e-12f32 as f64) / 4.0;
        assert_eq!(s.mean(), Vec3::splat(exact as f32));
        assert_eq!(SampleSum::default().mean(), Vec3::ZERO);
    }

    #[test]
    fn extremes_clamp_and_bad_samples_are_counted() {
        let mut s = SampleSum::default();
        s.add(Vec3::new(f32::MAX, -f32::MAX, f32::MIN_POSITIVE / 4.0));
        assert_eq!(s.mean(), Vec3::new(MAX_SAMPLE, -MAX_SAMPLE, 0.0));
        s.add(Vec3::new(1.0, f32::NAN, 0.0));
        s.add(Vec3::INFINITY);
        assert_eq!((s.samples, s.invalid), (3, 2));
        assert!(s.mean().is_nan());
        // u32::MAX samples at the clamp do not overflow.
        let mut big = SampleSum::default();
        big.add_summed(Vec3::splat(f32::MAX), u32::MAX);
        big.add(Vec3::ZERO);
        assert_eq!(big.samples, u32::MAX);
        assert!(big.rgb[0] > 0 && big.mean().x > 0.0);
        let full = SampleSum { samples: u32::MAX, ..Default::default() };
        assert_eq!(full.clone().merge(&SampleSum { samples: 1, ..Default::default() }), None);
    }
}
