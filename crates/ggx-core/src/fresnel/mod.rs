//! Fresnel reflectance: Schlick, exact dielectric, complex-IOR conductor and `One`.
//!
//! [`Fresnel`] is the convenient Rust enum; [`FresnelParams`] is its `#[repr(C)]` POD twin
//! that uploads to a GPU and is what [`crate::GgxConductor`] stores.

mod complex;
mod formulas;

pub use formulas::{fresnel_complex, fresnel_dielectric, fresnel_schlick};

use glam::Vec3;
// Fields and results are clamped to [0, 1], -0.0 and NaN read as +0.0.
use crate::math::saturate as unit;

/// A Fresnel model. Reflectances are RGB; every evaluation returns values in `[0, 1]`.
#[derive(Clone, Copy, PartialEq)]
#[cfg_attr(not(target_arch = "spirv"), derive(Debug))]
pub enum Fresnel {
    /// `F = 1`: a perfect reflector, for white-furnace tests.
    One,
    /// Schlick 1994 with normal-incidence reflectance `f0` and grazing reflectance 1.
    Schlick {
        /// Reflectance at normal incidence.
        f0: Vec3,
    },
    /// Schlick with an explicit grazing reflectance `f90` (Burley 2012's generalisation).
    SchlickF90 {
        /// Reflectance at normal incidence.
        f0: Vec3,
        /// Reflectance at grazing incidence.
        f90: Vec3,
    },
    /// Conductor with complex index of refraction `eta + i k` per RGB channel.
    Conductor {
        /// Real part of the index of refraction.
        eta: Vec3,
        /// Imaginary part (absorption).
        k: Vec3,
    },
    /// Exact unpolarised dielectric interface with relative index `eta` (outside to inside);
    /// a negative cosine means the ray arrives from inside, with total internal reflection.
    Dielectric {
        /// Relative index of refraction (e.g. 1.5 for glass in air).
        eta: f32,
    },
}

/// `FresnelParams::kind` values.
pub mod kind {
    /// [`super::Fresnel::One`].
    pub const ONE: u32 = 0;
    /// [`super::Fresnel::Schlick`] and [`super::Fresnel::SchlickF90`] (`a` = f0, `b` = f90).
    pub const SCHLICK: u32 = 1;
    /// [`super::Fresnel::Conductor`] (`a` = eta, `b` = k).
    pub const CONDUCTOR: u32 = 2;
    /// [`super::Fresnel::Dielectric`] (`eta`).
    pub const DIELECTRIC: u32 = 3;
}

/// GPU-uploadable form of [`Fresnel`]: 48 bytes, vectors 16-byte aligned as WGSL wants.
/// Unknown `kind` values evaluate as [`Fresnel::One`].
#[repr(C)]
#[derive(Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
#[cfg_attr(not(target_arch = "spirv"), derive(Debug))]
pub struct FresnelParams {
    /// One of the constants in [`kind`].
    pub kind: u32,
    /// Dielectric relative index of refraction.
    pub eta: f32,
    /// Padding to 16 bytes.
    pub pad: [u32; 2],
    /// `f0` (Schlick) or `eta` (conductor), RGB in `xyz`.
    pub a: [f32; 4],
    /// `f90` (Schlick) or `k` (conductor), RGB in `xyz`.
    pub b: [f32; 4],
}

#[inline]
fn v4(v: Vec3) -> [f32; 4] {
    [v.x, v.y, v.z, 0.0]
}

#[inline]
fn v3(a: [f32; 4]) -> Vec3 {
    Vec3::new(a[0], a[1], a[2])
}

impl From<Fresnel> for FresnelParams {
    fn from(f: Fresnel) -> Self {
        let p = FresnelParams { kind: kind::ONE, eta: 1.0, pad: [0; 2], a: [0.0; 4], b: [0.0; 4] };
        match f {
            Fresnel::One => p,
            Fresnel::Schlick { f0 } => FresnelParams { kind: kind::SCHLICK, a: v4(f0), b: v4(Vec3::ONE), ..p },
            Fresnel::SchlickF90 { f0, f90 } => FresnelParams { kind: kind::SCHLICK, a: v4(f0), b: v4(f90), ..p },
            Fresnel::Conductor { eta, k } => FresnelParams { kind: kind::CONDUCTOR, a: v4(eta), b: v4(k), ..p },
            Fresnel::Dielectric { eta } => FresnelParams { kind: kind::DIELECTRIC, eta, ..p },
        }
    }
}

