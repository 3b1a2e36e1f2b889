//! Renders split by samples and pixels: `--samples`, `--crop`, `ggx merge`, `--checkpoint`,
//! `--resume`, and the animation frames of `--frame`/`--frames`.

mod support;

use std::path::Path;

use ggx_film::{Film, FilmInfo};
use support::{TempDir, ggx, scene};

/// A cheap render: 40x30 pixels, 40 samples per pixel in all, of the three-spheres scene (area
/// light, environment, conductors, plastic).
const SIZE: [&str; 4] = ["--width", "40", "--height", "30"];

/// Runs `ggx args`, expecting success; returns stdout.
fn ok(args: &[&str]) -> String {
    let out = ggx(args);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "ggx {args:?} failed: {err}");
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// Runs `ggx args`, expecting exit code 1; returns stderr.
fn fails(args: &[&str]) -> String {
    let out = ggx(args);
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(1), "ggx {args:?} should fail: {err}");
    err
}

/// Renders `extra` of three-spheres into `dir/name` (40 spp unless `extra` says otherwise).
fn render(dir: &TempDir, name: &str, extra: &[&str]) -> String {
    let out = dir.path().join(name);
    let base = ["render", &scene("three-spheres.toml"), "-o", out.to_str().unwrap()];
    let spp: &[&str] = if extra.contains(&"--spp") { &[] } else { &["--spp", "40"] };
    ok(&[&base[..], &SIZE, spp, extra].concat())
}

fn film(dir: &TempDir, name: &str) -> (FilmInfo, Film) {
    ggx_film::read_film(&dir.path().join(name), 1 << 20).unwrap_or_else(|e| panic!("{e}"))
}

fn path(dir: &TempDir, name: &str) -> String {
    dir.path().join(name).to_str().unwrap().to_owned()
}

#[test]
fn any_split_merges_to_the_single_render_bit_for_bit() {
    let dir = TempDir::new("parts-split");
    render(&dir, "whole.exr", &["--samples", "0..40"]);
    render(&dir, "plain.exr", &[]);
    let (info, whole) = film(&dir, "whole.exr");
    assert_eq!((info.samples, info.total, info.window), ([0, 40], 40, [0, 0, 40, 30]));
    assert_eq!(info.backend, "cpu wide", "the BVH decides ties between triangles: part of the identity");
    assert!(info.stats.iter().any(|(k, _)| k == "cameraSamplesPerSecond"), "{:?}", info.stats);
    // The plain image is the same mean.
    let plain = ggx_film::read_exr(&dir.path().join("plain.exr")).unwrap().2;
    assert_eq!(plain, whole.mean());

    for (k, splits) in [vec![0, 1, 40], vec![0, 7, 16, 33, 40], vec![0, 20, 21, 40]].iter().enumerate() {
        let mut parts = Vec::new();
        for (i, w) in splits.windows(2).enumerate() {
            let name = format!("s{k}-{i}.exr");
            let threads = if i % 2 == 0 { "1" } else { "2" };
            render(&dir, &name, &["--samples", &format!("{}..{}", w[0], w[1]), "--threads", threads]);
            parts.push(path(&dir, &name));
        }
        parts.reverse();
        let merged = path(&dir, &format!("m{k}.exr"));
        let text =
            ok(&[&["merge"][..], &parts.iter().map(String::as_str).collect::<Vec<_>>(), &["-o", &merged]].concat());
        assert!(text.contains(&format!("merged {} parts: samples 0..40", parts.len())), "{text}");
        let (merged_info, merged_film) = film(&dir, &format!("m{k}.exr"));
        assert_eq!(merged_film, whole, "split {splits:?}");
        assert_eq!((merged_info.samples, merged_info.scene_hash), ([0, 40], info.scene_hash.clone()));
    }

    // Windows: four crops of the same samples merge to the whole too, and so do PNGs of it.
    let crops = ["0,0,16,30", "16,0,40,13", "16,13,40,30"];
    for (i, crop) in crops.iter().enumerate() {
        render(&dir, &format!("c{i}.exr"), &["--samples", "0..40", "--crop", crop]);
    }
    let (crop_info, crop_film) = film(&dir, "c1.exr");
    assert_eq!(crop_info.window, [16, 0, 40, 13]);
    assert_eq!(crop_film.pixels()[0].samples, 0, "outside the window");
    assert_eq!(crop_film.pixels()[16].samples, 40);
    ok(&["merge", &path(&dir, "c0.exr"), &path(&dir, "c1.exr"), &path(&dir, "c2.exr"), "-o", &path(&dir, "c.exr")]);
    assert_eq!(film(&dir, "c.exr").1, whole);
    ok(&["merge", &path(&dir, "c0.exr"), &path(&dir, "c1.exr"), &path(&dir, "c2.exr"), "-o", &path(&dir, "c.png")]);
    assert!(image::open(dir.path().join("c.png")).is_ok());
}

