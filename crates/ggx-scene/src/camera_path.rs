//! [`CameraPath`]: an animated camera, `[[camera.keys]]` interpolated at `frame / fps`.

use glam::Vec3;
use serde::Deserialize;
use thiserror::Error;

use crate::camera::{Camera, CameraPose};

/// Frames per second when `camera.fps` is absent.
pub const DEFAULT_FPS: f64 = 24.0;
/// Largest accepted `camera.fps`.
pub const MAX_FPS: f64 = 1000.0;
/// Most frames an animation may have (every frame's camera is checked when the scene loads).
pub const MAX_FRAMES: u32 = 100_000;

/// Times within this many frames below a whole frame count as that frame, so that a last key
/// at 0.29 s has frame 29 at 100 fps although `0.29 * 100` is `28.999999999999996` in `f64`.
const FRAME_ROUNDING: f64 = 1e-9;

/// How the camera moves between keys (`camera.interpolation`).
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq, Hash)]
#[serde(rename_all = "kebab-case")]
pub enum Interpolation {
    /// Straight lines: every quantity is `a (1 - u) + b u` between the keys around the time.
    #[default]
    Linear,
    /// `position` and `look_at` follow a Catmull-Rom spline through the keys (see
    /// [`CameraPath::pose_at`]); `up` and `fov_y` stay linear.
    Smooth,
}

/// One `[[camera.keys]]` entry, validated: a time and the camera's pose at that time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraKey {
    /// Seconds from the start of the animation, finite and >= 0.
    pub time: f64,
    /// Where the camera is and looks at that time (`up` and `fov_y` filled in from
    /// `[camera]` or their defaults).
    pub pose: CameraPose,
}

/// A validated camera animation: at least one key, times finite, >= 0 and strictly
/// increasing, `fps` in (0, [`MAX_FPS`]], at most [`MAX_FRAMES`] frames, and a camera at every
/// frame.
#[derive(Clone, Debug, PartialEq)]
pub struct CameraPath {
    keys: Vec<CameraKey>,
    fps: f64,
    interpolation: Interpolation,
}

/// Why [`crate::Scene::set_frame`] or [`CameraPath::camera_at_frame`] has no camera for a frame.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum FrameError {
    /// The frame is past the last frame of the animation.
    #[error("frame {frame} is outside the animation's frames 0..={last}")]
    OutOfRange {
        /// The frame asked for.
        frame: u32,
        /// The animation's last frame.
        last: u32,
    },
    /// A frame other than 0 of a scene whose camera does not move.
    #[error("frame {frame} is outside the scene's frames 0..=0: its camera has no [[camera.keys]]")]
    NotAnimated {
        /// The frame asked for.
        frame: u32,
    },
    /// The interpolated pose makes no camera (the loader checks every frame, so a loaded
    /// scene never gives this).
    #[error("frame {frame} (t = {time} s): the interpolated camera is degenerate: {message}")]
    Degenerate {
        /// The frame asked for.
        frame: u32,
        /// Its time in seconds.
        time: f64,
        /// What is wrong.
        message: String,
    },
}

impl CameraPath {
    /// A path through `keys` (non-empty, times finite, >= 0 and strictly increasing) at `fps`
    /// (in (0, [`MAX_FPS`]]); the loader validates all of it.
    pub(crate) fn new(keys: Vec<CameraKey>, fps: f64, interpolation: Interpolation) -> Self {
        Self { keys, fps, interpolation }
    }

    /// The keys, in time order.
    pub fn keys(&self) -> &[CameraKey] {
        &self.keys
    }

    /// Frames per second.
    pub fn fps(&self) -> f64 {
        self.fps
    }

    /// How the camera moves between keys.
    pub fn interpolation(&self) -> Interpolation {
        self.interpolation
    }

    /// Seconds from time 0 to the last key: `keys.last().time`.
    pub fn duration(&self) -> f64 {
        self.keys.last().map_or(0.0, |k| k.time)
    }

    /// Number of frames, `floor(duration * fps + 1e-9) + 1`: frames `0..=floor(duration * fps)`,
    /// the last at or just before the last key (1e-9 forgives `f64` rounding of the product).
    pub fn frame_count(&self) -> u32 {
        frames_for(self.duration(), self.fps).min(f64::from(MAX_FRAMES)) as u32
    }

    /// Time of `frame` in seconds: `frame / fps`.
    pub fn frame_time(&self, frame: u32) -> f64 {
        f64::from(frame) / self.fps
    }

