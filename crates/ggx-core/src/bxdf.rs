//! One BSDF interface over every lobe of the crate: [`Bxdf`], with [`TransportMode`] and
//! [`BxdfFlags`]. Static dispatch only (generics), no trait objects, so it compiles for GPUs.

use crate::conductor::{BsdfSample, GgxConductor};
use crate::conductor_ms::GgxConductorMs;
use crate::sampling::Sampling;
use glam::{Vec2, Vec3};

/// What a path carries (pbrt-v4 `TransportMode`): radiance from the camera, or importance
/// from a light. It only matters for transmission, where radiance is scaled by
/// `1 / eta'^2` (Veach 1997, sec. 5.2). `#[repr(u32)]` so it uploads to a GPU as is.
#[repr(u32)]
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(not(target_arch = "spirv"), derive(Debug))]
pub enum TransportMode {
    /// Camera paths: `wo` points to the camera, the transmitted `f` includes `1 / eta'^2`.
    Radiance = 0,
    /// Light paths: `wo` points to the light, no radiance scaling.
    Importance = 1,
}

impl TransportMode {
    /// Mode for a GPU-side `u32`: 1 is `Importance`, anything else `Radiance`.
    #[inline]
    pub fn from_u32(v: u32) -> TransportMode {
        if v == 1 { TransportMode::Importance } else { TransportMode::Radiance }
    }
}

/// Lobe flags of a BSDF (a `u32` bit set, pbrt-v4 `BxDFFlags`).
#[repr(transparent)]
#[derive(Clone, Copy, PartialEq, Eq, Hash, bytemuck::Pod, bytemuck::Zeroable)]
#[cfg_attr(not(target_arch = "spirv"), derive(Debug))]
pub struct BxdfFlags(pub u32);

impl BxdfFlags {
    /// Scatters into the hemisphere of `wo`.
    pub const REFLECTION: BxdfFlags = BxdfFlags(1);
    /// Scatters into the opposite hemisphere.
    pub const TRANSMISSION: BxdfFlags = BxdfFlags(2);
    /// A rough (non-delta) microfacet lobe: `eval` and `pdf` are densities.
    pub const GLOSSY: BxdfFlags = BxdfFlags(4);
    /// A delta lobe: `eval` and `pdf` are 0, only `sample` returns it (`is_delta`).
    pub const SPECULAR: BxdfFlags = BxdfFlags(8);

    /// True when every bit of `other` is set.
    #[inline]
    pub fn contains(self, other: BxdfFlags) -> bool {
        self.0 & other.0 == other.0
    }

    /// The union of both sets.
    #[inline]
    pub fn union(self, other: BxdfFlags) -> BxdfFlags {
        BxdfFlags(self.0 | other.0)
    }

    /// True for a delta lobe ([`Self::SPECULAR`] set).
    #[inline]
    pub fn is_delta(self) -> bool {
        self.contains(Self::SPECULAR)
    }

    /// True when the BSDF transmits ([`Self::TRANSMISSION`] set).
    #[inline]
    pub fn is_transmissive(self) -> bool {
        self.contains(Self::TRANSMISSION)
    }
}

/// A BSDF in tangent space (`+z` = shading normal, directions point away from the surface).
///
/// Contract of every implementation: `eval` returns `f(wo, wi) |wi.z|`, `pdf` the solid-angle
/// density with which `sample` returns `wi`, and a returned sample has `weight == eval / pdf`
/// and `pdf == pdf()` to rounding (a delta sample: `pdf` = probability of its lobe, `eval`
/// and `pdf()` are 0). Any `f32` in, no NaN out. Use generics (`impl Bxdf`), not `dyn`.
pub trait Bxdf {
    /// `f(wo, wi) |wi.z|` for the transport mode.
    fn eval(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> Vec3;
    /// Solid-angle density of `wi` under `sampling` (0 for a delta lobe or a refused technique).
    fn pdf(&self, wo: Vec3, wi: Vec3, sampling: Sampling, mode: TransportMode) -> f32;
    /// `(eval, pdf)` of one pair in one call, equal to both bit for bit (Mitsuba 3's
    /// `eval_pdf`): what light sampling with MIS needs. The microfacet lobes override it to
    /// compute their half vector, `D` and Smith terms once; the default calls both.
    #[inline]
    fn eval_pdf(&self, wo: Vec3, wi: Vec3, sampling: Sampling, mode: TransportMode) -> (Vec3, f32) {
        (self.eval(wo, wi, mode), self.pdf(wo, wi, sampling, mode))
    }
    /// Draws `wi`: `u` picks the microfacet normal, `u_lobe` the lobe (reflection or transmission).
    fn sample(&self, wo: Vec3, u: Vec2, u_lobe: f32, sampling: Sampling, mode: TransportMode) -> Option<BsdfSample>;
    /// The lobes this BSDF has.
    fn flags(&self) -> BxdfFlags;
}

/// The conductor through the interface: `mode` and `u_lobe` are ignored (one lobe, no transmission).
impl Bxdf for GgxConductor {
    #[inline]
    fn eval(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> Vec3 {
        GgxConductor::eval(self, wo, wi)
    }

    #[inline]
    fn pdf(&self, wo: Vec3, wi: Vec3, sampling: Sampling, _mode: TransportMode) -> f32 {
        GgxConductor::pdf(self, wo, wi, sampling)
    }

    #[inline]
    fn eval_pdf(&self, wo: Vec3, wi: Vec3, sampling: Sampling, _mode: TransportMode) -> (Vec3, f32) {
        GgxConductor::eval_pdf(self, wo, wi, sampling)
    }

    #[inline]
    fn sample(&self, wo: Vec3, u: Vec2, _u_lobe: f32, sampling: Sampling, _mode: TransportMode) -> Option<BsdfSample> {
        GgxConductor::sample(self, wo, u, sampling)
    }

    #[inline]
    fn flags(&self) -> BxdfFlags {
        let lobe = if self.is_delta() { BxdfFlags::SPECULAR } else { BxdfFlags::GLOSSY };
        BxdfFlags::REFLECTION.union(lobe)
    }
}

/// The compensated conductor through the interface: `u_lobe` picks the single- or
/// multiple-scattering lobe, `mode` is ignored (reflection only).
impl Bxdf for GgxConductorMs {
    #[inline]
    fn eval(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> Vec3 {
        GgxConductorMs::eval(self, wo, wi)
    }

    #[inline]
    fn pdf(&self, wo: Vec3, wi: Vec3, sampling: Sampling, _mode: TransportMode) -> f32 {
        GgxConductorMs::pdf(self, wo, wi, sampling)
    }

    #[inline]
    fn eval_pdf(&self, wo: Vec3, wi: Vec3, sampling: Sampling, _mode: TransportMode) -> (Vec3, f32) {
        GgxConductorMs::eval_pdf(self, wo, wi, sampling)
    }

    #[inline]
    fn sample(&self, wo: Vec3, u: Vec2, u_lobe: f32, sampling: Sampling, _mode: TransportMode) -> Option<BsdfSample> {
        GgxConductorMs::sample(self, wo, u, u_lobe, sampling)
    }

    #[inline]
    fn flags(&self) -> BxdfFlags {
        Bxdf::flags(&self.conductor)
    }
}
