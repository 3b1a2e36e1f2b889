//! Fresnel reflectance: Schlick, exact dielectric, complex-IOR conductor and `One`.
//!
//! [`Fresnel`] is the convenient Rust enum; [`FresnelParams`] is its `#[repr(C)]` POD twin
//! that uploads to a GPU and is what [`crate::GgxConductor`] stores.

mod complex;
mod formulas;

pub use formulas::{fresnel_complex, fresnel_dielectric, fresnel_schlick};

use glam::Vec3;

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
        let f = match self.kind {
            kind::SCHLICK => fresnel_schlick(cos_theta, v3(self.a), v3(self.b)),
            kind::CONDUCTOR => {
                let (eta, k) = (self.a, self.b);
                Vec3::new(
                    fresnel_complex(cos_theta, eta[0], k[0]),
                    fresnel_complex(cos_theta, eta[1], k[1]),
                    fresnel_complex(cos_theta, eta[2], k[2]),
                )
            }
            kind::DIELECTRIC => Vec3::splat(fresnel_dielectric(cos_theta, self.eta)),
            _ => Vec3::ONE,
        };
        // Keep the contract "in [0, 1], never NaN" whatever the stored parameters.
        Vec3::new(unit(f.x), unit(f.y), unit(f.z))
    }
}

impl Fresnel {
    /// Reflectance for the cosine between the incident direction and the microfacet normal.
    #[inline]
    pub fn eval(&self, cos_theta: f32) -> Vec3 {
        FresnelParams::from(*self).eval(cos_theta)
    }
}

/// Clamps into `[0, 1]`, NaN to 0.
#[inline(always)]
fn unit(x: f32) -> f32 {
    x.max(0.0).min(1.0)
}

#[cfg(test)]
mod tests;
