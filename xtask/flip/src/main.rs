//! `xtask-flip TEST.exr REFERENCE.exr MAP.png`: mean FLIP between the two images, tone-mapped
//! as ggx writes PNGs (display-referred sRGB, 67 pixels per degree: the FLIP default), printed
//! on stdout, and the FLIP error map through magma written to `MAP.png`.
//!
//! `cargo xtask diff` builds and runs it. It is a binary of its own because NVIDIA's FLIP is
//! C++ (built by the `cc` crate): xtask itself then builds with only the Rust toolchain and
//! installs a C++ compiler before it builds this (see xtask's `system.rs`).

use std::path::Path;
use std::process::ExitCode;

use ggx_film::{OutputOptions, Vec3, tonemap_to_srgb8};

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [test, reference, map] = args.as_slice() else {
        eprintln!("usage: xtask-flip TEST.exr REFERENCE.exr MAP.png");
        return ExitCode::from(2);
    };
    match run(Path::new(test), Path::new(reference), Path::new(map)) {
        Ok(mean) => {
            println!("{mean:e}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("xtask-flip: {e}");
            ExitCode::FAILURE
        }
    }
}

/// Reads both images, writes the map and returns the mean FLIP.
fn run(test: &Path, reference: &Path, map: &Path) -> Result<f64, String> {
    let (w, h, a) = ggx_film::read_exr(test).map_err(|e| e.to_string())?;
    let (rw, rh, b) = ggx_film::read_exr(reference).map_err(|e| e.to_string())?;
    if (w, h) != (rw, rh) {
        return Err(format!("{} is {w}x{h}, {} is {rw}x{rh}", test.display(), reference.display()));
    }
    let (mean, rgb) = flip(&a, &b, w, h);
    image::save_buffer_with_format(map, &rgb, w, h, image::ColorType::Rgb8, image::ImageFormat::Png)
        .map_err(|e| format!("{}: {e}", map.display()))?;
    Ok(mean)
}

/// Mean FLIP between the tone-mapped images and the error map through magma as 8-bit RGB.
fn flip(test: &[Vec3], reference: &[Vec3], width: u32, height: u32) -> (f64, Vec<u8>) {
    let options = OutputOptions::default();
    let to_flip =
        |pixels: &[Vec3]| nv_flip::FlipImageRgb8::with_data(width, height, &tonemap_to_srgb8(pixels, &options));
    let error = nv_flip::flip(to_flip(reference), to_flip(test), nv_flip::DEFAULT_PIXELS_PER_DEGREE);
    let mean = f64::from(nv_flip::FlipPool::from_image(&error).mean());
    (mean, error.apply_color_lut(&nv_flip::magma_lut()).to_vec())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flip_is_zero_for_equal_images_and_grows_with_the_difference() {
        let (w, h) = (24, 16);
        let a: Vec<Vec3> = (0..w * h).map(|i| Vec3::splat((i % 7) as f32 / 7.0)).collect();
        let b: Vec<Vec3> = a.iter().map(|p| *p * 1.05).collect();
        let c: Vec<Vec3> = a.iter().map(|p| Vec3::ONE - *p).collect();
        let (same, map) = flip(&a, &a, w, h);
        assert_eq!((same, map.len()), (0.0, (w * h * 3) as usize));
        let (small, _) = flip(&b, &a, w, h);
        let (large, _) = flip(&c, &a, w, h);
        assert!(0.0 < small && small < large, "{small} {large}");
    }

    #[test]
    fn files_round_trip_and_sizes_must_match() {
        let dir = std::env::temp_dir().join(format!("xtask-flip-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let write = |name: &str, w: u32, v: f32| {
            let path = dir.join(name);
            let pixels = vec![Vec3::splat(v); (w * 4) as usize];
            ggx_film::write_image(&path, w, 4, &pixels, &OutputOptions::default()).unwrap();
            path
        };
        let (a, b, c) = (write("a.exr", 8, 0.5), write("b.exr", 8, 0.25), write("c.exr", 6, 0.5));
        let mean = run(&a, &b, &dir.join("map.png")).unwrap();
        assert!(mean > 0.0);
        assert!(image::open(dir.join("map.png")).is_ok());
        assert!(run(&a, &c, &dir.join("x.png")).unwrap_err().contains("is 8x4"));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