#[test]
fn merge_refuses_overlaps_strangers_and_holes() {
    let dir = TempDir::new("parts-refuse");
    render(&dir, "a.exr", &["--samples", "0..8"]);
    render(&dir, "b.exr", &["--samples", "4..12"]);
    render(&dir, "c.exr", &["--samples", "16..20"]);
    render(&dir, "seed.exr", &["--samples", "8..16", "--seed", "5"]);
    render(&dir, "plain.exr", &["--spp", "2"]);
    render(&dir, "bvh2.exr", &["--samples", "8..16", "--accel", "bvh2"]);
    let merge = |parts: &[&str], out: &str| {
        let mut args = vec!["merge".to_owned()];
        args.extend(parts.iter().map(|p| path(&dir, p)));
        args.extend(["-o".to_owned(), path(&dir, out)]);
        args
    };
    let run = |args: Vec<String>| fails(&args.iter().map(String::as_str).collect::<Vec<_>>());
    let err = run(merge(&["a.exr", "b.exr"], "x.exr"));
    assert!(err.contains("both hold samples 4..8 of pixel (0, 0): their ranges overlap"), "{err}");
    let err = run(merge(&["a.exr", "seed.exr"], "x.exr"));
    assert!(err.contains("rendered another scene"), "{err}");
    let err = run(merge(&["a.exr", "c.exr"], "x.exr"));
    assert!(err.contains("samples 8..16: no part was rendered for them"), "{err}");
    assert!(err.contains("--allow-missing"), "{err}");
    let err = run(merge(&["a.exr", "bvh2.exr"], "x.exr"));
    assert!(err.contains("was rendered on cpu bvh2, but"), "{err}");
    // Without the first or the last part, the render is not complete.
    render(&dir, "rest.exr", &["--samples", "8..40"]);
    let err = run(merge(&["rest.exr"], "x.exr"));
    assert!(err.contains("samples 0..8: no part was rendered for them"), "{err}");
    let err = run(merge(&["a.exr"], "x.exr"));
    assert!(err.contains("samples 8..40: no part was rendered for them"), "{err}");
    let err = run(merge(&["a.exr", "plain.exr"], "x.exr"));
    assert!(err.contains("holds no exact film"), "{err}");
    assert!(!dir.path().join("x.exr").exists());
    // A gap inside the pixels cannot be written even with --allow-missing; a missing tail can.
    let mut args = merge(&["a.exr", "c.exr"], "x.exr");
    args.push("--allow-missing".into());
    let err = run(args);
    assert!(err.contains("leave gaps"), "{err}");
    // A missing window is missing too.
    render(&dir, "left.exr", &["--samples", "0..40", "--crop", "0,0,20,30"]);
    let err = run(merge(&["left.exr"], "x.exr"));
    assert!(err.contains("600 of 1200 pixels lack samples of 0..40"), "{err}");
    assert!(err.contains("tile (32, 0)-(40, 16): samples from 0 on"), "{err}");
    // Gaps can be shown in a PNG.
    let mut args = merge(&["a.exr", "c.exr"], "gaps.png");
    args.push("--allow-missing".into());
    ok(&args.iter().map(String::as_str).collect::<Vec<_>>());
    render(&dir, "crop.exr", &["--samples", "8..16", "--crop", "0,0,8,8"]);
    let mut args = merge(&["a.exr", "crop.exr"], "tail.exr");
    args.push("--allow-missing".into());
    ok(&args.iter().map(String::as_str).collect::<Vec<_>>());
    let (_, tail) = film(&dir, "tail.exr");
    assert_eq!((tail.pixels()[0].samples, tail.pixels()[39].samples), (16, 8));
    // Parts need .exr; a checkpoint is never the output, by any spelling; a bad window fails
    // before anything is built.
    let err = fails(&["render", &scene("three-spheres.toml"), "-o", &path(&dir, "p.png"), "--samples", "0..4"]);
    assert!(err.contains("--samples writes an exact film, which needs an .exr file"), "{err}");
    let same = format!("{}/./o.exr", dir.path().display());
    let err = fails(&["render", &scene("three-spheres.toml"), "-o", &path(&dir, "o.exr"), "--checkpoint", &same]);
    assert!(err.contains("is also the image output"), "{err}");
    let err = fails(
        &[&["render", &scene("three-spheres.toml"), "-o", &path(&dir, "w.exr")][..], &SIZE, &["--crop", "0,0,41,2"]]
            .concat(),
    );
    assert!(err.contains("the pixel window 0,0,41,2 is empty or leaves the 40x30 image"), "{err}");
    assert!(!err.contains("built in"), "checked before the BVH: {err}");
}

