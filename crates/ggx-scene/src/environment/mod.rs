//! The environment: constant radiance or an importance-sampled equirectangular map.
//!
//! Convention (y up): a unit direction `d = (sin t cos p, cos t, sin t sin p)` has polar
//! angle `t = acos(d.y)` measured from +y and azimuth `p = atan2(d.z, d.x)` in `[0, 2 pi)`;
//! its map coordinates are `u = p / (2 pi)`, `v = t / pi`. Row 0 of a map is the top
//! (v = 0, +y), column 0 starts at +x and u grows towards +z.

mod build;
mod exr_file;
mod hdr_file;
mod inverse_trig;
mod load;
mod map;
mod procedural;

use std::borrow::Cow;
use std::f32::consts::{FRAC_1_PI, PI, TAU};

use glam::{Vec2, Vec3};

use crate::{IntegratorSettings, LightStrategy};

pub use build::MAX_PROCEDURAL_WIDTH;
pub(crate) use build::{build, check_with_triangles};
pub use load::{MAX_MAP_SIZE, load_image};
pub use map::EnvMap;
pub use procedural::{sky, studio};

/// Radiance arriving from infinitely far away.
// A scene holds one, read on every escaped path: unboxed, the map is one pointer closer.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug, PartialEq)]
pub enum Environment {
    /// The same radiance from every direction.
    Constant(Vec3),
    /// An equirectangular map.
    Map(EnvMap),
}

impl Environment {
    /// The environment as a renderer lights with it under `settings`, and whether
    /// next-event estimation samples it. With MIS and `mis_compensation` (Karlik et al.
    /// 2019, as pbrt-v4's `allowIncompletePDF`), a map samples only what stands above its
    /// mean ([`EnvMap::mis_compensated`]) and a constant or uniform environment is left to
    /// BSDF sampling alone: it takes no share of the light selection and its density in the
    /// MIS weight of a BSDF sample is 0. Otherwise the environment as it is (borrowed, not
    /// copied), sampled whenever lights are.
    pub fn for_integrator(&self, settings: &IntegratorSettings) -> (Cow<'_, Environment>, bool) {
        let sampled = settings.light_strategy != LightStrategy::Bsdf;
        if !settings.compensates_mis() {
            return (Cow::Borrowed(self), sampled);
        }
        match self {
            Self::Map(m) => match m.mis_compensated() {
                Some(c) => (Cow::Owned(Self::Map(c)), true),
                None => (Cow::Borrowed(self), false),
            },
            Self::Constant(_) => (Cow::Borrowed(self), false),
        }
    }

    /// Radiance arriving along `-direction` (i.e. seen looking towards unit `direction`).
    pub fn radiance(&self, direction: Vec3) -> Vec3 {
        match self {
            Self::Constant(l) => *l,
            Self::Map(m) => m.radiance(direction),
        }
    }

    /// Samples a unit direction from `u` in `[0, 1)^2`; returns it with its solid-angle pdf.
    /// A constant environment is sampled uniformly (`pdf = 1 / (4 pi)`).
    pub fn sample(&self, u: Vec2) -> (Vec3, f32) {
        let (d, pdf, _) = self.sample_with_radiance(u);
        (d, pdf)
    }

    /// [`Self::sample`] and the radiance along the sampled direction ([`EnvMap::sample_with_radiance`]).
    pub fn sample_with_radiance(&self, u: Vec2) -> (Vec3, f32, Vec3) {
        match self {
            Self::Constant(l) => (uniform_sphere(u), 0.25 * FRAC_1_PI, *l),
            Self::Map(m) => m.sample_with_radiance(u),
        }
    }

    /// [`Self::sample_with_radiance`] of each of `us` into `out` (the shorter length of the two),
    /// the same bits; a map samples in batches ([`EnvMap::sample_with_radiance_batch`]).
    pub fn sample_with_radiance_batch(&self, us: &[Vec2], out: &mut [(Vec3, f32, Vec3)]) {
        match self {
            Self::Constant(_) => {
                out.iter_mut().zip(us).for_each(|(o, &u)| *o = self.sample_with_radiance(u));
            }
            Self::Map(m) => m.sample_with_radiance_batch(us, out),
        }
    }

