//! Sobol' sequence in 4 dimensions with hash-based Owen scrambling and index
//! shuffling (Burley 2020, "Practical Hash-based Owen Scrambling").

use super::hash::{hash_combine, u32_to_unit_f32};

/// Number of Sobol' dimensions in one group; `sobol` wraps `dim` modulo this.
pub const SOBOL_DIMENSIONS: u32 = 4;

/// Direction words of the dimension with primitive polynomial degree `s`, inner coefficients `a`, initial `m`.
// v_k = m_k 2^(32-k), m_k = 2a_1 m_{k-1} ^ .. ^ 2^s m_{k-s} ^ m_{k-s} (Bratley & Fox 1988; Joe & Kuo 2008).
const fn directions(s: usize, a: u32, m: [u32; 3]) -> [u32; 32] {
    let mut v = [0u32; 32];
    let mut i = 0;
    while i < 32 {
        v[i] = if i < s {
            m[i] << (31 - i)
        } else {
            let mut w = v[i - s] ^ (v[i - s] >> s);
            let mut k = 1;
            while k < s {
                if (a >> (s - 1 - k)) & 1 != 0 {
                    w ^= v[i - k];
                }
                k += 1;
            }
            w
        };
        i += 1;
    }
    v
}

/// Direction words of dimension 0, the van der Corput sequence.
// Van der Corput generator: v_k = 2^(32-k), the identity matrix (Sobol' 1967, dimension 1).
const fn van_der_corput() -> [u32; 32] {
    let mut v = [0u32; 32];
    let mut i = 0;
    while i < 32 {
        v[i] = 1 << (31 - i);
        i += 1;
    }
    v
}

/// Direction words of Sobol' dimensions 0..4: van der Corput, then the first three
/// polynomials of Joe & Kuo's `new-joe-kuo-6.21201` table.
pub const SOBOL_DIRECTIONS: [[u32; 32]; 4] =
    [van_der_corput(), directions(1, 0, [1, 0, 0]), directions(2, 1, [1, 3, 0]), directions(3, 1, [1, 3, 1])];

/// Bit-reversed direction numbers in reversed order: `R[d][j] = reverse(V[d][31 - j])`, so
/// that `reverse(sobol(reverse(r), d))` is the XOR of `R[d][j]` over the set bits `j` of `r`.
/// Lets the Owen-scrambled point skip two of its four bit reversals (x86 has no bit-reverse
/// instruction); the results are bit-identical.
const SOBOL_DIRECTIONS_REVERSED: [[u32; 32]; 4] = reverse_tables(SOBOL_DIRECTIONS);

const fn reverse_tables(v: [[u32; 32]; 4]) -> [[u32; 32]; 4] {
    let mut out = [[0u32; 32]; 4];
    let mut d = 0;
    while d < 4 {
        let mut j = 0;
        while j < 32 {
            out[d][j] = v[d][31 - j].reverse_bits();
            j += 1;
        }
        d += 1;
    }
    out
}

/// [`SOBOL_DIRECTIONS_REVERSED`] by bytes: `T[d][k][b]` is the XOR of `R[d][8k + j]` over the
/// set bits `j` of `b`, so the XOR over the set bits of a 32-bit `r` is four lookups,
/// `T[d][0][r & 255] ^ T[d][1][(r >> 8) & 255] ^ ...`, instead of a loop over up to 32 bits
/// (16 KiB; the same bits as the loop, which the GPU keeps).
static SOBOL_BYTE_TABLES: [[[u32; 256]; 4]; 4] = byte_tables(SOBOL_DIRECTIONS_REVERSED);

const fn byte_tables(r: [[u32; 32]; 4]) -> [[[u32; 256]; 4]; 4] {
    let mut out = [[[0u32; 256]; 4]; 4];
    let mut d = 0;
    while d < 4 {
        let mut k = 0;
        while k < 4 {
            let mut b = 0;
            while b < 256 {
                let mut x = 0;
                let mut j = 0;
                while j < 8 {
                    if (b >> j) & 1 != 0 {
                        x ^= r[d][8 * k + j];
                    }
                    j += 1;
                }
                out[d][k][b] = x;
                b += 1;
            }
            k += 1;
        }
        d += 1;
    }
    out
}

