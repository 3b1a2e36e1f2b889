//! D, Lambda, G1, G2 and D_wo against f64 closed forms written in a different form
//! (the trigonometric one of Walter et al. 2007 and Heitz 2014).

mod support;
mod util;

use ggx_core::{TrowbridgeReitz, Vec3};
use support::dielectric_ref::RefDielectric;
use util::dir;

/// Trigonometric `D` (Walter 2007 eq. 33) of the independent f64 reference, at an f32 direction.
fn d_ref(ax: f64, ay: f64, w: Vec3) -> f64 {
    RefDielectric { ax, ay, eta: 1.5 }.d([w.x as f64, w.y as f64, w.z as f64])
}

/// Heitz 2014 eq. 86 as printed, of the independent f64 reference, at an f32 direction.
fn lambda_ref(ax: f64, ay: f64, w: Vec3) -> f64 {
    RefDielectric { ax, ay, eta: 1.5 }.lambda([w.x as f64, w.y as f64, w.z as f64])
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-30)
}

fn grid() -> Vec<Vec3> {
    let mut v = vec![Vec3::Z];
    for t in 0..40 {
        for p in 0..12 {
            let theta = (t as f64 + 0.5) / 40.0 * 89.9f64.to_radians();
            v.push(dir(theta, p as f64 * 0.55));
        }
    }
    v
}

#[test]
fn d_lambda_g1_g2_match_closed_forms() {
    let mut worst = [0.0f64; 5];
    for (ax, ay) in [(0.05f32, 0.05f32), (0.3, 0.3), (1.0, 1.0), (0.05, 0.5), (0.5, 0.05), (0.002, 0.7)] {
        let d = TrowbridgeReitz::new(ax, ay);
        let (ax, ay) = (ax as f64, ay as f64);
        for &w in &grid() {
            let dr = d_ref(ax, ay, w);
            if dr > 1e-30 {
                worst[0] = worst[0].max(rel(d.d(w) as f64, dr));
            }
            let l = lambda_ref(ax, ay, w);
            worst[1] = worst[1].max((d.lambda(w) as f64 - l).abs() / l.max(1e-3));
            worst[2] = worst[2].max(rel(d.g1(w) as f64, 1.0 / (1.0 + l)));
            for &v in grid().iter().step_by(7) {
                let g2 = 1.0 / (1.0 + l + lambda_ref(ax, ay, v));
                worst[3] = worst[3].max(rel(d.g2(w, v) as f64, g2));
                let g2s = 1.0 / ((1.0 + l) * (1.0 + lambda_ref(ax, ay, v)));
                worst[4] = worst[4].max(rel(d.g2_separable(w, v) as f64, g2s));
            }
        }
    }
    println!(
        "worst relative error: D {:.2e} Lambda {:.2e} G1 {:.2e} G2 {:.2e} G2sep {:.2e}",
        worst[0], worst[1], worst[2], worst[3], worst[4]
    );
    assert!(worst.iter().all(|&e| e < 2e-5), "{worst:?}");
}

#[test]
fn d_visible_matches_its_definition() {
    let d = TrowbridgeReitz::new(0.2, 0.45);
    for &wo in grid().iter().step_by(5) {
        for &wm in grid().iter().step_by(3) {
            let g1 = 1.0 / (1.0 + lambda_ref(0.2, 0.45, wo));
            let expect = g1 * (wo.dot(wm).max(0.0) as f64) * d_ref(0.2, 0.45, wm) / wo.z as f64;
            let got = d.d_visible(wo, wm) as f64;
            assert!((got - expect).abs() <= 3e-5 * expect.max(1e-6), "{wo} {wm}: {got} vs {expect}");
        }
    }
}

#[test]
fn known_values_and_limits() {
    let d = TrowbridgeReitz::isotropic(0.5);
    // D(+z) = 1 / (pi alpha^2).
    assert!((d.d(Vec3::Z) - 1.0 / (std::f32::consts::PI * 0.25)).abs() < 1e-6);
    assert_eq!(d.lambda(Vec3::Z), 0.0);
    assert_eq!(d.g1(Vec3::Z), 1.0);
    // Grazing: Lambda -> inf, G1 -> 0, D of a horizontal normal = 0.
    assert_eq!(d.lambda(Vec3::X), f32::INFINITY);
    assert_eq!(d.g1(Vec3::X), 0.0);
    assert_eq!(d.g2(Vec3::X, Vec3::Z), 0.0);
    assert_eq!(d.d(Vec3::X), 0.0);
    assert_eq!(d.d(-Vec3::Z), 0.0);
    // Smith symmetry: masking depends on |cos| only (pbrt-v4 convention).
    let w = dir(1.0, 0.3);
    assert_eq!(d.g1(w), d.g1(Vec3::new(w.x, w.y, -w.z)));
    assert_eq!(d.g2(w, Vec3::Z), d.g2(Vec3::Z, w));
    // Height-correlated G2 >= separable G2 (correlation can only reduce shadowing).
    for t in 1..80 {
        let v = dir(t as f64 / 80.0 * 1.55, 2.0);
        assert!(d.g2(w, v) >= d.g2_separable(w, v) - 1e-6);
    }
}
