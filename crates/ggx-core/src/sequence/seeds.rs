//! Where a [`SampleStream`](super::SampleStream) takes the Owen-scramble seeds of its Sobol'
//! groups from: hashed at every draw ([`HashedSeeds`]), or hashed once per pixel and kept
//! ([`PixelSeeds`]). Both give the same seeds, so the same samples, bit for bit.

use super::hash::hash_combine;

/// A source of the scramble seeds of one pixel's Sobol' 4D groups.
pub trait ScrambleSeeds {
    /// The seeds of one group, as this source hands them out.
    type Group: GroupSeeds;

    /// Seeds of group `group` (dimensions `4 group .. 4 group + 3`) of the pixel seeded
    /// `pixel_seed`.
    fn group(&mut self, pixel_seed: u32, group: u32) -> Self::Group;
}

/// The seeds of one Sobol' 4D group.
pub trait GroupSeeds: Copy {
    /// The group's seed, which shuffles the sample index.
    // g = hash_combine(pixel_seed, group) (Burley 2020: one scramble per padded 4D group).
    fn seed(&self) -> u32;

    /// The Owen-scramble seed of dimension `dim` of the group.
    // hash_combine(g, dim & 3).
    fn dim_seed(&self, dim: u32) -> u32;
}

/// Seeds hashed at every draw: what the GPU does, and what [`SampleStream::next_1d`] and
/// [`SampleStream::next_2d`] use.
///
/// [`SampleStream::next_1d`]: super::SampleStream::next_1d
/// [`SampleStream::next_2d`]: super::SampleStream::next_2d
#[derive(Clone, Copy, Debug, Default)]
pub struct HashedSeeds;

/// A group's seed, its dimensions' seeds hashed when asked for.
#[derive(Clone, Copy, Debug)]
pub struct HashedGroup(u32);

impl ScrambleSeeds for HashedSeeds {
    type Group = HashedGroup;

    #[inline(always)]
    fn group(&mut self, pixel_seed: u32, group: u32) -> HashedGroup {
        HashedGroup(hash_combine(pixel_seed, group))
    }
}

impl GroupSeeds for HashedGroup {
    #[inline(always)]
    fn seed(&self) -> u32 {
        self.0
    }

    #[inline(always)]
    fn dim_seed(&self, dim: u32) -> u32 {
        hash_combine(self.0, dim & 3)
    }
}

/// A group's seed and its four dimensions' seeds, hashed together.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct KeptGroup([u32; 5]);

impl KeptGroup {
    /// All five seeds of group `group` of the pixel seeded `pixel_seed`.
    #[inline(always)]
    fn hash(pixel_seed: u32, group: u32) -> KeptGroup {
        let g = HashedSeeds.group(pixel_seed, group);
        KeptGroup([g.seed(), g.dim_seed(0), g.dim_seed(1), g.dim_seed(2), g.dim_seed(3)])
    }
}

impl GroupSeeds for KeptGroup {
    #[inline(always)]
    fn seed(&self) -> u32 {
        self.0[0]
    }

    #[inline(always)]
    fn dim_seed(&self, dim: u32) -> u32 {
        let [_, d0, d1, d2, d3] = self.0;
        match dim & 3 {
            0 => d0,
            1 => d1,
            2 => d2,
            _ => d3,
        }
    }
}

/// Groups whose seeds a [`PixelSeeds`] keeps: enough for the paths of 15 bounces (a camera
/// sample draws one group, a bounce two); deeper groups are hashed at each draw.
pub const PIXEL_SEED_GROUPS: usize = 32;

/// The scramble seeds of one pixel's first [`PIXEL_SEED_GROUPS`] groups, hashed on first use
/// and kept for the pixel's other samples: every sample of a pixel shares them, so hashing
/// them per sample (three `hash_combine`s per 2D draw) repeats the same work.
///
/// A stream whose pixel seed is not this one's gets hashed seeds, so a stale cache can cost
/// time but never change a sample.
#[derive(Clone, Debug)]
pub struct PixelSeeds {
    pixel_seed: u32,
    /// Groups `0..filled` hold their seeds.
    filled: u32,
    groups: [KeptGroup; PIXEL_SEED_GROUPS],
}

impl PixelSeeds {
    /// An empty cache for the pixel seeded `pixel_seed` ([`SampleStream::seed`]).
    ///
    /// [`SampleStream::seed`]: super::SampleStream::seed
    #[inline]
    pub fn new(pixel_seed: u32) -> Self {
        Self { pixel_seed, filled: 0, groups: [KeptGroup::default(); PIXEL_SEED_GROUPS] }
    }

    /// Empties the cache for the pixel seeded `pixel_seed`, as [`Self::new`] would, without
    /// rewriting its groups (only groups `0..filled` are ever read): a render loop that moves
    /// to the next pixel spares the 648-byte fill and copy a new cache costs.
    #[inline(always)]
    pub fn reset(&mut self, pixel_seed: u32) {
        (self.pixel_seed, self.filled) = (pixel_seed, 0);
    }
}

