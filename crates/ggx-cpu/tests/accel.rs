//! The wide BVH against obvhs' binary BVH it is collapsed from, on every shipped scene: the
//! same closest distance and barycentrics bit for bit and the same shadow-ray answers, and where
//! the two disagree the wide BVH's is a brute-force loop's over all triangles (its box test keeps
//! a rounding margin that obvhs' lacks).

use std::path::{Path, PathBuf};

use ggx_cpu::{Accel, AccelKind, Hit, PACKET_RAYS};
use glam::{Vec2, Vec3};
use obvhs::ray::Ray;
use obvhs::triangle::Triangle as BvhTriangle;

mod support;

use support::rays::scattered_rays;

/// Every shipped scene (`scenes/*.toml`) with a mesh, loaded, with its mesh's bounds.
fn shipped_scenes() -> Vec<(PathBuf, ggx_scene::Scene, Vec3, Vec3)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let mut scenes = Vec::new();
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "toml") {
            continue;
        }
        let scene = ggx_scene::load_scene(&path).unwrap();
        if let Some((lo, hi)) = scene.mesh.bounds() {
            scenes.push((path, scene, lo, hi));
        }
    }
    assert!(scenes.len() >= 6, "only {} scenes", scenes.len());
    scenes
}

#[test]
fn wide_bvh_finds_the_binary_bvhs_hits() {
    for (path, scene, lo, hi) in shipped_scenes() {
        let tris = &scene.mesh.triangles;
        let (wide, bvh2) = (Accel::build(tris, AccelKind::Wide), Accel::build(tris, AccelKind::Bvh2));
        let (mut hits, mut ties, mut disagreements) = (0, 0, 0);
        for (o, d) in scattered_rays(lo, hi, 3000, 11) {
            let (w, b) = (wide.closest(o, d, f32::INFINITY), bvh2.closest(o, d, f32::INFINITY));
            let agree = w.map(|h| h.t.to_bits()) == b.map(|h| h.t.to_bits());
            if !agree {
                let ray = Ray::new(o.into(), d.into(), 0.0, f32::INFINITY);
                let brute = tris
                    .iter()
                    .map(|t| BvhTriangle { v0: t.v0.into(), v1: t.v1.into(), v2: t.v2.into() }.intersect(&ray))
                    .fold(f32::INFINITY, f32::min);
                let t = w.map_or(f32::INFINITY, |h| h.t);
                assert_eq!(t.to_bits(), brute.to_bits(), "{}: ray {o} {d}, binary {b:?}", path.display());
                disagreements += 1;
            }
            if let (Some(w), Some(b)) = (w, b) {
                hits += 1;
                // Two triangles at the same distance (a shared edge or vertex): either is right.
                ties += u32::from(w.triangle != b.triangle);
                if agree && w.triangle == b.triangle {
                    // The wide tree's packets give back the triangle the barycentrics read.
                    assert_eq!(
                        (w.b1.to_bits(), w.b2.to_bits()),
                        (b.b1.to_bits(), b.b2.to_bits()),
                        "{}",
                        path.display()
                    );
                }
                let limit = w.t * 0.99;
                assert!(wide.unoccluded(o, d, limit), "{}: ray {o} {d}", path.display());
            }
            // Where the binary BVH missed the nearest hit its shadow answer may be wrong too.
            let blocked = w.is_some_and(|h| h.t < 1e6);
            assert_eq!(wide.unoccluded(o, d, 1e6), !blocked, "{}: ray {o} {d}", path.display());
            if agree {
                assert_eq!(wide.unoccluded(o, d, 1e6), bvh2.unoccluded(o, d, 1e6), "{}: ray {o} {d}", path.display());
            }
        }
        assert!(hits >= 500, "{}: only {hits} rays hit", path.display());
        assert!(ties * 100 <= hits, "{}: {ties} of {hits} hits on another triangle", path.display());
        assert!(disagreements * 100 <= hits, "{}: {disagreements} of {hits} hits differ", path.display());
    }
}

