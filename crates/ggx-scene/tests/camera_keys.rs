//! Animated cameras (`[[camera.keys]]`): interpolation, frames, the errors of every bad key,
//! and the turntable scene.

use std::path::Path;

use ggx_scene::{ErrorKind, FrameError, Interpolation, Scene, SceneError, load_scene, parse_scene};
use glam::Vec3;

const FILE: &str = "scenes/test.toml";

/// A lit floor to look at.
const WORLD: &str = "\n[materials.w]\ntype = \"diffuse\"\nalbedo = [0.5, 0.5, 0.5]\n\
                     [[shapes]]\ntype = \"rectangle\"\nmaterial = \"w\"\n\
                     [environment]\ntype = \"constant\"\nradiance = [1, 1, 1]\n";

fn parse(text: &str) -> Scene {
    parse_scene(text, FILE, Path::new(".")).unwrap_or_else(|e| panic!("{e}\n{text}"))
}

/// `[camera]` with `settings` and one `[[camera.keys]]` per `(time, position, look_at, extra)`.
fn animated(settings: &str, keys: &[(&str, &str, &str, &str)]) -> String {
    let mut text = format!("[camera]\nresolution = [32, 16]\n{settings}\n");
    for (time, position, look_at, extra) in keys {
        text += &format!("[[camera.keys]]\ntime = {time}\nposition = {position}\nlook_at = {look_at}\n{extra}\n");
    }
    text + WORLD
}

/// 1-based line and column of the `nth` (0-based) occurrence of `needle` in `text`.
fn position_of(text: &str, needle: &str, nth: usize) -> (usize, usize) {
    let (offset, _) = text.match_indices(needle).nth(nth).unwrap_or_else(|| panic!("`{needle}` #{nth} not in text"));
    let before = &text[..offset];
    let line = before.matches('\n').count() + 1;
    let column = before.len() - before.rfind('\n').map_or(0, |i| i + 1) + 1;
    (line, column)
}

/// Asserts `text` fails with `kind` at the `nth` occurrence of `needle`, in `field`, with a
/// message containing `message`.
#[track_caller]
fn check(text: &str, (needle, nth): (&str, usize), field: &str, kind: ErrorKind, message: &str) -> SceneError {
    let err = match parse_scene(text, FILE, Path::new(".")) {
        Ok(_) => panic!("expected an error for:\n{text}"),
        Err(e) => e,
    };
    let shown = err.to_string();
    let (line, column) = position_of(text, needle, nth);
    let prefix = format!("{FILE}:{line}:{column}: {field}: ");
    assert!(shown.starts_with(&prefix), "expected prefix `{prefix}`, got `{shown}`");
    assert!(shown.contains(message), "expected `{message}` in `{shown}`");
    assert_eq!(err.kind(), kind, "{shown}");
    assert_eq!(err.field(), field);
    err
}

#[test]
fn linear_interpolation_halfway_between_keys_is_the_midpoint() {
    let text = animated(
        "",
        &[
            ("0", "[0.1, 1, 4]", "[0, 0, 0]", "fov_y = 30"),
            ("1", "[0.7, 3.3, 6]", "[1, 0.3, -1]", "fov_y = 50.5"),
            ("3", "[0, 1, 4]", "[0, 0, 0]", ""),
        ],
    );
    let mut scene = parse(&text);
    let path = scene.camera_path.clone().expect("animated");
    assert_eq!((path.fps(), path.interpolation(), path.duration()), (24.0, Interpolation::Linear, 3.0));
    let [a, b] = [&path.keys()[0].pose, &path.keys()[1].pose];
    scene.set_frame(12).unwrap();
    assert_eq!(path.frame_time(12), 0.5);
    let mid = path.pose_at(0.5);
    assert_eq!(mid.position, (a.position + b.position) * 0.5);
    assert_eq!(mid.look_at, (a.look_at + b.look_at) * 0.5);
    assert_eq!(mid.fov_y_degrees, 40.25);
    assert_eq!(scene.camera.position, mid.position);
    assert_eq!(scene.camera.fov_y_degrees, 40.25);
    assert_eq!(scene.camera.forward, (mid.look_at - mid.position).normalize());
    // The third key takes the default fov.
    assert_eq!(path.keys()[2].pose.fov_y_degrees, 40.0);
    // A quarter of the way from key 1 to key 2 (t = 1.5, frame 36).
    let quarter = path.pose_at(1.5);
    let expected = b.position * 0.75 + path.keys()[2].pose.position * 0.25;
    assert!((quarter.position - expected).length() < 1e-6, "{quarter:?}");
}

