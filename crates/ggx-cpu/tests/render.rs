//! End-to-end tests of the CPU renderer: every shipped scene renders, the white furnace
//! vanishes, a disk light over a diffuse plane matches its closed form on and off its axis,
//! every BSDF and light strategy converges to the same image, MIS compensation changes the
//! noise and not the image, and the image is bit-identical whatever the thread count or
//! kernel specialization.

mod support;

use ggx_cpu::{AccelKind, RenderControl, RenderOptions, Renderer};
use glam::Vec3;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use support::{mean, render, scene_from};

#[test]
fn every_shipped_scene_renders() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let mut count = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "toml") {
            continue;
        }
        let mut scene = ggx_scene::load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
        scene.camera.resolution = [24, 16];
        scene.integrator.spp = 2;
        scene.integrator.time_budget = None;
        for accel in [AccelKind::Wide, AccelKind::Cwbvh, AccelKind::Bvh2] {
            let r = Renderer::new(&scene, accel).render(&RenderOptions::default(), &RenderControl::default()).unwrap();
            let px = r.film.mean();
            assert_eq!(r.spp, 2);
            assert!(px.iter().all(|p| p.is_finite() && p.min_element() >= 0.0), "{}", path.display());
            assert!(mean(&px).max_element() > 0.0, "{} is black", path.display());
        }
        count += 1;
    }
    assert!(count >= 6, "only {count} scenes found");
}

const FURNACE: &str = r#"
[camera]
position = [0, 0, 4]
look_at = [0, 0, 0]
fov_y = 20.0
resolution = [32, 32]
[integrator]
spp = 64
max_depth = 64
russian_roulette = 4
light_strategy = "STRATEGY"
[environment]
type = "constant"
radiance = [0.7, 0.7, 0.7]
[materials.white]
type = "diffuse"
albedo = [1, 1, 1]
[[shapes]]
type = "sphere"
material = "white"
subdivisions = 5
"#;

/// A white diffuse sphere in a uniform environment is invisible: every pixel is 0.7.
#[test]
fn white_furnace_renders_the_environment_radiance() {
    for strategy in ["bsdf", "nee", "mis"] {
        let r = render(&scene_from(&FURNACE.replace("STRATEGY", strategy)));
        let m = mean(&r.film.mean());
        println!("{strategy}: furnace mean {m}");
        assert!((m - Vec3::splat(0.7)).abs().max_element() < 0.007, "{strategy}: {m}");
    }
}

/// An F = 1 GGX sphere in the same furnace never reflects more than it receives
/// (single scattering loses energy at high roughness).
#[test]
fn ggx_furnace_never_gains_energy() {
    let conductor = |compensation: &str| {
        FURNACE.replace("STRATEGY", "mis").replace(
            "type = \"diffuse\"\nalbedo = [1, 1, 1]",
            &format!("type = \"conductor\"\nalpha = 0.8\npreset = \"ideal\"\nenergy_compensation = {compensation}"),
        )
    };
    let single = mean(&render(&scene_from(&conductor("false"))).film.mean());
    println!("rough ideal conductor in the furnace, single scattering: {single}");
    // The sphere fills the frame; single-scattering GGX at alpha 0.8 keeps roughly half.
    assert!(single.max_element() <= 0.7 * 1.005 && single.min_element() > 0.2, "{single}");
    // Kulla & Conty's lobe restores what the single-scattering lobe loses.
    let multiple = mean(&render(&scene_from(&conductor("true"))).film.mean());
    println!("rough ideal conductor in the furnace, compensated: {multiple}");
    assert!((multiple - Vec3::splat(0.7)).abs().max_element() < 0.007, "{multiple}");
}

