//! Ray queries per second against [`Accel`] (`cargo bench -p ggx-cpu --bench accel`), one
//! thread, on the peer scenes' meshes for each [`AccelKind`]: closest hits of camera rays
//! (coherent: one per pixel of a 64x64 image) and of scattered rays (from anywhere around the
//! scene's bounds toward a random point inside them), and shadow rays over the same scattered
//! rays up to 0.9 of their closest hit (every one unoccluded, the full walk) and to infinity.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use ggx_cpu::{Accel, AccelKind, PACKET_RAYS};
use glam::{Vec2, Vec3};
use std::hint::black_box;
use std::path::Path;

#[path = "../tests/support/rays.rs"]
mod rays;

use rays::scattered_rays;

fn queries(c: &mut Criterion) {
    let mut g = c.benchmark_group("accel");
    for name in ["three-spheres", "bunny", "anisotropic"] {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/peer").join(format!("{name}.toml"));
        let mut scene = ggx_scene::load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
        scene.camera.resolution = [64, 64];
        let camera = scene.camera.ray_generator();
        let primary: Vec<(Vec3, Vec3)> = (0..64 * 64)
            .map(|i| camera.generate_ray(Vec2::new((i % 64) as f32 + 0.5, (i / 64) as f32 + 0.5)))
            .collect();
        // Sixteen rays through each pixel of the 16x16 pixels at the image's centre, pixel by
        // pixel, as the renderer traces a pass: what packets are for.
        let jitter = |j: u32| Vec2::new((j % 4) as f32 + 0.5, (j / 4) as f32 + 0.5) / 4.0;
        let pixels: Vec<(Vec3, Vec3)> = (0..16 * 16 * PACKET_RAYS as u32)
            .map(|i| {
                let (p, j) = (i / PACKET_RAYS as u32, i % PACKET_RAYS as u32);
                camera.generate_ray(Vec2::new((24 + p % 16) as f32, (24 + p / 16) as f32) + jitter(j))
            })
            .collect();
        let Some((lo, hi)) = scene.mesh.bounds() else { continue };
        let rays = scattered_rays(lo, hi, 4096, 7);
        for kind in [AccelKind::Wide, AccelKind::Cwbvh, AccelKind::Bvh2] {
            let accel = Accel::build(&scene.mesh.triangles, kind);
            // Shadow rays that stop short of the nearest hit: nothing blocks them.
            let free: Vec<(Vec3, Vec3, f32)> = rays
                .iter()
                .filter_map(|&(o, d)| accel.closest(o, d, f32::INFINITY).map(|h| (o, d, h.t * 0.9)))
                .collect();
            g.throughput(Throughput::Elements(primary.len() as u64));
            g.bench_function(format!("{name}/{kind:?}/closest-camera"), |b| {
                b.iter(|| {
                    primary.iter().filter(|&&(o, d)| black_box(&accel).closest(o, d, f32::INFINITY).is_some()).count()
                })
            });
            g.throughput(Throughput::Elements(pixels.len() as u64));
            g.bench_function(format!("{name}/{kind:?}/closest-pixel-rays"), |b| {
                b.iter(|| {
                    pixels.iter().filter(|&&(o, d)| black_box(&accel).closest(o, d, f32::INFINITY).is_some()).count()
                })
            });
            g.bench_function(format!("{name}/{kind:?}/closest-pixel-packets"), |b| {
                let mut hits = vec![None; pixels.len()];
                b.iter(|| {
                    for (rays, hits) in pixels.chunks(PACKET_RAYS).zip(hits.chunks_mut(PACKET_RAYS)) {
                        black_box(&accel).closest_packet(rays, hits);
                    }
                    hits.iter().filter(|h| h.is_some()).count()
                })
            });
            g.throughput(Throughput::Elements(rays.len() as u64));
            g.bench_function(format!("{name}/{kind:?}/closest-scattered"), |b| {
                b.iter(|| {
                    rays.iter().filter(|&&(o, d)| black_box(&accel).closest(o, d, f32::INFINITY).is_some()).count()
                })
            });
            g.bench_function(format!("{name}/{kind:?}/shadow-to-infinity"), |b| {
                b.iter(|| rays.iter().filter(|&&(o, d)| black_box(&accel).unoccluded(o, d, f32::INFINITY)).count())
            });
            g.throughput(Throughput::Elements(free.len() as u64));
            g.bench_function(format!("{name}/{kind:?}/shadow-unoccluded"), |b| {
                b.iter(|| free.iter().filter(|&&(o, d, t)| black_box(&accel).unoccluded(o, d, t)).count())
            });
        }
    }
    g.finish();
}

criterion_group!(benches, queries);
criterion_main!(benches);