#[test]
fn smooth_interpolation_passes_through_the_keys() {
    let keys = [
        ("0", "[0, 1, 4]", "[0, 0, 0]", ""),
        ("0.5", "[4, 1.5, 0]", "[0.2, 0, 0]", "up = [0, 1, 0.1]"),
        ("1.25", "[0, 2, -4]", "[0, 0.4, 0]", "fov_y = 60"),
        ("2", "[-4, 1, 0]", "[0, 0, 0]", ""),
    ];
    let mut scene = parse(&animated("fps = 4\ninterpolation = \"smooth\"", &keys));
    let path = scene.camera_path.clone().expect("animated");
    assert_eq!((path.frame_count(), path.interpolation()), (9, Interpolation::Smooth));
    for (frame, key) in [(0, 0), (2, 1), (5, 2), (8, 3)] {
        scene.set_frame(frame).unwrap();
        let pose = path.keys()[key].pose;
        assert_eq!(path.pose_at(path.frame_time(frame)), pose, "key {key}");
        assert_eq!((scene.camera.position, scene.camera.fov_y_degrees), (pose.position, pose.fov_y_degrees));
    }
    // Between keys the path bends: it is not the chord...
    let (a, b) = (path.keys()[1].pose.position, path.keys()[2].pose.position);
    let t = 0.875;
    assert!((path.pose_at(t).position - (a + b) * 0.5).length() > 0.1);
    // ...and it is continuous with a continuous velocity through a key.
    let at = |t: f64| path.pose_at(t).position;
    let (before, after) = ((at(0.5) - at(0.5 - 1e-4)) / 1e-4, (at(0.5 + 1e-4) - at(0.5)) / 1e-4);
    assert!((before - after).length() < 0.05 * before.length(), "{before} {after}");
    // The catmull-rom tangent at key 1 is (p2 - p0) / (t2 - t0).
    let tangent = (b - path.keys()[0].pose.position) / 1.25;
    assert!((before - tangent).length() < 0.05 * tangent.length(), "{before} {tangent}");
}

#[test]
fn fps_and_frame_counts() {
    let two = |settings: &str, last: &str| {
        let keys = [("0", "[0, 1, 4]", "[0, 0, 0]", ""), (last, "[4, 1, 0]", "[0, 0, 0]", "")];
        parse(&animated(settings, &keys))
    };
    assert_eq!(two("", "2").frame_count(), 49);
    assert_eq!(two("fps = 30", "1.5").frame_count(), 46);
    assert_eq!(two("fps = 12.5", "1").frame_count(), 13);
    // 0.29 * 100 is 28.999999999999996 in f64: the last frame is still at the last key.
    let s = two("fps = 100", "0.29");
    assert_eq!(s.frame_count(), 30);
    let path = s.camera_path.as_ref().unwrap();
    assert_eq!(path.pose_at(path.frame_time(29)), path.keys()[1].pose);
    // Frames end at or before the last key.
    assert_eq!(two("fps = 10", "0.55").frame_count(), 6);
    // A still camera has exactly one frame.
    let mut still = parse(&format!("[camera]\nposition = [0, 1, 4]\nlook_at = [0, 0, 0]\n{WORLD}"));
    let camera = still.camera;
    assert_eq!((still.frame_count(), still.camera_path.as_ref()), (1, None));
    still.set_frame(0).unwrap();
    assert_eq!(still.camera, camera);
    let err = still.set_frame(1).unwrap_err();
    assert_eq!(err, FrameError::NotAnimated { frame: 1 });
    assert_eq!(err.to_string(), "frame 1 is outside the scene's frames 0..=0: its camera has no [[camera.keys]]");
}

#[test]
fn frames_past_the_last_are_errors() {
    let keys = [("0", "[0, 1, 4]", "[0, 0, 0]", ""), ("10", "[4, 1, 0]", "[0, 0, 0]", "")];
    let mut scene = parse(&animated("", &keys));
    assert_eq!(scene.frame_count(), 241);
    let err = scene.set_frame(300).unwrap_err();
    assert_eq!(err.to_string(), "frame 300 is outside the animation's frames 0..=240");
    assert_eq!(err, FrameError::OutOfRange { frame: 300, last: 240 });
    assert!(scene.set_frame(241).is_err() && scene.set_frame(u32::MAX).is_err());
    scene.set_frame(240).unwrap();
    assert_eq!(scene.camera.position, Vec3::new(4.0, 1.0, 0.0));
}

