//! The wide BVH against obvhs' binary BVH it is collapsed from, on every shipped scene: the
//! same closest distance and barycentrics bit for bit and the same shadow-ray answers, and where
//! the two disagree the wide BVH's is a brute-force loop's over all triangles (its box test keeps
//! a rounding margin that obvhs' lacks).

use std::path::Path;

use ggx_cpu::{Accel, AccelKind};
use obvhs::ray::Ray;
use obvhs::triangle::Triangle as BvhTriangle;

mod support;

use support::rays::scattered_rays;

#[test]
fn wide_bvh_finds_the_binary_bvhs_hits() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let mut scenes = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "toml") {
            continue;
        }
        let scene = ggx_scene::load_scene(&path).unwrap();
        let Some((lo, hi)) = scene.mesh.bounds() else { continue };
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
        scenes += 1;
    }
    assert!(scenes >= 6, "only {scenes} scenes");
}
