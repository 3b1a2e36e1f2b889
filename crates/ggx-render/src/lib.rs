//! # ggx-render
//!
//! What the ggx renderers have in common, so that neither backend depends on the other:
//!
//! * the interface every backend implements: [`RenderOptions`] and [`RenderControl`] in,
//!   [`Progress`] during, [`RenderResult`] or [`RenderError`] out;
//! * the pass schedule ([`pass_end`]), the stream seed ([`stream_seed`]) and the time budget
//!   ([`time_budget`]), which make the CPU and GPU backends trace the same samples;
//! * the scene's materials as ggx-core BSDFs ([`Bsdf`]), shared by the CPU kernels and the
//!   GPU upload;
//! * [`KernelVariant`]: the features a specialized kernel keeps, named alike on both backends;
//! * [`new_film`]: the image buffer, allocated fallibly (an error, never an abort).
#![deny(missing_docs)]

mod bsdf;
mod interface;
mod kernel;
mod schedule;
mod textured;

pub use bsdf::{Bsdf, sampling_for};
pub use interface::{Job, Progress, RenderControl, RenderError, RenderOptions, RenderResult, new_film};
pub use kernel::KernelVariant;
pub use schedule::{MAX_PASS_SPP, pass_end, stream_seed, time_budget};
pub use textured::{
    anisotropy_direction, emission_at, metal_rough_at, metal_rough_bsdf, normal_map_at, perturb_normal, tangent_at,
    tangent_frame,
};