#[test]
fn set_frame_keeps_the_resolution() {
    let keys = [("0", "[0, 1, 4]", "[0, 0, 0]", ""), ("1", "[4, 1, 0]", "[0, 0, 0]", "")];
    let mut scene = parse(&animated("", &keys));
    assert_eq!(scene.camera.resolution, [32, 16]);
    scene.camera.resolution = [640, 480];
    scene.set_frame(7).unwrap();
    assert_eq!(scene.camera.resolution, [640, 480]);
}

#[test]
fn one_key_is_a_still_camera() {
    let still = parse(&format!(
        "[camera]\nposition = [1, 2, 3]\nlook_at = [0, 0.5, 0]\nfov_y = 33\nresolution = [32, 16]\n{WORLD}"
    ));
    let one = parse(&animated("fov_y = 33", &[("0", "[1, 2, 3]", "[0, 0.5, 0]", "")]));
    assert_eq!(one.camera, still.camera);
    assert_eq!(one.frame_count(), 1);
    assert_eq!(one.camera_path.as_ref().map(|p| p.keys().len()), Some(1));
    // A single key later than 0 holds the camera still for every frame up to it.
    let mut late = parse(&animated("fps = 2\ninterpolation = \"smooth\"", &[("1.5", "[1, 2, 3]", "[0, 0.5, 0]", "")]));
    assert_eq!(late.frame_count(), 4);
    for frame in 0..4 {
        late.set_frame(frame).unwrap();
        assert_eq!(late.camera.forward, still.camera.forward);
        assert_eq!(late.camera.position, still.camera.position);
    }
}

#[test]
fn key_times_must_be_finite_non_negative_and_increasing() {
    let key = |t| (t, "[0, 1, 4]", "[0, 0, 0]", "");
    let text = animated("", &[key("1"), key("0.5")]);
    check(&text, ("0.5", 0), "camera.keys[1].time", ErrorKind::OutOfRange, "greater than the previous key's time 1");
    let text = animated("", &[key("0"), key("1"), key("1.0")]);
    check(&text, ("1.0", 0), "camera.keys[2].time", ErrorKind::OutOfRange, "strictly increase");
    let text = animated("", &[key("-1")]);
    check(&text, ("-1", 0), "camera.keys[0].time", ErrorKind::OutOfRange, "must be >= 0, got -1");
    let text = animated("", &[key("0"), key("nan")]);
    check(&text, ("nan", 0), "camera.keys[1].time", ErrorKind::NonFinite, "must be a finite number, got NaN");
    let text = animated("", &[key("0"), key("inf")]);
    check(&text, ("inf", 0), "camera.keys[1].time", ErrorKind::NonFinite, "finite");
    let text = animated("", &[key("1e39")]);
    check(&text, ("1e39", 0), "camera.keys[0].time", ErrorKind::OutOfRange, "too large for f32");
    let text = animated("", &[key("\"soon\"")]);
    check(&text, ("\"soon\"", 0), "camera.keys[0].time", ErrorKind::Schema, "invalid type");
}

#[test]
fn bad_fps_and_interpolation() {
    let keys = [("0", "[0, 1, 4]", "[0, 0, 0]", ""), ("2", "[4, 1, 0]", "[0, 0, 0]", "")];
    for (fps, kind, message) in [
        ("0", ErrorKind::OutOfRange, "must be in (0, 1000], got 0"),
        ("-24", ErrorKind::OutOfRange, "must be in (0, 1000], got -24"),
        ("1001", ErrorKind::OutOfRange, "must be in (0, 1000], got 1001"),
        ("nan", ErrorKind::NonFinite, "must be a finite number, got NaN"),
        ("inf", ErrorKind::NonFinite, "must be a finite number, got inf"),
    ] {
        let text = animated(&format!("fps = {fps}"), &keys);
        check(&text, (&format!("= {fps}")[2..], 0), "camera.fps", kind, message);
    }
    let text = animated("interpolation = \"cubic\"", &keys);
    check(&text, ("\"cubic\"", 0), "camera.interpolation", ErrorKind::Schema, "unknown variant `cubic`");
    // Without keys, neither applies.
    let still = "[camera]\nposition = [0, 1, 4]\nlook_at = [0, 0, 0]\n";
    let text = format!("{still}fps = 24\n{WORLD}");
    check(&text, ("24", 0), "camera.fps", ErrorKind::Conflict, "only to an animated camera");
    let text = format!("{still}interpolation = \"linear\"\n{WORLD}");
    check(&text, ("\"linear\"", 0), "camera.interpolation", ErrorKind::Conflict, "[[camera.keys]]");
}