/// A plastic with a white base: with compensation the base sees the coat's `1 - E` and the
/// sphere vanishes; with two Fresnel transmissions it loses the light the coat reflects back.
#[test]
fn white_plastic_conserves_energy_only_with_compensation() {
    let plastic = |alpha: f32, compensation: &str| {
        let material =
            format!("type = \"plastic\"\nalpha = {alpha}\nalbedo = [1, 1, 1]\nenergy_compensation = {compensation}");
        let text = FURNACE.replace("STRATEGY", "mis").replace("type = \"diffuse\"\nalbedo = [1, 1, 1]", &material);
        mean(&render(&scene_from(&text)).film.mean())
    };
    for alpha in [0.05, 0.3, 1.0] {
        let (on, off) = (plastic(alpha, "true"), plastic(alpha, "false"));
        println!("white plastic alpha {alpha}: compensated {on}, two Fresnel transmissions {off}");
        assert!((on - Vec3::splat(0.7)).abs().max_element() < 0.007, "alpha {alpha}: {on}");
        assert!(off.max_element() < 0.7 * 0.97, "alpha {alpha}: {off}");
    }
}

const DISK: &str = r#"
[camera]
position = [X, 0.95, 2]
look_at = [X, 0, 0]
fov_y = 0.5
resolution = [16, 16]
[integrator]
spp = 1024
max_depth = 1
light_strategy = "STRATEGY"
[materials.plane]
type = "diffuse"
albedo = [0.5, 0.5, 0.5]
[materials.lamp]
type = "emissive"
radiance = [4, 4, 4]
[[shapes]]
type = "rectangle"
material = "plane"
transform = { rotate = [-90, 0, 0], scale = 100 }
[[shapes]]
type = "disk"
material = "lamp"
segments = 256
transform = { translate = [0, 1, 0], rotate = [90, 0, 0], scale = 0.5 }
"#;

/// Radiance of a diffuse plane under a parallel disk light of radius R at height h, at a
/// point a distance d off the disk's axis: `L_o = albedo L F`, with the view factor
/// `F = (1 - (h^2 + d^2 - R^2) / sqrt((h^2 + d^2 + R^2)^2 - 4 R^2 d^2)) / 2` (Howell's catalog,
/// differential element to a parallel disk; `R^2 / (h^2 + R^2)` on the axis). Off the axis the
/// disk's 256 triangles light the point unequally, so next-event estimation must pick among
/// them (it once always took the first, which the on-axis point's symmetry hid).
#[test]
fn disk_light_matches_its_closed_form() {
    let (h, r, albedo, radiance) = (1.0f32, 0.5f32, 0.5, 4.0);
    for d in [0.0f32, 0.8] {
        let view_factor =
            0.5 * (1.0 - (h * h + d * d - r * r) / ((h * h + d * d + r * r).powi(2) - 4.0 * r * r * d * d).sqrt());
        let expected = albedo * radiance * view_factor;
        for strategy in ["bsdf", "nee", "mis"] {
            let text = DISK.replace("STRATEGY", strategy).replace("X", &d.to_string());
            let m = mean(&render(&scene_from(&text)).film.mean());
            println!("d = {d}, {strategy}: {m} (closed form {expected})");
            assert!((m.x - expected).abs() < 0.005 * expected, "d = {d}, {strategy}: {m} vs {expected}");
        }
    }
}

const MIXED: &str = r#"
[camera]
position = [0, 1.2, 3]
look_at = [0, 0.3, 0]
fov_y = 40.0
resolution = [16, 16]
[integrator]
spp = 16
max_depth = 4
russian_roulette = 2
seed = SEED
bsdf_sampling = "BSDF"
light_strategy = "LIGHT"
[environment]
type = "constant"
radiance = [0.3, 0.35, 0.4]
[materials.floor]
type = "diffuse"
albedo = [0.6, 0.6, 0.6]
[materials.glossy]
type = "conductor"
alpha = 0.15
preset = "gold"
[materials.rough]
type = "conductor"
alpha = [0.2, 0.6]
preset = "copper"
[materials.plastic]
type = "plastic"
roughness = 0.4
albedo = [0.1, 0.3, 0.6]
[materials.lamp]
type = "emissive"
radiance = [6, 6, 6]
[[shapes]]
type = "rectangle"
material = "floor"
transform = { rotate = [-90, 0, 0], scale = 6 }
[[shapes]]
type = "sphere"
material = "glossy"
center = [-0.7, 0.35, 0]
radius = 0.35
subdivisions = 3
[[shapes]]
type = "sphere"
material = "rough"
center = [0.7, 0.35, 0]
radius = 0.35
subdivisions = 3
[[shapes]]
type = "sphere"
material = "plastic"
center = [0, 0.3, -0.6]
radius = 0.3
subdivisions = 3
[[shapes]]
type = "disk"
material = "lamp"
transform = { translate = [0, 2, 0.5], rotate = [90, 0, 0], scale = 0.6 }
"#;

