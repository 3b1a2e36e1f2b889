//! The J. Schutte (2018) comparison: the Stanford bunny (`scenes/bunny.toml`, a gold conductor
//! of alpha 0.05 lit only by an environment map) rendered with cosine, NDF and VNDF sampling at
//! equal spp, the scene's other settings kept (MIS, sobol, CPU, specialized kernel). Written as
//! one PNG with the three images side by side (tone-mapped like `ggx render`'s PNGs) plus one
//! EXR each, with their relMSE and firefly counts against a baseline reference.

use super::configs::{BASELINE, Config, bsdf_name};
use super::files::write_atomic;
use super::ladder::LADDER_SEED;
use super::{fireflies, reference};
use crate::render::{self, Overrides};
use ggx_film::{OutputOptions, tonemap_to_srgb8, write_image};
use ggx_scene::BsdfStrategy;
use image::ImageEncoder;
use std::path::{Path, PathBuf};

/// The scene of the comparison.
pub const SCENE: &str = "bunny";
/// The samplers compared, left to right.
pub const SAMPLERS: [BsdfStrategy; 3] = [BsdfStrategy::Cosine, BsdfStrategy::Ndf, BsdfStrategy::Vndf];

/// One sampler's image.
#[derive(Clone, Debug, PartialEq)]
pub struct Entry {
    /// The BSDF sampler.
    pub bsdf: BsdfStrategy,
    /// relMSE against the reference.
    pub rel_mse: f64,
    /// RMSE against the reference.
    pub rmse: f64,
    /// Pixels over the firefly threshold (see [`fireflies`]).
    pub fireflies: usize,
    /// Render time in seconds.
    pub seconds: f64,
    /// The EXR written.
    pub exr: PathBuf,
}

/// The comparison's results.
#[derive(Clone, Debug, PartialEq)]
pub struct Comparison {
    /// Image width of each of the three images.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Samples per pixel of each image.
    pub spp: u32,
    /// Samples per pixel of the reference.
    pub ref_spp: u32,
    /// The reference EXR (cache).
    pub reference: PathBuf,
    /// The side-by-side PNG.
    pub png: PathBuf,
    /// Cosine, NDF, VNDF in that order.
    pub entries: Vec<Entry>,
}

/// Renders the comparison at `width` and `spp` into `out_dir`, against a `ref_spp` reference
/// cached in `cache_dir`.
pub fn run(width: u32, spp: u32, ref_spp: u32, out_dir: &Path, cache_dir: &Path) -> Result<Comparison, String> {
    let path = render::scene_paths(&[SCENE.to_string()])?.into_iter().next().ok_or("no bunny scene")?;
    let base = render::load(&path, Overrides { width, spp })?;
    let [w, h] = base.camera.resolution;
    eprintln!("\nbunny comparison: {w}x{h}, {spp} spp, cosine vs NDF vs VNDF");
    let reference = reference::load_or_render(&path, &base, ref_spp, cache_dir)?;
    let mut entries = Vec::new();
    let mut tonemapped = Vec::new();
    for bsdf in SAMPLERS {
        let config = Config { bsdf, ..BASELINE };
        let mut scene = base.clone();
        config.apply(&mut scene);
        scene.integrator.seed = LADDER_SEED;
        scene.integrator.spp = spp;
        let result = render::render(&scene, config.backend, config.specialize, None)?;
        let pixels = result.film.mean();
        let metrics = ggx_film::compare(&pixels, &reference.pixels, 1.0).map_err(|e| e.to_string())?;
        let exr = out_dir.join(format!("{SCENE}-{}-{spp}spp.exr", bsdf_name(bsdf)));
        write_image(&exr, w, h, &pixels, &OutputOptions::default()).map_err(|e| e.to_string())?;
        let entry = Entry {
            bsdf,
            rel_mse: metrics.rel_mse,
            rmse: metrics.rmse,
            fireflies: fireflies::count(&pixels, &reference.pixels)?,
            seconds: result.elapsed.as_secs_f64(),
            exr,
        };
        eprintln!(
            "    {:<8} relMSE {:.3e}  {} fireflies  {:.3} s",
            bsdf_name(bsdf),
            entry.rel_mse,
            entry.fireflies,
            entry.seconds
        );
        entries.push(entry);
        tonemapped.push(tonemap_to_srgb8(&pixels, &OutputOptions::default()));
    }
    let png = out_dir.join(format!("{SCENE}-cosine-ndf-vndf-{spp}spp.png"));
    let rgb = side_by_side(&tonemapped, w, h)?;
    write_png(&png, &rgb, w * SAMPLERS.len() as u32, h)?;
    Ok(Comparison { width: w, height: h, spp, ref_spp, reference: reference.path, png, entries })
}

/// Concatenates RGB8 images of `width x height` each horizontally, left to right.
pub fn side_by_side(images: &[Vec<u8>], width: u32, height: u32) -> Result<Vec<u8>, String> {
    let row = 3 * width as usize;
    if let Some(bad) = images.iter().find(|i| i.len() != row * height as usize) {
        return Err(format!("side by side: an image has {} bytes, expected {}", bad.len(), row * height as usize));
    }
    let mut out = Vec::with_capacity(images.len() * row * height as usize);
    for y in 0..height as usize {
        for image in images {
            out.extend_from_slice(&image[y * row..(y + 1) * row]);
        }
    }
    Ok(out)
}

/// Encodes RGB8 `rgb` as a PNG and writes it atomically.
fn write_png(path: &Path, rgb: &[u8], width: u32, height: u32) -> Result<(), String> {
    let mut bytes = Vec::new();
    image::codecs::png::PngEncoder::new(&mut bytes)
        .write_image(rgb, width, height, image::ExtendedColorType::Rgb8)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    write_atomic(path, &bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn concatenates_rows() {
        // Two 2x2 images: a = pixels 1..4, b = pixels 5..8 (one byte value per pixel).
        let img = |start: u8| (start..start + 4).flat_map(|v| [v; 3]).collect::<Vec<u8>>();
        let out = side_by_side(&[img(1), img(5)], 2, 2).unwrap();
        let pixels: Vec<u8> = out.chunks(3).map(|p| p[0]).collect();
        assert_eq!(pixels, [1, 2, 5, 6, 3, 4, 7, 8]);
        assert!(side_by_side(&[img(1), vec![0; 3]], 2, 2).is_err());
    }

    #[test]
    fn png_round_trip() {
        let path = std::env::temp_dir().join(format!("ggx-bench-png-{}.png", std::process::id()));
        write_png(&path, &[255, 0, 0, 0, 255, 0], 2, 1).unwrap();
        let back = image::open(&path).unwrap().to_rgb8();
        std::fs::remove_file(&path).unwrap();
        assert_eq!((back.width(), back.height()), (2, 1));
        assert_eq!(back.as_raw(), &[255, 0, 0, 0, 255, 0]);
    }
}