#[test]
fn an_animation_has_at_most_max_frames() {
    let keys = [("0", "[0, 1, 4]", "[0, 0, 0]", ""), ("5000", "[4, 1, 0]", "[0, 0, 0]", "")];
    let text = animated("", &keys);
    check(&text, ("5000", 0), "camera.keys[1].time", ErrorKind::OutOfRange, "120001 frames");
    let text = animated("fps = 20", &keys);
    check(&text, ("5000", 0), "camera.keys[1].time", ErrorKind::OutOfRange, "100001 frames");
    let keys = [("0", "[0, 1, 4]", "[0, 0, 0]", ""), ("4999.5", "[4, 1, 0]", "[0, 0, 0]", "")];
    let longest = parse(&animated("fps = 20.002", &keys));
    assert_eq!((longest.frame_count(), ggx_scene::MAX_FRAMES), (100_000, 100_000));
}

#[test]
fn position_and_look_at_come_from_the_camera_or_the_keys() {
    let text = format!("[camera]\nlook_at = [0, 1, 0]\n{WORLD}");
    check(&text, ("[camera]", 0), "camera", ErrorKind::Schema, "missing field `position`");
    let text = format!("[camera]\nposition = [0, 1, 3]\n{WORLD}");
    check(&text, ("[camera]", 0), "camera", ErrorKind::Schema, "missing field `look_at`");
    let keys = [("0", "[0, 1, 4]", "[0, 0, 0]", "")];
    let text = animated("position = [0, 2, 2]", &keys);
    check(&text, ("[0, 2, 2]", 0), "camera.position", ErrorKind::Conflict, "either camera.position");
    let text = animated("look_at = [0, 2, 2]", &keys);
    check(&text, ("[0, 2, 2]", 0), "camera.look_at", ErrorKind::Conflict, "not both");
    // A key needs both.
    let text = format!("[camera]\n[[camera.keys]]\ntime = 0\nlook_at = [0, 0, 0]\n{WORLD}");
    check(&text, ("[[camera.keys]]", 0), "camera.keys[0]", ErrorKind::Schema, "missing field `position`");
    let text = format!("[camera]\n[[camera.keys]]\nposition = [0, 0, 1]\nlook_at = [0, 0, 0]\n{WORLD}");
    check(&text, ("[[camera.keys]]", 0), "camera.keys[0]", ErrorKind::Schema, "missing field `time`");
    let text = animated("", &[("0", "[0, 1, 4]", "[0, 0, 0]", "focus = 3")]);
    check(&text, ("focus", 0), "camera.keys[0].focus", ErrorKind::Schema, "unknown field `focus`");
    let text = format!("[camera]\nkeys = []\n{WORLD}");
    check(&text, ("[]", 0), "camera.keys", ErrorKind::Schema, "at least one key");
    let text = animated("", &[("0", "[0, 1, nan]", "[0, 0, 0]", "")]);
    check(&text, ("[0, 1, nan]", 0), "camera.keys[0].position", ErrorKind::NonFinite, "component 2");
    let text = animated("", &[("0", "[0, 1, 4]", "[0, 0, 0]", "fov_y = 180")]);
    check(&text, ("180", 0), "camera.keys[0].fov_y", ErrorKind::OutOfRange, "must be in (0, 180), got 180");
}

#[test]
fn degenerate_keys_are_errors() {
    let ok = ("0", "[0, 1, 4]", "[0, 0, 0]", "");
    let text = animated("", &[ok, ("1", "[1, 2, 3]", "[1.0, 2.0, 3.0]", "")]);
    check(&text, ("[1.0, 2.0, 3.0]", 0), "camera.keys[1].look_at", ErrorKind::Degenerate, "coincide");
    let text = animated("", &[ok, ("1", "[0, 0, 0]", "[0, 5, 0]", "up = [0, 2, 0]")]);
    check(&text, ("[0, 2, 0]", 0), "camera.keys[1].up", ErrorKind::Degenerate, "parallel");
    // Without its own up, a key takes camera.up: the error says so.
    let text = animated("up = [1, 0, 0]", &[ok, ("1", "[0, 0, 0]", "[7, 0, 0]", "")]);
    let err = check(&text, ("[7, 0, 0]", 0), "camera.keys[1].up", ErrorKind::Degenerate, "parallel");
    assert!(err.to_string().contains("takes camera.up [1, 0, 0]"), "{err}");
    let text = animated("", &[ok, ("1", "[0, 0, 0]", "[0, -3, 0]", "")]);
    check(&text, ("[0, -3, 0]", 0), "camera.keys[1].up", ErrorKind::Degenerate, "the default [0, 1, 0]");
    let text = animated("", &[ok, ("1", "[0, 0, 1e38]", "[0, 0, -3e38]", "")]);
    check(&text, ("[0, 0, -3e38]", 0), "camera.keys[1].look_at", ErrorKind::Degenerate, "too far apart for f32");
}

