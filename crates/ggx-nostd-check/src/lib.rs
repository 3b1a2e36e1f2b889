//! A `#![no_std]` crate that uses ggx-core without its `std` feature and defines its own
//! panic handler. If anything in ggx-core's dependency graph linked std, rustc would reject
//! this crate with "duplicate lang item `panic_impl`", so `cargo build -p ggx-nostd-check`
//! is the proof that the core is usable on targets without std (`cargo xtask ci` runs it).
#![no_std]
#![deny(missing_docs)]

use ggx_core::{Fresnel, GgxConductor, SampleStream, Sampling, SequenceKind, Vec3};

/// One VNDF-sampled bounce, as an embedded or GPU caller would write it: returns the
/// sampled direction's weight for a view direction and a pixel's first 2D sample.
pub fn first_bounce_weight(wo: Vec3, pixel: u32) -> Vec3 {
    let brdf = GgxConductor::new(0.3, 0.3, Fresnel::One);
    let mut stream = SampleStream::new(SequenceKind::Sobol, 0, pixel, 0);
    match brdf.sample(wo, stream.next_2d(), Sampling::Vndf) {
        Some(s) => s.weight,
        None => Vec3::ZERO,
    }
}

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    loop {}
}
