//! [`EnvMap`]: an equirectangular radiance map with nearest-texel lookup and importance
//! sampling proportional to `luminance * sin(theta)`.

use std::f32::consts::PI;
use std::fmt;

use glam::{Quat, Vec2, Vec3};

use super::{direction_to_uv, uv_to_direction};
use crate::distribution::{Distribution2D, LOOKUP_BATCH};
use crate::material::LUMINANCE_WEIGHTS;
use crate::radiance::{MAX_RADIANCE, OVER_MAX_RADIANCE};
use crate::sample_inputs::{SampleInputSink, pod_part, write_distribution_2d};

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
    /// Row-major linear RGB radiance, row 0 at the top (+y); `w` is the cell's sampling
    /// density [`Distribution2D::cell_pdf`], written by the constructor (whatever was passed
    /// in), so that a lookup reads radiance and density from one cache line.
    pub texels: Vec<[f32; 4]>,
    /// Multiplier applied to every texel.
    pub scale: f32,
    /// Rotation of the map about +y in radians ([`Self::rotation`]); private, so that the
    /// lookups' quaternions below always follow it.
    rotation: f32,
    /// Sampling distribution over texels, weights `luminance * sin(theta of the row centre)`.
    pub distribution: Distribution2D,
    /// `R_y(-rotation)`, world to map (the same quaternion every lookup used to rebuild).
    to_map: Quat,
    /// `R_y(rotation)`, map to world.
    to_world: Quat,
}

/// Why texels and a scale cannot make an [`EnvMap`].
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum TexelError {
    /// A side is zero or the texel count is not `width * height`.
    Size,
    /// The scale is negative or not finite.
    Scale(f32),
    /// Texel `(col, row)` has a negative or non-finite channel.
    Invalid {
        /// Column.
        col: u32,
        /// Row.
        row: u32,
        /// The channel.
        value: f32,
    },
    /// Texel `(col, row)` times the scale is over [`MAX_RADIANCE`] (computed in `f64`).
    TooBright {
        /// Column.
        col: u32,
        /// Row.
        row: u32,
        /// The brightest channel of the texel.
        value: f32,
        /// `value * scale`.
        scaled: f64,
    },
}

impl fmt::Display for TexelError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Self::Size => write!(f, "the texel count does not match the map size"),
            Self::Scale(s) => write!(f, "scale {s} is negative or not finite"),
            Self::Invalid { col, row, value } => {
                write!(f, "texel ({col}, {row}) has a negative or non-finite channel ({value})")
            }
            Self::TooBright { col, row, value, scaled } => write!(
                f,
                "texel ({col}, {row}) has radiance {value:e}, which times the scale is {scaled:e}, over the \
                 largest radiance {MAX_RADIANCE:e} ({OVER_MAX_RADIANCE})"
            ),
        }
    }
}

impl EnvMap {
    /// Writes size, texels, scale, rotation and distribution as [`crate::Scene::write_sample_inputs`] parts.
    pub(crate) fn write_sample_inputs(&self, out: &mut SampleInputSink<'_>) {
        let EnvMap { width, height, texels, scale, rotation, distribution, to_map, to_world } = self;
        pod_part(out, &[*width, *height]);
        pod_part(out, texels);
        pod_part(out, &[*scale, *rotation]);
        write_distribution_2d(out, distribution);
        pod_part(out, &[*to_map, *to_world]);
    }

    /// Builds a map from row-major RGB texels; `None` when the size does not match, any
    /// texel is negative or not finite, or any texel times `scale` is over [`MAX_RADIANCE`].
    pub fn new(width: u32, height: u32, texels: Vec<[f32; 4]>, scale: f32, rotation_degrees: f32) -> Option<Self> {
        Self::try_new(width, height, texels, scale, rotation_degrees).ok()
    }

    /// [`Self::new`] that says which texel is wrong. Every scaled channel must be at most
    /// [`MAX_RADIANCE`] (checked in `f64`); then every luminance, each row's integral and
    /// the map's integral are at most that too, so the sampling distribution stays finite
    /// in `f32`. The weights are computed in `f64` and rounded once.
    pub(crate) fn try_new(
        width: u32,
        height: u32,
        texels: Vec<[f32; 4]>,
        scale: f32,
        rotation_degrees: f32,
    ) -> Result<Self, TexelError> {
        let w = width as usize;
        if w == 0 || height == 0 || Some(texels.len()) != w.checked_mul(height as usize) {
            return Err(TexelError::Size);
        }
        if !scale.is_finite() || scale < 0.0 {
            return Err(TexelError::Scale(scale));
        }
        check_texels(width, &texels, scale)?;
        let weights: Vec<f32> = luminance_sin_theta(width, height, &texels).map(|x| to_weight(x.0 * x.1)).collect();
        let distribution = Distribution2D::new(width, height, &weights).ok_or(TexelError::Size)?;
        let rotation = rotation_degrees.to_radians();
        let (to_map, to_world) = (Quat::from_rotation_y(-rotation), Quat::from_rotation_y(rotation));
        let mut map = Self { width, height, texels, scale, rotation, distribution, to_map, to_world };
        map.write_cell_pdfs();
        Ok(map)
    }

