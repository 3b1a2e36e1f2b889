//! Counter-based random number generator: output n is a pure function of (key, n).

use bytemuck::{Pod, Zeroable};
use glam::Vec2;

use super::hash::{hash_combine, u32_to_unit_f32};

/// Counter-based independent generator: output `n` is a pure function of
/// `(key, n)`, so any sample of any pixel is addressable on CPU and GPU alike.
///
/// Output `n` is `hash_combine(key, n)`, a bijection of `n` for a fixed key:
/// a stream never repeats within its 2^32 outputs.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Pod, Zeroable)]
pub struct CounterRng {
    /// Stream key, `hash_combine(seed, stream)`.
    pub key: u32,
    /// Index of the next output (wraps after 2^32 outputs).
    pub counter: u32,
}

impl CounterRng {
    /// Creates the generator of `stream` under `seed`, at counter 0.
    // key = hash_combine(seed, stream) (Salmon et al. 2011, "Parallel Random Numbers: As Easy as 1, 2, 3").
    #[inline]
    pub fn new(seed: u32, stream: u32) -> Self {
        Self { key: hash_combine(seed, stream), counter: 0 }
    }

    /// Returns output `counter` without advancing.
    // x_n = hash_combine(key, n) (Salmon et al. 2011, counter-based RNG; Wellons 2018 lowbias32 rounds).
    #[inline]
    pub fn get_u32(&self, counter: u32) -> u32 {
        hash_combine(self.key, counter)
    }

    /// Next 32 random bits.
    // x = hash_combine(key, counter); counter += 1 mod 2^32 (Salmon et al. 2011).
    #[inline]
    pub fn next_u32(&mut self) -> u32 {
        let x = self.get_u32(self.counter);
        self.counter = self.counter.wrapping_add(1);
        x
    }

    /// Next float in `[0, 1)` (24 random bits, never 1.0).
    // u = (next_u32 >> 8) * 2^-24 (exact, see `u32_to_unit_f32`).
    #[inline]
    pub fn next_f32(&mut self) -> f32 {
        u32_to_unit_f32(self.next_u32())
    }

    /// Next point in `[0, 1)^2`, x drawn before y.
    // (u0, u1) = (next_f32, next_f32) (two consecutive counters).
    #[inline]
    pub fn next_vec2(&mut self) -> Vec2 {
        let x = self.next_f32();
        let y = self.next_f32();
        Vec2::new(x, y)
    }

    /// Moves the counter by `delta` outputs (wrapping, may be "negative").
    // counter += delta mod 2^32 (counter-based RNGs skip in O(1), Salmon et al. 2011).
    #[inline]
    pub fn advance(&mut self, delta: u32) {
        self.counter = self.counter.wrapping_add(delta);
    }
}

#[cfg(not(target_arch = "spirv"))]
mod rand_impls {
    use core::convert::Infallible;

    use rand_core::{SeedableRng, TryRng, utils};

    use super::CounterRng;

    impl TryRng for CounterRng {
        type Error = Infallible;

        // x = hash_combine(key, counter); counter += 1 (see `CounterRng::next_u32`).
        #[inline]
        fn try_next_u32(&mut self) -> Result<u32, Infallible> {
            Ok(CounterRng::next_u32(self))
        }

        // (hi << 32) | lo with lo drawn first (rand_core little-endian convention).
        #[inline]
        fn try_next_u64(&mut self) -> Result<u64, Infallible> {
            utils::next_u64_via_u32(self)
        }

        // Consecutive next_u32 words as little-endian bytes, the last one truncated.
        #[inline]
        fn try_fill_bytes(&mut self, dst: &mut [u8]) -> Result<(), Infallible> {
            utils::fill_bytes_via_next_word(dst, || self.try_next_u32())
        }
    }

    impl SeedableRng for CounterRng {
        /// `seed` then `stream`, each a little-endian `u32`.
        type Seed = [u8; 8];