/// `closest_packet`'s hits for `rays` cut into packets of the sizes in `sizes` (cycled).
fn packet_hits(accel: &Accel, rays: &[(Vec3, Vec3)], sizes: &[usize]) -> Vec<Option<Hit>> {
    let mut hits = vec![None; rays.len()];
    let (mut at, mut k) = (0, 0);
    while at < rays.len() {
        let n = sizes[k % sizes.len()].min(rays.len() - at);
        accel.closest_packet(&rays[at..at + n], &mut hits[at..at + n]);
        (at, k) = (at + n, k + 1);
    }
    hits
}

/// A hit's bits, for exact comparison.
fn bits(h: Option<Hit>) -> Option<(u32, u32, u32, u32)> {
    h.map(|h| (h.triangle, h.t.to_bits(), h.b1.to_bits(), h.b2.to_bits()))
}

/// Camera rays, sixteen through each of a grid of pixels (what the renderer packs), scattered
/// rays, and hostile ones (NaN, infinite origin, zero direction components).
fn packet_test_rays(scene: &ggx_scene::Scene, lo: Vec3, hi: Vec3) -> Vec<(Vec3, Vec3)> {
    let camera = scene.camera.ray_generator();
    let [w, h] = scene.camera.resolution;
    let mut rays = Vec::new();
    for y in (0..h).step_by(((h / 12).max(1)) as usize) {
        for x in (0..w).step_by(((w / 12).max(1)) as usize) {
            for j in 0..PACKET_RAYS as u32 {
                let jitter = Vec2::new((j % 4) as f32 + 0.5, (j / 4) as f32 + 0.5) / 4.0;
                rays.push(camera.generate_ray(Vec2::new(x as f32, y as f32) + jitter));
            }
        }
    }
    rays.extend(scattered_rays(lo, hi, 1500, 5));
    let centre = (lo + hi) * 0.5;
    let (nan, inf) = (f32::NAN, f32::INFINITY);
    rays.extend([
        (centre + Vec3::Z * 100.0, Vec3::new(nan, 0.0, -1.0)),
        (Vec3::new(nan, 0.0, 0.0), -Vec3::Z),
        (Vec3::new(0.0, inf, 0.0), -Vec3::Y),
        (centre + Vec3::Y * 100.0, -Vec3::Y),
        (centre + Vec3::Y * 100.0, Vec3::new(-0.0, -1.0, 0.0)),
        (Vec3::new(lo.x, centre.y, centre.z), Vec3::X),
        (centre, Vec3::ZERO),
    ]);
    rays
}