    /// Writes each cell's sampling density into its texel record's `w`.
    fn write_cell_pdfs(&mut self) {
        let w = self.width as usize;
        for (i, t) in self.texels.iter_mut().enumerate() {
            t[3] = self.distribution.cell_pdf(i % w, i / w);
        }
    }

    /// The map sampled by its MIS-compensated distribution (Karlik et al. 2019, pbrt-v4's
    /// `compensatedDistribution`): weights `max(L - mean L, 0) sin(theta)`, the mean over
    /// solid angle. Next-event estimation then samples only what stands above the mean, and
    /// BSDF sampling, which MIS combines with it, finds the rest. `None` when no texel is
    /// brighter than the mean by more than a relative `1e-6` (a uniform map: BSDF sampling
    /// alone is the better estimator). Radiance, rotation and scale are unchanged.
    pub fn mis_compensated(&self) -> Option<EnvMap> {
        let (mut sum, mut solid_angle) = (0.0f64, 0.0f64);
        for (luminance, sin_theta) in luminance_sin_theta(self.width, self.height, &self.texels) {
            sum += luminance * sin_theta;
            solid_angle += sin_theta;
        }
        let mean = sum / solid_angle;
        let threshold = mean * (1.0 + 1e-6);
        let weights: Vec<f32> = luminance_sin_theta(self.width, self.height, &self.texels)
            .map(
                |(luminance, sin_theta)| {
                    if luminance > threshold { to_weight((luminance - mean) * sin_theta) } else { 0.0 }
                },
            )
            .collect();
        if !weights.iter().any(|&x| x > 0.0) {
            return None;
        }
        let distribution = Distribution2D::new(self.width, self.height, &weights)?;
        let EnvMap { width, height, ref texels, scale, rotation, to_map, to_world, .. } = *self;
        let texels = texels.clone();
        let mut map = EnvMap { width, height, texels, scale, rotation, distribution, to_map, to_world };
        map.write_cell_pdfs();
        Some(map)
    }

    /// Rotation of the map about +y in radians: world direction = `R_y(rotation)` * map
    /// direction.
    pub fn rotation(&self) -> f32 {
        self.rotation
    }

    #[inline(always)]
    fn to_map(&self, world: Vec3) -> Vec3 {
        self.to_map * world
    }

    /// Column and row of the texel seen along unit map-space `d`.
    #[inline(always)]
    fn cell(&self, d: Vec3) -> (usize, usize) {
        let uv = direction_to_uv(d);
        // `u32` conversions, which vectorize in a batch (`locate_batch`); the same cells as
        // through `usize`, a map side being at most `u32::MAX` texels.
        let col = ((uv.x * self.width as f32) as u32).min(self.width - 1);
        let row = ((uv.y * self.height as f32) as u32).min(self.height - 1);
        (col as usize, row as usize)
    }

    /// Row-major index of texel `(col, row)`: `row width + col`.
    #[inline(always)]
    fn texel_index(&self, col: usize, row: usize) -> usize {
        row * self.width as usize + col
    }

    /// Scaled radiance of texel `(col, row)` (zero outside the map).
    pub fn texel(&self, col: usize, row: usize) -> Vec3 {
        self.scaled(self.record(col, row))
    }

    /// The scaled radiance of a stored record.
    fn scaled(&self, t: [f32; 4]) -> Vec3 {
        self.scale * Vec3::new(t[0], t[1], t[2])
    }

    /// The stored `[r, g, b, cell pdf]` of texel `(col, row)` (zeros outside the map).
    fn record(&self, col: usize, row: usize) -> [f32; 4] {
        if col >= self.width as usize {
            return [0.0; 4];
        }
        self.record_at(self.texel_index(col, row))
    }

    /// The stored record at row-major `index` (zeros past the map).
    #[inline(always)]
    fn record_at(&self, index: usize) -> [f32; 4] {
        self.texels.get(index).copied().unwrap_or_default()
    }

