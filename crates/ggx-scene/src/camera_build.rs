//! Validates `[camera]`: a still camera from `position` and `look_at`, or an animated one from
//! `[[camera.keys]]`, `fps` and `interpolation` ([`CameraPath`]) whose frame-0 camera is the
//! scene's.

use std::ops::Range;

use glam::Vec3;
use toml::Spanned;

use crate::camera::{Camera, CameraPose, MAX_RESOLUTION, PoseProblem};
use crate::camera_path::{CameraKey, CameraPath, DEFAULT_FPS, MAX_FPS, MAX_FRAMES, frames_for};
use crate::check::{Interval, span_of};
use crate::error::{ErrorKind, SceneError, Source};
use crate::raw::{RawCamera, RawCameraKey};

/// Default `fov_y` in degrees.
const DEFAULT_FOV_Y: f32 = 40.0;

/// The pose fields of `[camera]` or of one key, as written, with the prefix of their field
/// paths (`camera`, `camera.keys[2]`).
struct RawPose<'a> {
    prefix: &'a str,
    position: &'a Spanned<[f64; 3]>,
    look_at: &'a Spanned<[f64; 3]>,
    up: Option<&'a Spanned<[f64; 3]>>,
    fov_y: Option<&'a Spanned<f64>>,
}

/// Validates `[camera]` (`raw` spans its header): the scene's camera (frame 0 when
/// animated) and the animation, if any.
pub(crate) fn build(src: Source<'_>, raw: &Spanned<RawCamera>) -> Result<(Camera, Option<CameraPath>), SceneError> {
    let table = raw.span();
    let raw = raw.get_ref();
    match &raw.keys {
        None => still(src, table, raw).map(|camera| (camera, None)),
        Some(keys) => animated(src, raw, keys).map(|(camera, path)| (camera, Some(path))),
    }
}

/// A camera without keys: `position` and `look_at` are required, `fps` and `interpolation`
/// do not apply.
fn still(src: Source<'_>, table: Range<usize>, raw: &RawCamera) -> Result<Camera, SceneError> {
    for (key, span) in [("fps", span_of(&raw.fps)), ("interpolation", span_of(&raw.interpolation))] {
        if let Some(span) = span {
            let msg = "applies only to an animated camera (one with [[camera.keys]])";
            return Err(src.error(span, &format!("camera.{key}"), ErrorKind::Conflict, msg));
        }
    }
    let required = |v: &Option<Spanned<[f64; 3]>>, key: &str| {
        v.as_ref().cloned().ok_or_else(|| {
            let msg = format!(
                "missing field `{key}` (a still camera needs `position` and `look_at`, an animated one \
                 [[camera.keys]])"
            );
            src.error(table.clone(), "camera", ErrorKind::Schema, msg)
        })
    };
    let (position, look_at) = (required(&raw.position, "position")?, required(&raw.look_at, "look_at")?);
    let raw_pose = RawPose {
        prefix: "camera",
        position: &position,
        look_at: &look_at,
        up: raw.up.as_ref(),
        fov_y: raw.fov_y.as_ref(),
    };
    let pose = pose(src, &raw_pose, None)?;
    let resolution = resolution(src, raw)?;
    pose.camera(resolution).map_err(|p| pose_error(src, &raw_pose, None, p))
}

