//! [`Limits`] on what the loader reads and builds: the scene file's size and kind, the
//! triangle count and the estimated memory, checked before the triangles are allocated.

use std::path::{Path, PathBuf};

use ggx_scene::{
    BYTES_PER_TEXEL, BYTES_PER_TRIANGLE, ErrorKind, FILM_BYTES_PER_PIXEL, Limits, SceneError, estimate_memory,
    load_scene, load_scene_with, parse_scene_with,
};

/// `HEADER` and `count` mesh shapes that all name `file`.
fn meshes(count: usize, file: &str) -> String {
    let shape = format!("\n[[shapes]]\ntype = \"mesh\"\nmaterial = \"white\"\nfile = \"{file}\"\n");
    format!("{HEADER}{}", shape.repeat(count))
}

const FILE: &str = "scenes/test.toml";

const HEADER: &str = "[camera]\nposition = [0, 1, 3.5]\nlook_at = [0, 1, 0]\nresolution = [64, 32]\n\n\
                      [materials.white]\ntype = \"diffuse\"\nalbedo = [0.5, 0.5, 0.5]\n";

fn tmp_dir(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("limits").join(name);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// `HEADER` and `count` spheres at `subdivisions`.
fn spheres(count: usize, subdivisions: u32) -> String {
    let sphere = format!("\n[[shapes]]\ntype = \"sphere\"\nmaterial = \"white\"\nsubdivisions = {subdivisions}\n");
    format!("{HEADER}{}", sphere.repeat(count))
}

/// 1-based line and column of the `n`-th (0-based) occurrence of `needle`.
fn nth_position(text: &str, needle: &str, n: usize) -> (usize, usize) {
    let offset = text.match_indices(needle).nth(n).unwrap_or_else(|| panic!("no {n}-th `{needle}`")).0;
    let before = &text[..offset];
    (before.matches('\n').count() + 1, offset - before.rfind('\n').map_or(0, |i| i + 1) + 1)
}

#[track_caller]
fn parse_err(text: &str, limits: &Limits) -> SceneError {
    match parse_scene_with(text, FILE, Path::new("."), limits) {
        Ok(_) => panic!("expected an error"),
        Err(e) => e,
    }
}

#[test]
fn scene_file_over_the_size_limit_is_refused() {
    let path = tmp_dir("size").join("big.toml");
    std::fs::write(&path, format!("{HEADER}{}", "# padding\n".repeat(200))).unwrap();
    let limits = Limits { max_scene_bytes: 1000, ..Limits::default() };
    let err = load_scene_with(&path, &limits).unwrap_err();
    let shown = err.to_string();
    assert_eq!(err.kind(), ErrorKind::Limit, "{shown}");
    assert!(shown.starts_with(&path.display().to_string()), "{shown}");
    assert!(shown.contains("over the limit of 1000 B") && shown.contains("--max-scene-bytes"), "{shown}");
    assert!(load_scene(&path).is_ok());
    let err = parse_err(&std::fs::read_to_string(&path).unwrap(), &limits);
    assert_eq!(err.kind(), ErrorKind::Limit, "{err}");
}

#[cfg(unix)]
#[test]
fn devices_fifos_and_directories_are_not_read() {
    // `/dev/zero` never ends and a FIFO without a writer blocks forever: both are refused
    // before they are opened.
    let err = load_scene(Path::new("/dev/zero")).unwrap_err();
    assert_eq!(err.kind(), ErrorKind::Io, "{err}");
    assert_eq!(err.to_string(), "/dev/zero: cannot read scene file: not a regular file (a FIFO, socket or device)");
    let dir = tmp_dir("special");
    let fifo = dir.join("scene.fifo");
    let _ = std::fs::remove_file(&fifo);
    let made = std::process::Command::new("mkfifo").arg(&fifo).status();
    if made.is_ok_and(|s| s.success()) {
        let err = load_scene(&fifo).unwrap_err();
        assert!(err.to_string().ends_with("not a regular file (a FIFO, socket or device)"), "{err}");
    }
    let err = load_scene(&dir).unwrap_err();
    assert_eq!(err.kind(), ErrorKind::Io, "{err}");
    assert!(err.to_string().ends_with("cannot read scene file: is a directory"), "{err}");
}

#[test]
fn a_scene_that_is_not_utf8_says_where() {
    let path = tmp_dir("utf8").join("latin1.toml");
    std::fs::write(&path, b"[camera]\n# caf\xe9\n").unwrap();
    let err = load_scene(&path).unwrap_err();
    assert_eq!(err.kind(), ErrorKind::Io, "{err}");
    let expected =
        format!("{}: cannot read scene file: not UTF-8 text (invalid byte at line 2, column 6)", path.display());
    assert_eq!(err.to_string(), expected);
}

#[test]
fn triangle_limit_fails_at_the_shape_that_crosses_it() {
    // 327 680 triangles per sphere: three fit in 1 000 000, the fourth crosses the limit.
    let text = spheres(6, 7);
    let limits = Limits { max_triangles: 1_000_000, ..Limits::default() };
    let err = parse_err(&text, &limits);
    let (line, column) = nth_position(&text, "\"sphere\"", 3);
    let shown = err.to_string();
    assert!(shown.starts_with(&format!("{FILE}:{line}:{column}: shapes[3]: ")), "{shown}");
    assert!(shown.contains("needs 1310720, over the limit of 1000000"), "{shown}");
    assert!(shown.contains("--max-triangles"), "{shown}");
    assert_eq!((err.kind(), err.field()), (ErrorKind::Limit, "shapes[3]"));
}

#[test]
fn memory_limit_fails_at_the_shape_that_crosses_it() {
    // One sphere of 327 680 triangles fits in 1.5x its memory, the second does not.
    let one = 327_680 * BYTES_PER_TRIANGLE;
    let limits = Limits { max_memory: one + one / 2, ..Limits::default() };
    let text = spheres(3, 7);
    let err = parse_err(&text, &limits);
    let (line, column) = nth_position(&text, "\"sphere\"", 1);
    let shown = err.to_string();
    assert!(shown.starts_with(&format!("{FILE}:{line}:{column}: shapes[1]: 655360 triangles")), "{shown}");
    assert!(shown.contains("(max_memory; raise it with --max-memory)"), "{shown}");
    assert_eq!(err.kind(), ErrorKind::Limit);
}

#[test]
fn environment_map_and_triangles_share_the_memory_limit() {
    let text =
        format!("{}\n[environment]\ntype = \"procedural\"\npreset = \"sky\"\nresolution = [256, 128]\n", spheres(1, 5));
    let triangles = 20 * 4u64.pow(5) * BYTES_PER_TRIANGLE;
    let map = 256 * 128 * BYTES_PER_TEXEL;
    let limits = Limits { max_memory: triangles.max(map) + 1, ..Limits::default() };
    let err = parse_err(&text, &limits);
    let (line, column) = nth_position(&text, "\"procedural\"", 0);
    let shown = err.to_string();
    assert!(
        shown.starts_with(&format!("{FILE}:{line}:{column}: environment: 20480 triangles and a 256x128")),
        "{shown}"
    );
    assert_eq!(err.kind(), ErrorKind::Limit);
    let limits = Limits { max_memory: triangles + map, ..Limits::default() };
    let scene = parse_scene_with(&text, FILE, Path::new("."), &limits).unwrap_or_else(|e| panic!("{e}"));
    let estimate = estimate_memory(&scene);
    assert_eq!((estimate.triangles, estimate.triangle_bytes), (20480, triangles));
    assert_eq!((estimate.map_texels, estimate.map_bytes), (256 * 128, map));
    assert_eq!((estimate.film_pixels, estimate.film_bytes), (64 * 32, 64 * 32 * FILM_BYTES_PER_PIXEL));
    assert_eq!(estimate.total(), triangles + map + estimate.film_bytes);
}

#[test]
fn mesh_vertices_count_against_memory_before_the_mesh_is_parsed() {
    // 200 000 vertices and one triangle: 1.6 MB of text and 14 MB of parse buffers, over
    // 8 MiB, though its one triangle per shape (400 B) is far below it.
    let dir = tmp_dir("mesh_vertices");
    let mut obj = "v 0 0 0\n".repeat(200_000);
    obj.push_str("f 1 2 3\n");
    std::fs::write(dir.join("many.obj"), &obj).unwrap();
    let text = meshes(100, "many.obj");
    let limits = Limits { max_memory: 8 << 20, ..Limits::default() };
    let err = match parse_scene_with(&text, FILE, &dir, &limits) {
        Ok(_) => panic!("a mesh whose vertices need more than max_memory was loaded"),
        Err(e) => e,
    };
    let shown = err.to_string();
    let (line, column) = nth_position(&text, "\"many.obj\"", 0);
    assert!(shown.starts_with(&format!("{FILE}:{line}:{column}: shapes[0].file: ")), "{shown}");
    assert!(shown.contains("many.obj: mesh of 200000 vertex and 1 face lines"), "{shown}");
    assert!(shown.contains("over the limit of 8.0 MiB (max_memory; raise it with --max-memory)"), "{shown}");
    assert_eq!(err.kind(), ErrorKind::Limit);
}

#[test]
fn shapes_that_name_one_mesh_share_it() {
    // 1000 triangles with their own vertices: 48 KB of parsed mesh. Ten shapes of it need
    // 10 x 400 KB for their triangles and the mesh once; a copy per shape would not fit.
    let dir = tmp_dir("shared_mesh");
    let mut obj = String::new();
    for i in 0..1000 {
        obj.push_str(&format!("v {i} 0 0\nv {i} 1 0\nv {i} 0 1\nf {} {} {}\n", 3 * i + 1, 3 * i + 2, 3 * i + 3));
    }
    std::fs::write(dir.join("grid.obj"), &obj).unwrap();
    let text = meshes(10, "grid.obj");
    let limits = Limits { max_memory: 10 * 1000 * BYTES_PER_TRIANGLE + 200_000, ..Limits::default() };
    let scene = parse_scene_with(&text, FILE, &dir, &limits).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.mesh.triangles.len(), 10_000);
    // The memory of the mesh counts: without it, these triangles alone fit.
    let limits = Limits { max_memory: 10 * 1000 * BYTES_PER_TRIANGLE + 1000, ..Limits::default() };
    let err = match parse_scene_with(&text, FILE, &dir, &limits) {
        Ok(_) => panic!("the parsed mesh was not counted"),
        Err(e) => e,
    };
    assert!(err.to_string().contains("and their meshes ("), "{err}");
    assert_eq!(err.kind(), ErrorKind::Limit);
}