        // CounterRng::new(le(seed[0..4]), le(seed[4..8])).
        #[inline]
        fn from_seed(seed: [u8; 8]) -> Self {
            let [s0, s1, s2, s3, t0, t1, t2, t3] = seed;
            Self::new(u32::from_le_bytes([s0, s1, s2, s3]), u32::from_le_bytes([t0, t1, t2, t3]))
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use rand_core::{Rng, SeedableRng};
    use std::vec::Vec;

    /// Chi-square statistic of `values` in [0, 1) over 64 equal buckets.
    pub(crate) fn chi_square_64(values: impl Iterator<Item = f32>) -> f64 {
        let mut count = [0u32; 64];
        let mut n = 0u32;
        for u in values {
            assert!((0.0..1.0).contains(&u), "{u} outside [0, 1)");
            count[(u * 64.0) as usize] += 1;
            n += 1;
        }
        let expected = n as f64 / 64.0;
        count.iter().map(|&c| (c as f64 - expected).powi(2) / expected).sum()
    }

    /// Pearson correlation of two equally long samples.
    pub(crate) fn correlation(a: &[f32], b: &[f32]) -> f64 {
        let mean = |s: &[f32]| s.iter().map(|&x| x as f64).sum::<f64>() / s.len() as f64;
        let (ma, mb) = (mean(a), mean(b));
        let (mut sab, mut saa, mut sbb) = (0.0, 0.0, 0.0);
        for (&x, &y) in a.iter().zip(b) {
            let (dx, dy) = (x as f64 - ma, y as f64 - mb);
            sab += dx * dy;
            saa += dx * dx;
            sbb += dy * dy;
        }
        sab / (saa * sbb).sqrt()
    }

    /// Pearson correlation of consecutive values.
    pub(crate) fn serial_correlation(v: &[f32]) -> f64 {
        correlation(&v[..v.len() - 1], &v[1..])
    }

    /// 0.999 quantile of chi-square with 63 degrees of freedom.
    pub(crate) const CHI2_63_P999: f64 = 103.44;

    #[test]
    fn golden_vectors() {
        // Frozen outputs; the WGSL port must reproduce them bit for bit.
        let mut r = CounterRng::new(0, 0);
        assert_eq!(r.key, 0xae6f_80f1);
        let u: [u32; 4] = core::array::from_fn(|_| r.next_u32());
        assert_eq!(u, [0x22fd_b629, 0x6a5a_fcd6, 0xaffd_37f9, 0x71db_b9d7]);
        let mut r = CounterRng::new(7, 3);
        assert_eq!(r.key, 0x055b_3aff);
        let u: [u32; 4] = core::array::from_fn(|_| r.next_u32());
        assert_eq!(u, [0x2263_985c, 0x0dd9_f64f, 0xf4a8_cc93, 0xa4a6_1b49]);
        let mut r = CounterRng::new(7, 3);
        let f: [u32; 4] = core::array::from_fn(|_| r.next_f32().to_bits());
        assert_eq!(f, [0x3e09_8e60, 0x3d5d_9f60, 0x3f74_a8cc, 0x3f24_a61b]);
        let mut r = CounterRng::new(0, 0);
        let v = r.next_vec2();
        assert_eq!([v.x.to_bits(), v.y.to_bits()], [0x3e0b_f6d8, 0x3ed4_b5f8]);
    }

    #[test]
    fn counter_is_addressable() {
        let mut r = CounterRng::new(42, 9);
        let seq: Vec<u32> = (0..100).map(|_| r.next_u32()).collect();
        assert_eq!(r.counter, 100);
        let mut s = CounterRng::new(42, 9);
        s.advance(37);
        assert_eq!(s.next_u32(), seq[37]);
        assert_eq!(s.get_u32(99), seq[99]);
        let mut w = CounterRng { key: r.key, counter: u32::MAX };
        w.next_u32();
        assert_eq!(w.counter, 0);
        assert_eq!(w.next_u32(), seq[0]);
    }

    #[test]
    fn rand_core_traits() {
        let mut a = CounterRng::new(7, 3);
        let mut b = a;
        let (lo, hi) = (b.next_u32(), b.next_u32());
        assert_eq!(Rng::next_u64(&mut a), (hi as u64) << 32 | lo as u64);
        let mut bytes = [0u8; 10];
        Rng::fill_bytes(&mut a, &mut bytes);
        let (w0, w1, w2) = (b.next_u32(), b.next_u32(), b.next_u32());
        assert_eq!(bytes[..4], w0.to_le_bytes());
        assert_eq!(bytes[4..8], w1.to_le_bytes());
        assert_eq!(bytes[8..], w2.to_le_bytes()[..2]);
        assert_eq!(a, b);
        let s = CounterRng::from_seed([7, 0, 0, 0, 3, 0, 0, 0]);
        assert_eq!(s, CounterRng::new(7, 3));
        assert_eq!(
            CounterRng::from_seed(*b"\x01\x02\x03\x04\x05\x06\x07\x08"),
            CounterRng::new(0x0403_0201, 0x0807_0605)
        );
    }

    #[test]
    fn uniform_chi_square() {
        for (seed, stream) in [(0, 0), (7, 3), (u32::MAX, 1)] {
            let mut r = CounterRng::new(seed, stream);
            let chi2 = chi_square_64((0..100_000).map(|_| r.next_f32()));
            assert!(chi2 < CHI2_63_P999, "chi2 {chi2} for ({seed}, {stream})");
        }
    }

    #[test]
    fn low_bits_uniform() {
        // The low 6 bits alone (not used by next_f32) are uniform too.
        let mut r = CounterRng::new(1, 2);
        let chi2 = chi_square_64((0..100_000).map(|_| (r.next_u32() & 63) as f32 / 64.0));
        assert!(chi2 < CHI2_63_P999, "chi2 {chi2}");
    }

    #[test]
    fn no_serial_correlation() {
        let mut r = CounterRng::new(3, 4);
        let v: Vec<f32> = (0..100_000).map(|_| r.next_f32()).collect();
        let rho = serial_correlation(&v);
        assert!(rho.abs() < 0.015, "serial correlation {rho}");
        // Neighbouring streams are uncorrelated with each other.
        let (mut p, mut q) = (CounterRng::new(3, 5), CounterRng::new(3, 6));
        let a: Vec<f32> = (0..100_000).map(|_| p.next_f32()).collect();
        let b: Vec<f32> = (0..100_000).map(|_| q.next_f32()).collect();
        let cross = correlation(&a, &b);
        assert!(cross.abs() < 0.015, "cross correlation {cross}");
    }

    #[test]
    fn never_one() {
        for key in [0, 1, 0xffff_ffff] {
            let mut r = CounterRng { key, counter: 0 };
            for _ in 0..100_000 {
                let v = r.next_vec2();
                assert!(v.x < 1.0 && v.y < 1.0 && v.x >= 0.0 && v.y >= 0.0);
            }
        }
    }
}
