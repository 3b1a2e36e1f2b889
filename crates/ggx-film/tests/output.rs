//! `write_image` / `read_exr` against the real file system: formats, exactness, atomicity and
//! error reporting.

mod common;

use std::io::ErrorKind;

use common::Scratch;
use ggx_film::{OutputError, OutputOptions, ToneMap, Vec3, read_exr, write_image};

fn clamp_opts() -> OutputOptions {
    OutputOptions { exposure: 0.0, tonemap: ToneMap::Clamp }
}

fn bits(px: &[Vec3]) -> Vec<[u32; 3]> {
    px.iter().map(|p| p.to_array().map(f32::to_bits)).collect()
}

fn decode_png(path: &std::path::Path) -> image::RgbImage {
    image::ImageReader::open(path).unwrap().with_guessed_format().unwrap().decode().unwrap().to_rgb8()
}

#[test]
fn exr_round_trip_is_bit_exact() {
    let dir = Scratch::new("exr-round-trip");
    let pixels = vec![
        Vec3::new(0.1, 0.2, 0.3),
        Vec3::new(-0.0, -1.5, 1e-45),
        Vec3::new(f32::MIN_POSITIVE, f32::MAX, f32::MIN),
        Vec3::new(f32::INFINITY, f32::NEG_INFINITY, f32::NAN),
        Vec3::new(std::f32::consts::PI, 65504.0, 123456.79),
        Vec3::new(1.0 / 3.0, 7.0e-39, 0.5),
    ];
    let path = dir.path().join("round.EXR");
    // The tone map never touches EXR data, and exposure 0 is exact.
    let opts = OutputOptions { exposure: 0.0, tonemap: ToneMap::Reinhard };
    write_image(&path, 2, 3, &pixels, &opts).unwrap();
    let (w, h, back) = read_exr(&path).unwrap();
    assert_eq!((w, h), (2, 3));
    assert_eq!(bits(&back), bits(&pixels));
    assert_eq!(dir.entries(), ["round.EXR"]);
}

#[test]
fn exr_rows_run_top_to_bottom() {
    let dir = Scratch::new("exr-orientation");
    let pixels: Vec<Vec3> = (0..12).map(|i| Vec3::new(i as f32, (i % 4) as f32, (i / 4) as f32)).collect();
    let path = dir.path().join("o.exr");
    write_image(&path, 4, 3, &pixels, &OutputOptions::default()).unwrap();
    let (w, h, back) = read_exr(&path).unwrap();
    assert_eq!((w, h, back), (4, 3, pixels));
}

#[test]
fn png_has_the_size_and_known_pixel_values() {
    let dir = Scratch::new("png");
    // Clamp: srgb(0.5) * 255 = 187.5 -> 188; srgb(0.0031308) * 255 = 10.3 -> 10.
    let pixels = [
        Vec3::ZERO,
        Vec3::new(0.5, 1.0, 0.0031308),
        Vec3::new(f32::NAN, f32::INFINITY, -1.0),
        Vec3::splat(3.0),
        Vec3::new(0.25, 0.0, 0.0),
        Vec3::ONE,
    ];
    let path = dir.path().join("img.png");
    write_image(&path, 3, 2, &pixels, &clamp_opts()).unwrap();
    let img = decode_png(&path);
    assert_eq!(img.dimensions(), (3, 2));
    let expected: [[u8; 3]; 6] = [[0, 0, 0], [188, 255, 10], [0, 255, 0], [255, 255, 255], [137, 0, 0], [255; 3]];
    for (i, want) in expected.iter().enumerate() {
        let (x, y) = (i as u32 % 3, i as u32 / 3);
        assert_eq!(img.get_pixel(x, y).0, *want, "pixel ({x}, {y})");
    }
    // ACES with one stop of exposure: 0.5 -> 1 -> 2.54 / 3.16 -> 231.6.
    write_image(&path, 3, 2, &[Vec3::splat(0.5); 6], &OutputOptions { exposure: 1.0, tonemap: ToneMap::Aces }).unwrap();
    assert!(decode_png(&path).pixels().all(|p| p.0 == [232; 3]));
    assert_eq!(dir.entries(), ["img.png"]);
}