#[test]
fn environment_map_is_read_within_what_the_triangles_leave() {
    // 20 480 triangles take 7.8 MiB; a 64x32 map needs 56 KiB and more for its decoder. With
    // 1000 bytes left, the map is refused while its header is read, before its texels are
    // allocated, naming the file.
    let dir = tmp_dir("map_after_triangles");
    exr::prelude::write_rgba_file(dir.join("sky.exr"), 64, 32, |_, _| (1.0f32, 1.0, 1.0, 1.0)).unwrap();
    let text = format!("{}\n[environment]\ntype = \"map\"\nfile = \"sky.exr\"\n", spheres(1, 5));
    let triangles = 20 * 4u64.pow(5) * BYTES_PER_TRIANGLE;
    let limits = Limits { max_memory: triangles + 1000, ..Limits::default() };
    let err = match parse_scene_with(&text, FILE, &dir, &limits) {
        Ok(_) => panic!("expected an error"),
        Err(e) => e,
    };
    let shown = err.to_string();
    assert_eq!(err.field(), "environment.file", "{shown}");
    assert!(shown.contains("sky.exr: environment map 64x32 needs"), "{shown}");
    assert!(shown.contains("what the 20480 triangles (7.8 MiB) leave of 7.8 MiB"), "{shown}");
    let limits = Limits { max_memory: triangles + (1 << 20), ..Limits::default() };
    parse_scene_with(&text, FILE, &dir, &limits).unwrap_or_else(|e| panic!("{e}"));
}