/// Mean and standard error over seeds of the 4x4-pixel block averages of a 16x16 image of
/// [`MIXED`].
fn block_stats(bsdf: &str, light: &str, seeds: std::ops::Range<u64>) -> (Vec<f64>, Vec<f64>) {
    block_stats_of(|seed| MIXED.replace("SEED", &seed.to_string()).replace("BSDF", bsdf).replace("LIGHT", light), seeds)
}

/// Mean squared z-score of the 48 block/channel means of `m` against `reference`.
fn mean_z2((m, se): &(Vec<f64>, Vec<f64>), (reference, ref_se): &(Vec<f64>, Vec<f64>)) -> f64 {
    (0..48).map(|j| (m[j] - reference[j]).powi(2) / (se[j].powi(2) + ref_se[j].powi(2) + 1e-10)).sum::<f64>() / 48.0
}

/// [`block_stats`] of the scene `text_of(seed)`.
fn block_stats_of(text_of: impl Fn(u64) -> String, seeds: std::ops::Range<u64>) -> (Vec<f64>, Vec<f64>) {
    let mut samples: Vec<Vec<f64>> = vec![];
    let seeds_n = seeds.end - seeds.start;
    for seed in seeds {
        let text = text_of(seed);
        let px = render(&scene_from(&text)).film.mean();
        let mut blocks = vec![0.0f64; 16 * 3];
        for (i, p) in px.iter().enumerate() {
            let b = (i / 16 / 4) * 4 + (i % 16) / 4;
            for c in 0..3 {
                blocks[b * 3 + c] += p[c] as f64 / 16.0;
            }
        }
        samples.push(blocks);
    }
    let n = seeds_n as f64;
    let mean: Vec<f64> = (0..48).map(|j| samples.iter().map(|s| s[j]).sum::<f64>() / n).collect();
    let se = (0..48)
        .map(|j| (samples.iter().map(|s| (s[j] - mean[j]).powi(2)).sum::<f64>() / (n - 1.0) / n).sqrt())
        .collect();
    (mean, se)
}

const SEEDS: u64 = 32;

/// Every BSDF sampling technique with every light strategy converges to the same image:
/// the mean squared z-score of the 48 block/channel means against the reference
/// (VNDF + MIS) stays near 1 (a biased configuration drives it far above).
#[test]
fn all_strategies_converge_to_the_same_image() {
    // Independent seeds for the reference, so no configuration shares its random numbers.
    let reference = block_stats("vndf", "mis", 1000..1032);
    for bsdf in ["cosine", "ndf", "vndf", "spherical-caps", "bounded"] {
        for light in ["bsdf", "nee", "mis"] {
            let z2 = mean_z2(&block_stats(bsdf, light, 0..SEEDS), &reference);
            println!("{bsdf:>14} + {light:<4}: mean z^2 = {z2:.2}");
            assert!(z2 < 3.0, "{bsdf} + {light} disagrees with vndf + mis: mean z^2 = {z2}");
        }
    }
}

/// MIS compensation (`integrator.mis_compensation`) changes the noise, not the image: under
/// a procedural sky (sampled by its compensated distribution) and under a constant
/// environment beside an area light (left to BSDF sampling), compensated MIS with every BSDF
/// sampling technique agrees with uncompensated MIS, and so do NEE alone and BSDF sampling
/// alone. Compensation is unbiased only where BSDF sampling reaches every direction the
/// compensated density leaves out: each technique must.
#[test]
fn mis_compensation_changes_the_noise_not_the_image() {
    let sky = "[environment]\ntype = \"procedural\"\npreset = \"sky\"\nresolution = [64, 32]\nrotation = 30\n";
    let constant = "[environment]\ntype = \"constant\"\nradiance = [0.3, 0.35, 0.4]\n";
    assert!(MIXED.contains(constant));
    let techniques = ["cosine", "ndf", "vndf", "spherical-caps", "bounded"];
    let configurations = techniques.iter().map(|&b| (b, "mis")).chain([("vndf", "nee"), ("vndf", "bsdf")]);
    let configurations: Vec<_> = configurations.collect();
    for environment in [sky, constant] {
        let scene = |bsdf: &str, light: &str, compensation: bool, seed: u64| {
            MIXED
                .replace(constant, environment)
                .replace("SEED", &format!("{seed}\nmis_compensation = {compensation}"))
                .replace("BSDF", bsdf)
                .replace("LIGHT", light)
        };
        let reference = block_stats_of(|seed| scene("vndf", "mis", false, seed), 1000..1032);
        for &(bsdf, light) in &configurations {
            let z2 = mean_z2(&block_stats_of(|seed| scene(bsdf, light, true, seed), 0..SEEDS), &reference);
            let env = environment.lines().nth(1).unwrap_or_default();
            println!("{env}, {bsdf} + {light} (compensated): mean z^2 = {z2:.2}");
            assert!(z2 < 3.0, "{env}, {bsdf} + {light}: disagrees with uncompensated MIS: mean z^2 = {z2}");
        }
    }
}