    /// Radiance seen looking towards unit world `direction` (nearest texel).
    pub fn radiance(&self, direction: Vec3) -> Vec3 {
        let (col, row) = self.cell(self.to_map(direction));
        self.texel(col, row)
    }

    /// Samples a unit world direction from `u` in `[0, 1)^2`; returns it with its
    /// solid-angle pdf (0 only at the poles, where the sample should be discarded).
    pub fn sample(&self, u: Vec2) -> (Vec3, f32) {
        let (d, pdf, _) = self.sample_with_radiance(u);
        (d, pdf)
    }

    /// [`Self::sample`] and the radiance of the sampled texel, read from the same cache line
    /// as its pdf: what a light sample needs, without mapping the direction back to a texel
    /// (two inverse trigonometric calls and a second lookup). Along the direction,
    /// [`Self::radiance`] finds the same texel except within float rounding of its border.
    pub fn sample_with_radiance(&self, u: Vec2) -> (Vec3, f32, Vec3) {
        let (uv, [col, row]) = self.distribution.sample_cell(u);
        self.light_sample_of(uv, self.record(col as usize, row as usize))
    }

    /// [`Self::sample_with_radiance`] of each of `us` into `out` (the shorter length of the
    /// two), the same bits: the cells sampled in a batch ([`Distribution2D::sample_cells`]),
    /// then every cell's record read, so that the cache misses of a batch overlap.
    pub fn sample_with_radiance_batch(&self, us: &[Vec2], out: &mut [(Vec3, f32, Vec3)]) {
        for (us, out) in us.chunks(LOOKUP_BATCH).zip(out.chunks_mut(LOOKUP_BATCH)) {
            let mut cells = [(Vec2::ZERO, [0u32; 2]); LOOKUP_BATCH];
            self.distribution.sample_cells(us, &mut cells);
            let mut records = [[0.0f32; 4]; LOOKUP_BATCH];
            for (r, &(_, [col, row])) in records.iter_mut().zip(&cells).take(us.len()) {
                *r = self.record(col as usize, row as usize);
            }
            for ((o, &(uv, _)), &r) in out.iter_mut().zip(&cells).zip(&records).take(us.len()) {
                *o = self.light_sample_of(uv, r);
            }
        }
    }

    /// The light sample at map point `uv` whose cell's record is `record`: the world
    /// direction, its solid-angle density and the cell's radiance.
    #[inline(always)]
    fn light_sample_of(&self, uv: Vec2, record: [f32; 4]) -> (Vec3, f32, Vec3) {
        let d = uv_to_direction(uv);
        let (radiance, pdf) = self.radiance_and_pdf_of(record, (PI * uv.y).sin());
        (self.to_world * d, pdf, radiance)
    }

    /// Solid-angle density of [`Self::sample`] producing unit world `direction`.
    pub fn pdf(&self, direction: Vec3) -> f32 {
        self.radiance_and_pdf(direction).1
    }

    /// [`Self::radiance`] and [`Self::pdf`] along unit world `direction` (the same values),
    /// finding the texel once: what a path that escapes to the environment needs.
    pub fn radiance_and_pdf(&self, direction: Vec3) -> (Vec3, f32) {
        let (index, sin_theta) = self.locate(direction);
        self.radiance_and_pdf_of(self.record_at(index), sin_theta)
    }

    /// [`Self::radiance_and_pdf`] of each of `directions` into `out` (the shorter length of
    /// the two), the same bits, in three passes over up to [`LOOKUP_BATCH`] directions at a
    /// time: locate every texel, read every record, then scale them. The reads of a batch do not
    /// wait for one another, so their cache misses (the texels of a large map are beyond a
    /// core's L2) overlap instead of following one by one.
    pub fn radiance_and_pdf_batch(&self, directions: &[Vec3], out: &mut [(Vec3, f32)]) {
        for (directions, out) in directions.chunks(LOOKUP_BATCH).zip(out.chunks_mut(LOOKUP_BATCH)) {
            let located = self.locate_batch(directions);
            let mut records = [[0.0f32; 4]; LOOKUP_BATCH];
            for (r, &(index, _)) in records.iter_mut().zip(&located).take(directions.len()) {
                *r = self.record_at(index);
            }
            for ((o, &r), &(_, sin_theta)) in out.iter_mut().zip(&records).zip(&located).take(directions.len()) {
                *o = self.radiance_and_pdf_of(r, sin_theta);
            }
        }
    }

