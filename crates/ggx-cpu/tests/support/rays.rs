//! Rays for the BVH tests and the `accel` bench (which includes this file by path).

use ggx_core::{SampleStream, SequenceKind};
use glam::Vec3;

/// `count` rays from anywhere around the bounds `lo..hi` (a box twice their size) toward random
/// points inside them, from independent random numbers of `seed`.
pub fn scattered_rays(lo: Vec3, hi: Vec3, count: u32, seed: u32) -> Vec<(Vec3, Vec3)> {
    (0..count)
        .map(|i| {
            let mut s = SampleStream::new(SequenceKind::Independent, seed, i, 0);
            let mut point = |scale: f32| {
                let (a, b) = (s.next_2d(), s.next_1d());
                (lo + hi) * 0.5 + (Vec3::new(a.x, a.y, b) - 0.5) * (hi - lo) * scale
            };
            let o = point(2.0);
            (o, (point(1.0) - o).normalize_or(Vec3::Y))
        })
        .collect()
}
