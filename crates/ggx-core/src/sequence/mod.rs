//! Sample sequences shared bit for bit by the CPU and GPU path tracers.
//!
//! Everything here is `no_std`, allocation free, panic free and uses only
//! wrapping `u32` arithmetic, so a WGSL port reproduces it bit for bit:
//!
//! - [`hash_u32`], [`hash_combine`], [`u32_to_unit_f32`]: stateless hashing.
//! - [`CounterRng`]: counter-based independent generator (also a `rand_core` RNG).
//! - [`sobol`], [`owen_scramble`], [`sobol_owen`]: Owen-scrambled Sobol' points (Burley 2020).
//! - [`SampleStream`]: per-pixel (sample, dimension) stream over either sequence.
//! - [`PixelSeeds`]: a pixel's scramble seeds hashed once for all its samples.

mod counter;
mod hash;
mod seeds;
mod sobol;
mod stream;

pub use counter::CounterRng;
pub use hash::{hash_combine, hash_u32, u32_to_unit_f32};
pub use seeds::{GroupSeeds, HashedGroup, HashedSeeds, KeptGroup, PIXEL_SEED_GROUPS, PixelSeeds, ScrambleSeeds};
pub use sobol::{
    SOBOL_DIMENSIONS, SOBOL_DIRECTIONS, owen_scramble, shuffle_index_reversed, sobol, sobol_owen, sobol_owen_shuffled,
    sobol_owen_u32,
};
pub use stream::{SampleStream, SequenceKind};
