//! Scene files for the ggx path tracers.
//!
//! A scene is a TOML file (format: the crate README) that [`load_scene`] turns into a
//! validated [`Scene`]: a camera (animated by an optional [`CameraPath`]), integrator settings, materials, every shape tessellated
//! into world-space triangles ([`TriangleMesh`]), area lights with a power distribution for
//! next-event estimation ([`AreaLights`]) and an optional importance-sampled
//! [`Environment`]. Flat tables ([`Triangle`], [`ShadingNormals`], [`Emitter`],
//! [`Distribution2D`]) are `bytemuck::Pod` or plain `Vec<f32>` so the GPU
//! renderer can upload them as they are.
//!
//! Errors never panic: every problem with the file becomes a [`SceneError`] that names the
//! file, line, column and field, e.g.
//! `scenes/x.toml:12:9: materials.gold.roughness: must be in [0, 1], got 1.5`.
#![deny(missing_docs)]

mod camera;
mod camera_build;
mod camera_path;
mod check;
mod distribution;
mod environment;
mod error;
mod features;
mod geometry;
mod gltf_asset;
mod gltf_scene;
mod integrator;
mod lights;
mod limits;
mod material;
mod material_build;
mod memory;
mod mesh;
mod punctual;
mod radiance;
mod raw;
mod sample_inputs;
mod scene;
mod scene_build;
mod shape_build;
mod shorten;
mod stats;
mod texture;
mod texture_load;
mod toml_error;

use std::path::Path;

pub use camera::{Camera, CameraPose, MAX_RESOLUTION, RayGenerator};
pub use camera_path::{CameraKey, CameraPath, DEFAULT_FPS, FrameError, Interpolation, MAX_FPS, MAX_FRAMES};
pub use distribution::{Distribution1D, Distribution2D, LOOKUP_BATCH};
pub use environment::{
    EnvMap, Environment, MAX_MAP_SIZE, MAX_PROCEDURAL_WIDTH, direction_to_uv, load_image, sky, studio, uniform_sphere,
    uv_to_direction,
};
pub use error::{ErrorKind, SceneError};
pub use features::SceneFeatures;
pub use geometry::{Geometry, cube, disk, icosphere, parse_obj, parse_obj_with_limits, rectangle};
pub use gltf_asset::{GltfCamera, SUPPORTED_EXTENSIONS};
pub use gltf_scene::{GLTF_DEFAULT_WIDTH, GltfEnvironment, GltfOptions, is_gltf_path, load_gltf_scene};
pub use integrator::{BsdfStrategy, IntegratorSettings, LightStrategy, MAX_DEPTH, MAX_SEED, MAX_SPP, SamplerKind};
pub use lights::{AreaLight, AreaLights, Emitter};
pub use limits::{Limit, LimitError, Limits, ReadError, format_bytes, read_regular_file, read_regular_file_or};
pub use material::{ConductorFresnel, LUMINANCE_WEIGHTS, Material, MaterialPreset, MetalRough, luminance};
pub use memory::{
    BYTES_PER_TEXEL, BYTES_PER_TRIANGLE, FILM_BYTES_PER_PIXEL, MemoryEstimate, estimate_memory, film_bytes, map_bytes,
    triangle_bytes,
};
pub use mesh::{NO_INDEX, ShadingNormals, Triangle, TriangleMesh, TriangleTangents, TriangleUvs};
pub use punctual::{PUNCTUAL_DIRECTIONAL, PUNCTUAL_POINT, PUNCTUAL_SPOT, PunctualLight};
pub use radiance::MAX_RADIANCE;
pub use sample_inputs::SampleInputSink;
pub use scene::Scene;
pub use shape_build::{MAX_SEGMENTS, MAX_SUBDIVISIONS};
pub use stats::SceneStats;
pub use texture::{
    REF_CHANNEL_SHIFT, REF_SRGB, SRGB_LUT_WORDS, TEXTURE_FLOAT, TEXTURE_NEAREST, TEXTURE_WRAP_S_SHIFT,
    TEXTURE_WRAP_T_SHIFT, Texels, TextureInfo, TextureRef, TextureSet, Wrap, srgb_to_linear, wrap_coord,
};

use error::Source;

/// Reads and validates the scene file at `path` within [`Limits::default`]; meshes and maps
/// resolve relative to its directory.
pub fn load_scene(path: &Path) -> Result<Scene, SceneError> {
    load_scene_with(path, &Limits::default())
}

/// Reads and validates the scene file at `path` within `limits`: only a regular file of at
/// most [`Limits::max_scene_bytes`] is read (a directory, FIFO or device such as `/dev/zero`
/// is refused before it is opened), it must be UTF-8, and its meshes, maps, triangles and
/// memory stay within `limits`. Meshes and maps resolve relative to its directory.
///
/// A `.gltf` or `.glb` file is loaded as a scene of its own ([`load_gltf_scene`] with the
/// default [`GltfOptions`]).
pub fn load_scene_with(path: &Path, limits: &Limits) -> Result<Scene, SceneError> {
    if is_gltf_path(path) {
        return load_gltf_scene(path, limits, &GltfOptions::default());
    }
    let name = path.display().to_string();
    let bytes = read_regular_file_or(path, "scene file", Limit::SceneBytes, limits).map_err(|e| {
        let kind = if matches!(e, ReadError::Limit(_)) { ErrorKind::Limit } else { ErrorKind::Io };
        SceneError::Unreadable { path: name.clone(), kind, message: e.to_string() }
    })?;
    let text = String::from_utf8(bytes).map_err(|e| {
        let valid = e.utf8_error().valid_up_to();
        let (line, column) = error::line_column(&String::from_utf8_lossy(&e.as_bytes()[..valid]), valid);
        let message = format!("not UTF-8 text (invalid byte at line {line}, column {column})");
        SceneError::Read { path: name.clone(), source: std::io::Error::new(std::io::ErrorKind::InvalidData, message) }
    })?;
    parse_scene_with(&text, &name, path.parent().unwrap_or(Path::new(".")), limits)
}

/// Parses and validates scene `text` within [`Limits::default`]. `file_name` is only used in
/// error messages and [`Scene::source`]; relative mesh and map paths resolve against
/// `base_dir`.
pub fn parse_scene(text: &str, file_name: &str, base_dir: &Path) -> Result<Scene, SceneError> {
    parse_scene_with(text, file_name, base_dir, &Limits::default())
}

/// [`parse_scene`] within `limits`: the text (at most [`Limits::max_scene_bytes`]), its
/// meshes and maps, the triangle count and the estimated memory ([`MemoryEstimate`]) are
/// checked before anything big is allocated.
pub fn parse_scene_with(text: &str, file_name: &str, base_dir: &Path, limits: &Limits) -> Result<Scene, SceneError> {
    let src = Source { text, file: file_name };
    limits
        .check(Limit::SceneBytes, "scene text", text.len() as u64)
        .map_err(|e| src.error(0..0, "", ErrorKind::Limit, e.to_string()))?;
    let raw: raw::RawScene = toml::from_str(text).map_err(|e| toml_error::convert(src, &e))?;
    scene_build::build(src, &raw, base_dir, limits)
}
