//! [`EnvMap`]: an equirectangular radiance map with nearest-texel lookup and importance
//! sampling proportional to `luminance * sin(theta)`.

use std::f32::consts::PI;

use glam::{Quat, Vec2, Vec3};

use super::{direction_to_uv, uv_to_direction};
use crate::distribution::Distribution2D;
use crate::material::luminance;

/// An equirectangular environment map (see the module docs for the convention).
///
/// Lookups are nearest-texel, so radiance is constant over each texel; the sampling
/// distribution uses the same texels, which makes [`Self::sample`] and [`Self::pdf`] exact
/// for the radiance that [`Self::radiance`] returns.
#[derive(Clone, Debug, PartialEq)]
pub struct EnvMap {
    /// Columns.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// Row-major linear RGB radiance (`w` unused, 1), row 0 at the top (+y).
    pub texels: Vec<[f32; 4]>,
    /// Multiplier applied to every texel.
    pub scale: f32,
    /// Rotation of the map about +y in radians: world direction = `R_y(rotation)` * map
    /// direction.
    pub rotation: f32,
    /// Sampling distribution over texels, weights `luminance * sin(theta of the row centre)`.
    pub distribution: Distribution2D,
}

impl EnvMap {
    /// Builds a map from row-major RGB texels; `None` when the size does not match or any
    /// texel is negative or not finite.
    pub fn new(width: u32, height: u32, texels: Vec<[f32; 4]>, scale: f32, rotation_degrees: f32) -> Option<Self> {
        if texels.iter().any(|t| t[..3].iter().any(|c| !c.is_finite() || *c < 0.0)) {
            return None;
        }
        let weights: Vec<f32> = texels
            .iter()
            .enumerate()
            .map(|(i, t)| {
                let sin_theta = (PI * ((i / width.max(1) as usize) as f32 + 0.5) / height as f32).sin();
                luminance(Vec3::new(t[0], t[1], t[2])) * sin_theta
            })
            .collect();
        let distribution = Distribution2D::new(width, height, &weights)?;
        Some(Self { width, height, texels, scale, rotation: rotation_degrees.to_radians(), distribution })
    }

    fn to_map(&self, world: Vec3) -> Vec3 {
        Quat::from_rotation_y(-self.rotation) * world
    }

    /// Column and row of the texel seen along unit map-space `d`.
    fn cell(&self, d: Vec3) -> (usize, usize) {
        let uv = direction_to_uv(d);
        let col = ((uv.x * self.width as f32) as usize).min(self.width as usize - 1);
        let row = ((uv.y * self.height as f32) as usize).min(self.height as usize - 1);
        (col, row)
    }

    /// Scaled radiance of texel `(col, row)` (zero outside the map).
    pub fn texel(&self, col: usize, row: usize) -> Vec3 {
        if col >= self.width as usize {
            return Vec3::ZERO;
        }
        let t = self.texels.get(row * self.width as usize + col).copied().unwrap_or_default();
        self.scale * Vec3::new(t[0], t[1], t[2])
    }

    /// Radiance seen looking towards unit world `direction` (nearest texel).
    pub fn radiance(&self, direction: Vec3) -> Vec3 {
        let (col, row) = self.cell(self.to_map(direction));
        self.texel(col, row)
    }

    /// Solid-angle density in cell `(col, row)` at polar angle `theta`:
    /// `p(u, v) / (2 pi^2 sin theta)`, the Jacobian of `(u, v) -> direction` being
    /// `2 pi^2 sin theta` (PBR 3rd ed., 14.2.4).
    fn solid_angle_pdf(&self, col: usize, row: usize, sin_theta: f32) -> f32 {
        if sin_theta <= 0.0 {
            return 0.0;
        }
        self.distribution.cell_pdf(col, row) / (2.0 * PI * PI * sin_theta)
    }

    /// Samples a unit world direction from `u` in `[0, 1)^2`; returns it with its
    /// solid-angle pdf (0 only at the poles, where the sample should be discarded).
    pub fn sample(&self, u: Vec2) -> (Vec3, f32) {
        let (uv, _, [col, row]) = self.distribution.sample(u);
        let d = uv_to_direction(uv);
        let sin_theta = (PI * uv.y).sin();
        (Quat::from_rotation_y(self.rotation) * d, self.solid_angle_pdf(col as usize, row as usize, sin_theta))
    }

    /// Solid-angle density of [`Self::sample`] producing unit world `direction`.
    pub fn pdf(&self, direction: Vec3) -> f32 {
        let d = self.to_map(direction);
        let (col, row) = self.cell(d);
        let sin_theta = (1.0 - d.y * d.y).max(0.0).sqrt();
        self.solid_angle_pdf(col, row, sin_theta)
    }
}
