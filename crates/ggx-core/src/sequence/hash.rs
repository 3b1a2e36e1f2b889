//! Stateless 32-bit integer hashes and the u32 -> [0, 1) float mapping.

/// 32-bit integer hash with good avalanche: Wellons' `lowbias32`.
///
/// A bijection on `u32` (each step is invertible); `hash_u32(0) == 0`.
// x ^= x >> 16; x *= 0x7feb352d; x ^= x >> 15; x *= 0x846ca68b; x ^= x >> 16 (Wellons 2018, lowbias32).
#[inline]
pub fn hash_u32(x: u32) -> u32 {
    let mut x = x;
    x ^= x >> 16;
    x = x.wrapping_mul(0x7feb_352d);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846c_a68b);
    x ^= x >> 16;
    x
}

/// Combines two words into one hash (order-dependent).
///
/// For a fixed `a` the map `b -> hash_combine(a, b)` is a bijection, so a key
/// never repeats an output over its 2^32 counters.
// h(a ^ h(a ^ b ^ 0x9e3779b9)), h = lowbias32: two rounds keyed by a (Wellons 2018; Boost golden-ratio offset).
#[inline]
pub fn hash_combine(a: u32, b: u32) -> u32 {
    hash_u32(a ^ hash_u32(a ^ b ^ 0x9e37_79b9))
}

/// Maps the top 24 bits of `x` to `[0, 1)`: `(x >> 8) as f32 * 2^-24`.
///
/// Exact (24 bits fit the f32 mantissa), so it never rounds up to 1.0.
// u = floor(x / 2^8) 2^-24: exact 24-bit fixed point, so no rounding up to 1 (cf. pbrt-v4's min(x 2^-32, 1 - ulp)).
#[inline]
pub fn u32_to_unit_f32(x: u32) -> f32 {
    (x >> 8) as f32 * (1.0 / 16_777_216.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::vec::Vec;

    #[test]
    fn unit_f32_range() {
        assert!(u32_to_unit_f32(u32::MAX) < 1.0);
        assert_eq!(u32_to_unit_f32(u32::MAX), 1.0 - 1.0 / 16_777_216.0);
        assert_eq!(u32_to_unit_f32(0), 0.0);
        assert_eq!(u32_to_unit_f32(0x8000_0000), 0.5);
        assert_eq!(u32_to_unit_f32(0xff), 0.0);
    }

    #[test]
    fn hash_golden() {
        // Frozen values, cross-checked against an independent Python implementation.
        assert_eq!(hash_u32(0), 0);
        let got: Vec<u32> = (1..5).map(hash_u32).collect();
        assert_eq!(got, [0x6889_90c0, 0xd113_2181, 0x53f1_e9dd, 0xd97e_5ed1]);
        assert_eq!(hash_combine(0, 0), 0xae6f_80f1);
        assert_eq!(hash_combine(7, 3), 0x055b_3aff);
    }

    #[test]
    fn hash_is_bijective_on_sample() {
        let mut v: Vec<u32> = (0..1u32 << 16).map(|i| hash_u32(i.wrapping_mul(0x9e37_79b9))).collect();
        v.sort_unstable();
        v.dedup();
        assert_eq!(v.len(), 1 << 16);
    }

    #[test]
    fn hash_avalanche() {
        // Flipping one input bit flips each output bit with probability ~1/2.
        let mut flips = [[0u32; 32]; 32];
        let n = 4096u32;
        for i in 0..n {
            let x = hash_u32(i ^ 0xdead_beef);
            let h = hash_u32(x);
            for (j, row) in flips.iter_mut().enumerate() {
                let d = h ^ hash_u32(x ^ (1 << j));
                for (k, c) in row.iter_mut().enumerate() {
                    *c += (d >> k) & 1;
                }
            }
        }
        for row in &flips {
            for &c in row {
                let p = c as f64 / n as f64;
                assert!((p - 0.5).abs() < 0.1, "bias {p}");
            }
        }
    }

    #[test]
    fn combine_is_order_dependent_and_keyed() {
        assert_ne!(hash_combine(1, 2), hash_combine(2, 1));
        assert_ne!(hash_combine(0, 0), 0);
        let mut v: Vec<u32> = (0..1u32 << 16).map(|b| hash_combine(12345, b)).collect();
        v.sort_unstable();
        v.dedup();
        assert_eq!(v.len(), 1 << 16);
    }
}