    /// The camera at `frame` (time [`Self::frame_time`]), at `resolution`; an error when the
    /// frame is past the last or its interpolated pose makes no camera.
    pub fn camera_at_frame(&self, frame: u32, resolution: [u32; 2]) -> Result<Camera, FrameError> {
        let frames = self.frame_count();
        if frame >= frames {
            return Err(FrameError::OutOfRange { frame, last: frames.saturating_sub(1) });
        }
        let time = self.frame_time(frame);
        self.pose_at(time).camera(resolution).map_err(|p| FrameError::Degenerate {
            frame,
            time,
            message: p.message().to_owned(),
        })
    }

    /// Index of the key that starts the segment containing `time` (0 before the first key, the
    /// last key at or after it).
    pub(crate) fn segment(&self, time: f64) -> usize {
        self.keys.partition_point(|k| k.time <= time).saturating_sub(1)
    }

    /// The pose at `time` seconds: the first key's before it, the last key's after it, and
    /// between keys `a` and `b` at `u = (time - t_a) / (t_b - t_a)`: `up` and `fov_y` are
    /// `a (1 - u) + b u`, and so are `position` and `look_at` when linear. When smooth,
    /// `position` and `look_at` follow the non-uniform (time-parameterised) Catmull-Rom
    /// spline: the cubic Hermite segment from `p[a]` to `p[b]` whose tangent at key `k` is
    /// `(p[k+1] - p[k-1]) / (t[k+1] - t[k-1])`, with indices clamped at the ends (the first
    /// and last tangents are the chords to their neighbours); with evenly spaced keys it is
    /// the uniform Catmull-Rom spline, and with two keys a straight line. Computed in `f64`
    /// and rounded once, so every key is reproduced exactly at its own time and a linear
    /// midpoint is `(a + b) / 2`.
    pub fn pose_at(&self, time: f64) -> CameraPose {
        // A path has at least one key (the only constructor is the validating loader's).
        let last = self.keys.len() - 1;
        let key = |k: usize| &self.keys[k.min(last)];
        let i = self.segment(time);
        let (a, b) = (key(i), key(i + 1));
        if i == last || time.is_nan() || time <= a.time {
            return a.pose;
        }
        let u = (time - a.time) / (b.time - a.time);
        let (pa, pb) = (a.pose, b.pose);
        let (position, look_at) = match self.interpolation {
            Interpolation::Linear => (lerp3(pa.position, pb.position, u), lerp3(pa.look_at, pb.look_at, u)),
            Interpolation::Smooth => {
                let scales = self.tangent_scales(i);
                let curve = |f: fn(&CameraPose) -> Vec3| {
                    let p = |k: usize| f(&key(k).pose);
                    hermite([p(i.saturating_sub(1)), p(i), p(i + 1), p(i + 2)], scales, u)
                };
                (curve(|p| p.position), curve(|p| p.look_at))
            }
        };
        CameraPose {
            position,
            look_at,
            up: lerp3(pa.up, pb.up, u),
            fov_y_degrees: lerp(f64::from(pa.fov_y_degrees), f64::from(pb.fov_y_degrees), u) as f32,
        }
    }

    /// `[h / (t[i+1] - t[i-1]), h / (t[i+2] - t[i])]` with `h = t[i+1] - t[i]` and indices clamped
    /// to the keys: what scales the chords `p[i+1] - p[i-1]` and `p[i+2] - p[i]` into the
    /// Hermite tangents of segment `i` (Catmull-Rom tangent `(p[i+1] - p[i-1]) / (t[i+1] - t[i-1])`
    /// times the segment's length `h`).
    fn tangent_scales(&self, i: usize) -> [f64; 2] {
        let last = self.keys.len().saturating_sub(1);
        let t = |k: usize| self.keys[k.min(last)].time;
        let h = t(i + 1) - t(i);
        [h / (t(i + 1) - t(i.saturating_sub(1))), h / (t(i + 2) - t(i))]
    }
}

/// Frames of an animation `duration` seconds long at `fps`: `floor(duration * fps + 1e-9) + 1`,
/// in `f64` (the loader compares it with [`MAX_FRAMES`] before it becomes a `u32`).
pub(crate) fn frames_for(duration: f64, fps: f64) -> f64 {
    (duration * fps + FRAME_ROUNDING).floor() + 1.0
}

/// `a (1 - u) + b u`: exactly `a` at `u = 0`, `b` at `u = 1`.
fn lerp(a: f64, b: f64, u: f64) -> f64 {
    a * (1.0 - u) + b * u
}

