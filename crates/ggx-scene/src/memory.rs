//! [`MemoryEstimate`]: how much memory a scene needs to load and render, estimated from
//! counts known before anything big is allocated (triangles per shape, map size, film size).
//! The loader checks it against [`crate::Limits::max_memory`]; `ggx info` prints it.

use std::fmt;

use crate::environment::Environment;
use crate::limits::format_bytes;
use crate::scene::Scene;

/// Peak bytes per triangle of loading and rendering a scene: the 48-byte [`crate::Triangle`],
/// its 48-byte [`crate::ShadingNormals`], the tessellation's temporary vertices and indices,
/// the vectors' growth slack (up to 2x while they are pushed to) and the renderer's BVH
/// (obvhs builds over per-triangle boxes and keeps a reordered copy of the triangles).
///
/// Measured: the peak resident set (`/usr/bin/time -v`) of the debug `ggx info`, which
/// loads the scene and builds every BVH kind, on scenes of 0, 1, 3 and 8 smooth icospheres
/// at `subdivisions = 7` (327 680 triangles each) grows by 378 bytes per triangle at every
/// size (the crate README, "Scene limits"); rounded up.
pub const BYTES_PER_TRIANGLE: u64 = 400;

/// Peak bytes per environment map texel: the 16-byte RGBA `f32` texel, its 4-byte sampling
/// weight and the 12 bytes of the distribution's cell weight, conditional CDF entry and
/// guide-table entry.
pub const BYTES_PER_TEXEL: u64 = 32;

/// Bytes per film pixel: the 64-byte exact sum (three 128-bit sums and two counts), as much
/// again for the tiles of a pass in flight (or a backend's read-back), the 12-byte mean and
/// the 68 bytes of the film file's channels when it is written.
pub const FILM_BYTES_PER_PIXEL: u64 = 208;

/// Memory of `triangles` triangles, [`BYTES_PER_TRIANGLE`] each.
pub fn triangle_bytes(triangles: u64) -> u64 {
    triangles.saturating_mul(BYTES_PER_TRIANGLE)
}

/// Memory of an environment map of `texels` texels, [`BYTES_PER_TEXEL`] each.
pub fn map_bytes(texels: u64) -> u64 {
    texels.saturating_mul(BYTES_PER_TEXEL)
}

/// Memory of a `width x height` film, [`FILM_BYTES_PER_PIXEL`] per pixel.
pub fn film_bytes(width: u32, height: u32) -> u64 {
    (u64::from(width) * u64::from(height)).saturating_mul(FILM_BYTES_PER_PIXEL)
}

/// Estimated peak memory of loading and rendering a scene, by part.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MemoryEstimate {
    /// Triangles after tessellation.
    pub triangles: u64,
    /// Their memory: mesh, shading normals and BVH ([`triangle_bytes`]).
    pub triangle_bytes: u64,
    /// Environment map texels (0 without a map).
    pub map_texels: u64,
    /// Their memory: texels and sampling tables ([`map_bytes`]).
    pub map_bytes: u64,
    /// Film pixels.
    pub film_pixels: u64,
    /// Their memory ([`film_bytes`]).
    pub film_bytes: u64,
    /// Textures and their texture coordinates ([`crate::TextureSet::bytes`] and the
    /// per-triangle records), known once they are loaded (0 in [`MemoryEstimate::new`]).
    pub texture_bytes: u64,
}

impl MemoryEstimate {
    /// The estimate for `triangles` triangles, a map of `map_texels` texels and a
    /// `width x height` film.
    pub fn new(triangles: u64, map_texels: u64, [width, height]: [u32; 2]) -> Self {
        Self {
            triangles,
            triangle_bytes: triangle_bytes(triangles),
            map_texels,
            map_bytes: map_bytes(map_texels),
            film_pixels: u64::from(width) * u64::from(height),
            film_bytes: film_bytes(width, height),
            texture_bytes: 0,
        }
    }

    /// The sum of the parts.
    pub fn total(&self) -> u64 {
        self.triangle_bytes
            .saturating_add(self.map_bytes)
            .saturating_add(self.film_bytes)
            .saturating_add(self.texture_bytes)
    }
}

impl fmt::Display for MemoryEstimate {
    /// `1.2 GiB (triangles 1.1 GiB, map 28.0 MiB, film 4.0 MiB)`, with `textures 3.0 MiB`
    /// when there are any.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} (triangles {}, map {}, film {}",
            format_bytes(self.total()),
            format_bytes(self.triangle_bytes),
            format_bytes(self.map_bytes),
            format_bytes(self.film_bytes)
        )?;
        if self.texture_bytes > 0 {
            write!(f, ", textures {}", format_bytes(self.texture_bytes))?;
        }
        f.write_str(")")
    }
}

/// The memory estimate of a loaded `scene` at its camera's resolution (a renderer that
/// overrides the resolution replaces the film part: [`MemoryEstimate::new`]).
pub fn estimate_memory(scene: &Scene) -> MemoryEstimate {
    let texels = match &scene.environment {
        Some(Environment::Map(m)) => u64::from(m.width) * u64::from(m.height),
        _ => 0,
    };
    let mut e = MemoryEstimate::new(scene.mesh.triangles.len() as u64, texels, scene.camera.resolution);
    if !scene.textures.is_empty() || !scene.mesh.uvs.is_empty() {
        let records = (scene.mesh.uvs.len() * size_of::<crate::TriangleUvs>()
            + scene.mesh.tangents.len() * size_of::<crate::TriangleTangents>()) as u64;
        e.texture_bytes = scene.textures.bytes().saturating_add(records);
    }
    e
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parts_add_up() {
        let e = MemoryEstimate::new(1000, 10, [4, 2]);
        assert_eq!(e.triangle_bytes, 1000 * BYTES_PER_TRIANGLE);
        assert_eq!(e.map_bytes, 320);
        assert_eq!((e.film_pixels, e.film_bytes), (8, 8 * FILM_BYTES_PER_PIXEL));
        assert_eq!(e.total(), e.triangle_bytes + 320 + e.film_bytes);
        assert!(MemoryEstimate::new(u64::MAX, u64::MAX, [u32::MAX; 2]).total() == u64::MAX);
        assert_eq!(film_bytes(16384, 16384), 52 << 30);
    }
}
