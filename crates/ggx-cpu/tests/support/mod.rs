//! What the renderer's integration tests share: a scene from TOML text, a render with the
//! default options, the mean radiance of an image.

#![allow(dead_code)] // each test binary uses its own subset

pub mod rays;

use ggx_cpu::{AccelKind, RenderControl, RenderOptions, RenderResult, Renderer};
use ggx_scene::{Scene, parse_scene};
use glam::Vec3;
use std::path::Path;

/// The scene of `text` (panics with the located error).
pub fn scene_from(text: &str) -> Scene {
    parse_scene(text, "test.toml", Path::new(".")).unwrap_or_else(|e| panic!("{e}"))
}

/// `scene` rendered with the default BVH and options.
pub fn render(scene: &Scene) -> RenderResult {
    Renderer::new(scene, AccelKind::default()).render(&RenderOptions::default(), &RenderControl::default()).unwrap()
}

/// Mean of `pixels`.
pub fn mean(pixels: &[Vec3]) -> Vec3 {
    pixels.iter().copied().sum::<Vec3>() / pixels.len() as f32
}

/// Mean radiance of `scene`'s rendered image.
pub fn render_mean(scene: &Scene) -> Vec3 {
    mean(&render(scene).film.mean())
}
