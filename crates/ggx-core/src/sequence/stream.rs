//! Per-pixel sample streams over either sequence, addressed by (pixel, sample, dimension).

use bytemuck::{Pod, Zeroable};
use glam::Vec2;

use super::hash::{hash_combine, u32_to_unit_f32};
use super::seeds::{GroupSeeds, HashedSeeds, ScrambleSeeds};
use super::sobol::{shuffle_index_reversed, sobol_owen_scrambled};

/// Which sequence a [`SampleStream`] draws from.
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SequenceKind {
    /// Independent uniform samples: a hash of (seed, sample, dimension).
    Independent = 0,
    /// Owen-scrambled, index-shuffled Sobol' points in padded 4D groups.
    Sobol = 1,
}

impl SequenceKind {
    /// Kind stored as `u32` in GPU data; unknown values read as `Independent`.
    // kind = 1 -> Sobol, otherwise Independent (total, so GPU data can never be invalid).
    #[inline]
    pub fn from_u32(kind: u32) -> Self {
        if kind == Self::Sobol as u32 { Self::Sobol } else { Self::Independent }
    }
}

/// Per-pixel sample stream: which sample of which pixel, and the next dimension to draw.
///
/// Every value is a pure function of `(kind, seed, sample_index, dimension)`,
/// so the CPU and GPU draw bit-identical samples.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Pod, Zeroable)]
pub struct SampleStream {
    /// [`SequenceKind`] as `u32`.
    pub kind: u32,
    /// Pixel seed, `hash_combine(scene seed, pixel index)`.
    pub seed: u32,
    /// Index of the sample within the pixel.
    pub sample_index: u32,
    /// Next dimension to draw.
    pub dimension: u32,
}

impl SampleStream {
    /// Stream of sample `sample_index` of pixel `pixel`, starting at dimension 0.
    // seed = hash_combine(scene seed, pixel) (Burley 2020: one seed per pixel decorrelates pixels).
    #[inline]
    pub fn new(kind: SequenceKind, seed: u32, pixel: u32, sample_index: u32) -> Self {
        Self { kind: kind as u32, seed: hash_combine(seed, pixel), sample_index, dimension: 0 }
    }

    /// The sequence this stream draws from.
    // SequenceKind::from_u32(kind).
    #[inline]
    pub fn sequence_kind(&self) -> SequenceKind {
        SequenceKind::from_u32(self.kind)
    }

    /// Value of dimension `dim` of this sample as a 32-bit fraction, without advancing.
    // Independent: h(h(seed, sample), dim); Sobol: sobol_owen_u32(sample, dim, seed) (Burley 2020).
    #[inline]
    pub fn get_u32(&self, dim: u32) -> u32 {
        self.get_u32_with(&mut HashedSeeds, dim)
    }

    /// [`Self::get_u32`] with the scramble seeds taken from `seeds`.
    #[inline(always)]
    pub fn get_u32_with<S: ScrambleSeeds>(&self, seeds: &mut S, dim: u32) -> u32 {
        if self.kind == SequenceKind::Sobol as u32 {
            // sobol_owen_u32(sample_index, dim, seed), its seeds from `seeds`.
            let group = seeds.group(self.seed, dim >> 2);
            let reversed = shuffle_index_reversed(self.sample_index, group.seed());
            sobol_owen_scrambled(reversed, group.dim_seed(dim), dim)
        } else {
            hash_combine(hash_combine(self.seed, self.sample_index), dim)
        }
    }

    /// Next 1D value in `[0, 1)`; consumes one dimension.
    // u = u32_to_unit_f32(get_u32(dimension)); dimension += 1.
    #[inline]
    pub fn next_1d(&mut self) -> f32 {
        self.next_1d_with(&mut HashedSeeds)
    }

    /// [`Self::next_1d`] with the scramble seeds taken from `seeds`.
    #[inline(always)]
    pub fn next_1d_with<S: ScrambleSeeds>(&mut self, seeds: &mut S) -> f32 {
        let u = u32_to_unit_f32(self.get_u32_with(seeds, self.dimension));
        self.dimension = self.dimension.wrapping_add(1);
        u
    }

