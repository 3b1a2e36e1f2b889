//! Render throughput on the shipped scenes (`cargo bench -p ggx-cpu`): camera samples per
//! second for the specialized and the generic kernel with the wide BVH, and the specialized
//! kernel with obvhs' CWBVH and BVH2, on all cores. Scenes are rendered at 128x128 with 4 samples per pixel per iteration.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use ggx_cpu::{AccelKind, RenderControl, RenderOptions, Renderer};
use std::path::Path;

fn scene(name: &str) -> ggx_scene::Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes").join(name);
    let mut scene = ggx_scene::load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    scene.camera.resolution = [128, 128];
    scene.integrator.spp = 4;
    scene.integrator.time_budget = None;
    scene
}

fn throughput(c: &mut Criterion) {
    let mut g = c.benchmark_group("render");
    g.sample_size(10);
    g.throughput(Throughput::Elements(128 * 128 * 4));
    for name in ["cornell.toml", "furnace.toml", "bunny.toml", "roughness-sweep.toml"] {
        let scene = scene(name);
        for accel in [AccelKind::Wide, AccelKind::Cwbvh, AccelKind::Bvh2] {
            let renderer = Renderer::new(&scene, accel);
            for specialize in [true, false] {
                if accel != AccelKind::Wide && !specialize {
                    continue;
                }
                let id = format!("{name}/{accel:?}/{}", if specialize { "specialized" } else { "generic" });
                let options = RenderOptions { threads: 0, specialize, ..Default::default() };
                g.bench_function(id, |b| {
                    b.iter(|| renderer.render(&options, &RenderControl::default()).map(|r| r.spp).ok())
                });
            }
        }
    }
    g.finish();
}

criterion_group!(benches, throughput);
criterion_main!(benches);
