//! The peer run's figures: relMSE against time and against spp per scene (bench's plotters
//! SVG, one line per configuration) and the two references side by side as a PNG.

use std::path::{Path, PathBuf};

use ggx_film::{OutputOptions, Vec3};
use image::ImageEncoder as _;

use super::metrics::Rung;
use super::series::{Renderer, Series};
use crate::bench::files::write_atomic;
use crate::bench::plots::{Line, Style};

/// How a renderer's lines are drawn: ggx solid, Mitsuba's LLVM variant dashed with rings,
/// its scalar variant dashed with crosses.
fn style(r: Renderer) -> Style {
    match r {
        Renderer::GgxSobol | Renderer::GgxIndependent => Style::Solid,
        Renderer::MitsubaLlvm => Style::DashedRing,
        Renderer::MitsubaScalar => Style::DashedCross,
    }
}

/// Writes `<scene>-relmse-vs-time.svg` and `<scene>-relmse-vs-spp.svg` into `dir`.
pub fn plots(dir: &Path, scene: &str, series: &[Series]) -> Result<Vec<PathBuf>, String> {
    let lines = |x: &dyn Fn(&Rung) -> f64| -> Vec<Line> {
        series
            .iter()
            .map(|s| Line {
                name: s.config.label(),
                style: style(s.config.renderer),
                points: s.rungs.iter().map(|r| (x(r), r.rel_mse)).collect(),
            })
            .collect()
    };
    let titles = [
        format!("{scene}: relMSE vs render time, ggx and Mitsuba 3"),
        format!("{scene}: relMSE vs spp, ggx and Mitsuba 3"),
    ];
    let (by_time, by_spp) = (lines(&|r| r.steady_seconds()), lines(&|r| f64::from(r.spp)));
    crate::bench::plots::write_pair(dir, scene, &titles, "render time without JIT (s)", &by_time, &by_spp)
}

/// The images side by side, left to right, with a 4-pixel black gap, tone-mapped as `ggx
/// render` writes PNGs (ACES, sRGB): RGB8 bytes of the `(2 width + 4) x height` strip.
pub fn side_by_side(left: &[Vec3], right: &[Vec3], width: usize, height: usize) -> Vec<u8> {
    let gap = 4;
    let total = 2 * width + gap;
    let mut strip = vec![Vec3::ZERO; total * height];
    for y in 0..height {
        strip[y * total..y * total + width].copy_from_slice(&left[y * width..(y + 1) * width]);
        strip[y * total + width + gap..(y + 1) * total].copy_from_slice(&right[y * width..(y + 1) * width]);
    }
    ggx_film::tonemap_to_srgb8(&strip, &OutputOptions::default())
}

/// Writes [`side_by_side`] as `<dir>/<scene>-references.png`.
pub fn references_png(
    dir: &Path,
    scene: &str,
    left: &[Vec3],
    right: &[Vec3],
    width: u32,
    height: u32,
) -> Result<PathBuf, String> {
    let (w, h) = (width as usize, height as usize);
    if left.len() != w * h || right.len() != w * h {
        return Err(format!(
            "{scene}: reference images of {} and {} pixels for {width}x{height}",
            left.len(),
            right.len()
        ));
    }
    let bytes = side_by_side(left, right, w, h);
    let mut png = Vec::new();
    image::codecs::png::PngEncoder::new(&mut png)
        .write_image(&bytes, 2 * width + 4, height, image::ExtendedColorType::Rgb8)
        .map_err(|e| format!("{scene}: PNG: {e}"))?;
    let path = dir.join(format!("{scene}-references.png"));
    write_atomic(&path, &png)?;
    Ok(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strip_places_both_images() {
        let left = vec![Vec3::splat(0.5); 6];
        let right = vec![Vec3::splat(2.0); 6];
        let bytes = side_by_side(&left, &right, 3, 2);
        assert_eq!(bytes.len(), 10 * 2 * 3);
        let px = |x: usize, y: usize| &bytes[(y * 10 + x) * 3..(y * 10 + x) * 3 + 3];
        assert_eq!(px(3, 0), [0, 0, 0], "the gap is black");
        assert!(px(0, 1)[0] > 0 && px(9, 1)[0] > px(0, 1)[0], "right is brighter");
    }
}
