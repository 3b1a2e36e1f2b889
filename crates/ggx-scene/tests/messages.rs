//! Error messages stay short whatever the file holds (user strings are echoed as 40
//! characters and their size), and name what is wrong with a file (a directory or a FIFO is
//! not "not found").

use std::path::{Path, PathBuf};

use ggx_scene::{ErrorKind, SceneError, parse_scene};

const FILE: &str = "scenes/test.toml";

const CAMERA: &str = "[camera]\nposition = [0, 1, 3.5]\nlook_at = [0, 1, 0]\n";

/// Longest message any of these tests accepts.
const SHORT: usize = 400;

fn tmp_dir(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("messages").join(name);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[track_caller]
fn parse_err(text: &str, base: &Path) -> SceneError {
    match parse_scene(text, FILE, base) {
        Ok(_) => panic!("expected an error"),
        Err(e) => e,
    }
}

/// Asserts the error for `text` is short and shows `long` as its first 40 characters and
/// its size.
#[track_caller]
fn check_short(text: &str, long: &str, kind: ErrorKind) -> SceneError {
    let err = parse_err(text, Path::new("."));
    let shown = err.to_string();
    assert!(shown.len() < SHORT, "{} bytes: {}…", shown.len(), &shown[..SHORT]);
    let cut = format!("{}… ({} bytes)", &long[..40], long.len());
    assert!(shown.contains(&cut), "expected `{cut}` in `{shown}`");
    assert_eq!(err.kind(), kind, "{shown}");
    err
}

#[test]
fn a_long_unknown_key_is_cut() {
    let key = "k".repeat(1 << 20);
    check_short(&format!("{CAMERA}{key} = 1\n"), &key, ErrorKind::Schema);
}

#[test]
fn a_long_string_value_is_cut() {
    let value = "v".repeat(100_000);
    let text = format!("{CAMERA}\n[integrator]\nsampler = \"{value}\"\n");
    check_short(&text, &value, ErrorKind::Schema);
    let text = format!("{CAMERA}\n[materials.m]\ntype = \"{value}\"\n");
    check_short(&text, &value, ErrorKind::Schema);
}

#[test]
fn a_long_material_name_is_cut() {
    let name = "n".repeat(100_000);
    let text = format!("{CAMERA}\n[[shapes]]\ntype = \"sphere\"\nmaterial = \"{name}\"\n");
    check_short(&text, &name, ErrorKind::UnknownMaterial);
    // In the field path too.
    let text = format!("{CAMERA}\n[materials.{name}]\ntype = \"diffuse\"\nalbedo = [2, 0, 0]\n");
    let err = check_short(&text, &name, ErrorKind::OutOfRange);
    assert!(err.field().len() < 100 && err.field().ends_with(".albedo"), "{}", err.field());
    let text = format!("{CAMERA}\n[materials.{name}]\ntype = \"diffuse\"\nalbedo = [0, 0, 0]\nior = 1.5\n");
    check_short(&text, &name, ErrorKind::Conflict);
}

#[test]
fn many_defined_materials_are_not_all_listed() {
    let materials: String =
        (0..1000).map(|i| format!("[materials.m{i:04}]\ntype = \"diffuse\"\nalbedo = [0, 0, 0]\n")).collect();
    let text = format!("{CAMERA}{materials}\n[[shapes]]\ntype = \"sphere\"\nmaterial = \"x\"\n");
    let shown = parse_err(&text, Path::new(".")).to_string();
    assert!(shown.len() < SHORT && shown.ends_with("m0015, … and 984 more)"), "{shown}");
}

#[test]
fn a_long_mesh_path_is_cut() {
    let file = "f".repeat(100_000);
    let text = format!(
        "{CAMERA}\n[materials.m]\ntype = \"diffuse\"\nalbedo = [0, 0, 0]\n\n[[shapes]]\ntype = \"mesh\"\nmaterial = \"m\"\nfile = \"{file}\"\n"
    );
    let shown = parse_err(&text, Path::new(".")).to_string();
    assert!(shown.len() < SHORT && shown.contains("mesh file not found"), "{shown}");
}

fn mesh_scene(file: &str) -> String {
    format!(
        "{CAMERA}\n[materials.m]\ntype = \"diffuse\"\nalbedo = [0, 0, 0]\n\n[[shapes]]\ntype = \"mesh\"\nmaterial = \"m\"\nfile = \"{file}\"\n"
    )
}

#[test]
fn a_directory_as_a_mesh_is_not_not_found() {
    let dir = tmp_dir("directory");
    std::fs::create_dir_all(dir.join("mesh.obj")).unwrap();
    let err = parse_err(&mesh_scene("mesh.obj"), &dir);
    assert_eq!((err.kind(), err.field()), (ErrorKind::File, "shapes[0].file"));
    assert!(err.to_string().ends_with("cannot read mesh: is a directory"), "{err}");
}

#[cfg(unix)]
#[test]
fn a_device_or_fifo_as_a_mesh_is_not_a_regular_file() {
    let err = parse_err(&mesh_scene("/dev/zero"), Path::new("."));
    assert_eq!((err.kind(), err.field()), (ErrorKind::File, "shapes[0].file"));
    assert!(err.to_string().ends_with("not a regular file (a FIFO, socket or device)"), "{err}");
    let dir = tmp_dir("fifo");
    let fifo = dir.join("mesh.obj");
    let _ = std::fs::remove_file(&fifo);
    if std::process::Command::new("mkfifo").arg(&fifo).status().is_ok_and(|s| s.success()) {
        let err = parse_err(&mesh_scene("mesh.obj"), &dir);
        assert!(err.to_string().ends_with("not a regular file (a FIFO, socket or device)"), "{err}");
    }
}

#[test]
fn long_mesh_and_map_paths_are_cut_and_the_reason_kept() {
    // A 3000-character path (many `./`), within PATH_MAX: the message shows its first 256
    // characters and still says what is wrong with the file.
    let dir = tmp_dir("long_paths");
    std::fs::write(dir.join("empty.obj"), "# no faces\n").unwrap();
    std::fs::write(dir.join("bad.exr"), "not an OpenEXR file").unwrap();
    let long = |name: &str| format!("{}{name}", "./".repeat(1500));
    let mesh = format!(
        "{CAMERA}[materials.m]\ntype = \"diffuse\"\nalbedo = [1, 1, 1]\n[[shapes]]\ntype = \"mesh\"\nmaterial = \"m\"\n\
         file = \"{}\"\n",
        long("empty.obj")
    );
    let map = format!("{CAMERA}[environment]\ntype = \"map\"\nfile = \"{}\"\n", long("bad.exr"));
    for (text, reason) in [(mesh, "the mesh has no triangles"), (map, "invalid OpenEXR header")] {
        let err = parse_err(&text, &dir);
        let shown = err.to_string();
        assert!(shown.len() < SHORT, "{} bytes: {shown}", shown.len());
        assert!(shown.contains(reason) && shown.contains(" bytes): "), "{shown}");
        assert_eq!(err.kind(), ErrorKind::File, "{shown}");
    }
}