impl ScrambleSeeds for PixelSeeds {
    type Group = KeptGroup;

    #[inline(always)]
    fn group(&mut self, pixel_seed: u32, group: u32) -> KeptGroup {
        if pixel_seed != self.pixel_seed {
            return KeptGroup::hash(pixel_seed, group);
        }
        if (group as usize) < PIXEL_SEED_GROUPS {
            // Fill up to `group` on first use: draws go to higher groups as a path deepens.
            while self.filled <= group {
                if let Some(slot) = self.groups.get_mut(self.filled as usize) {
                    *slot = KeptGroup::hash(pixel_seed, self.filled);
                }
                self.filled += 1;
            }
            if let Some(kept) = self.groups.get(group as usize) {
                return *kept;
            }
        }
        KeptGroup::hash(pixel_seed, group)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sequence::{SampleStream, SequenceKind};

    /// A path-like run of draws: 2D, 1D, 2D, 1D, 1D per bounce, past the kept groups.
    fn draws<S: ScrambleSeeds>(stream: &mut SampleStream, seeds: &mut S, out: &mut [u32]) {
        let mut i = 0;
        while i + 7 <= out.len() {
            let a = stream.next_2d_with(seeds);
            let b = stream.next_1d_with(seeds);
            let c = stream.next_2d_with(seeds);
            let (d, e) = (stream.next_1d_with(seeds), stream.next_1d_with(seeds));
            for (slot, v) in out[i..i + 7].iter_mut().zip([a.x, a.y, b, c.x, c.y, d, e]) {
                *slot = v.to_bits();
            }
            i += 7;
        }
    }

    #[test]
    fn pixel_seeds_draw_the_hashed_samples() {
        const N: usize = 7 * 40; // 80 groups: past PIXEL_SEED_GROUPS
        for kind in [SequenceKind::Sobol, SequenceKind::Independent] {
            for pixel in [0u32, 1, 77, 1 << 20, u32::MAX] {
                let seed = SampleStream::new(kind, 12345, pixel, 0).seed;
                let mut kept = PixelSeeds::new(seed);
                for sample in [0u32, 1, 2, 3, 100, 65_535, u32::MAX] {
                    let (mut a, mut b) = ([0u32; N], [0u32; N]);
                    draws(&mut SampleStream::new(kind, 12345, pixel, sample), &mut HashedSeeds, &mut a);
                    draws(&mut SampleStream::new(kind, 12345, pixel, sample), &mut kept, &mut b);
                    assert_eq!(a, b, "{kind:?} pixel {pixel} sample {sample}");
                    for dim in [0, 3, 5, 127, 128, 129, 1000, u32::MAX] {
                        let s = SampleStream::new(kind, 12345, pixel, sample);
                        assert_eq!(s.get_u32(dim), s.get_u32_with(&mut kept, dim), "dim {dim}");
                    }
                }
                // Sobol' streams fill every kept group; independent ones need no seeds.
                let filled = if kind == SequenceKind::Sobol { PIXEL_SEED_GROUPS } else { 0 };
                assert_eq!(kept.filled as usize, filled);
            }
        }
    }

    #[test]
    fn a_reset_cache_draws_the_new_pixels_samples() {
        let (a_seed, b_seed) = (
            SampleStream::new(SequenceKind::Sobol, 3, 8, 0).seed,
            SampleStream::new(SequenceKind::Sobol, 3, 9, 0).seed,
        );
        let mut kept = PixelSeeds::new(a_seed);
        let (mut a, mut b) = ([0u32; 70], [0u32; 70]);
        draws(&mut SampleStream::new(SequenceKind::Sobol, 3, 8, 1), &mut kept, &mut a);
        assert_eq!(kept.filled, 20);
        // Pixel 9 with the groups pixel 8 left behind: none of them may be read.
        kept.reset(b_seed);
        assert_eq!((kept.pixel_seed, kept.filled), (b_seed, 0));
        draws(&mut SampleStream::new(SequenceKind::Sobol, 3, 9, 1), &mut kept, &mut b);
        let mut hashed = [0u32; 70];
        draws(&mut SampleStream::new(SequenceKind::Sobol, 3, 9, 1), &mut HashedSeeds, &mut hashed);
        assert_eq!(b, hashed);
        assert_ne!(a, b);
    }

    #[test]
    fn another_pixels_stream_gets_hashed_seeds() {
        let mut kept = PixelSeeds::new(SampleStream::new(SequenceKind::Sobol, 0, 5, 0).seed);
        for pixel in [4u32, 5, 6] {
            let (mut a, mut b) = ([0u32; 70], [0u32; 70]);
            draws(&mut SampleStream::new(SequenceKind::Sobol, 0, pixel, 9), &mut HashedSeeds, &mut a);
            draws(&mut SampleStream::new(SequenceKind::Sobol, 0, pixel, 9), &mut kept, &mut b);
            assert_eq!(a, b, "pixel {pixel}");
        }
    }
}
