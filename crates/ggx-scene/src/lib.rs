//! Scene files for the ggx path tracers.
//!
//! A scene is a TOML file (format: the crate README) that [`load_scene`] turns into a
//! validated [`Scene`]: a camera, integrator settings, materials, every shape tessellated
//! into world-space triangles ([`TriangleMesh`]), area lights with a power distribution for
//! next-event estimation ([`AreaLights`]) and an optional importance-sampled
//! [`Environment`]. Flat tables ([`Triangle`], [`ShadingNormals`], [`Emitter`],
//! [`GpuMaterial`], [`Distribution2D`]) are `bytemuck::Pod` or plain `Vec<f32>` so the GPU
//! renderer can upload them as they are.
//!
//! Errors never panic: every problem with the file becomes a [`SceneError`] that names the
//! file, line, column and field, e.g.
//! `scenes/x.toml:12:9: materials.gold.roughness: must be in [0, 1], got 1.5`.
#![deny(missing_docs)]

mod camera;
mod check;
mod distribution;
mod environment;
mod error;
mod features;
mod geometry;
mod integrator;
mod lights;
mod material;
mod material_build;
mod mesh;
mod raw;
mod scene;
mod scene_build;
mod shape_build;
mod stats;
mod toml_error;

use std::path::Path;

pub use camera::{Camera, MAX_RESOLUTION};
pub use distribution::{Distribution1D, Distribution2D};
pub use environment::{
    EnvMap, Environment, MAX_MAP_SIZE, MAX_PROCEDURAL_WIDTH, direction_to_uv, load_image, sky, studio, uniform_sphere,
    uv_to_direction,
};
pub use error::{ErrorKind, SceneError};
pub use features::SceneFeatures;
pub use geometry::{Geometry, cube, disk, icosphere, parse_obj, rectangle};
pub use integrator::{BsdfStrategy, IntegratorSettings, LightStrategy, MAX_DEPTH, MAX_SPP, SamplerKind};
pub use lights::{AreaLight, AreaLights, Emitter};
pub use material::{ConductorFresnel, ConductorPreset, GpuMaterial, Material, luminance};
pub use mesh::{NO_INDEX, ShadingNormals, Triangle, TriangleMesh};
pub use scene::Scene;
pub use shape_build::{MAX_SEGMENTS, MAX_SUBDIVISIONS};
pub use stats::SceneStats;

use error::Source;

/// Reads and validates the scene file at `path`; meshes and maps resolve relative to its
/// directory.
pub fn load_scene(path: &Path) -> Result<Scene, SceneError> {
    let name = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|source| SceneError::Read { path: name.clone(), source })?;
    parse_scene(&text, &name, path.parent().unwrap_or(Path::new(".")))
}

/// Parses and validates scene `text`. `file_name` is only used in error messages and
/// [`Scene::source`]; relative mesh and map paths resolve against `base_dir`.
pub fn parse_scene(text: &str, file_name: &str, base_dir: &Path) -> Result<Scene, SceneError> {
    let src = Source { text, file: file_name };
    let raw: raw::RawScene = toml::from_str(text).map_err(|e| toml_error::convert(src, &e))?;
    scene_build::build(src, &raw, base_dir)
}