    /// Solid-angle density of [`Self::sample`] producing unit `direction`.
    pub fn pdf(&self, direction: Vec3) -> f32 {
        match self {
            Self::Constant(_) => 0.25 * FRAC_1_PI,
            Self::Map(m) => m.pdf(direction),
        }
    }

    /// [`Self::radiance`] and [`Self::pdf`] along unit `direction` (the same values), with one
    /// texel lookup for a map.
    #[inline]
    pub fn radiance_and_pdf(&self, direction: Vec3) -> (Vec3, f32) {
        match self {
            Self::Constant(l) => (*l, 0.25 * FRAC_1_PI),
            Self::Map(m) => m.radiance_and_pdf(direction),
        }
    }

    /// [`Self::radiance_and_pdf`] of each of `directions` into `out` (the shorter length of the
    /// two), the same bits; a map reads its texels in batches ([`EnvMap::radiance_and_pdf_batch`]).
    pub fn radiance_and_pdf_batch(&self, directions: &[Vec3], out: &mut [(Vec3, f32)]) {
        match self {
            Self::Constant(_) => out.iter_mut().zip(directions).for_each(|(o, &d)| *o = self.radiance_and_pdf(d)),
            Self::Map(m) => m.radiance_and_pdf_batch(directions, out),
        }
    }
}

/// Uniform direction on the unit sphere: `z = 1 - 2 u.x`, `phi = 2 pi u.y` (Archimedes'
/// hat-box theorem).
pub fn uniform_sphere(u: Vec2) -> Vec3 {
    let z = 1.0 - 2.0 * u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let (s, c) = (TAU * u.y).sin_cos();
    Vec3::new(r * c, r * s, z)
}

/// Equirectangular coordinates of unit `d`: `u = atan2(d.z, d.x) / (2 pi)` wrapped to
/// `[0, 1)`, `v = acos(d.y) / pi` (the inverse functions as polynomials within 5e-7 rad,
/// branch-free, so that a batch of directions maps in vector lanes: [`inverse_trig`]).
#[inline(always)]
pub fn direction_to_uv(d: Vec3) -> Vec2 {
    let phi = inverse_trig::atan2(d.z, d.x);
    let u = if phi < 0.0 { phi / TAU + 1.0 } else { phi / TAU };
    Vec2::new(if u >= 1.0 { 0.0 } else { u }, inverse_trig::acos(d.y.clamp(-1.0, 1.0)) * FRAC_1_PI)
}

/// Inverse of [`direction_to_uv`]: `d = (sin t cos p, cos t, sin t sin p)` with
/// `p = 2 pi u`, `t = pi v`.
pub fn uv_to_direction(uv: Vec2) -> Vec3 {
    let (sin_t, cos_t) = (PI * uv.y).sin_cos();
    let (sin_p, cos_p) = (TAU * uv.x).sin_cos();
    Vec3::new(sin_t * cos_p, cos_t, sin_t * sin_p)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uv_round_trip_and_axes() {
        assert!((direction_to_uv(Vec3::Y) - Vec2::new(0.0, 0.0)).length() < 1e-6);
        assert!((direction_to_uv(Vec3::X) - Vec2::new(0.0, 0.5)).length() < 1e-6);
        assert!((direction_to_uv(Vec3::Z) - Vec2::new(0.25, 0.5)).length() < 1e-6);
        assert!((direction_to_uv(-Vec3::Y).y - 1.0).abs() < 1e-6);
        for i in 0..100 {
            let uv = Vec2::new((i as f32 * 0.618_034).fract(), 0.01 + 0.98 * (i as f32 * 0.754_878).fract());
            let back = direction_to_uv(uv_to_direction(uv));
            assert!((back - uv).length() < 1e-4, "{uv} {back}");
        }
    }
}
