//! `[camera]`: a pinhole perspective camera, primary-ray generation, and the pose (eye,
//! target, up hint, field of view) a camera is built from.

use glam::{Vec2, Vec3};

/// Largest accepted image width or height, in pixels.
pub const MAX_RESOLUTION: u32 = 16384;

/// [`Camera::generate_ray`] with its per-camera terms computed once: the same arithmetic in the
/// same order, so the same bits.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayGenerator {
    position: Vec3,
    forward: Vec3,
    right: Vec3,
    up: Vec3,
    size: Vec2,
    tan_half_fov: f32,
    aspect: f32,
}

impl RayGenerator {
    /// Pinhole model: `d = normalize(forward + x_ndc * tan(fov/2) * aspect * right +
    /// y_ndc * tan(fov/2) * up)` with `x_ndc = 2 px / w - 1`, `y_ndc = 1 - 2 py / h`.
    #[inline]
    pub fn generate_ray(&self, pixel: Vec2) -> (Vec3, Vec3) {
        let t = self.tan_half_fov;
        let x = (2.0 * pixel.x / self.size.x - 1.0) * t * self.aspect;
        let y = (1.0 - 2.0 * pixel.y / self.size.y) * t;
        (self.position, (self.forward + x * self.right + y * self.up).normalize())
    }
}

/// A validated pinhole camera with an orthonormal right-handed basis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Eye position (world space).
    pub position: Vec3,
    /// Unit view direction.
    pub forward: Vec3,
    /// Unit vector towards the right of the image.
    pub right: Vec3,
    /// Unit vector towards the top of the image (orthogonal to `forward`).
    pub up: Vec3,
    /// Vertical field of view in degrees, in (0, 180).
    pub fov_y_degrees: f32,
    /// Image size `[width, height]` in pixels.
    pub resolution: [u32; 2],
}

impl Camera {
    /// Builds a camera looking from `position` at `look_at`; `None` when the two coincide or
    /// `up` is (nearly) parallel to the view direction.
    ///
    /// The basis is computed in `f32`, or in `f64` where `f32` overflows (a camera `1e20`
    /// away from what it looks at: the squared distance is over `f32::MAX`).
    pub fn look_at(position: Vec3, look_at: Vec3, up: Vec3, fov_y_degrees: f32, resolution: [u32; 2]) -> Option<Self> {
        let [forward, right, up] = basis_f32(position, look_at, up).or_else(|| basis_f64(position, look_at, up))?;
        Some(Self { position, forward, right, up, fov_y_degrees, resolution })
    }

    /// `tan(fov_y / 2)`: half the height of the image plane at distance 1.
    pub fn tan_half_fov(&self) -> f32 {
        (self.fov_y_degrees.to_radians() * 0.5).tan()
    }

    /// Width / height.
    pub fn aspect(&self) -> f32 {
        self.resolution[0] as f32 / self.resolution[1] as f32
    }

    /// Primary ray through the continuous image position `pixel`: `(0, 0)` is the top-left
    /// corner of the image, `(width, height)` the bottom-right; pixel `(i, j)` covers
    /// `[i, i+1) x [j, j+1)`. Returns `(origin, unit direction)`; see [`RayGenerator`], which
    /// renderers keep to skip the per-ray `tan`.
    pub fn generate_ray(&self, pixel: Vec2) -> (Vec3, Vec3) {
        self.ray_generator().generate_ray(pixel)
    }

    /// The camera with `tan(fov/2)`, the aspect ratio and the image size computed once.
    pub fn ray_generator(&self) -> RayGenerator {
        RayGenerator {
            position: self.position,
            forward: self.forward,
            right: self.right,
            up: self.up,
            size: Vec2::new(self.resolution[0] as f32, self.resolution[1] as f32),
            tan_half_fov: self.tan_half_fov(),
            aspect: self.aspect(),
        }
    }
}

/// `[forward, right, up]` in `f32`; `None` when degenerate or when `f32` overflows.
fn basis_f32(position: Vec3, look_at: Vec3, up: Vec3) -> Option<[Vec3; 3]> {
    let forward = (look_at - position).try_normalize()?;
    let right = forward.cross(up.try_normalize()?);
    if right.length() < 1e-4 {
        return None;
    }
    let right = right.normalize();
    Some([forward, right, right.cross(forward)])
}

/// `[forward, right, up]` computed in `f64`, for positions whose squared distances overflow
/// `f32`; `None` when degenerate.
fn basis_f64(position: Vec3, look_at: Vec3, up: Vec3) -> Option<[Vec3; 3]> {
    let forward = f64x3::normalize(f64x3::sub(f64x3::from(look_at), f64x3::from(position)))?;
    let right = f64x3::cross(forward, f64x3::normalize(f64x3::from(up))?);
    if f64x3::length(right) < 1e-4 {
        return None;
    }
    let right = f64x3::normalize(right)?;
    Some([forward, right, f64x3::cross(right, forward)].map(|v| Vec3::from(v.map(|c| c as f32)).normalize()))
}

/// The few `f64` vector operations the far-camera fallback needs (glam is built without
/// its `f64` types here).
mod f64x3 {
    use glam::Vec3;

    /// An `f64` 3-vector.
    pub type V = [f64; 3];