#[test]
fn existing_file_is_replaced_only_on_success() {
    let dir = Scratch::new("replace");
    let path = dir.path().join("a.png");
    write_image(&path, 2, 2, &[Vec3::ZERO; 4], &clamp_opts()).unwrap();
    write_image(&path, 2, 2, &[Vec3::ONE; 4], &clamp_opts()).unwrap();
    assert!(decode_png(&path).pixels().all(|p| p.0 == [255; 3]), "second write must replace the first");
    let before = std::fs::read(&path).unwrap();

    // Failures before any file is touched.
    let err = write_image(&path, 2, 2, &[Vec3::ZERO; 3], &clamp_opts()).unwrap_err();
    assert!(matches!(err, OutputError::PixelCount { expected: 4, actual: 3, .. }), "{err}");
    assert!(err.to_string().starts_with(&path.display().to_string()), "{err}");
    let err = write_image(&path, 0, 2, &[], &clamp_opts()).unwrap_err();
    assert!(matches!(err, OutputError::Empty { .. }), "{err}");

    assert_eq!(std::fs::read(&path).unwrap(), before);
    assert_eq!(dir.entries(), ["a.png"]);
}

#[test]
fn failed_rename_leaves_the_old_state_and_no_temp_file() {
    // The target is a directory: the image is fully written to the temporary file, then the
    // rename fails. The directory and its contents must survive and the temp file must go.
    let dir = Scratch::new("target-is-dir");
    for name in ["out.exr", "out.png"] {
        let target = dir.path().join(name);
        std::fs::create_dir(&target).unwrap();
        std::fs::write(target.join("keep.txt"), b"keep").unwrap();
        let err = write_image(&target, 2, 1, &[Vec3::ONE; 2], &clamp_opts()).unwrap_err();
        assert!(matches!(err, OutputError::Io { .. }), "{err}");
        assert!(err.to_string().starts_with(&target.display().to_string()), "{err}");
        assert!(target.is_dir());
        assert_eq!(common::entries(&target), ["keep.txt"]);
        assert_eq!(std::fs::read(target.join("keep.txt")).unwrap(), b"keep");
    }
    assert_eq!(dir.entries(), ["out.exr", "out.png"]);
}

#[test]
fn missing_directory_is_an_error_naming_the_path() {
    let dir = Scratch::new("missing-dir");
    let path = dir.path().join("no").join("such").join("img.exr");
    let err = write_image(&path, 1, 1, &[Vec3::ONE], &clamp_opts()).unwrap_err();
    match &err {
        OutputError::Io { source, .. } => assert_eq!(source.kind(), ErrorKind::NotFound),
        other => panic!("expected an I/O error, got {other:?}"),
    }
    let msg = err.to_string();
    assert!(msg.starts_with(&path.display().to_string()), "{msg}");
    assert!(msg.contains("output directory") && msg.contains("does not exist"), "{msg}");
    assert!(dir.entries().is_empty(), "nothing may be left behind: {:?}", dir.entries());
}

#[test]
fn unsupported_extension_is_rejected_before_writing() {
    let dir = Scratch::new("bad-ext");
    for name in ["img.jpg", "img", "img.hdr"] {
        let path = dir.path().join(name);
        let err = write_image(&path, 1, 1, &[Vec3::ONE], &clamp_opts()).unwrap_err();
        assert!(matches!(err, OutputError::UnsupportedFormat { .. }), "{err}");
        assert_eq!(
            err.to_string(),
            format!("{}: unsupported image format (supported extensions: exr, png)", path.display())
        );
    }
    assert!(dir.entries().is_empty());
}

#[test]
fn concurrent_writers_use_distinct_temp_files() {
    let dir = Scratch::new("concurrent");
    let path = dir.path().join("c.exr");
    std::thread::scope(|s| {
        for i in 0..8 {
            let path = &path;
            s.spawn(move || write_image(path, 4, 4, &[Vec3::splat(i as f32); 16], &clamp_opts()).unwrap());
        }
    });
    let (_, _, px) = read_exr(&path).unwrap();
    assert!(px.iter().all(|&p| p == px[0]), "one writer's image, whole");
    assert_eq!(dir.entries(), ["c.exr"]);
}

#[test]
fn read_exr_errors_name_the_path() {
    let dir = Scratch::new("read-errors");
    let missing = dir.path().join("missing.exr");
    let err = read_exr(&missing).unwrap_err();
    assert!(matches!(err, OutputError::Decode { .. }), "{err}");
    assert!(err.to_string().starts_with(&format!("{}: cannot read EXR", missing.display())), "{err}");

    let garbage = dir.path().join("garbage.exr");
    std::fs::write(&garbage, b"not an exr file at all").unwrap();
    let err = read_exr(&garbage).unwrap_err();
    assert!(err.to_string().starts_with(&garbage.display().to_string()), "{err}");
}

