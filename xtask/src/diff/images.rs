//! The pictures of a diff: the false-colour relative-error map, FLIP on the tone-mapped images
//! (NVIDIA's reference implementation through `nv-flip`) and atomic PNG output.

use ggx_film::{OutputOptions, Vec3, tonemap_to_srgb8};
use std::path::Path;

/// Decades of relative error the false-colour map spans: `1e-7` (black) to `1` (white-yellow).
const DECADES: f64 = 7.0;

/// Largest per-channel relative error `|a - b| / sqrt(b^2 + REL_EPSILON)` of one pixel, the
/// quantity `ggx_film::compare` counts against the tolerance (the root of
/// [`ggx_film::channel_rel_sq`]): `+inf` for a channel that is non-finite on one side only.
pub fn pixel_rel_error(a: Vec3, reference: Vec3) -> f64 {
    a.to_array()
        .into_iter()
        .zip(reference.to_array())
        .map(|(x, y)| ggx_film::channel_rel_sq(x.into(), y.into()).sqrt())
        .fold(0.0, f64::max)
}

/// Maps relative errors to `[0, 1]` on a log scale: `1e-7` and below to 0, `1` and above to 1.
pub fn log_scale(error: f64) -> f32 {
    if !(error > 0.0) {
        return 0.0;
    }
    ((error.log10() + DECADES) / DECADES).clamp(0.0, 1.0) as f32
}

/// The false-colour difference image: each pixel's largest relative channel error on a log
/// scale through the magma colour map, as 8-bit RGB.
pub fn false_colour(a: &[Vec3], reference: &[Vec3], width: u32, height: u32) -> Vec<u8> {
    let values: Vec<f32> = a.iter().zip(reference).map(|(&p, &q)| log_scale(pixel_rel_error(p, q))).collect();
    let map = nv_flip::FlipImageFloat::with_data(width, height, &values);
    map.apply_color_lut(&nv_flip::magma_lut()).to_vec()
}

/// Mean FLIP between the tone-mapped images (display-referred sRGB, 67 pixels per degree, the
/// FLIP default) and the FLIP error map through magma as 8-bit RGB.
pub fn flip(test: &[Vec3], reference: &[Vec3], width: u32, height: u32) -> (f64, Vec<u8>) {
    let options = OutputOptions::default();
    let to_flip =
        |pixels: &[Vec3]| nv_flip::FlipImageRgb8::with_data(width, height, &tonemap_to_srgb8(pixels, &options));
    let error = nv_flip::flip(to_flip(reference), to_flip(test), nv_flip::DEFAULT_PIXELS_PER_DEGREE);
    let mean = f64::from(nv_flip::FlipPool::from_image(&error).mean());
    (mean, error.apply_color_lut(&nv_flip::magma_lut()).to_vec())
}

/// Writes 8-bit RGB as PNG through a temporary file in the same directory and a rename.
pub fn write_png(path: &Path, width: u32, height: u32, rgb: &[u8]) -> Result<(), String> {
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let tmp = path.with_file_name(format!(".{name}.tmp-{}", std::process::id()));
    let result =
        image::save_buffer_with_format(&tmp, rgb, width, height, image::ColorType::Rgb8, image::ImageFormat::Png)
            .map_err(|e| format!("{}: {e}", path.display()))
            .and_then(|()| std::fs::rename(&tmp, path).map_err(|e| format!("{}: {e}", path.display())));
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

#[cfg(test)]
mod tests {
    use super::*;
    use ggx_film::REL_EPSILON;

    #[test]
    fn relative_error_matches_the_metric_and_handles_non_finite_pixels() {
        let e = pixel_rel_error(Vec3::new(1.1, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0));
        assert!((e - 0.1 / (1.0f64 + REL_EPSILON).sqrt()).abs() < 1e-6, "{e}");
        assert_eq!(pixel_rel_error(Vec3::splat(f32::NAN), Vec3::splat(f32::NAN)), 0.0);
        assert_eq!(pixel_rel_error(Vec3::splat(f32::INFINITY), Vec3::splat(f32::INFINITY)), 0.0);
        assert_eq!(pixel_rel_error(Vec3::splat(f32::NAN), Vec3::ONE), f64::INFINITY);
        assert_eq!(log_scale(f64::INFINITY), 1.0);
    }

    #[test]
    fn log_scale_spans_seven_decades() {
        assert_eq!(log_scale(0.0), 0.0);
        assert_eq!(log_scale(f64::NAN), 0.0);
        assert_eq!(log_scale(1e-9), 0.0);
        assert!((log_scale(1e-7 * 10f64.powf(3.5)) - 0.5).abs() < 1e-6);
        assert_eq!(log_scale(5.0), 1.0);
    }

    #[test]
    fn flip_is_zero_for_equal_images_and_grows_with_the_difference() {
        let (w, h) = (16, 16);
        let a: Vec<Vec3> = (0..w * h).map(|i| Vec3::splat((i % 7) as f32 / 7.0)).collect();
        let (same, map) = flip(&a, &a, w, h);
        assert_eq!(same, 0.0);
        assert_eq!(map.len(), (3 * w * h) as usize);
        let b: Vec<Vec3> = a.iter().map(|&p| p * 1.5).collect();
        let c: Vec<Vec3> = a.iter().map(|&p| p * 3.0).collect();
        let (small, _) = flip(&b, &a, w, h);
        let (large, _) = flip(&c, &a, w, h);
        assert!(0.0 < small && small < large && large <= 1.0, "{small} {large}");
    }

    #[test]
    fn false_colour_is_black_where_equal() {
        let a = vec![Vec3::ONE; 4];
        let rgb = false_colour(&a, &a, 2, 2);
        assert_eq!(rgb.len(), 12);
        let lut = nv_flip::magma_lut().to_vec();
        assert_eq!(&rgb[..3], &lut[..3]);
        let mut b = a.clone();
        b[3] = Vec3::splat(2.0);
        assert_ne!(&false_colour(&b, &a, 2, 2)[9..], &lut[..3]);
    }
}