/// XOR of `R[dim & 3][j]` over the set bits `j` of `bits`, by four byte lookups.
#[inline(always)]
fn xor_reversed_directions(dim: u32, bits: u32) -> u32 {
    let t = &SOBOL_BYTE_TABLES[(dim & 3) as usize];
    t[0][(bits & 255) as usize]
        ^ t[1][((bits >> 8) & 255) as usize]
        ^ t[2][((bits >> 16) & 255) as usize]
        ^ t[3][(bits >> 24) as usize]
}

/// XOR of `table[j]` over the set bits `j` of `bits`.
#[inline(always)]
fn xor_set_bits(table: &[u32; 32], bits: u32) -> u32 {
    let mut x = 0;
    let mut bits = bits;
    while bits != 0 {
        x ^= table.get(bits.trailing_zeros() as usize).copied().unwrap_or(0);
        bits &= bits - 1;
    }
    x
}

/// Sobol' point `index` in dimension `dim % 4`, as a 32-bit fraction of 2^32.
///
/// Direct (non Gray code) order: the first 2^m points are the same set as
/// Gray-code order, and dimension 0 is `index.reverse_bits()`.
// x = XOR of v_k over the set bits k of index (Sobol' 1967; Joe & Kuo 2008).
#[inline]
pub fn sobol(index: u32, dim: u32) -> u32 {
    xor_set_bits(&SOBOL_DIRECTIONS[(dim & 3) as usize], index)
}

/// Nested uniform (Owen) scramble of a 32-bit fraction.
///
/// Each bit is flipped by a hash of `seed` and all the more significant bits,
/// so it is a bijection on `u32` that keeps every (t, m, s)-net a (t, m, s)-net.
/// `seed` should be a well-mixed hash.
// reverse(LK(reverse(x), seed)), LK = x += seed then 4 rounds x ^= x * even_k (Laine & Karras 2011; Burley 2020).
#[inline]
pub fn owen_scramble(x: u32, seed: u32) -> u32 {
    laine_karras(x.reverse_bits(), seed).reverse_bits()
}

/// The hash-based nested-uniform permutation on bit-reversed values (Burley 2020's
/// constants): `v += seed`, then `v ^= v * c` for four constants.
#[inline(always)]
fn laine_karras(v: u32, seed: u32) -> u32 {
    let mut x = v.wrapping_add(seed);
    x ^= x.wrapping_mul(0x6c50_b47c);
    x ^= x.wrapping_mul(0xb82f_1e52);
    x ^= x.wrapping_mul(0xc7af_e638);
    x ^= x.wrapping_mul(0x8d22_f6e6);
    x
}

/// Owen-scrambled, index-shuffled Sobol' point as a 32-bit fraction.
///
/// Dimensions are taken in groups of 4 (`dim / 4`); each group has its own
/// index shuffle and scrambles, so groups are independent padded 4D sets.
// g = h(seed, dim / 4); x = owen(sobol(owen(index, g), dim % 4), h(g, dim % 4)) (Burley 2020, shuffled scrambled Sobol').
#[inline]
pub fn sobol_owen_u32(index: u32, dim: u32, seed: u32) -> u32 {
    let group_seed = hash_combine(seed, dim >> 2);
    sobol_owen_shuffled(laine_karras(index.reverse_bits(), group_seed), group_seed, dim)
}

/// The second half of [`sobol_owen_u32`] for an index already shuffled and *kept in
/// bit-reversed form* (`reversed = reverse(owen_scramble(index, group_seed))`), so a 2D draw
/// shuffles its index once for both dimensions and skips the reversals that cancel.
// reverse(LK(XOR of R[dim & 3][j] over set bits j of reversed, hash_combine(group_seed, dim & 3))).
#[inline]
pub fn sobol_owen_shuffled(reversed: u32, group_seed: u32, dim: u32) -> u32 {
    sobol_owen_scrambled(reversed, hash_combine(group_seed, dim & 3), dim)
}

/// [`sobol_owen_shuffled`] with its scramble seed `hash_combine(group_seed, dim & 3)` given,
/// so a caller that keeps the seeds of a pixel hashes them once.
// reverse(LK(XOR of R[dim & 3][j] over set bits j of reversed, dim_seed)).
#[inline]
pub(crate) fn sobol_owen_scrambled(reversed: u32, dim_seed: u32, dim: u32) -> u32 {
    let point = xor_reversed_directions(dim, reversed);
    laine_karras(point, dim_seed).reverse_bits()
}