#[test]
fn exr_is_scaled_by_the_exposure() {
    let dir = Scratch::new("exr-exposure");
    let pixels = [Vec3::new(0.1, 1.0, 3e38), Vec3::new(-0.5, 0.0, f32::INFINITY)];
    let path = dir.path().join("e.exr");
    write_image(&path, 2, 1, &pixels, &OutputOptions { exposure: 2.0, tonemap: ToneMap::Aces }).unwrap();
    let (_, _, back) = read_exr(&path).unwrap();
    // x4 is exact in binary; 3e38 * 4 saturates at f32::MAX instead of becoming inf.
    assert_eq!(bits(&back), bits(&[Vec3::new(0.4, 4.0, f32::MAX), Vec3::new(-2.0, 0.0, f32::INFINITY)]));
}

#[cfg(unix)]
#[test]
fn a_symlink_is_followed_and_the_mode_is_kept() {
    use std::os::unix::fs::PermissionsExt as _;
    let dir = Scratch::new("symlink");
    let real = dir.path().join("real.png");
    std::fs::write(&real, b"old").unwrap();
    std::fs::set_permissions(&real, std::fs::Permissions::from_mode(0o600)).unwrap();
    let link = dir.path().join("link.png");
    std::os::unix::fs::symlink("real.png", &link).unwrap();
    write_image(&link, 1, 1, &[Vec3::ONE], &clamp_opts()).unwrap();
    assert!(std::fs::symlink_metadata(&link).unwrap().file_type().is_symlink(), "the link stays a link");
    assert_eq!(decode_png(&real).get_pixel(0, 0).0, [255, 255, 255]);
    assert_eq!(std::fs::metadata(&real).unwrap().permissions().mode() & 0o777, 0o600);
    assert_eq!(dir.entries(), ["link.png", "real.png"]);
}

#[cfg(unix)]
#[test]
fn only_regular_files_are_replaced() {
    let dir = Scratch::new("not-regular");
    let sub = dir.path().join("d.png");
    std::fs::create_dir(&sub).unwrap();
    let msg = write_image(&sub, 1, 1, &[Vec3::ONE], &clamp_opts()).unwrap_err().to_string();
    assert!(msg.contains("refusing to replace") && msg.contains("a directory"), "{msg}");
    let msg = ggx_film::check_output(&sub).unwrap_err().to_string();
    assert!(msg.contains("a directory"), "{msg}");
    assert_eq!(dir.entries(), ["d.png"]);
}

#[test]
fn check_output_finds_unwritable_places_before_any_work() {
    let dir = Scratch::new("check-output");
    ggx_film::check_output(&dir.path().join("ok.exr")).unwrap();
    assert_eq!(dir.entries(), Vec::<String>::new(), "the probe file is removed");
    let msg = ggx_film::check_output(&dir.path().join("no/such/x.png")).unwrap_err().to_string();
    assert!(msg.contains("does not exist"), "{msg}");
    let long = dir.path().join(format!("{}.png", "n".repeat(300)));
    let msg = ggx_film::check_output(&long).unwrap_err().to_string();
    assert!(msg.contains("name too long"), "{msg}");
    let msg = ggx_film::check_output(std::path::Path::new("/proc/x.png")).unwrap_err().to_string();
    assert!(msg.contains("cannot create a file in /proc"), "{msg}");
    assert!(ggx_film::check_output(&dir.path().join("x.jpg")).is_err());
}

/// `write_file` writes any bytes the way images are written: it replaces a regular file
/// through its link, leaves no temporary file behind, and refuses a directory;
/// `check_file` says so before any work.
#[test]
fn write_file_is_atomic_like_the_images() {
    let dir = Scratch::new("write-file");
    let path = dir.path().join("stats.json");
    ggx_film::check_file(&path).unwrap();
    ggx_film::write_file(&path, b"{\"a\": 1}\n").unwrap();
    ggx_film::write_file(&path, b"{}\n").unwrap();
    assert_eq!(std::fs::read(&path).unwrap(), b"{}\n");
    let link = dir.path().join("link.json");
    std::os::unix::fs::symlink(&path, &link).unwrap();
    ggx_film::write_file(&link, b"[]\n").unwrap();
    assert_eq!(std::fs::read(&path).unwrap(), b"[]\n");
    assert!(std::fs::symlink_metadata(&link).unwrap().file_type().is_symlink(), "the link stays");
    let names: Vec<_> = std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(names.len(), 2, "no temporary file left: {names:?}");
    let sub = dir.path().join("sub.json");
    std::fs::create_dir(&sub).unwrap();
    assert!(ggx_film::check_file(&sub).is_err() && ggx_film::write_file(&sub, b"x").is_err());
}