#[test]
fn image_is_bit_identical_for_any_thread_count_and_kernel() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/cornell.toml");
    let mut scene = ggx_scene::load_scene(&path).unwrap();
    scene.camera.resolution = [40, 24];
    scene.integrator.spp = 6;
    for accel in [AccelKind::Cwbvh, AccelKind::Wide] {
        let renderer = Renderer::new(&scene, accel);
        let image = |threads, specialize| {
            let r = renderer
                .render(&RenderOptions { threads, specialize, ..Default::default() }, &RenderControl::default())
                .unwrap();
            r.film.mean().iter().flat_map(|p| p.to_array().map(f32::to_bits)).collect::<Vec<u32>>()
        };
        let one = image(1, true);
        assert_eq!(one, image(2, true), "{accel:?}: 1 vs 2 threads");
        assert_eq!(one, image(3, true), "{accel:?}: 1 vs 3 threads");
        assert_eq!(one, image(2, false), "{accel:?}: specialized vs generic kernel");
    }
    let renderer = Renderer::new(&scene, AccelKind::Wide);
    let wide = mean(&renderer.render(&RenderOptions::default(), &RenderControl::default()).unwrap().film.mean());
    for other in [AccelKind::Cwbvh, AccelKind::Bvh2] {
        let r = Renderer::new(&scene, other).render(&RenderOptions::default(), &RenderControl::default()).unwrap();
        let diff = mean(&r.film.mean()) - wide;
        assert!(diff.abs().max_element() < 1e-3, "{other:?} and the wide BVH differ by {diff}");
    }
}

#[test]
fn cancelling_keeps_the_completed_passes() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/cornell.toml");
    let mut scene = ggx_scene::load_scene(&path).unwrap();
    scene.camera.resolution = [32, 32];
    scene.integrator.spp = 1000;
    let renderer = Renderer::new(&scene, AccelKind::Cwbvh);
    let cancel = AtomicBool::new(false);
    let stop_after_first = |p: ggx_cpu::Progress| {
        if p.pass_end && p.spp_done >= 2 {
            cancel.store(true, Ordering::Relaxed);
        }
    };
    let r = renderer
        .render(
            &RenderOptions::default(),
            &RenderControl { cancel: Some(&cancel), progress: Some(&stop_after_first), pass_film: None },
        )
        .unwrap();
    assert!(r.interrupted);
    assert_eq!(r.spp, 2, "passes 1 + 1 completed before the flag was seen");
    assert!(mean(&r.film.mean()).max_element() > 0.0);

    let cancelled = AtomicBool::new(true);
    let r = renderer
        .render(&RenderOptions::default(), &RenderControl { cancel: Some(&cancelled), progress: None, pass_film: None })
        .unwrap();
    assert!(r.interrupted && r.spp == 0);
}

#[test]
fn time_budget_ends_the_render_early() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/cornell.toml");
    let mut scene = ggx_scene::load_scene(&path).unwrap();
    scene.camera.resolution = [64, 64];
    scene.integrator.spp = 1 << 20;
    scene.integrator.time_budget = Some(0.3);
    let r = render(&scene);
    assert!(!r.interrupted && r.spp >= 1 && r.spp < 1 << 20, "spp {}", r.spp);
}
