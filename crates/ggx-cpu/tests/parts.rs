//! Renders of sample ranges and pixel windows, cancelled and resumed: the film is exact, so
//! every way of splitting the work gives the single render's film bit for bit.

use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

use ggx_cpu::{AccelKind, RenderControl, RenderOptions, Renderer};
use ggx_film::Film;

fn renderer(name: &str, size: [u32; 2]) -> Renderer {
    renderer_on(name, size, AccelKind::Cwbvh)
}

fn renderer_on(name: &str, size: [u32; 2], accel: AccelKind) -> Renderer {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes").join(name);
    let mut scene = ggx_scene::load_scene(&path).unwrap();
    scene.camera.resolution = size;
    scene.integrator.spp = 40;
    Renderer::new(&scene, accel)
}

fn film(r: &Renderer, samples: [u32; 2], window: Option<[u32; 4]>, threads: usize) -> Film {
    let options = RenderOptions { threads, samples: Some(samples), window, ..Default::default() };
    r.render(&options, &RenderControl::default()).unwrap().film
}

#[test]
fn ranges_and_windows_add_up_to_the_whole() {
    // Glass and plastic: every kernel feature but the environment map. On the wide tree the
    // camera rays go in packets whose make-up follows the pass schedule, which a split
    // changes: the anisotropic scene's flat-shaded spheres have exact ties on shared edges.
    let cases = [
        ("three-spheres.toml", AccelKind::Cwbvh),
        ("glass.toml", AccelKind::Cwbvh),
        ("three-spheres.toml", AccelKind::Wide),
        ("peer/anisotropic.toml", AccelKind::Wide),
    ];
    for (scene, accel) in cases {
        let r = renderer_on(scene, [24, 18], accel);
        let whole = r.render(&RenderOptions::default(), &RenderControl::default()).unwrap().film;
        assert_eq!(film(&r, [0, 40], None, 2), whole);
        for splits in [[0, 1, 40], [0, 13, 40], [0, 39, 40]] {
            let mut merged = film(&r, [splits[1], splits[2]], None, 1);
            merged.merge(&film(&r, [splits[0], splits[1]], None, 2)).unwrap();
            assert_eq!(merged, whole, "{scene} {splits:?}");
        }
        let mut tiles = film(&r, [0, 40], Some([0, 0, 7, 18]), 2);
        assert_eq!((tiles.pixels()[6].samples, tiles.pixels()[7].samples), (40, 0));
        tiles.merge(&film(&r, [0, 40], Some([7, 0, 24, 18]), 1)).unwrap();
        assert_eq!(tiles, whole, "{scene}");
    }
}

#[test]
fn a_cancelled_pass_keeps_its_finished_tiles_and_resumes_exactly() {
    // 48x32: six 16x16 tiles; one thread finishes them one by one.
    let r = renderer("cornell.toml", [48, 32]);
    let whole = film(&r, [0, 40], None, 1);
    let cancel = AtomicBool::new(false);
    let tiles_seen = std::sync::atomic::AtomicU32::new(0);
    let stop = |p: ggx_cpu::Progress| {
        // In the third pass (samples 2..4), after its second tile.
        if !p.pass_end && p.samples_done > 2 * 48 * 32 && tiles_seen.fetch_add(1, Ordering::Relaxed) == 1 {
            cancel.store(true, Ordering::Relaxed);
        }
    };
    let passes = std::sync::Mutex::new(Vec::new());
    let on_pass = |f: &Film| passes.lock().unwrap().push(f.spp());
    let control = RenderControl { cancel: Some(&cancel), progress: Some(&stop), pass_film: Some(&on_pass) };
    let options = RenderOptions { threads: 1, samples: Some([0, 40]), ..Default::default() };
    let cut = r.render(&options, &control).unwrap();
    assert!(cut.interrupted);
    assert_eq!(*passes.lock().unwrap(), [1, 2], "checkpoints after each whole pass");
    let counts: Vec<u32> = cut.film.pixels().iter().map(|p| p.samples).collect();
    let kept = counts.iter().filter(|&&n| n == 4).count();
    assert_eq!(kept, 2 * 16 * 16, "two finished tiles of the pass in flight");
    assert_eq!(counts.iter().filter(|&&n| n == 2).count(), 48 * 32 - kept);
    assert_eq!((cut.spp, cut.camera_samples), (2, (2 * 48 * 32 + 2 * 2 * 256) as u64));
    // Resumed, per pixel from the samples it holds: the uninterrupted film, bit for bit.
    let resumed = r.render_film(&options, &RenderControl::default(), cut.film).unwrap();
    assert!(!resumed.interrupted);
    assert_eq!(resumed.film, whole);
}

#[test]
fn bad_jobs_are_errors() {
    let r = renderer("cornell.toml", [16, 8]);
    let run = |samples, window| {
        let options = RenderOptions { samples, window, ..Default::default() };
        r.render(&options, &RenderControl::default()).err().map(|e| e.to_string()).unwrap_or_default()
    };
    assert_eq!(run(Some([4, 4]), None), "the sample range 4..4 is empty");
    assert!(run(None, Some([0, 0, 17, 8])).contains("leaves the 16x8 image"));
    let mut too_many = Film::new(16, 8);
    too_many.add_pass(&[glam::Vec3::ONE; 128], 41).unwrap();
    let err = r.render_film(&RenderOptions::default(), &RenderControl::default(), too_many).err().unwrap();
    assert!(err.to_string().contains("holds 41 samples"), "{err}");
}
