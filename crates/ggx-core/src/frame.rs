//! Orthonormal frames and reflection.

use crate::math::normalize_or_zero;
use glam::Vec3;

/// An orthonormal basis `(x, y, z)`; `z` is the shading normal.
#[repr(C)]
#[derive(Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
#[cfg_attr(not(target_arch = "spirv"), derive(Debug))]
pub struct Frame {
    /// First tangent.
    pub x: Vec3,
    /// Second tangent (`z x x`).
    pub y: Vec3,
    /// Normal.
    pub z: Vec3,
}

impl Frame {
    /// Branchless ONB around a unit normal, Duff et al. 2017 ("Building an Orthonormal Basis,
    /// Revisited", JCGT 6(1)): `s = sign(n.z)`, `a = -1/(s + n.z)`, `b = n.x n.y a`.
    /// A zero or non-finite `n` gives the canonical frame.
    #[inline]
    pub fn from_z(n: Vec3) -> Self {
        let n = normalize_or_zero(n);
        let n = if n == Vec3::ZERO { Vec3::Z } else { n };
        let sign = 1.0f32.copysign(n.z);
        let a = -1.0 / (sign + n.z);
        let b = n.x * n.y * a;
        Frame {
            x: Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
            y: Vec3::new(b, sign + n.y * n.y * a, -n.y),
            z: n,
        }
    }

    /// Coordinates of a world vector in this frame (zero for a non-finite result).
    #[inline]
    pub fn to_local(&self, v: Vec3) -> Vec3 {
        finite_or_zero3(Vec3::new(v.dot(self.x), v.dot(self.y), v.dot(self.z)))
    }

    /// World vector from coordinates in this frame (zero for a non-finite result).
    #[inline]
    pub fn to_world(&self, v: Vec3) -> Vec3 {
        finite_or_zero3(self.x * v.x + self.y * v.y + self.z * v.z)
    }
}

/// Mirror reflection of `wo` about `n`: `2 (wo . n) n - wo` (zero for a non-finite result).
#[inline]
pub fn reflect(wo: Vec3, n: Vec3) -> Vec3 {
    finite_or_zero3(2.0 * wo.dot(n) * n - wo)
}

/// `v` if every component is finite, else zero.
#[inline(always)]
fn finite_or_zero3(v: Vec3) -> Vec3 {
    if v.is_finite() { v } else { Vec3::ZERO }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_is_orthonormal_for_every_octant_and_the_poles() {
        let mut normals = std::vec![Vec3::Z, -Vec3::Z, Vec3::X, Vec3::Y, Vec3::new(0.0, 0.0, -0.0)];
        for i in 0..2000 {
            let t = i as f32 * 0.37;
            normals.push(Vec3::new(t.sin() * (t * 1.7).cos(), t.sin() * (t * 1.7).sin(), t.cos()));
            normals.push(Vec3::new(1e-20, -1e-20, -1.0));
        }
        for n in normals {
            let f = Frame::from_z(n);
            for (a, b) in [(f.x, f.y), (f.y, f.z), (f.x, f.z)] {
                assert!(a.dot(b).abs() < 1e-5, "{n:?}");
            }
            for v in [f.x, f.y, f.z] {
                assert!((v.length() - 1.0).abs() < 1e-5, "{n:?}");
            }
            assert!(f.x.cross(f.y).dot(f.z) > 0.999, "right-handed for {n:?}");
            let w = Vec3::new(0.3, -0.5, 0.81);
            assert!((f.to_world(f.to_local(w)) - w).length() < 1e-5);
        }
    }

    #[test]
    fn degenerate_normals_give_a_valid_frame() {
        for n in [Vec3::ZERO, Vec3::NAN, Vec3::INFINITY] {
            let f = Frame::from_z(n);
            assert_eq!(f.z, Vec3::Z);
            assert!(f.x.is_finite() && f.y.is_finite());
        }
    }

    #[test]
    fn reflect_mirrors_about_the_normal() {
        let wo = Vec3::new(0.6, 0.0, 0.8);
        assert!((reflect(wo, Vec3::Z) - Vec3::new(-0.6, 0.0, 0.8)).length() < 1e-7);
    }
}
