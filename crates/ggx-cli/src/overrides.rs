//! Command-line overrides of the scene's settings. The renderer reads spp, time budget,
//! seed and resolution from the scene, so they are applied to the loaded scene.

use anyhow::{Result, bail};
use ggx_scene::{MAX_RESOLUTION, Scene};

use crate::args::{OnOff, RenderArgs};

/// Applies `--spp`, `--time`, `--seed`, `--width`, `--height` (clap has range-checked
/// each already) and `--energy-compensation`.
pub fn apply(scene: &mut Scene, args: &RenderArgs) -> Result<()> {
    if let Some(spp) = args.spp {
        scene.integrator.spp = spp;
    }
    if let Some(time) = args.time {
        scene.integrator.time_budget = (time > 0.0).then_some(time);
    }
    if let Some(seed) = args.seed {
        scene.integrator.seed = seed;
    }
    scene.camera.resolution = resolution(scene.camera.resolution, args.size.width, args.size.height)?;
    if let Some(on) = args.energy_compensation {
        scene.set_energy_compensation(on == OnOff::On);
    }
    Ok(())
}

/// The image size from the scene's and the requested width and height: a lone width or
/// height keeps the scene's aspect ratio (rounded, at least 1 pixel).
pub fn resolution(scene: [u32; 2], width: Option<u32>, height: Option<u32>) -> Result<[u32; 2]> {
    // `a * b / c` rounded; u64 cannot overflow for u32 inputs.
    let scale =
        |a: u32, b: u32, c: u32| ((u64::from(a) * u64::from(b) + u64::from(c) / 2) / u64::from(c).max(1)).max(1);
    let [w, h] = match (width, height) {
        (Some(w), Some(h)) => [u64::from(w), u64::from(h)],
        (Some(w), None) => [u64::from(w), scale(w, scene[1], scene[0])],
        (None, Some(h)) => [scale(h, scene[0], scene[1]), u64::from(h)],
        (None, None) => return Ok(scene),
    };
    let max = u64::from(MAX_RESOLUTION);
    if w > max || h > max {
        bail!(
            "keeping the scene's {}x{} aspect ratio gives {w}x{h}, larger than {MAX_RESOLUTION}; give both --width and --height",
            scene[0],
            scene[1]
        );
    }
    // Both are in [1, MAX_RESOLUTION] here.
    Ok([w as u32, h as u32])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lone_dimension_keeps_the_aspect_ratio() {
        assert_eq!(resolution([256, 128], None, None).unwrap(), [256, 128]);
        assert_eq!(resolution([256, 128], Some(32), Some(24)).unwrap(), [32, 24]);
        assert_eq!(resolution([256, 128], Some(100), None).unwrap(), [100, 50]);
        assert_eq!(resolution([256, 128], None, Some(25)).unwrap(), [50, 25]);
        assert_eq!(resolution([3, 2], Some(5), None).unwrap(), [5, 3]);
        assert_eq!(resolution([16384, 1], Some(1), None).unwrap(), [1, 1]);
    }

    #[test]
    fn too_large_is_an_error() {
        let msg = resolution([1, 16384], Some(2), None).unwrap_err().to_string();
        assert!(msg.contains("2x32768") && msg.contains("give both"), "{msg}");
    }
}
