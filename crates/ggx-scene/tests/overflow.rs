//! Values that overflow `f32` (or the renderers' 32-bit seed) are located errors, never
//! silently infinite or folded: numbers over `f32::MAX`, far cameras, too bright emitters,
//! triangles whose area overflows, light power sums, seeds over `MAX_SEED`.

use std::path::Path;

use ggx_scene::{ErrorKind, MAX_RADIANCE, MAX_SEED, Scene, SceneError, parse_scene};
use glam::Vec3;

const FILE: &str = "scenes/test.toml";

const CAMERA: &str = "[camera]\nposition = [0, 1, 3.5]\nlook_at = [0, 1, 0]\n";

const WHITE: &str = "\n[materials.white]\ntype = \"diffuse\"\nalbedo = [0.5, 0.5, 0.5]\n";

fn parse(text: &str) -> Result<Scene, SceneError> {
    parse_scene(text, FILE, Path::new("."))
}

/// Asserts `text` fails at the first `needle`, in `field`, of `kind`, with `message` in it.
#[track_caller]
fn check(text: &str, needle: &str, field: &str, kind: ErrorKind, message: &str) {
    let err = match parse(text) {
        Ok(_) => panic!("expected an error for:\n{text}"),
        Err(e) => e,
    };
    let shown = err.to_string();
    let offset = text.find(needle).unwrap_or_else(|| panic!("`{needle}` not in text"));
    let before = &text[..offset];
    let (line, column) = (before.matches('\n').count() + 1, offset - before.rfind('\n').map_or(0, |i| i + 1) + 1);
    assert!(shown.starts_with(&format!("{FILE}:{line}:{column}: {field}: ")), "{shown}");
    assert!(shown.contains(message), "expected `{message}` in `{shown}`");
    assert_eq!(err.kind(), kind, "{shown}");
}

#[test]
fn numbers_too_large_for_f32_are_out_of_range() {
    let text = format!("{CAMERA}{WHITE}\n[[shapes]]\ntype = \"sphere\"\nmaterial = \"white\"\nradius = 1e39\n");
    let msg = "is too large for f32 (max 3.4e38), got 1e39";
    check(&text, "1e39", "shapes[0].radius", ErrorKind::OutOfRange, msg);
    let text = format!(
        "{CAMERA}{WHITE}\n[[shapes]]\ntype = \"box\"\nmaterial = \"white\"\ntransform = {{ translate = [0, -4e38, 0] }}\n"
    );
    let msg = "is too large for f32 (max 3.4e38), got -4e38 (component 1)";
    check(&text, "[0, -4e38", "shapes[0].transform.translate", ErrorKind::OutOfRange, msg);
    let text = format!("{CAMERA}fov_y = 1e300\n");
    check(&text, "1e300", "camera.fov_y", ErrorKind::OutOfRange, "got 1e300");
    // Range errors show huge values in scientific notation, not 39 digits.
    let text = format!("{CAMERA}fov_y = -3e38\n");
    check(&text, "-3e38", "camera.fov_y", ErrorKind::OutOfRange, "must be in (0, 180), got -3e38");
}

#[test]
fn a_far_camera_gets_its_basis_in_f64() {
    // |look_at - position|^2 = 1e40 overflows f32: the basis is computed in f64.
    let scene = parse("[camera]\nposition = [0, 0, 1e20]\nlook_at = [0, 0, 0]\n").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!((scene.camera.forward, scene.camera.right, scene.camera.up), (-Vec3::Z, Vec3::X, Vec3::Y));
}