#[test]
fn degenerate_interpolated_frames_are_errors() {
    // Halfway, at t = 0.5, the eye passes through the point it looks at.
    let keys = [("0", "[0, 0, 1]", "[0, 0, -1]", ""), ("1", "[0, 0, -1]", "[0, 0, 1]", "")];
    let text = animated("fps = 2", &keys);
    let err = check(&text, ("[[camera.keys]]", 0), "camera.keys[0]", ErrorKind::Degenerate, "coincide");
    assert!(err.to_string().contains("the camera at frame 1 (t = 0.5 s, between keys 0 and 1) is degenerate"), "{err}");
    // At 1 fps no frame falls there: the animation is valid, and the pose at 0.5 s is there
    // to inspect without a panic.
    let scene = parse(&animated("fps = 1", &keys));
    let path = scene.camera_path.as_ref().unwrap();
    assert_eq!(scene.frame_count(), 2);
    let halfway = path.pose_at(0.5);
    assert_eq!(halfway.position, halfway.look_at);
    // Ups that cancel halfway: at t = 1.5 the second segment's up is zero.
    let keys = [
        ("0", "[0, 0, 4]", "[0, 0, 0]", "up = [0, 1, 0]"),
        ("1", "[0, 0, 4]", "[0, 0, 0]", "up = [0, 1, 0]"),
        ("2", "[0, 0, 4]", "[0, 0, 0]", "up = [0, -1, 0]"),
    ];
    let text = animated("fps = 4\ninterpolation = \"smooth\"", &keys);
    let err = check(&text, ("[[camera.keys]]", 1), "camera.keys[1]", ErrorKind::Degenerate, "not parallel");
    assert!(err.to_string().contains("frame 6 (t = 1.5 s, between keys 1 and 2)"), "{err}");
}

#[test]
fn the_turntable_orbits_and_every_frame_builds() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/turntable.toml");
    let mut scene = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    let again = load_scene(&path).unwrap();
    assert_eq!(format!("{scene:?}"), format!("{again:?}"), "the Debug text identifies the scene");
    let orbit = scene.camera_path.clone().expect("animated");
    assert_eq!((orbit.fps(), orbit.interpolation(), orbit.keys().len()), (24.0, Interpolation::Smooth, 17));
    assert_eq!(scene.frame_count(), 49);
    let first = scene.camera;
    scene.camera.resolution = [24, 16];
    let target = Vec3::new(0.0, 0.45, 0.0);
    for frame in 0..scene.frame_count() {
        scene.set_frame(frame).unwrap_or_else(|e| panic!("{e}"));
        let c = scene.camera;
        let radius = c.position.with_y(0.0).length();
        assert!((radius - 5.5).abs() < 0.02 * 5.5, "frame {frame}: radius {radius}");
        assert_eq!((c.position.y, c.resolution), (2.0, [24, 16]), "frame {frame}");
        assert!((c.forward - (target - c.position).normalize()).length() < 1e-6, "frame {frame}");
    }
    // A full turn: the last frame is the first.
    assert_eq!(scene.camera.position, first.position);
    assert_eq!(scene.camera.forward, first.forward);
    // A quarter turn (frame 12, t = 0.5 s) is the key at +x.
    scene.set_frame(12).unwrap();
    assert_eq!(scene.camera.position, Vec3::new(5.5, 2.0, 0.0));
    assert!(scene.set_frame(49).is_err());
}

/// The `[[camera.keys]]` example in the crate README parses and does what it says.
#[test]
fn the_readme_example_is_valid() {
    let readme = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("README.md")).unwrap();
    let after = &readme[readme.find("#### `[[camera.keys]]`").expect("README documents camera keys")..];
    let start = after.find("```toml\n").expect("a toml block") + "```toml\n".len();
    let text = &after[start..start + after[start..].find("```").expect("closed block")];
    let mut scene = parse(&format!("{text}{WORLD}"));
    assert_eq!(scene.frame_count(), 13);
    scene.set_frame(12).unwrap();
    assert_eq!((scene.camera.position, scene.camera.fov_y_degrees), (Vec3::new(4.2, 1.6, 0.0), 30.0));
}
