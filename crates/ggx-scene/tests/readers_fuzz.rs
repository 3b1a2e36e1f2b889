//! Mutation testing of the readers of user files (`.exr` and `.hdr` environment maps, OBJ
//! meshes), and regression tests for the defects a hostile trial found in them.
//!
//! Each proptest target writes a small valid file, mutates it (bit flips, truncation,
//! splicing, and header fields: sizes, data windows, channel lists, chunk tables, RGBE
//! dimension lines, OBJ indices and face sizes) and reads it under small [`Limits`]. The
//! reader must return `Ok` with a consistent result within the limits, or an error that
//! names the file; it must not panic or abort. On Linux every test runs again in a child
//! process whose address space is capped at [`fuzz_cases::ADDRESS_SPACE_CAP`], so a reader that
//! allocates from an unchecked size aborts the child and fails the test.
//!
//! `GGX_FUZZ_CASES` sets the number of cases per target (default [`DEFAULT_CASES`]).

mod fuzz_cases;
mod readers_support;

use std::path::{Path, PathBuf};

use ggx_scene::{ErrorKind, Limits, MAX_RADIANCE, load_image, parse_obj_with_limits, parse_scene};
use proptest::prelude::*;
use readers_support::{
    MUTATED_EXR_FIELDS, Mutation, exr_bytes, hdr_bytes, mutate, obj_text, rle_hdr, set_attribute_i32s,
};

/// Cases per proptest target when `GGX_FUZZ_CASES` is unset: about a second each in the dev
/// profile.
const DEFAULT_CASES: u32 = 96;

/// The small limits the mutated files are read under.
const SMALL: Limits = Limits {
    max_scene_bytes: 1 << 20,
    max_mesh_bytes: 1 << 20,
    max_map_pixels: 1 << 16,
    max_triangles: 1 << 14,
    max_memory: 32 << 20,
};

/// Cases per target: `GGX_FUZZ_CASES` (a value that is not a number stops the test), else
/// [`DEFAULT_CASES`].
fn cases() -> u32 {
    fuzz_cases::fuzz_cases(DEFAULT_CASES)
}

fn config() -> ProptestConfig {
    ProptestConfig { cases: cases(), failure_persistence: None, ..ProptestConfig::default() }
}

/// [`fuzz_cases::ran_capped`] for this binary.
fn ran_capped(name: &str) -> bool {
    fuzz_cases::ran_capped(name, "GGX_READERS_CHILD")
}