#[test]
fn cameras_beyond_f32_blame_position_or_look_at() {
    let text = "[camera]\nposition = [0, 0, 1e38]\nlook_at = [0, 0, -3e38]\n";
    check(text, "[0, 0, -3e38]", "camera.look_at", ErrorKind::Degenerate, "too far apart for f32");
    let text = "[camera]\nposition = [0, 0, -3e38]\nlook_at = [0, 0, 1e38]\n";
    check(text, "[0, 0, -3e38]", "camera.position", ErrorKind::Degenerate, "too far apart for f32");
    let text = "[camera]\nposition = [1e20, 0, 0]\nlook_at = [1e20, 1e13, 0]\n";
    check(text, "[1e20, 1e13", "camera.look_at", ErrorKind::Degenerate, "coincide in f32 precision");
}

#[test]
fn emitters_brighter_than_max_radiance_are_out_of_range() {
    let text = format!("{CAMERA}\n[materials.sun]\ntype = \"emissive\"\nradiance = [1, 2e20, 1]\n");
    let msg = format!("radiance 2e20 is over the largest radiance {MAX_RADIANCE:e}");
    check(&text, "[1, 2e20", "materials.sun.radiance", ErrorKind::OutOfRange, &msg);
    let text = format!("{CAMERA}\n[materials.sun]\ntype = \"emissive\"\nradiance = [1, 1e20, 1]\n");
    parse(&text).unwrap_or_else(|e| panic!("{e}"));
}

#[test]
fn triangles_whose_area_overflows_are_errors() {
    // A sphere of radius 1e20: each triangle's area is finite but its squared length is not,
    // so its normal would silently be zero.
    let text = format!("{CAMERA}{WHITE}\n[[shapes]]\ntype = \"sphere\"\nmaterial = \"white\"\nradius = 1e20\n");
    check(&text, "\"sphere\"", "shapes[0]", ErrorKind::Degenerate, "too large for f32: a triangle's area overflows");
}

#[test]
fn light_power_sums_that_overflow_are_errors() {
    // A 3e9 x 3e9 light (each triangle's area still fits f32): pi * 9e18 * 1e20 = 2.8e39.
    let lamp = "\n[[shapes]]\ntype = \"rectangle\"\nmaterial = \"lamp\"\ntransform = { scale = 3e9 }\n";
    let with = |radiance: &str, lamps: usize| {
        format!("{CAMERA}\n[materials.lamp]\ntype = \"emissive\"\nradiance = {radiance}\n{}", lamp.repeat(lamps))
    };
    let text = with("[1e20, 1e20, 1e20]", 1);
    check(&text, "\"rectangle\"", "shapes[0]", ErrorKind::OutOfRange, "the emitted power");
    // pi * 9e18 * 1e19 = 2.8e38 fits alone, two of them do not: the second is blamed.
    parse(&with("[1e19, 1e19, 1e19]", 1)).unwrap_or_else(|e| panic!("{e}"));
    let err = parse(&with("[1e19, 1e19, 1e19]", 2)).unwrap_err();
    assert!(err.to_string().contains("shapes[1]: the emitted power"), "{err}");
    assert_eq!(err.kind(), ErrorKind::OutOfRange);
}

#[test]
fn seeds_are_limited_to_32_bits() {
    let seed = |s: &str| parse(&format!("{CAMERA}[integrator]\nseed = {s}\n"));
    assert_eq!(MAX_SEED, 4_294_967_295);
    assert_eq!(seed("4294967295").unwrap().integrator.seed, MAX_SEED);
    assert_eq!(seed("0").unwrap().integrator.seed, 0);
    let msg = "must be in [0, 4294967295] (2^32 - 1), got 4294967296";
    check(
        &format!("{CAMERA}[integrator]\nseed = 4294967296\n"),
        "4294967296",
        "integrator.seed",
        ErrorKind::OutOfRange,
        msg,
    );
    let text = format!("{CAMERA}[integrator]\nseed = 9223372036854775807\n");
    check(&text, "9223", "integrator.seed", ErrorKind::OutOfRange, "must be in [0, 4294967295]");
    check(&format!("{CAMERA}[integrator]\nseed = -1\n"), "-1", "integrator.seed", ErrorKind::OutOfRange, "got -1");
}