/// Packets find each ray's own closest hit, on every shipped scene and every tree: the same
/// distance as the single-ray walk bit for bit, the same triangle and barycentrics, except
/// where two triangles tie (a shared edge): there the packet takes the lower-numbered one,
/// whatever the order it met them in. And a ray's hit does not depend on its packet: cut into
/// packets of other sizes (one to sixteen rays, other companions and lanes), every hit is the
/// same bits.
#[test]
fn packets_find_each_rays_own_hit() {
    for (path, scene, lo, hi) in shipped_scenes() {
        let all = packet_test_rays(&scene, lo, hi);
        // obvhs' own walk debug-asserts finite rays: the binary tree takes the others out.
        let finite: Vec<_> = all.iter().copied().filter(|(o, d)| o.is_finite() && d.is_finite()).collect();
        for (kind, rays) in [(AccelKind::Wide, &all), (AccelKind::Bvh2, &finite)] {
            let accel = Accel::build(&scene.mesh.triangles, kind);
            let full = packet_hits(&accel, rays, &[PACKET_RAYS]);
            for (&(o, d), hit) in rays.iter().zip(&full) {
                // A ray with a NaN component or an infinite origin hits nothing, and as a
                // shadow ray nothing blocks it.
                if !o.is_finite() || d.is_nan() {
                    assert!(hit.is_none(), "{}: ray {o} {d} hit {hit:?}", path.display());
                    assert!(accel.unoccluded(o, d, f32::INFINITY), "{}: ray {o} {d}", path.display());
                }
            }
            let (mut hits, mut ties) = (0, 0);
            for (&(o, d), packet) in rays.iter().zip(&full) {
                let single = accel.closest(o, d, f32::INFINITY);
                let what = format!("{} {kind:?}: ray {o} {d}", path.display());
                assert_eq!(packet.map(|h| h.t.to_bits()), single.map(|h| h.t.to_bits()), "{what}");
                if let (Some(p), Some(s)) = (packet, single) {
                    hits += 1;
                    if p.triangle == s.triangle {
                        assert_eq!(bits(*packet), bits(single), "{what}");
                    } else {
                        // A tie: the packet's is the lower-numbered triangle, hit at the same t.
                        ties += 1;
                        assert!(p.triangle < s.triangle, "{what}: {p:?} {s:?}");
                        let t = &scene.mesh.triangles[p.triangle as usize];
                        let tri = BvhTriangle { v0: t.v0.into(), v1: t.v1.into(), v2: t.v2.into() };
                        let ray = Ray::new(o.into(), d.into(), 0.0, f32::INFINITY);
                        assert_eq!(tri.intersect(&ray).to_bits(), p.t.to_bits(), "{what}");
                    }
                }
            }
            assert!(hits >= 1000, "{}: only {hits} rays hit", path.display());
            assert!(ties * 100 <= hits, "{}: {ties} ties in {hits} hits", path.display());
            for sizes in [&[1usize][..], &[7, 16, 3, 1, 11], &[16, 15, 2]] {
                let other = packet_hits(&accel, rays, sizes);
                for (i, (a, b)) in full.iter().zip(&other).enumerate() {
                    assert_eq!(bits(*a), bits(*b), "{} {kind:?}: ray {i}, packets of {sizes:?}", path.display());
                }
            }
            // And in reverse order: other lanes, other companions.
            let reversed: Vec<_> = rays.iter().rev().copied().collect();
            let back = packet_hits(&accel, &reversed, &[PACKET_RAYS]);
            for (a, b) in full.iter().zip(back.iter().rev()) {
                assert_eq!(bits(*a), bits(*b), "{} {kind:?}: reversed", path.display());
            }
        }
    }
}

/// Where every triangle is there twice, every hit is a tie: a packet always answers with the
/// lower-numbered copy, whichever of the two the walk meets first (the copies are numbered in
/// both orders, so the lower one is the first copy for half the triangles and the second for
/// the others), at the distance the single-ray walk finds.
#[test]
fn packets_break_ties_by_triangle_number() {
    let (n, grid) = (400u32, 20u32);
    let tri = |i: u32| {
        let (x, z) = ((i % grid) as f32, (i / grid) as f32);
        ggx_scene::Triangle {
            v0: [x, 0.0, z],
            material: 0,
            v1: [x + 1.0, 0.0, z],
            normals: ggx_scene::NO_INDEX,
            v2: [x, 0.0, z + 1.0],
            emitter: ggx_scene::NO_INDEX,
        }
    };
    // Triangle i at numbers i and 2n - 1 - i.
    let tris: Vec<_> = (0..2 * n).map(|k| tri(if k < n { k } else { 2 * n - 1 - k })).collect();
    let rays: Vec<(Vec3, Vec3)> = (0..n * 4)
        .map(|i| {
            let (x, z) = ((i % 80) as f32 * 0.25 + 0.1, (i / 80) as f32 * 0.25 + 0.05);
            (Vec3::new(x, 5.0, z), Vec3::new(0.01, -1.0, 0.02).normalize())
        })
        .collect();
    let accel = Accel::build(&tris, AccelKind::Wide);
    let (mut hits, mut first_was_higher) = (0, 0);
    for (&(o, d), hit) in rays.iter().zip(packet_hits(&accel, &rays, &[PACKET_RAYS])) {
        let single = accel.closest(o, d, f32::INFINITY);
        assert_eq!(hit.map(|h| h.t.to_bits()), single.map(|h| h.t.to_bits()), "ray {o}");
        let (Some(h), Some(s)) = (hit, single) else { continue };
        hits += 1;
        let copy = 2 * n - 1 - h.triangle;
        assert!(h.triangle < copy, "ray {o}: triangle {} is the higher copy", h.triangle);
        first_was_higher += u32::from(s.triangle != h.triangle);
    }
    assert!(hits >= 500, "{hits} hits");
    // The single walk met the higher copy first on some rays: the rule did something.
    assert!(first_was_higher > 0, "the single walk always met the lower copy first");
}