    /// The row-major index of the texel seen along unit world `direction`, and `sin theta`
    /// there.
    #[inline(always)]
    fn locate(&self, direction: Vec3) -> (usize, f32) {
        let d = self.to_map(direction);
        let (col, row) = self.cell(d);
        (self.texel_index(col, row), sin_theta(d))
    }

    /// [`Self::locate`] of up to [`LOOKUP_BATCH`] directions (the lanes past them hold
    /// `locate(0)`'s answer): the directions turned into map space and split into components,
    /// then every lane mapped in one loop of fixed length without a call or a branch, which
    /// the compiler runs in vector lanes. The same bits as [`Self::locate`].
    #[inline(always)]
    fn locate_batch(&self, directions: &[Vec3]) -> [(usize, f32); LOOKUP_BATCH] {
        let mut d = [[0.0f32; LOOKUP_BATCH]; 3];
        for (k, &w) in directions.iter().take(LOOKUP_BATCH).enumerate() {
            let m = self.to_map(w);
            (d[0][k], d[1][k], d[2][k]) = (m.x, m.y, m.z);
        }
        let mut cells = [[0u32; 2]; LOOKUP_BATCH];
        let mut sines = [0.0f32; LOOKUP_BATCH];
        for k in 0..LOOKUP_BATCH {
            let m = Vec3::new(d[0][k], d[1][k], d[2][k]);
            let (col, row) = self.cell(m);
            cells[k] = [col as u32, row as u32];
            sines[k] = sin_theta(m);
        }
        core::array::from_fn(|k| (self.texel_index(cells[k][0] as usize, cells[k][1] as usize), sines[k]))
    }

    /// Scaled radiance and solid-angle density of a texel's record seen at `sin theta`.
    #[inline(always)]
    fn radiance_and_pdf_of(&self, record: [f32; 4], sin_theta: f32) -> (Vec3, f32) {
        (self.scaled(record), solid_angle_pdf(record[3], sin_theta))
    }
}

/// Each texel's unscaled luminance and the sine of its row centre's polar angle, in `f64`.
fn luminance_sin_theta(width: u32, height: u32, texels: &[[f32; 4]]) -> impl Iterator<Item = (f64, f64)> + '_ {
    let w = width.max(1) as usize;
    texels.iter().enumerate().map(move |(i, t)| {
        let sin_theta = (std::f64::consts::PI * ((i / w) as f64 + 0.5) / f64::from(height)).sin();
        let luminance: f64 = LUMINANCE_WEIGHTS.iter().zip(t).map(|(w, &c)| w * f64::from(c)).sum();
        (luminance, sin_theta)
    })
}

/// A sampling weight computed in `f64`, rounded once to `f32` (at most `f32::MAX`).
fn to_weight(x: f64) -> f32 {
    x.min(f64::from(f32::MAX)) as f32
}

/// `sin theta` of unit map-space `d`, whose `y` is `cos theta`: `sqrt(max(1 - y^2, 0))`.
#[inline(always)]
fn sin_theta(d: Vec3) -> f32 {
    (1.0 - d.y * d.y).max(0.0).sqrt()
}

/// Solid-angle density of a cell of density `cell_pdf` (over the unit square) at polar angle
/// `theta`: `p(u, v) / (2 pi^2 sin theta)`, the Jacobian of `(u, v) -> direction` being
/// `2 pi^2 sin theta` (PBR 3rd ed., 14.2.4); 0 at the poles.
fn solid_angle_pdf(cell_pdf: f32, sin_theta: f32) -> f32 {
    if sin_theta <= 0.0 {
        return 0.0;
    }
    cell_pdf / (2.0 * PI * PI * sin_theta)
}

/// Checks that every texel is finite and non-negative and that its brightest channel times
/// `scale` is at most [`MAX_RADIANCE`], in `f64` so that the product itself cannot overflow.
fn check_texels(width: u32, texels: &[[f32; 4]], scale: f32) -> Result<(), TexelError> {
    let w = width as usize;
    for (i, t) in texels.iter().enumerate() {
        let (col, row) = ((i % w) as u32, (i / w) as u32);
        if let Some(&value) = t[..3].iter().find(|c| !c.is_finite() || **c < 0.0) {
            return Err(TexelError::Invalid { col, row, value });
        }
        let value = t[0].max(t[1]).max(t[2]);
        let scaled = f64::from(value) * f64::from(scale);
        if scaled > f64::from(MAX_RADIANCE) {
            return Err(TexelError::TooBright { col, row, value, scaled });
        }
    }
    Ok(())
}