#[test]
fn checkpoints_resume_and_extend_to_the_same_bits() {
    let dir = TempDir::new("parts-resume");
    render(&dir, "whole.exr", &["--samples", "0..96", "--spp", "96"]);
    // A time budget stops the first run early; its checkpoint holds what it rendered. The
    // budget is 1 µs, far less than any pass takes, so the cut does not depend on the
    // machine's speed: the first pass always runs (it measures the rate), and no later pass
    // fits (a 50 ms budget stopped nothing once 64 spp of 40x30 took less).
    let ckpt = path(&dir, "ckpt.exr");
    render(
        &dir,
        "first.png",
        &["--spp", "64", "--time", "0.000001", "--checkpoint", &ckpt, "--checkpoint-every", "0.01"],
    );
    let (info, held) = film(&dir, "ckpt.exr");
    assert_eq!(info.samples, [0, 64]);
    assert_eq!(held.spp(), 1, "the budget cut the render after its first pass");
    render(&dir, "resumed.exr", &["--resume", &ckpt]);
    let (resumed_info, resumed) = film(&dir, "resumed.exr");
    assert_eq!((resumed_info.samples, resumed.spp()), ([0, 64], 64));
    // Extending the range continues it; the result is the single render of 0..96.
    render(&dir, "extended.exr", &["--resume", &path(&dir, "resumed.exr"), "--samples", "0..96"]);
    assert_eq!(film(&dir, "extended.exr").1, film(&dir, "whole.exr").1);
    // Another scene's film, another seed or another start cannot be continued.
    let other = ["render", &scene("furnace.toml"), "-o", &path(&dir, "x.exr"), "--resume", &ckpt];
    assert!(fails(&[&other[..], &SIZE].concat()).contains("another scene"));
    let err = fails(
        &[
            &["render", &scene("three-spheres.toml"), "-o", &path(&dir, "x.exr")][..],
            &SIZE,
            &["--resume", &ckpt, "--seed", "3"],
        ]
        .concat(),
    );
    assert!(err.contains("another scene") || err.contains("seed"), "{err}");
    let err = fails(
        &[
            &["render", &scene("three-spheres.toml"), "-o", &path(&dir, "x.exr")][..],
            &SIZE,
            &["--resume", &ckpt, "--samples", "8..96"],
        ]
        .concat(),
    );
    assert!(err.contains("must start where the film's range does"), "{err}");
    assert!(!Path::new(&path(&dir, "x.exr")).exists());
}

#[test]
fn frames_render_the_camera_path() {
    let dir = TempDir::new("parts-frames");
    let template = path(&dir, "t-##.exr");
    let turntable = scene("turntable.toml");
    let small = ["--width", "24", "--height", "16", "--spp", "2"];
    let stats = path(&dir, "s-#.json");
    ok(&[&["render", &turntable, "-o", &template, "--frames", "0..3", "--stats", &stats][..], &small].concat());
    for n in 0..3 {
        let text = std::fs::read_to_string(dir.path().join(format!("s-{n}.json"))).unwrap();
        assert!(text.contains(&format!("t-0{n}.exr")), "one statistics file per frame: {text}");
    }
    let frame = |n: &str| ggx_film::read_exr(&dir.path().join(format!("t-{n}.exr"))).unwrap().2;
    let (f0, f1, f2) = (frame("00"), frame("01"), frame("02"));
    assert!(f0 != f1 && f1 != f2, "the camera moves");
    ok(&[&["render", &turntable, "-o", &path(&dir, "one.exr"), "--frame", "1"][..], &small].concat());
    assert_eq!(ggx_film::read_exr(&dir.path().join("one.exr")).unwrap().2, f1);
    let err = fails(&[&["render", &turntable, "-o", &path(&dir, "x.exr"), "--frames", "0..2"][..], &small].concat());
    assert!(err.contains("needs `#`"), "{err}");
    let err =
        fails(&[&["render", &turntable, "-o", &path(&dir, "x-#.exr"), "--frames", "0..100000"][..], &small].concat());
    assert!(err.contains("has frames 0.."), "{err}");
}