/// A fresh directory for the files of test `name`.
fn test_dir(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("readers_fuzz").join(name);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Reads map `bytes` written to `path` under `limits` and checks the outcome.
fn check_map(path: &Path, bytes: &[u8], limits: &Limits) -> Result<(), TestCaseError> {
    std::fs::write(path, bytes).unwrap();
    match load_image(path, limits) {
        Ok((w, h, texels)) => {
            prop_assert!(w >= 1 && h >= 1 && w <= ggx_scene::MAX_MAP_SIZE && h <= ggx_scene::MAX_MAP_SIZE);
            prop_assert!(u64::from(w) * u64::from(h) <= limits.max_map_pixels);
            prop_assert_eq!(texels.len() as u64, u64::from(w) * u64::from(h));
        }
        Err(e) => prop_assert!(e.starts_with(&path.display().to_string()), "error does not name the file: {e}"),
    }
    Ok(())
}

fn mutations() -> impl Strategy<Value = Vec<Mutation>> {
    proptest::collection::vec(readers_support::mutation(), 1..4)
}

#[test]
fn exr_mutations() {
    if ran_capped("exr_mutations") {
        return;
    }
    let path = test_dir("exr_mutations").join("m.exr");
    let source = (1usize..12, 1usize..12, 0usize..6, any::<bool>(), 1usize..4);
    proptest!(config(), |((w, h, compression, tiled, layers) in source, muts in mutations())| {
        let Some(mut bytes) = exr_bytes(w, h, compression, tiled, layers) else { return Ok(()) };
        mutate(&mut bytes, &muts);
        check_map(&path, &bytes, &SMALL)?;
    });
}

#[test]
fn exr_header_fields() {
    if ran_capped("exr_header_fields") {
        return;
    }
    let path = test_dir("exr_header_fields").join("h.exr");
    let value = prop_oneof![
        Just(0),
        Just(1),
        Just(-1),
        Just(i32::MAX),
        Just(i32::MIN),
        Just(255),
        Just(16383),
        Just(16384),
        Just(99_999),
        Just(1 << 20),
        any::<i32>(),
    ];
    let edits = proptest::collection::vec((0..MUTATED_EXR_FIELDS.len(), 0usize..40, value), 1..4);
    let source = (1usize..12, 1usize..12, 0usize..6, any::<bool>(), 1usize..4);
    proptest!(config(), |((w, h, compression, tiled, layers) in source, edits in edits, tail in mutations())| {
        let Some(mut bytes) = exr_bytes(w, h, compression, tiled, layers) else { return Ok(()) };
        for (field, word, value) in edits {
            readers_support::set_attribute_word(&mut bytes, MUTATED_EXR_FIELDS[field], word, value);
        }
        check_map(&path, &bytes, &SMALL)?;
        mutate(&mut bytes, &tail);
        check_map(&path, &bytes, &SMALL)?;
    });
}

#[test]
fn hdr_mutations() {
    if ran_capped("hdr_mutations") {
        return;
    }
    let path = test_dir("hdr_mutations").join("m.hdr");
    let axis = prop_oneof![Just("-Y"), Just("+Y"), Just("-X"), Just("+X"), Just("Y"), Just("")];
    let number = prop_oneof![
        Just("0".to_string()),
        Just("1".to_string()),
        Just("-1".to_string()),
        Just("16384".to_string()),
        Just("16385".to_string()),
        Just("100000".to_string()),
        Just("4294967296".to_string()),
        Just("99999999999999999999999".to_string()),
        (0u32..64).prop_map(|n| n.to_string()),
        any::<u32>().prop_map(|n| n.to_string()),
    ];
    let dims = proptest::option::of((axis.clone(), number.clone(), axis, number));
    proptest!(config(), |(w in 1u32..40, h in 1u32..6, seed: u32, dims in dims, muts in mutations())| {
        let mut bytes = hdr_bytes(w, h, seed);
        if let Some((a, n, b, m)) = dims {
            bytes = readers_support::replace_dimension_line(&bytes, &format!("{a} {n} {b} {m}"));
        }
        check_map(&path, &bytes, &SMALL)?;
        mutate(&mut bytes, &muts);
        check_map(&path, &bytes, &SMALL)?;
    });
}

#[test]
fn obj_mutations() {
    if ran_capped("obj_mutations") {
        return;
    }
    let index = prop_oneof![
        Just(0i64),
        Just(-1),
        Just(i64::from(i32::MIN)),
        Just(i64::from(u32::MAX)),
        Just(i64::MAX),
        Just(i64::MIN),
        -10i64..20,
        any::<i64>(),
    ];
    let edits = proptest::collection::vec((any::<prop::sample::Index>(), index), 0..4);
    let big_face = proptest::option::of(3usize..5000);
    proptest!(config(), |(n in 3usize..20, seed: u32, edits in edits, big_face in big_face, muts in mutations())| {
        let mut text = obj_text(n, seed, &edits);
        if let Some(k) = big_face {
            text.push_str(&format!("f {}\n", vec!["1"; k].join(" ")));
        }
        let mut bytes = text.into_bytes();
        mutate(&mut bytes, &muts);
        let text = String::from_utf8_lossy(&bytes);
        if let Ok(g) = parse_obj_with_limits(&text, &SMALL) {
            prop_assert!(!g.indices.is_empty() && g.indices.len() as u64 <= SMALL.max_triangles);
            prop_assert!(g.indices.iter().flatten().all(|&i| (i as usize) < g.positions.len()));
            prop_assert!(g.normals.as_ref().is_none_or(|n| n.len() == g.positions.len()));
            prop_assert!(g.area().is_finite() || g.positions.iter().any(|p| p.abs().max_element() > 1e18));
        }
    });
}

// Regression tests, one per defect of the hostile trial.

/// Found by `obj_mutations` (2026-12-03): a normal index near `2^62` overflowed `tobj`'s
/// `vn * 3` (a panic in a debug build); it is refused, naming the line, before `tobj` runs.
#[test]
fn obj_index_that_would_overflow_the_parser_is_refused() {
    for face in ["1//1 2//1 3//4611686018427387904", "1/3074457345618258603 2 3", "-9223372036854775808 1 2"] {
        let text = format!("{}f {face}\n", obj_text(4, 1, &[]));
        let err = parse_obj_with_limits(&text, &SMALL).unwrap_err();
        assert!(err.contains("line 13: vertex") && err.contains("outside the"), "{face}: {err}");
    }
}

/// A 1x1 uncompressed EXR whose data and display windows (and chunk count, one scan line
/// per chunk) are patched to declare `w x h`.
fn exr_declaring(w: i32, h: i32) -> Vec<u8> {
    let mut bytes = exr_bytes(1, 1, 0, false, 1).unwrap();
    for name in ["dataWindow", "displayWindow"] {
        assert!(set_attribute_i32s(&mut bytes, name, &[0, 0, w - 1, h - 1]), "{name}");
    }
    set_attribute_i32s(&mut bytes, "chunkCount", &[h]);
    bytes
}

#[test]
fn huge_exr_header_is_refused_before_allocating() {
    if ran_capped("huge_exr_header_is_refused_before_allocating") {
        return;
    }
    let dir = test_dir("huge_exr_header");
    let path = dir.join("huge.exr");
    let bytes = exr_declaring(100_000, 100_000);
    assert!(bytes.len() < 512, "{} bytes", bytes.len());
    std::fs::write(&path, &bytes).unwrap();
    let msg = load_image(&path, &Limits::default()).unwrap_err();
    assert!(msg.contains("100000x100000") && msg.contains("16384"), "{msg}");
    // Allowed per side, but over the default pixel limit: refused before 4 GiB are allocated.
    std::fs::write(&path, exr_declaring(16384, 16384)).unwrap();
    let msg = load_image(&path, &Limits::default()).unwrap_err();
    assert!(msg.contains("16384x16384") && msg.contains("max_map_pixels"), "{msg}");
    // Within the pixel limit, but over the memory limit.
    let limits = Limits { max_memory: 64 << 20, ..Limits::default() };
    std::fs::write(&path, exr_declaring(4096, 2048)).unwrap();
    let msg = load_image(&path, &limits).unwrap_err();
    assert!(msg.contains("4096x2048") && msg.contains("max_memory") && msg.contains("--max-memory"), "{msg}");
}

#[test]
fn exr_other_layers_and_blocks_count_towards_memory() {
    if ran_capped("exr_other_layers_and_blocks_count_towards_memory") {
        return;
    }
    let path = test_dir("exr_other_layers").join("layers.exr");
    // Three 8x8 layers; the third declares a 16384x16384 data window. Its offset table
    // alone would be 128 KiB and one of its 16-line blocks 6 MiB.
    let mut bytes = exr_bytes(8, 8, 3, false, 3).unwrap();
    let windows = readers_support::attribute_values(&bytes, "dataWindow");
    assert_eq!(windows.len(), 3);
    readers_support::write_i32s(&mut bytes, windows[2], &[0, 0, 16383, 16383]);
    std::fs::write(&path, &bytes).unwrap();
    let limits = Limits { max_memory: 1 << 20, ..Limits::default() };
    let msg = load_image(&path, &limits).unwrap_err();
    assert!(msg.contains("max_memory"), "{msg}");
    // A tile size of 2^30 x 2^30 pixels would make one block 8 EiB.
    let mut bytes = exr_bytes(8, 8, 0, true, 1).unwrap();
    assert!(set_attribute_i32s(&mut bytes, "tiles", &[1 << 30, 1 << 30]));
    std::fs::write(&path, &bytes).unwrap();
    let msg = load_image(&path, &Limits::default()).unwrap_err();
    assert!(msg.starts_with(&path.display().to_string()), "{msg}");
}

#[test]
fn hdr_larger_than_image_default_limit_loads() {
    if ran_capped("hdr_larger_than_image_default_limit_loads") {
        return;
    }
    // 6700 x 6700 = 44.9 Mpx: 539 MB as Rgb32F, over `image`'s 512 MiB default. Decoding
    // needs the 718 MB of texels only, within the 1 GiB address-space cap.
    let path = test_dir("big_hdr").join("big.hdr");
    let (w, h) = (6700, 6700);
    std::fs::write(&path, rle_hdr(w, h, [128, 64, 32, 129])).unwrap();
    let (lw, lh, texels) = load_image(&path, &Limits::default()).unwrap();
    assert_eq!((lw, lh, texels.len()), (w, h, (w * h) as usize));
    let first = texels[0];
    assert_eq!(first, [1.0, 0.5, 0.25, 1.0]);
    assert!(texels.iter().all(|t| *t == first));
    // The same file is refused, before decoding, under a smaller pixel limit.
    let limits = Limits { max_map_pixels: 40_000_000, ..Limits::default() };
    let msg = load_image(&path, &limits).unwrap_err();
    assert!(msg.contains("6700x6700") && msg.contains("max_map_pixels"), "{msg}");
}

#[test]
fn texels_that_cannot_be_allocated_are_an_error() {
    // A 16384 x 16384 map (4 GiB of texels) allowed by raised limits, read under the 1 GiB
    // address-space cap: the allocation fails and the reader says so instead of aborting.
    if !cfg!(target_os = "linux") || ran_capped("texels_that_cannot_be_allocated_are_an_error") {
        return;
    }
    let path = test_dir("texels_alloc").join("huge.hdr");
    std::fs::write(&path, b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 16384 +X 16384\n").unwrap();
    let limits = Limits { max_map_pixels: u64::MAX, max_memory: u64::MAX, ..Limits::default() };
    let msg = load_image(&path, &limits).unwrap_err();
    assert!(msg.contains("cannot allocate 4.0 GiB for 268435456 texels"), "{msg}");
}

#[test]
fn hdr_header_without_end_is_refused() {
    let path = test_dir("hdr_header").join("long.hdr");
    let mut bytes = b"#?RADIANCE\n".to_vec();
    bytes.extend(std::iter::repeat_n(b'x', 200_000));
    std::fs::write(&path, &bytes).unwrap();
    let msg = load_image(&path, &Limits::default()).unwrap_err();
    assert!(msg.contains("no end of header"), "{msg}");
}

/// A scene with the given `[environment]` body; maps resolve in `dir`.
fn scene_with_environment(dir: &Path, environment: &str) -> Result<ggx_scene::Scene, ggx_scene::SceneError> {
    let text = format!("[camera]\nposition = [0, 0, 1]\nlook_at = [0, 0, 0]\n\n[environment]\n{environment}\n");
    parse_scene(&text, "test.toml", dir)
}

#[test]
fn overflowing_environment_radiance_is_refused() {
    let dir = test_dir("radiance");
    let err = scene_with_environment(&dir, "type = \"constant\"\nradiance = [3e38, 1, 1]").unwrap_err();
    let msg = err.to_string();
    assert_eq!(err.kind(), ErrorKind::OutOfRange);
    assert!(msg.starts_with("test.toml:7:") && msg.contains("environment.radiance") && msg.contains("1e20"), "{msg}");
    assert!(scene_with_environment(&dir, "type = \"constant\"\nradiance = [1e20, 1, 1]").is_ok());

    std::fs::write(dir.join("one.exr"), exr_bytes(4, 2, 0, false, 1).unwrap()).unwrap();
    let err = scene_with_environment(&dir, "type = \"map\"\nfile = \"one.exr\"\nscale = 3e38").unwrap_err();
    let msg = err.to_string();
    assert!(msg.starts_with("test.toml:8:") && msg.contains("environment.scale") && msg.contains("1e20"), "{msg}");
    let err = scene_with_environment(&dir, "type = \"procedural\"\npreset = \"sky\"\nscale = 1e30").unwrap_err();
    assert!(err.to_string().contains("environment.scale"), "{err}");

    exr::prelude::write_rgba_file(dir.join("bright.exr"), 4, 2, |x, _| {
        (if x == 3 { 3e38f32 } else { 1.0 }, 1.0, 1.0, 1.0)
    })
    .unwrap();
    let err = scene_with_environment(&dir, "type = \"map\"\nfile = \"bright.exr\"").unwrap_err();
    let msg = err.to_string();
    assert!(msg.starts_with("test.toml:7:") && msg.contains("environment.file"), "{msg}");
    assert!(msg.contains("bright.exr") && msg.contains("texel (3, 0)") && msg.contains("1e20"), "{msg}");
    const { assert!(MAX_RADIANCE * 1e10 < f32::MAX) };
}

#[test]
fn non_regular_map_and_mesh_files_are_refused() {
    let dir = test_dir("non_regular");
    std::fs::create_dir_all(dir.join("dir.exr")).unwrap();
    let msg = load_image(&dir.join("dir.exr"), &Limits::default()).unwrap_err();
    assert!(msg.ends_with("is a directory"), "{msg}");
    let err = scene_with_environment(&dir, "type = \"map\"\nfile = \"dir.exr\"").unwrap_err();
    assert!(err.to_string().contains("is a directory"), "{err}");

    std::fs::create_dir_all(dir.join("dir.obj")).unwrap();
    let text = "[camera]\nposition = [0, 0, 1]\nlook_at = [0, 0, 0]\n[materials.m]\ntype = \"diffuse\"\n\
                albedo = [1, 1, 1]\n[[shapes]]\ntype = \"mesh\"\nmaterial = \"m\"\nfile = \"dir.obj\"\n";
    let err = parse_scene(text, "test.toml", &dir).unwrap_err();
    assert!(err.to_string().contains("is a directory") && err.to_string().contains("shapes[0].file"), "{err}");

    #[cfg(unix)]
    {
        let fifo = dir.join("fifo.hdr");
        let _ = std::fs::remove_file(&fifo);
        let made = std::process::Command::new("mkfifo").arg(&fifo).status().is_ok_and(|s| s.success());
        if made {
            let (tx, rx) = std::sync::mpsc::channel();
            let path = fifo.clone();
            std::thread::spawn(move || tx.send(load_image(&path, &Limits::default())));
            let result = rx.recv_timeout(std::time::Duration::from_secs(10)).expect("reading a FIFO hangs");
            let msg = result.unwrap_err();
            assert!(msg.contains("not a regular file"), "{msg}");
        }
    }
}

#[test]
fn obj_triangles_are_limited_before_the_mesh_is_built() {
    let mut text = String::from("v 0 0 0\nv 1 0 0\nv 0 1 0\n");
    for _ in 0..100 {
        text.push_str("f 1 2 3\n");
    }
    let limits = Limits { max_triangles: 99, ..Limits::default() };
    let msg = parse_obj_with_limits(&text, &limits).unwrap_err();
    assert!(msg.contains("needs 100, over the limit of 99") && msg.contains("--max-triangles"), "{msg}");
    assert_eq!(parse_obj_with_limits(&text, &Limits { max_triangles: 100, ..limits }).unwrap().indices.len(), 100);
}

/// Loads the map named by `GGX_MEASURE_MAP` (for measuring peak memory with
/// `/usr/bin/time -v`); ignored unless run explicitly.
#[test]
#[ignore = "measurement tool: set GGX_MEASURE_MAP and run with --ignored"]
fn measure_map_load() {
    let Some(path) = std::env::var_os("GGX_MEASURE_MAP") else { return };
    let limits = Limits { max_memory: u64::MAX, max_map_pixels: u64::MAX, ..Limits::default() };
    let (w, h, texels) = load_image(Path::new(&path), &limits).unwrap();
    println!("loaded {w}x{h}, {} texels", texels.len());
}