/// A camera with keys: `position` and `look_at` belong to the keys, `up` and `fov_y` are
/// their defaults. Every key, the time order, `fps`, the frame count and the camera of every
/// frame are checked.
fn animated(
    src: Source<'_>,
    raw: &RawCamera,
    keys: &Spanned<Vec<Spanned<RawCameraKey>>>,
) -> Result<(Camera, CameraPath), SceneError> {
    for (key, span) in [("position", span_of(&raw.position)), ("look_at", span_of(&raw.look_at))] {
        if let Some(span) = span {
            let msg = "give either camera.position and camera.look_at (a still camera) or [[camera.keys]] (an \
                       animated one), not both";
            return Err(src.error(span, &format!("camera.{key}"), ErrorKind::Conflict, msg));
        }
    }
    let up = raw.up.as_ref().map(|up| src.array(up, "camera.up", Interval::ANY)).transpose()?;
    let fov = src.number_or(raw.fov_y.as_ref(), DEFAULT_FOV_Y, "camera.fov_y", Interval::open(0.0, 180.0))?;
    let defaults = (up.map(Vec3::from), fov);
    let resolution = resolution(src, raw)?;
    if keys.get_ref().is_empty() {
        let msg = "needs at least one key (one key is a still camera)";
        return Err(src.error(keys.span(), "camera.keys", ErrorKind::Schema, msg));
    }
    let mut validated: Vec<CameraKey> = Vec::with_capacity(keys.get_ref().len());
    for (i, key) in keys.get_ref().iter().enumerate() {
        let key = key.get_ref();
        let prefix = format!("camera.keys[{i}]");
        let time = key_time(src, &prefix, &key.time, validated.last())?;
        let raw_pose = RawPose {
            prefix: &prefix,
            position: &key.position,
            look_at: &key.look_at,
            up: key.up.as_ref(),
            fov_y: key.fov_y.as_ref(),
        };
        let pose = pose(src, &raw_pose, Some(defaults))?;
        pose.camera(resolution).map_err(|p| pose_error(src, &raw_pose, Some(defaults), p))?;
        validated.push(CameraKey { time, pose });
    }
    let fps = fps(src, raw)?;
    check_frame_count(src, keys.get_ref(), &validated, fps)?;
    let path = CameraPath::new(validated, fps, raw.interpolation.as_ref().map(|i| *i.get_ref()).unwrap_or_default());
    check_frames(src, keys.get_ref(), &path, resolution)?;
    let camera = path
        .camera_at_frame(0, resolution)
        .map_err(|e| src.error(keys.span(), "camera.keys", ErrorKind::Degenerate, e.to_string()))?;
    Ok((camera, path))
}

/// `camera.fps` in (0, [`MAX_FPS`]], [`DEFAULT_FPS`] when absent.
fn fps(src: Source<'_>, raw: &RawCamera) -> Result<f64, SceneError> {
    let Some(v) = &raw.fps else { return Ok(DEFAULT_FPS) };
    src.components(v.span(), &[*v.get_ref()], "camera.fps", Interval::open_closed(0.0, MAX_FPS as f32))?;
    Ok(*v.get_ref())
}

/// At most [`MAX_FRAMES`] frames, `floor(last time * fps) + 1`; the error points at the last
/// key's time.
fn check_frame_count(
    src: Source<'_>,
    keys: &[Spanned<RawCameraKey>],
    validated: &[CameraKey],
    fps: f64,
) -> Result<(), SceneError> {
    let (Some(raw), Some(last)) = (keys.last(), validated.last()) else { return Ok(()) };
    let frames = frames_for(last.time, fps);
    if frames <= f64::from(MAX_FRAMES) {
        return Ok(());
    }
    let msg = format!(
        "the animation would have {frames} frames (floor(time * fps) + 1 at {fps} fps), over the maximum of \
         {MAX_FRAMES}: shorten it or lower camera.fps"
    );
    let field = format!("camera.keys[{}].time", keys.len() - 1);
    Err(src.error(raw.get_ref().time.span(), &field, ErrorKind::OutOfRange, msg))
}

/// `camera.keys[i].time`: finite, >= 0, and greater than the previous key's.
fn key_time(
    src: Source<'_>,
    prefix: &str,
    time: &Spanned<f64>,
    previous: Option<&CameraKey>,
) -> Result<f64, SceneError> {
    let field = format!("{prefix}.time");
    src.components(time.span(), &[*time.get_ref()], &field, Interval::at_least(0.0))?;
    let t = *time.get_ref();
    match previous {
        Some(p) if t <= p.time => {
            let msg = format!("must be greater than the previous key's time {} (key times strictly increase)", p.time);
            Err(src.error(time.span(), &field, ErrorKind::OutOfRange, msg))
        }
        _ => Ok(t),
    }
}