/// `reverse(owen_scramble(index, group_seed))`: the shuffled index in the bit-reversed form
/// [`sobol_owen_shuffled`] takes.
#[inline]
pub fn shuffle_index_reversed(index: u32, group_seed: u32) -> u32 {
    laine_karras(index.reverse_bits(), group_seed)
}

/// Owen-scrambled, index-shuffled Sobol' point in `[0, 1)`: [`sobol_owen_u32`] as f32.
// u = u32_to_unit_f32(sobol_owen_u32(index, dim, seed)) (Burley 2020).
#[inline]
pub fn sobol_owen(index: u32, dim: u32, seed: u32) -> f32 {
    u32_to_unit_f32(sobol_owen_u32(index, dim, seed))
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use std::vec;
    use std::vec::Vec;

    #[test]
    fn byte_tables_are_the_set_bit_loop() {
        let mut x = 0x9e37_79b9u32;
        for i in 0..200_000u32 {
            x = x.wrapping_mul(0x2c1b_3c6d).wrapping_add(0x297a_2d39) ^ i;
            for bits in [x, i, !i, 1 << (i % 32), 0] {
                for d in 0..4 {
                    let looped = xor_set_bits(&SOBOL_DIRECTIONS_REVERSED[d as usize], bits);
                    assert_eq!(xor_reversed_directions(d, bits), looped, "dim {d} bits {bits:#x}");
                }
            }
        }
    }

    /// Top `bits` bits of a 32-bit fraction (0 when `bits == 0`).
    fn top(x: u32, bits: u32) -> u32 {
        if bits == 0 { 0 } else { x >> (32 - bits) }
    }

    /// Whether the 2^m points form a (t, m, 2)-net: every elementary interval of
    /// area 2^(t-m) holds exactly 2^t points.
    pub(crate) fn is_net(points: &[(u32, u32)], m: u32, t: u32) -> bool {
        assert_eq!(points.len(), 1 << m);
        let k = m - t;
        (0..=k).all(|a| {
            let mut count = vec![0u32; 1 << k];
            for &(x, y) in points {
                count[((top(x, a) << (k - a)) | top(y, k - a)) as usize] += 1;
            }
            count.iter().all(|&c| c == 1 << t)
        })
    }

    /// Whether 2^m values are stratified in 1D: one per interval of length 2^-m.
    pub(crate) fn is_stratified(values: &[u32], m: u32) -> bool {
        let mut count = vec![0u32; 1 << m];
        for &x in values {
            count[top(x, m) as usize] += 1;
        }
        count.iter().all(|&c| c == 1)
    }

    /// Smallest t such that the first 2^m points of dims (d0, d1) are a (t, m, 2)-net.
    fn t_value(d0: u32, d1: u32, m: u32) -> u32 {
        let points: Vec<(u32, u32)> = (0..1u32 << m).map(|i| (sobol(i, d0), sobol(i, d1))).collect();
        (0..=m).find(|&t| is_net(&points, m, t)).unwrap()
    }

    #[test]
    fn directions_match_joe_kuo() {
        // First and last 4 direction words of dims 1..3 as tabulated from
        // new-joe-kuo-6.21201 (e.g. pbrt-v3's SobolMatrices32).
        let reference: [[u32; 8]; 3] = [
            [0x8000_0000, 0xc000_0000, 0xa000_0000, 0xf000_0000, 0x8888_8888, 0xcccc_cccc, 0xaaaa_aaaa, 0xffff_ffff],
            [0x8000_0000, 0xc000_0000, 0x6000_0000, 0x9000_0000, 0xe800_6868, 0x5c00_9c9c, 0x8e00_eeee, 0xc500_5555],
            [0x8000_0000, 0xc000_0000, 0x2000_0000, 0x5000_0000, 0x8008_00f8, 0xc00c_0074, 0x2002_00a2, 0x5005_0093],
        ];
        for (v, r) in SOBOL_DIRECTIONS[1..].iter().zip(reference) {
            assert_eq!(v[..4], r[..4]);
            assert_eq!(v[28..], r[4..]);
        }
        for (k, &v) in SOBOL_DIRECTIONS[0].iter().enumerate() {
            assert_eq!(v, 0x8000_0000 >> k);
        }
    }

    #[test]
    fn dim0_is_bit_reversal() {
        for i in (0..1u32 << 12).chain([u32::MAX, 0x8000_0000, 0x1234_5678]) {
            assert_eq!(sobol(i, 0), i.reverse_bits());
        }
        assert_eq!(sobol(5, 4), sobol(5, 0));
        assert_eq!(sobol(5, 7), sobol(5, 3));
    }

    #[test]
    fn sobol_first_points() {
        // Classic Sobol' points (index order), dims 0..3, as fractions of 8.
        let p: Vec<[u32; 4]> = (0..4).map(|i| core::array::from_fn(|d| sobol(i, d as u32) >> 29)).collect();
        assert_eq!(p, [[0, 0, 0, 0], [4, 4, 4, 4], [2, 6, 6, 6], [6, 2, 2, 2]]);
    }

    #[test]
    fn golden_vectors() {
        // Frozen (index, dim, seed) -> sobol_owen_u32, sobol_owen bits; the WGSL
        // port must reproduce them bit for bit.
        let cases: [(u32, u32, u32, u32, u32); 10] = [
            (0, 0, 0, 0x2575_091e, 0x3e15_d424),
            (1, 0, 0, 0xe777_e3b6, 0x3f67_77e3),
            (1, 1, 0, 0xb5ed_80e4, 0x3f35_ed80),
            (2, 2, 0, 0x1ead_74d0, 0x3df5_6ba0),
            (3, 3, 0, 0x1eb2_b6df, 0x3df5_95b0),
            (5, 4, 0, 0x99e0_f596, 0x3f19_e0f5),
            (5, 7, 0, 0x5409_108b, 0x3ea8_1220),
            (123, 2, 42, 0x0605_cd7b, 0x3cc0_b9a0),
            (1000, 9, 0xdead_beef, 0xd024_db1a, 0x3f50_24db),
            (u32::MAX, 5, 7, 0xb2af_6975, 0x3f32_af69),
        ];
        for (index, dim, seed, x, bits) in cases {
            assert_eq!(sobol_owen_u32(index, dim, seed), x, "({index}, {dim}, {seed})");
            assert_eq!(sobol_owen(index, dim, seed).to_bits(), bits, "({index}, {dim}, {seed})");
        }
        assert_eq!(owen_scramble(0x1234_5678, 0x9abc_def0), 0x180f_3b55);
    }

    #[test]
    fn sobol_nets() {
        for m in 0..=10 {
            // Dims (0, 1) are a (0, 2)-sequence: every 2^m prefix is a (0, m, 2)-net.
            assert_eq!(t_value(0, 1, m), 0, "m {m}");
            // Dims (2, 3) are not: t is 1 (2 at m = 3), but each dim alone is stratified.
            assert_eq!(t_value(2, 3, m), [0, 0, 1, 2, 0, 1, 1, 1, 1, 1, 1][m as usize], "m {m}");
            for d in 0..4 {
                let v: Vec<u32> = (0..1u32 << m).map(|i| sobol(i, d)).collect();
                assert!(is_stratified(&v, m), "dim {d} m {m}");
            }
        }
        // Any aligned block of 2^m indices is a net too (used by the index shuffle).
        let block: Vec<(u32, u32)> = (0..1u32 << 8).map(|i| (sobol(0x5a00 + i, 0), sobol(0x5a00 + i, 1))).collect();
        assert!(is_net(&block, 8, 0));
    }

    #[test]
    fn owen_scramble_is_bijective() {
        for seed in [0, 1, 0x9e37_79b9, u32::MAX] {
            for inputs in [0..1u32 << 16, (1u32 << 16)..(1u32 << 17)] {
                for shift in [0, 8, 16] {
                    let mut v: Vec<u32> = inputs.clone().map(|x| owen_scramble(x << shift, seed)).collect();
                    v.sort_unstable();
                    v.dedup();
                    assert_eq!(v.len(), 1 << 16, "seed {seed:#x} shift {shift}");
                }
            }
        }
    }

    #[test]
    fn owen_scramble_is_nested() {
        // Points sharing their top k bits still share them after scrambling, and
        // the remaining bits are permuted: a nested uniform scramble.
        let seed = 0x1234_5678;
        for k in [1, 4, 13, 31] {
            let prefix = 0xb6d1_4f3au32 & !(u32::MAX >> k);
            let low = |i: u32| prefix | (i.wrapping_mul(0x9e37_79b9) >> k);
            let t = owen_scramble(prefix, seed) & !(u32::MAX >> k);
            assert!((0..256).all(|i| owen_scramble(low(i), seed) & !(u32::MAX >> k) == t));
        }
    }

    #[test]
    fn owen_scramble_changes_values() {
        let points = |seed: u32| -> Vec<u32> { (0..256).map(|i| owen_scramble(sobol(i, 1), seed)).collect() };
        let unscrambled: Vec<u32> = (0..256).map(|i| sobol(i, 1)).collect();
        let seeds = [0x2545_f491, 0x9e37_79b9, 0xdead_beef, 0x0bad_cafe];
        for (i, &a) in seeds.iter().enumerate() {
            let pa = points(a);
            assert!(pa.iter().zip(&unscrambled).filter(|(x, y)| x != y).count() > 250);
            for &b in &seeds[i + 1..] {
                let pb = points(b);
                assert!(pa.iter().zip(&pb).filter(|(x, y)| x != y).count() > 250, "{a:#x} vs {b:#x}");
            }
        }
    }

    #[test]
    fn owen_scramble_preserves_nets() {
        for seed in [0u32, 1, 0x2545_f491, 0x9e37_79b9, 0xdead_beef] {
            let (s0, s1) = (hash_combine(seed, 0), hash_combine(seed, 1));
            for m in 0..=10 {
                let pts: Vec<(u32, u32)> =
                    (0..1u32 << m).map(|i| (owen_scramble(sobol(i, 0), s0), owen_scramble(sobol(i, 1), s1))).collect();
                assert!(is_net(&pts, m, 0), "seed {seed:#x} m {m}");
                let pts: Vec<(u32, u32)> =
                    (0..1u32 << m).map(|i| (owen_scramble(sobol(i, 2), s0), owen_scramble(sobol(i, 3), s1))).collect();
                assert!(is_net(&pts, m, [0, 0, 1, 2, 0, 1, 1, 1, 1, 1, 1][m as usize]));
            }
        }
    }

    #[test]
    fn sobol_owen_nets() {
        // Shuffled + scrambled: dims (4g, 4g+1) stay (0, m, 2)-nets, every dim stays
        // stratified, for every prefix of 2^m samples.
        for seed in [0u32, 7, 0xdead_beef] {
            for m in 0..=10 {
                for g in [0, 1, 5] {
                    let pts: Vec<(u32, u32)> = (0..1u32 << m)
                        .map(|i| (sobol_owen_u32(i, 4 * g, seed), sobol_owen_u32(i, 4 * g + 1, seed)))
                        .collect();
                    assert!(is_net(&pts, m, 0), "seed {seed:#x} m {m} group {g}");
                    for d in 4 * g..4 * g + 4 {
                        let v: Vec<u32> = (0..1u32 << m).map(|i| sobol_owen_u32(i, d, seed)).collect();
                        assert!(is_stratified(&v, m), "seed {seed:#x} m {m} dim {d}");
                    }
                }
            }
        }
    }

    #[test]
    fn sobol_owen_groups_differ() {
        // Group 1 is not a copy of group 0, and seeds decorrelate the same dim.
        let n = 1024;
        let same = |a: &dyn Fn(u32) -> u32, b: &dyn Fn(u32) -> u32| (0..n).filter(|&i| a(i) == b(i)).count();
        assert!(same(&|i| sobol_owen_u32(i, 0, 3), &|i| sobol_owen_u32(i, 4, 3)) < 4);
        assert!(same(&|i| sobol_owen_u32(i, 1, 3), &|i| sobol_owen_u32(i, 5, 3)) < 4);
        assert!(same(&|i| sobol_owen_u32(i, 0, 3), &|i| sobol_owen_u32(i, 0, 4)) < 4);
        // Never 1.0.
        assert!(sobol_owen(u32::MAX, 3, u32::MAX) < 1.0);
        assert!((0..n).all(|i| sobol_owen(i, i, i) < 1.0));
    }
}
