//! Environment-map lookups (`cargo bench -p ggx-scene`): lookups per second on the procedural
//! sky the peer scenes use (512 x 256 texels: 2 MiB of texels and 1.5 MiB of sampling tables,
//! more than a core's L2), at random points, one thread. What the path tracer pays per
//! environment light sample (`light_sample`: the direction, its pdf and the radiance
//! along it) and per escaped path (`radiance_and_pdf`). Each lookup waits for the one before
//! (its input carries `0 x` the previous result), as a path's next bounce waits for this one:
//! the figures are latencies, with no cache miss overlapped across lookups.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use ggx_scene::{EnvMap, sky, uniform_sphere};
use glam::{Vec2, Vec3};

/// Lookups per iteration.
const N: usize = 1 << 16;

/// `N` points of the unit square from a 32-bit LCG (fixed seed), so each lookup lands on an
/// unpredictable texel, as a path's bounces do.
fn points() -> Vec<Vec2> {
    let mut s = 0x2545_f491_u32;
    let mut next = move || {
        s = s.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
        (s >> 8) as f32 / 16_777_216.0
    };
    (0..N).map(|_| Vec2::new(next(), next())).collect()
}

fn env_map(c: &mut Criterion) {
    let (w, h) = (512, 256);
    let map = EnvMap::new(w, h, sky(w, h), 1.0, 30.0).expect("the procedural sky is a valid map");
    let us = points();
    let directions: Vec<Vec3> = us.iter().map(|&u| uniform_sphere(u)).collect();
    let mut g = c.benchmark_group("env_map");
    g.throughput(Throughput::Elements(N as u64));
    g.bench_function("light_sample", |b| {
        b.iter(|| {
            us.iter().fold(0.0f32, |previous, &u| {
                let (_, pdf, l) = map.sample_with_radiance(u + Vec2::splat(0.0 * previous));
                l.x + pdf
            })
        })
    });
    g.bench_function("radiance_and_pdf", |b| {
        b.iter(|| {
            directions.iter().fold(0.0f32, |previous, &d| {
                let (l, pdf) = map.radiance_and_pdf(d + Vec3::splat(0.0 * previous));
                l.x + pdf
            })
        })
    });
    g.finish();
}

criterion_group!(benches, env_map);
criterion_main!(benches);