/// The pose of `raw` with finite numbers and `fov_y` in (0, 180); `defaults` are a key's
/// `(camera.up, camera.fov_y)` (validated), `None` for `[camera]` itself.
fn pose(src: Source<'_>, raw: &RawPose<'_>, defaults: Option<(Option<Vec3>, f32)>) -> Result<CameraPose, SceneError> {
    let field = |key: &str| format!("{}.{key}", raw.prefix);
    let position = Vec3::from(src.array(raw.position, &field("position"), Interval::ANY)?);
    let look_at = Vec3::from(src.array(raw.look_at, &field("look_at"), Interval::ANY)?);
    let (default_up, default_fov) = defaults.unwrap_or((None, DEFAULT_FOV_Y));
    let up = match raw.up {
        Some(up) => Vec3::from(src.array(up, &field("up"), Interval::ANY)?),
        None => default_up.unwrap_or(Vec3::Y),
    };
    let fov_y_degrees = src.number_or(raw.fov_y, default_fov, &field("fov_y"), Interval::open(0.0, 180.0))?;
    Ok(CameraPose { position, look_at, up, fov_y_degrees })
}

/// The located error for a pose that makes no camera: `position` or `look_at` when they are
/// too far apart (the farther one), `look_at` when they coincide, `up` (or, when absent,
/// `look_at`) when it is parallel to the view.
fn pose_error(
    src: Source<'_>,
    raw: &RawPose<'_>,
    defaults: Option<(Option<Vec3>, f32)>,
    problem: PoseProblem,
) -> SceneError {
    let (span, key) = match &problem {
        PoseProblem::Apart { position: true, .. } => (raw.position.span(), "position"),
        PoseProblem::Apart { position: false, .. } | PoseProblem::Coincide(_) => (raw.look_at.span(), "look_at"),
        PoseProblem::Up(_) => (raw.up.map_or(raw.look_at.span(), Spanned::span), "up"),
    };
    let mut msg = problem.message().to_owned();
    if let (PoseProblem::Up(_), None, Some((default_up, _))) = (&problem, raw.up, defaults) {
        let up = default_up.map_or("the default [0, 1, 0]".to_owned(), |u| format!("camera.up {u}"));
        msg = format!("{msg} (this key has no up and takes {up}: give it its own)");
    }
    src.error(span, &format!("{}.{key}", raw.prefix), ErrorKind::Degenerate, msg)
}

/// `camera.resolution`, each side in [1, [`MAX_RESOLUTION`]], default 256 x 256.
fn resolution(src: Source<'_>, raw: &RawCamera) -> Result<[u32; 2], SceneError> {
    let Some(r) = &raw.resolution else { return Ok([256, 256]) };
    let [w, h] = *r.get_ref();
    if !(1..=MAX_RESOLUTION).contains(&w) || !(1..=MAX_RESOLUTION).contains(&h) {
        let msg = format!("width and height must be in [1, {MAX_RESOLUTION}], got [{w}, {h}]");
        return Err(src.error(r.span(), "camera.resolution", ErrorKind::OutOfRange, msg));
    }
    Ok([w, h])
}

/// Checks that every frame of `path` has a camera; an error points at the key that starts the
/// segment of the first frame without one.
fn check_frames(
    src: Source<'_>,
    keys: &[Spanned<RawCameraKey>],
    path: &CameraPath,
    resolution: [u32; 2],
) -> Result<(), SceneError> {
    for frame in 0..path.frame_count() {
        let time = path.frame_time(frame);
        if let Err(problem) = path.pose_at(time).camera(resolution) {
            let i = path.segment(time);
            let between = if i + 1 < keys.len() { format!(", between keys {i} and {}", i + 1) } else { String::new() };
            let msg =
                format!("the camera at frame {frame} (t = {time} s{between}) is degenerate: {}", problem.message());
            let span = keys.get(i).map_or(0..0, Spanned::span);
            return Err(src.error(span, &format!("camera.keys[{i}]"), ErrorKind::Degenerate, msg));
        }
    }
    Ok(())
}
