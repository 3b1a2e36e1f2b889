//! `[camera]`: a pinhole perspective camera and primary-ray generation.

use glam::{Vec2, Vec3};

use crate::check::Interval;
use crate::error::{ErrorKind, SceneError, Source};
use crate::raw::RawCamera;

/// Largest accepted image width or height, in pixels.
pub const MAX_RESOLUTION: u32 = 16384;

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
    pub fn look_at(position: Vec3, look_at: Vec3, up: Vec3, fov_y_degrees: f32, resolution: [u32; 2]) -> Option<Self> {
        let forward = (look_at - position).try_normalize()?;
        let right = forward.cross(up.try_normalize()?);
        if right.length() < 1e-4 {
            return None;
        }
        let right = right.normalize();
        Some(Self { position, forward, right, up: right.cross(forward), fov_y_degrees, resolution })
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
    /// `[i, i+1) x [j, j+1)`. Returns `(origin, unit direction)`.
    ///
    /// Pinhole model: `d = normalize(forward + x_ndc * tan(fov/2) * aspect * right +
    /// y_ndc * tan(fov/2) * up)` with `x_ndc = 2 px / w - 1`, `y_ndc = 1 - 2 py / h`.
    pub fn generate_ray(&self, pixel: Vec2) -> (Vec3, Vec3) {
        let [w, h] = self.resolution.map(|r| r as f32);
        let t = self.tan_half_fov();
        let x = (2.0 * pixel.x / w - 1.0) * t * self.aspect();
        let y = (1.0 - 2.0 * pixel.y / h) * t;
        (self.position, (self.forward + x * self.right + y * self.up).normalize())
    }

    /// Validates `[camera]`.
    pub(crate) fn from_raw(src: Source<'_>, raw: &RawCamera) -> Result<Self, SceneError> {
        let position = Vec3::from(src.array(&raw.position, "camera.position", Interval::ANY)?);
        let look_at = Vec3::from(src.array(&raw.look_at, "camera.look_at", Interval::ANY)?);
        let up = raw.up.as_ref().map_or(Ok([0.0, 1.0, 0.0]), |up| src.array(up, "camera.up", Interval::ANY))?;
        let fov = src.number_or(raw.fov_y.as_ref(), 40.0, "camera.fov_y", Interval::open(0.0, 180.0))?;
        let resolution = match &raw.resolution {
            None => [256, 256],
            Some(r) => {
                let [w, h] = *r.get_ref();
                if !(1..=MAX_RESOLUTION).contains(&w) || !(1..=MAX_RESOLUTION).contains(&h) {
                    let msg = format!("width and height must be in [1, {MAX_RESOLUTION}], got [{w}, {h}]");
                    return Err(src.error(r.span(), "camera.resolution", ErrorKind::OutOfRange, msg));
                }
                [w, h]
            }
        };
        if (look_at - position).length() <= 1e-6 * position.abs().max_element().max(1.0) {
            let msg = "camera position and look_at coincide";
            return Err(src.error(raw.look_at.span(), "camera.look_at", ErrorKind::Degenerate, msg));
        }
        Self::look_at(position, look_at, Vec3::from(up), fov, resolution).ok_or_else(|| {
            let span = raw.up.as_ref().map_or(raw.look_at.span(), |u| u.span());
            let msg = "up must be non-zero and not parallel to the view direction";
            src.error(span, "camera.up", ErrorKind::Degenerate, msg)
        })
    }
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
}