/// [`lerp`] per component in `f64`, rounded to `f32` once.
fn lerp3(a: Vec3, b: Vec3, u: f64) -> Vec3 {
    let [a, b] = [a, b].map(|v| v.to_array().map(f64::from));
    Vec3::from(std::array::from_fn(|c| lerp(a[c], b[c], u) as f32))
}

/// Cubic Hermite segment of `[p0, p1, p2, p3]` from `p1` (u = 0) to `p2` (u = 1) with the
/// Catmull-Rom tangents
/// `m1 = s1 (p2 - p0)`, `m2 = s2 (p3 - p1)` ([`CameraPath::tangent_scales`]):
/// `(2u^3 - 3u^2 + 1) p1 + (u^3 - 2u^2 + u) m1 + (-2u^3 + 3u^2) p2 + (u^3 - u^2) m2`, per
/// component in `f64` and rounded to `f32` once (a point beyond `f32` becomes infinite and
/// is refused by [`CameraPose`]'s checks).
fn hermite(points: [Vec3; 4], [s1, s2]: [f64; 2], u: f64) -> Vec3 {
    let [p0, p1, p2, p3] = points.map(|v| v.to_array().map(f64::from));
    let (u2, u3) = (u * u, u * u * u);
    let h = [2.0 * u3 - 3.0 * u2 + 1.0, u3 - 2.0 * u2 + u, -2.0 * u3 + 3.0 * u2, u3 - u2];
    Vec3::from(std::array::from_fn(|c| {
        let (m1, m2) = (s1 * (p2[c] - p0[c]), s2 * (p3[c] - p1[c]));
        (h[0] * p1[c] + h[1] * m1 + h[2] * p2[c] + h[3] * m2) as f32
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key(time: f64, x: f32) -> CameraKey {
        let pose =
            CameraPose { position: Vec3::new(x, 0.0, 5.0), look_at: Vec3::ZERO, up: Vec3::Y, fov_y_degrees: 40.0 };
        CameraKey { time, pose }
    }

    #[test]
    fn two_smooth_keys_move_in_a_straight_line() {
        let keys = vec![key(0.0, 0.0), key(2.0, 4.0)];
        let linear = CameraPath::new(keys.clone(), 24.0, Interpolation::Linear);
        let smooth = CameraPath::new(keys, 24.0, Interpolation::Smooth);
        for t in [0.0, 0.25, 0.5, 1.0, 1.5, 2.0] {
            let (a, b) = (linear.pose_at(t).position, smooth.pose_at(t).position);
            assert!((a - b).length() < 1e-6, "{t}: {a} {b}");
        }
    }

    #[test]
    fn before_the_first_key_and_after_the_last_the_camera_holds() {
        let path = CameraPath::new(vec![key(1.0, 1.0), key(2.0, 3.0)], 10.0, Interpolation::Smooth);
        assert_eq!(path.pose_at(0.0), path.keys()[0].pose);
        assert_eq!(path.pose_at(f64::NAN), path.keys()[0].pose);
        assert_eq!(path.pose_at(5.0), path.keys()[1].pose);
        assert_eq!(path.frame_count(), 21);
    }

    #[test]
    fn degenerate_frames_are_errors_not_panics() {
        // The loader refuses this path; built directly, the frame through the target is an error.
        let mut back = key(1.0, 0.0);
        back.pose.position = Vec3::new(0.0, 0.0, -5.0);
        let path = CameraPath::new(vec![key(0.0, 0.0), back], 2.0, Interpolation::Linear);
        assert!(path.camera_at_frame(0, [4, 4]).is_ok());
        let err = path.camera_at_frame(1, [4, 4]).unwrap_err();
        assert_eq!(
            err.to_string(),
            "frame 1 (t = 0.5 s): the interpolated camera is degenerate: camera position and look_at coincide"
        );
        assert_eq!(path.camera_at_frame(3, [4, 4]).unwrap_err(), FrameError::OutOfRange { frame: 3, last: 2 });
    }

    #[test]
    fn frame_counts_forgive_rounding() {
        assert_eq!(0.29 * 100.0, 28.999999999999996);
        assert_eq!(frames_for(0.29, 100.0), 30.0);
        assert_eq!(frames_for(2.0, 24.0), 49.0);
        assert_eq!(frames_for(0.0, 24.0), 1.0);
        assert_eq!(frames_for(0.99 / 24.0, 24.0), 1.0);
    }
}
