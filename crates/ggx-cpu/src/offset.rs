//! Self-intersection-free secondary ray origins.

use glam::Vec3;

/// Wachter & Binder 2019 ("A Fast and Robust Method for Avoiding Self-Intersection", Ray
/// Tracing Gems ch. 6): move `p` along the normal `n` by `256 n` ulps of each coordinate, or by
/// `n / 65536` near the origin where ulps are too small. Scale-independent, no epsilon to tune.
#[inline(always)]
pub fn offset_ray_origin(p: Vec3, n: Vec3) -> Vec3 {
    const ORIGIN: f32 = 1.0 / 32.0;
    const FLOAT_SCALE: f32 = 1.0 / 65536.0;
    const INT_SCALE: f32 = 256.0;
    let offset = |p: f32, n: f32| {
        let of_i = (INT_SCALE * n) as i32;
        let moved = f32::from_bits((p.to_bits() as i32).wrapping_add(if p < 0.0 { -of_i } else { of_i }) as u32);
        if p.abs() < ORIGIN { p + FLOAT_SCALE * n } else { moved }
    };
    Vec3::new(offset(p.x, n.x), offset(p.y, n.y), offset(p.z, n.z))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offsets_move_along_the_normal_at_every_scale() {
        for scale in [1e-3f32, 0.5, 1.0, 37.0, 1e4] {
            for n in [Vec3::Y, -Vec3::Y, Vec3::new(0.6, 0.0, -0.8)] {
                let p = Vec3::new(0.3, -0.7, 0.9) * scale;
                let q = offset_ray_origin(p, n);
                let d = (q - p).dot(n);
                assert!(d > 0.0, "scale {scale} n {n}: moved {d} against the normal");
                assert!(d < 1e-4 * scale.max(1.0), "scale {scale}: moved {d}, too far");
            }
        }
    }
}
