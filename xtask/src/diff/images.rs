//! The pictures of a diff: the false-colour relative-error map (magma, from `colorous`) and
//! atomic PNG output. FLIP runs in its own binary ([`super::flip_tool`]).

use ggx_film::Vec3;
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
pub fn false_colour(a: &[Vec3], reference: &[Vec3]) -> Vec<u8> {
    a.iter()
        .zip(reference)
        .flat_map(|(&p, &q)| {
            let c = colorous::MAGMA.eval_continuous(f64::from(log_scale(pixel_rel_error(p, q))));
            [c.r, c.g, c.b]
        })
        .collect()
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
    fn false_colour_is_black_where_equal() {
        let a = vec![Vec3::ONE; 4];
        let rgb = false_colour(&a, &a);
        assert_eq!(rgb.len(), 12);
        let black = colorous::MAGMA.eval_continuous(0.0);
        assert_eq!(&rgb[..3], &[black.r, black.g, black.b]);
        assert!(rgb[..3].iter().all(|&c| c < 8), "magma starts near black: {:?}", &rgb[..3]);
        let mut b = a.clone();
        b[3] = Vec3::splat(2.0);
        let hot = false_colour(&b, &a);
        assert_ne!(&hot[9..], &rgb[..3]);
        assert!(hot[9] > 200, "an error of 1 is at the bright end: {:?}", &hot[9..]);
    }
}
