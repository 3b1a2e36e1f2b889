//! One test per error kind: each asserts the message names the file, the line:column of the
//! offending value and the field path.

use std::path::{Path, PathBuf};

use ggx_scene::{ErrorKind, SceneError, load_scene, parse_scene};

const FILE: &str = "scenes/test.toml";

const CAMERA: &str = "[camera]\nposition = [0, 1, 3.5]\nlook_at = [0, 1, 0]\n";

fn tmp_dir(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("errors").join(name);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn parse_err(text: &str, base: &Path) -> SceneError {
    match parse_scene(text, FILE, base) {
        Ok(_) => panic!("expected an error for:\n{text}"),
        Err(e) => e,
    }
}

/// 1-based line and column of the first occurrence of `needle` in `text`.
fn position_of(text: &str, needle: &str) -> (usize, usize) {
    let offset = text.find(needle).unwrap_or_else(|| panic!("`{needle}` not in text"));
    let before = &text[..offset];
    let line = before.matches('\n').count() + 1;
    let column = before.len() - before.rfind('\n').map_or(0, |i| i + 1) + 1;
    (line, column)
}

/// Asserts `text` fails with `kind` at the first occurrence of `needle`, in `field`, with a
/// message containing `message`.
#[track_caller]
fn check_in(base: &Path, text: &str, needle: &str, field: &str, kind: ErrorKind, message: &str) {
    let err = parse_err(text, base);
    let shown = err.to_string();
    let (line, column) = position_of(text, needle);
    let prefix = if field.is_empty() {
        format!("{FILE}:{line}:{column}: ")
    } else {
        format!("{FILE}:{line}:{column}: {field}: ")
    };
    assert!(shown.starts_with(&prefix), "expected prefix `{prefix}`, got `{shown}`");
    assert!(shown.contains(message), "expected `{message}` in `{shown}`");
    assert_eq!(err.kind(), kind, "{shown}");
    assert_eq!(err.field(), field);
}

#[track_caller]
fn check(text: &str, needle: &str, field: &str, kind: ErrorKind, message: &str) {
    check_in(Path::new("."), text, needle, field, kind, message);
}

fn with_material(material: &str) -> String {
    format!("{CAMERA}\n[materials.gold]\n{material}\n\n[[shapes]]\ntype = \"sphere\"\nmaterial = \"gold\"\n")
}

#[test]
fn example_from_the_docs() {
    let text = format!(
        "{CAMERA}\n# a comment\n\n\n\n\n[materials.gold]\ntype = \"conductor\"\nroughness = 1.5\npreset = \"gold\"\n"
    );
    let err = parse_err(&text, Path::new("."));
    assert_eq!(err.to_string(), "scenes/test.toml:12:13: materials.gold.roughness: must be in [0, 1], got 1.5");
    assert_eq!(err.line_column(), Some((12, 13)));
}

#[test]
fn syntax_error() {
    let text = format!("{CAMERA}fov_y = = 40\n");
    check(&text, "= 40", "", ErrorKind::Syntax, "");
}

#[test]
fn wrong_type() {
    let text = format!("{CAMERA}\n[integrator]\nspp = \"many\"\n");
    check(&text, "\"many\"", "integrator.spp", ErrorKind::Schema, "invalid type");
}

#[test]
fn negative_integer() {
    let text = format!("{CAMERA}\n[integrator]\nspp = -3\n");
    check(&text, "-3", "integrator.spp", ErrorKind::Schema, "");
}

#[test]
fn wrong_array_length() {
    let text = "[camera]\nposition = [0, 1]\nlook_at = [0, 1, 0]\n";
    check(text, "[0, 1]", "camera.position", ErrorKind::Schema, "invalid length 2");
}

#[test]
fn missing_field() {
    let text = "[camera]\nlook_at = [0, 1, 0]\n";
    check(text, "[camera]", "camera", ErrorKind::Schema, "missing field `position`");
}

#[test]
fn missing_camera() {
    let text = "[integrator]\nspp = 4\n";
    check(text, "[integrator]", "", ErrorKind::Schema, "missing field `camera`");
}

#[test]
fn unknown_key() {
    let text = format!("{CAMERA}focus = 2.0\n");
    check(&text, "focus", "camera.focus", ErrorKind::Schema, "unknown field `focus`");
}

#[test]
fn unknown_key_in_shape_transform() {
    let text =
        format!("{}transform = {{ shear = 1 }}\n", with_material("type = \"diffuse\"\nalbedo = [0.5, 0.5, 0.5]"));
    check(&text, "shear", "shapes[0].transform.shear", ErrorKind::Schema, "unknown field `shear`");
}

#[test]
fn unknown_material_type() {
    let text = with_material("type = \"glass\"");
    check(&text, "\"glass\"", "materials.gold.type", ErrorKind::Schema, "unknown variant `glass`");
}

#[test]
fn unknown_shape_type() {
    let text = with_material("type = \"diffuse\"\nalbedo = [0.5, 0.5, 0.5]").replace("\"sphere\"", "\"torus\"");
    check(&text, "\"torus\"", "shapes[0].type", ErrorKind::Schema, "unknown variant `torus`");
}

#[test]
fn unknown_strategy() {
    let text = format!("{CAMERA}\n[integrator]\nbsdf_sampling = \"ggx\"\n");
    check(&text, "\"ggx\"", "integrator.bsdf_sampling", ErrorKind::Schema, "unknown variant `ggx`");
}

#[test]
fn nan_number() {
    let text = format!("{CAMERA}fov_y = nan\n");
    check(&text, "nan", "camera.fov_y", ErrorKind::NonFinite, "must be a finite number, got NaN");
}

#[test]
fn infinite_component() {
    let text = with_material("type = \"diffuse\"\nalbedo = [0.5, inf, 0.5]");
    check(&text, "[0.5, inf", "materials.gold.albedo", ErrorKind::NonFinite, "got inf (component 1)");
}

#[test]
fn overflowing_number() {
    let text = format!("{CAMERA}up = [0, 1e300, 0]\n");
    let msg = "is too large for f32 (max 3.4e38), got 1e300 (component 1)";
    check(&text, "[0, 1e300", "camera.up", ErrorKind::OutOfRange, msg);
}

#[test]
fn roughness_out_of_range() {
    let text = with_material("type = \"conductor\"\nroughness = 1.5\npreset = \"gold\"");
    check(&text, "1.5", "materials.gold.roughness", ErrorKind::OutOfRange, "must be in [0, 1], got 1.5");
}

#[test]
fn anisotropic_alpha_out_of_range() {
    let text = with_material("type = \"conductor\"\nalpha = [0.1, -0.2]\nf0 = [1, 1, 1]");
    check(&text, "[0.1, -0.2]", "materials.gold.alpha", ErrorKind::OutOfRange, "got -0.2 (component 1)");
}

#[test]
fn alpha_wrong_shape() {
    let text = with_material("type = \"conductor\"\nalpha = [0.1, 0.2, 0.3]\npreset = \"gold\"");
    check(&text, "[0.1, 0.2, 0.3]", "materials.gold.alpha", ErrorKind::Schema, "a number or an array of 2 numbers");
}

#[test]
fn negative_albedo() {
    let text = with_material("type = \"plastic\"\nroughness = 0.2\nalbedo = [0.5, -0.1, 0.5]");
    check(&text, "[0.5, -0.1", "materials.gold.albedo", ErrorKind::OutOfRange, "must be in [0, 1], got -0.1");
}

#[test]
fn albedo_above_one() {
    let text = with_material("type = \"diffuse\"\nalbedo = [1.2, 0.5, 0.5]");
    check(&text, "[1.2", "materials.gold.albedo", ErrorKind::OutOfRange, "must be in [0, 1], got 1.2 (component 0)");
}

#[test]
fn negative_radiance() {
    let text = with_material("type = \"emissive\"\nradiance = [1, 1, -1]");
    check(&text, "[1, 1, -1]", "materials.gold.radiance", ErrorKind::OutOfRange, "must be >= 0, got -1");
}

#[test]
fn zero_radiance() {
    let text = with_material("type = \"emissive\"\nradiance = [0, 0, 0]");
    check(&text, "[0, 0, 0]", "materials.gold.radiance", ErrorKind::OutOfRange, "positive");
}

#[test]
fn ior_not_above_one() {
    let text = with_material("type = \"plastic\"\nroughness = 0.2\nior = 1.0\nalbedo = [0.5, 0.5, 0.5]");
    check(&text, "1.0\n", "materials.gold.ior", ErrorKind::OutOfRange, "must be > 1, got 1");
}

#[test]
fn ior_not_finite() {
    let text = with_material("type = \"plastic\"\nroughness = 0.2\nior = inf\nalbedo = [0.5, 0.5, 0.5]");
    check(&text, "inf", "materials.gold.ior", ErrorKind::NonFinite, "finite");
}

#[test]
fn conductor_eta_must_be_positive() {
    let text = with_material("type = \"conductor\"\nalpha = 0.1\neta = [0, 1, 1]\nk = [1, 1, 1]");
    check(&text, "[0, 1, 1]", "materials.gold.eta", ErrorKind::OutOfRange, "must be > 0, got 0");
}

#[test]
fn roughness_and_alpha_both_given() {
    let text = with_material("type = \"conductor\"\nroughness = 0.3\nalpha = 0.09\npreset = \"gold\"");
    check(&text, "0.09", "materials.gold.alpha", ErrorKind::Conflict, "either `roughness` or `alpha`");
}

#[test]
fn key_not_applicable_to_type() {
    let text = with_material("type = \"conductor\"\nroughness = 0.3\npreset = \"gold\"\nior = 1.5");
    check(&text, "1.5", "materials.gold.ior", ErrorKind::Conflict, "does not apply to type \"conductor\"");
}

#[test]
fn missing_key_for_type() {
    let text = with_material("type = \"conductor\"\npreset = \"gold\"");
    check(&text, "\"conductor\"", "materials.gold.type", ErrorKind::Conflict, "needs `roughness` or `alpha`");
}

#[test]
fn eta_without_k() {
    let text = with_material("type = \"conductor\"\nalpha = 0.1\neta = [1, 1, 1]");
    check(&text, "[1, 1, 1]", "materials.gold.eta", ErrorKind::Conflict, "`eta` needs `k` too");
}

#[test]
fn element_type_error() {
    let text = "[camera]\nposition = [0, \"one\", 3]\nlook_at = [0, 1, 0]\n";
    check(text, "\"one\"", "camera.position[1]", ErrorKind::Schema, "invalid type");
}

#[test]
fn two_fresnel_sources() {
    let text = with_material("type = \"conductor\"\nalpha = 0.1\nf0 = [1, 1, 1]\npreset = \"gold\"");
    check(&text, "\"gold\"\n", "materials.gold.preset", ErrorKind::Conflict, "only one of");
}

#[test]
fn fov_out_of_range() {
    let text = format!("{CAMERA}fov_y = 180\n");
    check(&text, "180", "camera.fov_y", ErrorKind::OutOfRange, "must be in (0, 180), got 180");
    let text = format!("{CAMERA}fov_y = 0.0\n");
    check(&text, "0.0", "camera.fov_y", ErrorKind::OutOfRange, "must be in (0, 180), got 0");
}

#[test]
fn zero_resolution() {
    let text = format!("{CAMERA}resolution = [0, 256]\n");
    check(&text, "[0, 256]", "camera.resolution", ErrorKind::OutOfRange, "got [0, 256]");
}

#[test]
fn huge_resolution() {
    let text = format!("{CAMERA}resolution = [100000, 256]\n");
    check(&text, "[100000", "camera.resolution", ErrorKind::OutOfRange, "[1, 16384]");
}

#[test]
fn zero_spp() {
    let text = format!("{CAMERA}\n[integrator]\nspp = 0\n");
    check(&text, "0\n", "integrator.spp", ErrorKind::OutOfRange, "must be in [1, 16777216], got 0");
}

#[test]
fn negative_time_budget() {
    let text = format!("{CAMERA}\n[integrator]\ntime = -1.0\n");
    check(&text, "-1.0", "integrator.time", ErrorKind::OutOfRange, "must be >= 0");
}

#[test]
fn unknown_material_name() {
    let text = with_material("type = \"diffuse\"\nalbedo = [0.5, 0.5, 0.5]")
        .replace("material = \"gold\"", "material = \"golf\"");
    check(
        &text,
        "\"golf\"",
        "shapes[0].material",
        ErrorKind::UnknownMaterial,
        "unknown material \"golf\" (defined: gold)",
    );
}

#[test]
fn sphere_radius_must_be_positive() {
    let text = format!("{}radius = -1\n", with_material("type = \"diffuse\"\nalbedo = [0.5, 0.5, 0.5]"));
    check(&text, "-1", "shapes[0].radius", ErrorKind::OutOfRange, "must be > 0, got -1");
}

#[test]
fn shape_key_not_applicable() {
    let text = format!("{}segments = 12\n", with_material("type = \"diffuse\"\nalbedo = [0.5, 0.5, 0.5]"));
    check(&text, "12", "shapes[0].segments", ErrorKind::Conflict, "does not apply to type \"sphere\"");
}

#[test]
fn zero_scale() {
    let text =
        format!("{}transform = {{ scale = 0 }}\n", with_material("type = \"diffuse\"\nalbedo = [0.5, 0.5, 0.5]"));
    check(&text, "0 }", "shapes[0].transform.scale", ErrorKind::OutOfRange, "must be > 0, got 0");
}

#[test]
fn negative_scale_component() {
    let text = format!(
        "{}transform = {{ scale = [1, -2, 1] }}\n",
        with_material("type = \"diffuse\"\nalbedo = [0.5, 0.5, 0.5]")
    );
    check(&text, "[1, -2, 1]", "shapes[0].transform.scale", ErrorKind::OutOfRange, "got -2 (component 1)");
}

#[test]
fn overflowing_transform() {
    let text = format!(
        "{}transform = {{ translate = [3e38, 0, 0], scale = 1e38 }}\n",
        with_material("type = \"diffuse\"\nalbedo = [0.5, 0.5, 0.5]")
    );
    check(&text, "\"sphere\"", "shapes[0]", ErrorKind::Degenerate, "non-finite vertices");
}

#[test]
fn zero_area_light() {
    let text = format!(
        "{CAMERA}\n[materials.lamp]\ntype = \"emissive\"\nradiance = [1, 1, 1]\n\n[[shapes]]\ntype = \"rectangle\"\nmaterial = \"lamp\"\ntransform = {{ scale = 1e-25 }}\n"
    );
    check(&text, "\"rectangle\"", "shapes[0]", ErrorKind::Degenerate, "zero-area");
}

#[test]
fn degenerate_emissive_mesh() {
    let dir = tmp_dir("degenerate_emissive_mesh");
    std::fs::write(dir.join("line.obj"), "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n").unwrap();
    let text = format!(
        "{CAMERA}\n[materials.lamp]\ntype = \"emissive\"\nradiance = [1, 1, 1]\n\n[[shapes]]\ntype = \"mesh\"\nmaterial = \"lamp\"\nfile = \"line.obj\"\n"
    );
    check_in(&dir, &text, "\"mesh\"", "shapes[0]", ErrorKind::Degenerate, "zero-area");
}

#[test]
fn camera_position_equals_look_at() {
    let text = "[camera]\nposition = [1, 2, 3]\nlook_at = [1.0, 2.0, 3.0]\n";
    check(text, "[1.0, 2.0, 3.0]", "camera.look_at", ErrorKind::Degenerate, "coincide");
}

#[test]
fn camera_up_parallel_to_view() {
    let text = "[camera]\nposition = [0, 0, 0]\nlook_at = [0, 5, 0]\nup = [0, 2, 0]\n";
    check(text, "[0, 2, 0]", "camera.up", ErrorKind::Degenerate, "parallel");
}

#[test]
fn missing_mesh_file() {
    let text = with_material("type = \"diffuse\"\nalbedo = [0.5, 0.5, 0.5]")
        .replace("\"sphere\"", "\"mesh\"\nfile = \"nope.obj\"");
    check(&text, "\"nope.obj\"", "shapes[0].file", ErrorKind::File, "mesh file not found");
}

#[test]
fn unreadable_mesh_file() {
    let dir = tmp_dir("unreadable_mesh_file");
    std::fs::write(dir.join("bad.obj"), [0xff, 0xfe, 0x00, 0x80]).unwrap();
    let text = with_material("type = \"diffuse\"\nalbedo = [0.5, 0.5, 0.5]")
        .replace("\"sphere\"", "\"mesh\"\nfile = \"bad.obj\"");
    check_in(&dir, &text, "\"bad.obj\"", "shapes[0].file", ErrorKind::File, "cannot read");
}

#[test]
fn invalid_mesh_file() {
    let dir = tmp_dir("invalid_mesh_file");
    std::fs::write(dir.join("bad.obj"), "v 0 0 0\nf 1 2 3\n").unwrap();
    let text = with_material("type = \"diffuse\"\nalbedo = [0.5, 0.5, 0.5]")
        .replace("\"sphere\"", "\"mesh\"\nfile = \"bad.obj\"");
    check_in(&dir, &text, "\"bad.obj\"", "shapes[0].file", ErrorKind::File, "bad.obj");
}

#[test]
fn empty_mesh_file() {
    let dir = tmp_dir("empty_mesh_file");
    std::fs::write(dir.join("empty.obj"), "# nothing\nv 0 0 0\n").unwrap();
    let text = with_material("type = \"diffuse\"\nalbedo = [0.5, 0.5, 0.5]")
        .replace("\"sphere\"", "\"mesh\"\nfile = \"empty.obj\"");
    check_in(&dir, &text, "\"empty.obj\"", "shapes[0].file", ErrorKind::File, "no triangles");
}

#[test]
fn mesh_needs_file() {
    let text = with_material("type = \"diffuse\"\nalbedo = [0.5, 0.5, 0.5]").replace("\"sphere\"", "\"mesh\"");
    check(&text, "\"mesh\"", "shapes[0].type", ErrorKind::Conflict, "needs `file`");
}

#[test]
fn missing_environment_map() {
    let text = format!("{CAMERA}\n[environment]\ntype = \"map\"\nfile = \"sky.exr\"\n");
    check(&text, "\"sky.exr\"", "environment.file", ErrorKind::File, "environment map not found");
}

#[test]
fn invalid_environment_map() {
    let dir = tmp_dir("invalid_environment_map");
    std::fs::write(dir.join("sky.hdr"), "not an hdr file").unwrap();
    std::fs::write(dir.join("sky.png"), "whatever").unwrap();
    let text = format!("{CAMERA}\n[environment]\ntype = \"map\"\nfile = \"sky.hdr\"\n");
    check_in(&dir, &text, "\"sky.hdr\"", "environment.file", ErrorKind::File, "sky.hdr");
    let text = text.replace("sky.hdr", "sky.png");
    check_in(&dir, &text, "\"sky.png\"", "environment.file", ErrorKind::File, "unsupported environment map format");
}

#[test]
fn environment_key_not_applicable() {
    let text = format!("{CAMERA}\n[environment]\ntype = \"constant\"\nradiance = [1, 1, 1]\nscale = 2.0\n");
    check(&text, "2.0", "environment.scale", ErrorKind::Conflict, "does not apply to type \"constant\"");
}

#[test]
fn procedural_resolution_too_large() {
    let text = format!("{CAMERA}\n[environment]\ntype = \"procedural\"\npreset = \"sky\"\nresolution = [100000, 10]\n");
    check(&text, "[100000", "environment.resolution", ErrorKind::OutOfRange, "width must be in [1, 4096]");
}

#[test]
fn unreadable_scene_file() {
    let err = load_scene(Path::new("no/such/scene.toml")).unwrap_err();
    assert_eq!(err.kind(), ErrorKind::Io);
    assert!(err.to_string().starts_with("no/such/scene.toml: cannot read scene file"), "{err}");
}

#[test]
fn load_scene_names_the_path() {
    let dir = tmp_dir("load_scene_names_the_path");
    let path = dir.join("bad.toml");
    std::fs::write(&path, format!("{CAMERA}fov_y = 200\n")).unwrap();
    let err = load_scene(&path).unwrap_err();
    assert!(err.to_string().starts_with(&format!("{}:4:9: camera.fov_y: ", path.display())), "{err}");
}