    /// `v` in `f64`.
    pub fn from(v: Vec3) -> V {
        v.to_array().map(f64::from)
    }
    /// `a - b`.
    pub fn sub(a: V, b: V) -> V {
        [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
    }
    /// `a x b`.
    pub fn cross(a: V, b: V) -> V {
        [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
    }
    /// Euclidean length.
    pub fn length(v: V) -> f64 {
        (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
    }
    /// `v / |v|`, `None` for a zero or non-finite length.
    pub fn normalize(v: V) -> Option<V> {
        let l = length(v);
        (l > 0.0 && l.is_finite()).then(|| v.map(|c| c / l))
    }
}

/// Where a camera is and where it looks, before its basis is built: `[camera]`, one of its
/// `[[camera.keys]]`, or a pose interpolated between keys.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraPose {
    /// Eye position (world space).
    pub position: Vec3,
    /// The point the camera looks at.
    pub look_at: Vec3,
    /// Up hint: any vector not parallel to the view direction.
    pub up: Vec3,
    /// Vertical field of view in degrees, in (0, 180).
    pub fov_y_degrees: f32,
}

/// Why a [`CameraPose`] makes no camera; each message says what is wrong.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum PoseProblem {
    /// `look_at - position` does not exist in `f32`: a point is not finite, or the two are
    /// too far apart. `position` is true when the position is to blame (it is the farther
    /// from the origin), false for `look_at`.
    Apart {
        /// Whether the position (rather than `look_at`) is to blame.
        position: bool,
        /// What is wrong.
        message: String,
    },
    /// `position` and `look_at` coincide in `f32` precision.
    Coincide(String),
    /// `up` is zero or parallel to the view direction.
    Up(String),
}

impl PoseProblem {
    /// What is wrong.
    pub fn message(&self) -> &str {
        match self {
            Self::Apart { message, .. } | Self::Coincide(message) | Self::Up(message) => message,
        }
    }
}

impl CameraPose {
    /// The camera of this pose at `resolution`: [`Camera::look_at`] once `look_at - position`
    /// is known to exist in `f32` (finite, and longer than `1e-6` times the position's largest
    /// coordinate, at least 1).
    pub(crate) fn camera(&self, resolution: [u32; 2]) -> Result<Camera, PoseProblem> {
        check_distance(self.position, self.look_at)?;
        Camera::look_at(self.position, self.look_at, self.up, self.fov_y_degrees, resolution)
            .ok_or_else(|| PoseProblem::Up("up must be non-zero and not parallel to the view direction".to_owned()))
    }
}

/// Checks that the view direction `look_at - position` exists in `f32`: both points finite,
/// its components not overflowing (the farther of the two points is blamed), and `look_at`
/// farther from `position` than `f32` can resolve at that distance from the origin.
fn check_distance(position: Vec3, look_at: Vec3) -> Result<(), PoseProblem> {
    for (point, name, is_position) in [(position, "position", true), (look_at, "look_at", false)] {
        if !point.is_finite() {
            let message = format!("{name} {point} is not finite in f32 (the interpolation overshoots f32's range)");
            return Err(PoseProblem::Apart { position: is_position, message });
        }
    }
    let d = look_at - position;
    let size = |p: Vec3| p.abs().max_element();
    if !d.is_finite() {
        let far = f64x3::sub(f64x3::from(look_at), f64x3::from(position)).map(f64::abs).into_iter().fold(0.0, f64::max);
        let message = format!(
            "position and look_at are too far apart for f32: look_at - position has a component of {far:.1e}, over \
             f32's max {:.1e}",
            f32::MAX
        );
        return Err(PoseProblem::Apart { position: size(position) > size(look_at), message });
    }
    let distance = f64x3::length(f64x3::from(d));
    let resolution = 1e-6 * f64::from(size(position).max(1.0));
    if distance <= resolution {
        let msg = if d == Vec3::ZERO {
            "camera position and look_at coincide".to_owned()
        } else {
            format!(
                "camera position and look_at coincide in f32 precision: they are {distance:.1e} apart, at most 1e-6 \
                 times the position's largest coordinate {:.1e}",
                size(position)
            )
        };
        return Err(PoseProblem::Coincide(msg));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn center_and_corner_rays() {
        let cam = Camera::look_at(Vec3::ZERO, -Vec3::Z, Vec3::Y, 90.0, [200, 100]).unwrap();
        let (_, d) = cam.generate_ray(Vec2::new(100.0, 50.0));
        assert!((d - -Vec3::Z).length() < 1e-6);
        let (_, d) = cam.generate_ray(Vec2::new(200.0, 0.0));
        let expected = Vec3::new(2.0, 1.0, -1.0).normalize();
        assert!((d - expected).length() < 1e-5, "{d}");
        assert!(Camera::look_at(Vec3::ZERO, Vec3::Y, Vec3::Y, 40.0, [1, 1]).is_none());
    }

    #[test]
    fn far_cameras_get_a_basis_in_f64() {
        let far = Vec3::new(0.0, 0.0, 1e20);
        assert!(basis_f32(far, Vec3::ZERO, Vec3::Y).is_none(), "f32 overflows, the f64 fallback is exercised");
        let cam = Camera::look_at(far, Vec3::ZERO, Vec3::Y, 40.0, [1, 1]).unwrap();
        assert_eq!(cam.forward, -Vec3::Z);
        assert_eq!(cam.right, Vec3::X);
        assert_eq!(cam.up, Vec3::Y);
    }
}