impl FresnelParams {
    /// The enum this encodes.
    pub fn to_fresnel(&self) -> Fresnel {
        match self.kind {
            kind::SCHLICK if v3(self.b) == Vec3::ONE => Fresnel::Schlick { f0: v3(self.a) },
            kind::SCHLICK => Fresnel::SchlickF90 { f0: v3(self.a), f90: v3(self.b) },
            kind::CONDUCTOR => Fresnel::Conductor { eta: v3(self.a), k: v3(self.b) },
            kind::DIELECTRIC => Fresnel::Dielectric { eta: self.eta },
            _ => Fresnel::One,
        }
    }

    /// Reflectance for the cosine between the incident direction and the microfacet normal.
    #[inline]
    pub fn eval(&self, cos_theta: f32) -> Vec3 {
        self.eval_as(self.kind, cos_theta)
    }

    /// [`Self::eval`] as if `kind` were stored: inlined everywhere, so a caller that passes a
    /// constant kind (ggx-core's batch loops, one loop per kind) gets a branch-free body.
    #[inline(always)]
    pub(crate) fn eval_as(&self, kind: u32, cos_theta: f32) -> Vec3 {
        let f = match kind {
            kind::SCHLICK => fresnel_schlick(cos_theta, v3(self.a), v3(self.b)),
            kind::CONDUCTOR => formulas::fresnel_complex_rgb(cos_theta, v3(self.a), v3(self.b)),
            kind::DIELECTRIC => Vec3::splat(fresnel_dielectric(cos_theta, self.eta)),
            _ => Vec3::ONE,
        };
        // Keep the contract "in [0, 1], never NaN" whatever the stored parameters.
        Vec3::new(unit(f.x), unit(f.y), unit(f.z))
    }
}

/// Nodes of the 8-point Gauss-Legendre rule mapped to `[0, 1]`: `(1 + t_k) / 2` (f64 digits).
#[allow(clippy::excessive_precision)]
const GL8_NODES: [f32; 8] = [
    0.019855071751231856,
    0.10166676129318664,
    0.2372337950418355,
    0.4082826787521751,
    0.5917173212478249,
    0.7627662049581645,
    0.8983332387068134,
    0.9801449282487681,
];
/// Weights of the 8-point Gauss-Legendre rule mapped to `[0, 1]` (they sum to 1).
#[allow(clippy::excessive_precision)]
const GL8_WEIGHTS: [f32; 8] = [
    0.05061426814518813,
    0.11119051722668724,
    0.15685332293894363,
    0.18134189168918100,
    0.18134189168918100,
    0.15685332293894363,
    0.11119051722668724,
    0.05061426814518813,
];

impl FresnelParams {
    /// Hemispherical average `F_avg = 2 integral_0^1 F(mu) mu dmu` (Kulla & Conty 2017, the
    /// Fresnel term of the multiple-scattering lobe), by the 8-point Gauss-Legendre rule on
    /// `[0, 1]` over [`Self::eval`] (exact to rounding for `One` and Schlick, whose integrand
    /// is a polynomial of degree 6; for the complex-IOR conductor and the dielectric with
    /// `eta >= 1` within 1e-4 of a 1000-node rule; `eta < 1` has a kink at the critical angle
    /// and is within 2e-3). In `[0, 1]` per channel, never NaN.
    #[inline]
    pub fn average(&self) -> Vec3 {
        let mut sum = Vec3::ZERO;
        let mut k = 0;
        while k < 8 {
            sum += self.eval(GL8_NODES[k]) * (2.0 * GL8_NODES[k] * GL8_WEIGHTS[k]);
            k += 1;
        }
        Vec3::new(unit(sum.x), unit(sum.y), unit(sum.z))
    }
}

impl Fresnel {
    /// [`FresnelParams::average`]: `F_avg = 2 integral_0^1 F(mu) mu dmu`.
    #[inline]
    pub fn average(&self) -> Vec3 {
        FresnelParams::from(*self).average()
    }

    /// Reflectance for the cosine between the incident direction and the microfacet normal.
    #[inline]
    pub fn eval(&self, cos_theta: f32) -> Vec3 {
        FresnelParams::from(*self).eval(cos_theta)
    }
}

#[cfg(test)]
mod tests;
