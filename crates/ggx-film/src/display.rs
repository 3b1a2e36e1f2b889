//! [`OutputOptions`] and [`tonemap_to_srgb8`]: linear radiance to displayable 8-bit sRGB.

use glam::Vec3;

use crate::ToneMap;
use crate::srgb::{quantize_u8, srgb_encode};

/// How linear radiance becomes a display image (PNG). EXR output ignores these.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct OutputOptions {
    /// Exposure in stops: radiance is multiplied by `2^exposure` before tone mapping.
    /// NaN counts as 0.
    pub exposure: f32,
    /// Tone-mapping operator.
    pub tonemap: ToneMap,
}

impl OutputOptions {
    /// `2^exposure` in f64 (1 for a NaN exposure, 0 for `-inf`, `+inf` for `+inf`).
    pub fn exposure_scale(&self) -> f64 {
        if self.exposure.is_nan() { 1.0 } else { f64::from(self.exposure).exp2() }
    }

    /// One linear pixel to 8-bit sRGB: exposure, tone map, [`srgb_encode`], rounding.
    /// NaN and negative channels give 0, `+inf` gives 255 whatever the exposure.
    pub fn encode_pixel(&self, linear: Vec3) -> [u8; 3] {
        self.encode_scaled(linear, self.exposure_scale())
    }

    fn encode_scaled(&self, linear: Vec3, scale: f64) -> [u8; 3] {
        let exposed = Vec3::new(expose(linear.x, scale), expose(linear.y, scale), expose(linear.z, scale));
        let mapped = self.tonemap.apply(exposed);
        [mapped.x, mapped.y, mapped.z].map(|c| quantize_u8(srgb_encode(c)))
    }
}

/// `c * scale` for a non-NaN `scale >= 0`, with NaN, negative and zero `c` giving 0 (never
/// `0 * inf = NaN`) and `+inf` staying `+inf` (never `inf * 0`); an overflowing product is `+inf`.
#[inline]
fn expose(c: f32, scale: f64) -> f32 {
    if !(c > 0.0) {
        return 0.0;
    }
    if c == f32::INFINITY {
        return c;
    }
    (f64::from(c) * scale) as f32
}

/// Tone-maps linear RGB pixels to interleaved 8-bit sRGB (`3 * pixels.len()` bytes, RGB8),
/// applying `options` (exposure, tone map) then [`srgb_encode`]. Accepts any `f32`:
/// NaN and negative channels give 0, `+inf` gives 255 whatever the exposure.
pub fn tonemap_to_srgb8(pixels: &[Vec3], options: &OutputOptions) -> Vec<u8> {
    let scale = options.exposure_scale();
    pixels.iter().flat_map(|&p| options.encode_scaled(p, scale)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn opts(exposure: f32, tonemap: ToneMap) -> OutputOptions {
        OutputOptions { exposure, tonemap }
    }

    #[test]
    fn default_is_zero_stops_aces() {
        assert_eq!(OutputOptions::default(), opts(0.0, ToneMap::Aces));
    }

    #[test]
    fn known_bytes() {
        let px = [Vec3::ZERO, Vec3::new(0.5, 1.0, 0.0031308), Vec3::splat(2.0)];
        // srgb(0.5) * 255 = 187.516, srgb(0.0031308) * 255 = 10.315.
        assert_eq!(tonemap_to_srgb8(&px, &opts(0.0, ToneMap::Clamp)), [0, 0, 0, 188, 255, 10, 255, 255, 255]);
        // One stop up: 0.25 -> 0.5.
        assert_eq!(tonemap_to_srgb8(&[Vec3::splat(0.25)], &opts(1.0, ToneMap::Clamp)), [188; 3]);
        // ACES(1) = 2.54 / 3.16 = 0.80380, srgb -> 231.599 * ...; ACES(0.5) -> 205.866.
        assert_eq!(tonemap_to_srgb8(&[Vec3::new(1.0, 0.5, 0.0)], &opts(0.0, ToneMap::Aces)), [232, 206, 0]);
        // Reinhard on grey 1: 0.5 -> 188.
        assert_eq!(tonemap_to_srgb8(&[Vec3::ONE], &opts(0.0, ToneMap::Reinhard)), [188; 3]);
    }

    #[test]
    fn special_values() {
        let px = [Vec3::new(f32::NAN, f32::INFINITY, -1.0), Vec3::splat(f32::NEG_INFINITY), Vec3::INFINITY];
        for t in ToneMap::ALL {
            for e in [0.0, -200.0, 200.0, f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
                let got = tonemap_to_srgb8(&px, &opts(e, t));
                assert_eq!(got, [0, 255, 0, 0, 0, 0, 255, 255, 255], "{t} exposure {e}");
            }
            // Overflow under exposure: finite * 2^200 -> white, not NaN.
            assert_eq!(tonemap_to_srgb8(&[Vec3::splat(1e30)], &opts(200.0, t)), [255; 3]);
            assert_eq!(tonemap_to_srgb8(&[Vec3::splat(1e30)], &opts(f32::NEG_INFINITY, t)), [0; 3]);
        }
    }
}
