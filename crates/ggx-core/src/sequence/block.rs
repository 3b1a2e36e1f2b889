//! [`sobol_owen_block`]: one group's Owen-scrambled Sobol' values for sixteen streams at once,
//! the scalar functions run lane by lane in a loop that LLVM vectorizes (one AVX-512 register
//! of `u32` per quantity: the multiplies of the hashes, the byte-table lookups as gathers and
//! the bit reversal), so every lane is [`SampleStream::get_u32`]'s value bit for bit.
//!
//! [`SampleStream::get_u32`]: super::SampleStream::get_u32

use super::hash::u32_to_unit_f32;
use super::seeds::{GroupSeeds, KeptGroup};
use super::sobol::{scramble_point, shuffle_index_reversed, xor_reversed_directions_lanes};
use crate::batch::{BatchLoop, dispatched};

/// Streams [`sobol_owen_block`] draws for at once.
pub const BLOCK_LANES: usize = 16;

/// Most dimensions of one group (a Sobol' group has four).
const GROUP_DIMS: usize = 4;

/// Values of dimensions `dims` (all in one 4D group; at most four, the rest ignored) of
/// [`BLOCK_LANES`] Sobol' streams, into `out[k][lane]` as `[0, 1)` floats: lane `l` is sample
/// `index[l]`, with `groups[l]` the seeds of that group of its pixel
/// ([`ScrambleSeeds::group`]), so `out[k][l] == u32_to_unit_f32(SampleStream::get_u32(dims[k]))`
/// of that stream, bit for bit. Runs on the widest vector ISA of the CPU with `std`.
///
/// [`ScrambleSeeds::group`]: super::ScrambleSeeds::group
/// [`SampleStream::get_u32`]: super::SampleStream::get_u32
// u = u32_to_unit_f32(reverse(LK(XOR of R[d & 3][j] over set bits j of LK(reverse(index), g), h(g, d & 3)))) (Burley 2020).
pub fn sobol_owen_block(
    index: &[u32; BLOCK_LANES],
    groups: &[KeptGroup; BLOCK_LANES],
    dims: &[u32],
    out: &mut [[f32; BLOCK_LANES]; GROUP_DIMS],
) {
    // The seeds as structure of arrays: the group's seed and each drawn dimension's.
    let mut group_seed = [0u32; BLOCK_LANES];
    let mut dim_seed = [[0u32; BLOCK_LANES]; GROUP_DIMS];
    for (l, g) in groups.iter().enumerate() {
        group_seed[l] = g.seed();
        for (k, &d) in dims.iter().take(GROUP_DIMS).enumerate() {
            dim_seed[k][l] = g.dim_seed(d);
        }
    }
    let count = dims.len().min(GROUP_DIMS);
    let mut dim = [0u32; GROUP_DIMS];
    dim[..count].copy_from_slice(&dims[..count]);
    dispatched(Block { index, group_seed: &group_seed, dim_seed: &dim_seed, dim, count, out });
}

/// [`sobol_owen_block`]'s loop, for [`dispatched`].
struct Block<'a> {
    index: &'a [u32; BLOCK_LANES],
    group_seed: &'a [u32; BLOCK_LANES],
    dim_seed: &'a [[u32; BLOCK_LANES]; GROUP_DIMS],
    dim: [u32; GROUP_DIMS],
    count: usize,
    out: &'a mut [[f32; BLOCK_LANES]; GROUP_DIMS],
}

impl BatchLoop for Block<'_> {
    type Output = ();

    #[inline(always)]
    fn run<const ROUND: bool>(self) {
        let mut reversed = [0u32; BLOCK_LANES];
        for l in 0..BLOCK_LANES {
            reversed[l] = shuffle_index_reversed(self.index[l], self.group_seed[l]);
        }
        for k in 0..self.count.min(GROUP_DIMS) {
            let (seeds, out) = (&self.dim_seed[k], &mut self.out[k]);
            let point = xor_reversed_directions_lanes(self.dim[k], &reversed);
            for l in 0..BLOCK_LANES {
                out[l] = u32_to_unit_f32(scramble_point(point[l], seeds[l]));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sequence::{HashedSeeds, PixelSeeds, SampleStream, ScrambleSeeds, SequenceKind};

    #[test]
    fn lanes_are_the_streams_values() {
        // Lanes from several pixels and far apart sample indices, every group and dimension
        // pattern a path draws, seeds kept and hashed.
        let mut x = 0x2545_f491u32;
        for round in 0..200u32 {
            let mut index = [0u32; BLOCK_LANES];
            let mut seed = [0u32; BLOCK_LANES];
            for l in 0..BLOCK_LANES {
                x = x.wrapping_mul(0x2c1b_3c6d).wrapping_add(0x297a_2d39);
                index[l] = if round % 3 == 0 { l as u32 + round } else { x };
                seed[l] = SampleStream::new(SequenceKind::Sobol, round, (x >> 7) % 5, 0).seed;
            }
            let group = x % 40;
            let mut pixel_seeds = PixelSeeds::new(seed[0]);
            let groups = core::array::from_fn(|l| pixel_seeds.group(seed[l], group));
            let first = 4 * group + round % 4;
            let dims: [u32; 4] = core::array::from_fn(|k| 4 * group + (first + k as u32) % 4);
            let count = 1 + (round as usize % 4);
            let mut out = [[f32::NAN; BLOCK_LANES]; GROUP_DIMS];
            sobol_owen_block(&index, &groups, &dims[..count], &mut out);
            for l in 0..BLOCK_LANES {
                let s = SampleStream { kind: SequenceKind::Sobol as u32, seed: seed[l], sample_index: index[l], dimension: 0 };
                for k in 0..count {
                    let want = u32_to_unit_f32(s.get_u32_with(&mut HashedSeeds, dims[k]));
                    assert_eq!(out[k][l].to_bits(), want.to_bits(), "round {round} lane {l} dim {}", dims[k]);
                }
                for k in count..GROUP_DIMS {
                    assert!(out[k][l].is_nan(), "dimension slot {k} past the count was written");
                }
            }
        }
    }
}
