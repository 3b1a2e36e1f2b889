//! # ggx-core
//!
//! A `no_std` implementation of the GGX (Trowbridge-Reitz) microfacet model that runs
//! unchanged on a CPU, in a GPU shader compiled by rust-gpu, and on embedded targets.
//!
//! Conventions (the same as pbrt-v4): directions live in tangent space with the shading
//! normal on `+z`, every direction points away from the surface, `wo` is the outgoing
//! (view) direction, `wi` the incident (light) direction and `wm` the microfacet normal.
//!
//! * [`TrowbridgeReitz`]: the distribution `D`, Smith `lambda`, `g1`, `g2` (height-correlated
//!   and separable) and the visible-normal distribution `d_visible`.
//! * Four microfacet-normal samplers with exact densities: [`TrowbridgeReitz::sample_wm_ndf`]
//!   (Walter 2007), [`TrowbridgeReitz::sample_wm_vndf`] (Heitz 2018),
//!   [`TrowbridgeReitz::sample_wm_spherical_caps`] (Dupuy & Benyoub 2023) and
//!   [`TrowbridgeReitz::sample_wm_bounded`] (Eto & Tokuyoshi 2023), plus cosine and uniform
//!   hemisphere baselines in [`warp`].
//! * [`Fresnel`]: Schlick, exact dielectric, complex-IOR conductor and `One`; the conductor
//!   is one source over [`lanes::Lanes`], evaluated for R, G and B at once as `Vec3A` lanes.
//! * [`GgxConductor`]: the reflection BRDF that ties them together (`eval`, `pdf`, `sample`).
//! * [`GgxConductorMs`]: the conductor with Kulla & Conty 2017's multiple-scattering lobe
//!   (energy compensation), tables in [`energy`] and [`energy_tables`].
//! * [`GgxDielectric`]: reflection and transmission through one rough interface (Walter et
//!   al. 2007), with [`TransportMode`] and [`refract`].
//! * [`GgxDielectricMs`]: the dielectric scaled by its inverse albedo (Turquin 2019), so that
//!   it loses no energy from either side; tables in [`energy_dielectric`] and
//!   [`energy_dielectric_tables`], which also hold the plastic coat's albedo and the base
//!   weight [`energy_dielectric::plastic_base_weight`].
//! * [`GltfMetalRough`]: the glTF 2.0 metallic-roughness BRDF (spec Appendix B, with
//!   `KHR_materials_specular` and `KHR_materials_ior`) composed from the conductor's specular
//!   lobe, Schlick's Fresnel term and a Lambertian base, sampled as a one-sample MIS mixture.
//! * [`GltfClearcoat`]: `KHR_materials_clearcoat`'s GGX coat over a [`GltfMetalRough`] base,
//!   weighted by Schlick's Fresnel term of the view.
//! * [`Bxdf`]: the one BSDF interface both implement (static dispatch), with [`BxdfFlags`].
//! * [`mis`]: balance and power heuristics that survive infinite and zero densities.
//! * [`Frame`]: the branchless orthonormal basis of Duff et al. 2017.
//! * [`sequence`]: counter-based and Owen-scrambled Sobol' sample streams that give
//!   bit-identical numbers on CPU and GPU.
//! * [`batch`]: slice APIs that the compiler auto-vectorizes.
//! * [`distribution::formulas`], [`distribution::samplers`], [`conductor::formulas`]: `D`,
//!   Lambda, `G1`, `G2`, `D_w`, the four samplers with their densities and the conductor's
//!   `eval` factor written once over [`lanes::Lanes`]; the methods are their `f32`
//!   instantiation, and the tests evaluate them in `f64` to bound the `f32` rounding.
//!
//! Every function accepts any `f32` (NaN, infinities, subnormals, zero, negative, huge)
//! without panicking and without returning NaN, and the `Pod` structs accept any bit pattern
//! in their public fields (alphas are read through [`TrowbridgeReitz::alphas`], the
//! constructor's clamp). The documented exceptions, all `+inf` or IEEE by design:
//! [`math::sqrt`] (NaN for negative input), [`math::safe_sqrt`] and
//! [`warp::pdf_cosine_hemisphere`] at `+inf`, and [`TrowbridgeReitz::lambda`] where its ratio
//! overflows (grazing). `tests/contract.rs` checks every public function. Nothing allocates,
//! nothing recurses, nothing panics.
#![no_std]
#![deny(missing_docs)]

#[cfg(any(test, feature = "std"))]
extern crate std;

pub mod alpha;
pub mod batch;
mod bxdf;
pub mod clearcoat;
pub mod conductor;
mod conductor_ms;
mod dielectric;
mod dielectric_ms;
pub mod distribution;
pub mod energy;
pub mod energy_dielectric;
#[rustfmt::skip]
pub mod energy_dielectric_tables;
#[rustfmt::skip]
pub mod energy_tables;
mod frame;
pub mod fresnel;
pub mod lanes;
pub mod math;
pub mod metal_rough;
pub mod mis;
mod sample_bounded;
mod sample_ndf;
mod sample_spherical_caps;
mod sample_vndf;
mod sampling;
pub mod sequence;
mod thin_dielectric;
pub mod warp;

pub use alpha::{ALPHA_MAX, ALPHA_MIN, DELTA_ALPHA, alpha_to_roughness, roughness_to_alpha};
pub use bxdf::{Bxdf, BxdfFlags, TransportMode};
pub use clearcoat::GltfClearcoat;
pub use conductor::{BsdfSample, GgxConductor};
pub use conductor_ms::GgxConductorMs;
pub use dielectric::{ETA_MAX, ETA_MIN, GgxDielectric, clamp_eta, refract};
pub use dielectric_ms::GgxDielectricMs;
pub use distribution::TrowbridgeReitz;
pub use frame::{Frame, reflect};
pub use fresnel::{Fresnel, FresnelParams};
pub use metal_rough::GltfMetalRough;
pub use sampling::Sampling;
pub use sequence::{CounterRng, SampleStream, SequenceKind};
pub use thin_dielectric::ThinDielectric;

/// Re-exported so users of the public API need not depend on glam themselves.
pub use glam::{Vec2, Vec3};