    /// Next 2D point in `[0, 1)^2`.
    ///
    /// Skips ahead to the first dimension of the next 4D group (unless already
    /// there) and consumes two dimensions, so that every 2D draw is Sobol'
    /// dimensions (0, 1) of a group: a (0, 2)-sequence whose first 2^m samples
    /// form a (0, m, 2)-net. (Joe & Kuo dimensions (2, 3) only give (1, m, 2)-nets,
    /// and a (2, 3, 2)-net at 8 samples.) Independent streams skip the same way.
    // d = 4 ceil(dimension / 4); p = (get(d), get(d + 1)); dimension = d + 2 (Burley 2020 padding; pbrt-v4).
    #[inline]
    pub fn next_2d(&mut self) -> Vec2 {
        self.next_2d_with(&mut HashedSeeds)
    }

    /// [`Self::next_2d`] with the scramble seeds taken from `seeds`.
    #[inline(always)]
    pub fn next_2d_with<S: ScrambleSeeds>(&mut self, seeds: &mut S) -> Vec2 {
        let d = self.dimension.wrapping_add(3) & !3;
        self.dimension = d.wrapping_add(2);
        let (x, y) = if self.kind == SequenceKind::Sobol as u32 {
            // Same bits as get_u32(d), get_u32(d + 1), with the index shuffled once.
            let group = seeds.group(self.seed, d >> 2);
            let reversed = shuffle_index_reversed(self.sample_index, group.seed());
            let d1 = d.wrapping_add(1);
            (
                sobol_owen_scrambled(reversed, group.dim_seed(d), d),
                sobol_owen_scrambled(reversed, group.dim_seed(d1), d1),
            )
        } else {
            (self.get_u32(d), self.get_u32(d.wrapping_add(1)))
        };
        Vec2::new(u32_to_unit_f32(x), u32_to_unit_f32(y))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sequence::counter::tests::{CHI2_63_P999, chi_square_64, correlation, serial_correlation};
    use crate::sequence::sobol::tests::{is_net, is_stratified};
    use std::vec::Vec;

    /// Top 24 bits of a float in [0, 1) back as a 32-bit fraction.
    fn to_u32(u: f32) -> u32 {
        ((u * 16_777_216.0) as u32) << 8
    }

    #[test]
    fn kind_round_trip() {
        assert_eq!(SequenceKind::from_u32(0), SequenceKind::Independent);
        assert_eq!(SequenceKind::from_u32(1), SequenceKind::Sobol);
        assert_eq!(SequenceKind::from_u32(7), SequenceKind::Independent);
        let s = SampleStream::new(SequenceKind::Sobol, 1, 2, 3);
        assert_eq!(s.sequence_kind(), SequenceKind::Sobol);
        assert_eq!((s.kind, s.sample_index, s.dimension), (1, 3, 0));
        assert_eq!(s.seed, hash_combine(1, 2));
    }

    #[test]
    fn dimension_bookkeeping() {
        for kind in [SequenceKind::Independent, SequenceKind::Sobol] {
            let mut s = SampleStream::new(kind, 5, 6, 7);
            let p = s.next_2d();
            assert_eq!(s.dimension, 2);
            let u = s.next_1d();
            assert_eq!(s.dimension, 3);
            let q = s.next_2d();
            assert_eq!(s.dimension, 6);
            s.next_2d();
            assert_eq!(s.dimension, 10);
            // Draws are pure functions of the dimension.
            assert_eq!(p.x, u32_to_unit_f32(s.get_u32(0)));
            assert_eq!(p.y, u32_to_unit_f32(s.get_u32(1)));
            assert_eq!(u, u32_to_unit_f32(s.get_u32(2)));
            assert_eq!(q, Vec2::new(u32_to_unit_f32(s.get_u32(4)), u32_to_unit_f32(s.get_u32(5))));
        }
        let mut s = SampleStream { dimension: u32::MAX, ..SampleStream::new(SequenceKind::Sobol, 0, 0, 0) };
        s.next_2d();
        assert_eq!(s.dimension, 2);
    }

    #[test]
    fn sobol_stream_is_stratified() {
        for pixel in [0, 1, 12345] {
            let m = 10;
            // Per sample: 2D, 1D, 2D, 2D -> dims (0,1), 2, (4,5), (8,9).
            let draws: Vec<[f32; 7]> = (0..1u32 << m)
                .map(|i| {
                    let mut s = SampleStream::new(SequenceKind::Sobol, 99, pixel, i);
                    let (a, b, c, d) = (s.next_2d(), s.next_1d(), s.next_2d(), s.next_2d());
                    [a.x, a.y, b, c.x, c.y, d.x, d.y]
                })
                .collect();
            for n in 0..=m {
                let pts = &draws[..1 << n];
                for (x, y) in [(0, 1), (3, 4), (5, 6)] {
                    let net: Vec<(u32, u32)> = pts.iter().map(|p| (to_u32(p[x]), to_u32(p[y]))).collect();
                    assert!(is_net(&net, n, 0), "pixel {pixel} m {n} dims {x},{y}");
                }
                let one: Vec<u32> = pts.iter().map(|p| to_u32(p[2])).collect();
                assert!(is_stratified(&one, n));
            }
        }
    }

    #[test]
    fn sobol_pixels_differ() {
        let point = |pixel| {
            let mut s = SampleStream::new(SequenceKind::Sobol, 0, pixel, 0);
            s.next_2d()
        };
        let pts: Vec<Vec2> = (0..64).map(point).collect();
        for (i, p) in pts.iter().enumerate() {
            assert!(pts[i + 1..].iter().all(|q| q != p), "pixel {i} repeats");
        }
        // Pixels' first samples cover the square uniformly, not one stratum.
        let pts: Vec<Vec2> = (0..100_000).map(point).collect();
        assert!(chi_square_64(pts.iter().map(|p| p.x)) < CHI2_63_P999);
        assert!(chi_square_64(pts.iter().map(|p| p.y)) < CHI2_63_P999);
        assert!(
            correlation(&pts.iter().map(|p| p.x).collect::<Vec<_>>(), &pts.iter().map(|p| p.y).collect::<Vec<_>>())
                .abs()
                < 0.015
        );
    }

    #[test]
    fn independent_uniform() {
        let mut values = Vec::with_capacity(100_000);
        for pixel in 0..100 {
            for sample in 0..100 {
                let mut s = SampleStream::new(SequenceKind::Independent, 3, pixel, sample);
                for _ in 0..5 {
                    let p = s.next_2d();
                    values.push(p.x);
                    values.push(p.y);
                }
            }
        }
        let chi2 = chi_square_64(values.iter().copied());
        assert!(chi2 < CHI2_63_P999, "chi2 {chi2}");
        let rho = serial_correlation(&values);
        assert!(rho.abs() < 0.015, "serial correlation {rho}");
        // Same dimension of consecutive samples.
        let d0: Vec<f32> = values.iter().step_by(10).copied().collect();
        let rho = serial_correlation(&d0);
        assert!(rho.abs() < 0.05, "sample-to-sample correlation {rho}");
        let d1: Vec<f32> = values.iter().skip(1).step_by(10).copied().collect();
        let rho = correlation(&d0, &d1);
        assert!(rho.abs() < 0.05, "x-y correlation {rho}");
    }

    #[test]
    fn golden_vectors() {
        let draws = |kind| {
            let mut s = SampleStream::new(kind, 7, 3, 5);
            let (a, b, c) = (s.next_1d(), s.next_2d(), s.next_1d());
            [a, b.x, b.y, c].map(f32::to_bits)
        };
        // Frozen draws (1D at dim 0, 2D at dims 4, 5, 1D at dim 6) of sample 5 of
        // pixel 3 under seed 7; the WGSL port must reproduce them bit for bit.
        assert_eq!(SampleStream::new(SequenceKind::Sobol, 7, 3, 5).seed, 0x055b_3aff);
        assert_eq!(draws(SequenceKind::Independent), [0x3f64_49de, 0x3ebe_701a, 0x3f70_0cec, 0x3dc8_83b8]);
        assert_eq!(draws(SequenceKind::Sobol), [0x3f11_29f4, 0x3f06_bba3, 0x3e99_307c, 0x3ece_6a46]);
    }
}
