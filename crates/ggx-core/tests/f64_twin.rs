//! The distribution's formulas ([`ggx_core::distribution::formulas`], one source over `Lanes`)
//! evaluated in `f64`: held to the closed forms to 1e-12, which checks the formulas themselves
//! far below `f32` rounding, and used as the reference that bounds the `f32` methods' rounding
//! error in units of `f32::EPSILON`, down to grazing angles and the extreme alphas.

use ggx_core::conductor::formulas::reflection;
use ggx_core::distribution::formulas::{self, Widths};
use ggx_core::lanes::Vec3Lanes;
use ggx_core::{ALPHA_MAX, ALPHA_MIN, DELTA_ALPHA, Fresnel, GgxConductor, TrowbridgeReitz, Vec3};
use std::f64::consts::PI;

type V64 = Vec3Lanes<f64>;

/// Walter 2007 eq. 33, anisotropic (Heitz 2014 eq. 85), in the polar angles (exact `tan`, so
/// that no closed form cancels near the pole): `1 / (pi ax ay cos^4 (1 + tan^2 (cos^2 phi / ax^2 + sin^2 phi / ay^2))^2)`.
fn d_closed(ax: f64, ay: f64, theta: f64, phi: f64) -> f64 {
    let (cos2, tan2) = (theta.cos().powi(2), theta.tan().powi(2));
    let e = tan2 * (phi.cos().powi(2) / (ax * ax) + phi.sin().powi(2) / (ay * ay));
    1.0 / (PI * ax * ay * cos2 * cos2 * (1.0 + e) * (1.0 + e))
}

/// Heitz 2014 eq. 86 as printed: `Lambda = (-1 + sqrt(1 + alpha(phi)^2 tan^2 theta)) / 2`.
fn lambda_closed(ax: f64, ay: f64, theta: f64, phi: f64) -> f64 {
    let alpha2 = (phi.cos() * ax).powi(2) + (phi.sin() * ay).powi(2);
    (-1.0 + (1.0 + alpha2 * theta.tan().powi(2)).sqrt()) / 2.0
}

fn dir64(theta: f64, phi: f64) -> V64 {
    V64::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos())
}

fn widths64(ax: f64, ay: f64) -> Widths<f64> {
    Widths { x: ax, y: ay, isotropic: ax == ay }
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// Polar angles from the pole to within 1e-4 degrees of the horizon, azimuths off the axes.
fn angles() -> Vec<(f64, f64)> {
    let mut v = vec![(0.0, 0.0)];
    let thetas_deg = [1e-3, 1.0, 10.0, 30.0, 45.0, 60.0, 75.0, 85.0, 89.0, 89.9, 89.99, 89.9999];
    for &t in &thetas_deg {
        for p in 0..8 {
            v.push((f64::to_radians(t), 0.3 + p as f64 * 0.77));
        }
    }
    v
}

fn alpha_pairs() -> Vec<(f32, f32)> {
    let mut v = vec![(ALPHA_MIN, ALPHA_MIN), (ALPHA_MAX, ALPHA_MAX), (ALPHA_MIN, ALPHA_MAX), (ALPHA_MAX, ALPHA_MIN)];
    v.extend([(0.05, 0.05), (0.3, 0.3), (0.05, 0.5), (0.5, 0.05), (0.002, 0.7), (0.9, 0.999)]);
    v
}

#[test]
fn f64_formulas_match_closed_forms_to_1e12() {
    let mut worst = [0.0f64; 6];
    for (ax, ay) in alpha_pairs() {
        let (ax, ay) = (f64::from(ax), f64::from(ay));
        let a = widths64(ax, ay);
        for (t, p) in angles() {
            let w = dir64(t, p);
            worst[0] = worst[0].max(rel(formulas::d(a, w), d_closed(ax, ay, t, p)));
            let l = lambda_closed(ax, ay, t, p);
            // The printed form cancels where `alpha^2 tan^2` is small: compare where it holds 1e-4 of its digits.
            if l > 1e-4 {
                worst[1] = worst[1].max(rel(formulas::lambda(a, w), l));
            }
            worst[2] = worst[2].max(rel(formulas::g1(a, w), 1.0 / (1.0 + l)));
            for (t2, p2) in angles().into_iter().step_by(5) {
                let v = dir64(t2, p2);
                let lv = lambda_closed(ax, ay, t2, p2);
                worst[3] = worst[3].max(rel(formulas::g2(a, w, v), 1.0 / (1.0 + l + lv)));
                // Heitz 2014 eq. 2 with the closed forms: G1(w) max(0, w.m) D(m) / w.z.
                let dv = (1.0 / (1.0 + l)) * w.dot(v).max(0.0) * d_closed(ax, ay, t2, p2) / w.z;
                if dv > 0.0 && w.z > 1e-3 {
                    worst[4] = worst[4].max(rel(formulas::d_visible(a, w, v), dv));
                }
                // The conductor's microfacet factor (F = 1): D(h) G2 / (4 zo zi) times zi, `h`
                // the half vector in polar angles.
                let h = V64::new(w.x + v.x, w.y + v.y, w.z + v.z);
                let (th, ph) = ((h.x * h.x + h.y * h.y).sqrt().atan2(h.z), h.y.atan2(h.x));
                let f = d_closed(ax, ay, th, ph) / (1.0 + l + lv) / (4.0 * w.z);
                if w.z > 1e-3 && v.z > 1e-3 && f > 0.0 {
                    worst[5] = worst[5].max(rel(reflection(a, w, v).0, f));
                }
            }
        }
    }
    println!(
        "f64 formulas vs closed forms, worst relative error: D {:.1e} Lambda {:.1e} G1 {:.1e} G2 {:.1e} D_w {:.1e} conductor {:.1e}",
        worst[0], worst[1], worst[2], worst[3], worst[4], worst[5]
    );
    assert!(worst.iter().all(|&e| e < 1e-12), "{worst:?}");
}

/// The widths `t`'s methods read, widened to `f64` exactly.
fn widened(t: &TrowbridgeReitz) -> Widths<f64> {
    let w = t.widths();
    Widths { x: f64::from(w.x), y: f64::from(w.y), isotropic: w.isotropic }
}

/// The grid's directions rounded to `f32`, as the `f32` methods see them.
fn dirs32() -> Vec<Vec3> {
    angles()
        .into_iter()
        .map(|(t, p)| {
            let v = dir64(t, p);
            Vec3::new(v.x as f32, v.y as f32, v.z as f32)
        })
        .collect()
}

/// `|f32 - f64| / f64` in units of `f32::EPSILON` (2^-23), the f64 value at the very same
/// (widened) inputs; 0 where both are 0.
fn eps_error(got: f32, reference: f64) -> f64 {
    if reference == 0.0 {
        assert_eq!(got, 0.0);
        return 0.0;
    }
    rel(f64::from(got), reference) / f64::from(f32::EPSILON)
}

#[test]
fn f32_methods_round_within_a_few_eps_of_their_f64_twin() {
    let mut worst = [0.0f64; 6];
    for (ax, ay) in alpha_pairs() {
        let d = TrowbridgeReitz::new(ax, ay);
        let (a, dirs) = (widened(&d), dirs32());
        for &w in &dirs {
            let w64 = V64::from(w);
            worst[0] = worst[0].max(eps_error(d.d(w), formulas::d(a, w64)));
            worst[1] = worst[1].max(eps_error(d.lambda(w), formulas::lambda(a, w64)));
            worst[2] = worst[2].max(eps_error(d.g1(w), formulas::g1(a, w64)));
            for &v in dirs.iter().step_by(3) {
                let v64 = V64::from(v);
                worst[3] = worst[3].max(eps_error(d.g2(w, v), formulas::g2(a, w64, v64)));
                worst[4] = worst[4].max(eps_error(d.g2_separable(w, v), formulas::g1(a, w64) * formulas::g1(a, v64)));
                // D_w holds the dot product `w . wm`, which cancels: measure its error against
                // the size of its terms, `G1(w) D(wm) |w| |wm| / w.z`.
                let dv = formulas::d_visible(a, w64, v64);
                let scale = formulas::g1(a, w64) * formulas::d(a, v64) / w64.z;
                if w.z > 0.0 && scale > 0.0 {
                    let e = (f64::from(d.d_visible(w, v)) - dv).abs() / scale / f64::from(f32::EPSILON);
                    worst[5] = worst[5].max(e);
                }
            }
        }
    }
    println!(
        "f32 vs f64 twin, worst error in f32 eps: D {:.2} Lambda {:.2} G1 {:.2} G2 {:.2} G2sep {:.2} D_w {:.2}",
        worst[0], worst[1], worst[2], worst[3], worst[4], worst[5]
    );
    let bounds = [5.0, 3.0, 2.0, 3.0, 3.0, 6.0];
    for (i, (&e, &b)) in worst.iter().zip(&bounds).enumerate() {
        assert!(e <= b, "function {i}: {e} eps > {b}: {worst:?}");
    }
}

/// The `f64` instantiation keeps the `f32` contract's special values: 0 below the horizon,
/// `+inf` Lambda at grazing, 0 for NaN input, never NaN.
#[test]
fn f64_formulas_keep_the_special_values() {
    let a = widths64(0.3, 0.3);
    let below = V64::new(0.6, 0.0, -0.8);
    let grazing = V64::new(1.0, 0.0, 0.0);
    let nan = V64::new(f64::NAN, 0.0, 1.0);
    assert_eq!(formulas::d(a, below), 0.0);
    assert_eq!(formulas::d_visible(a, below, V64::new(0.0, 0.0, 1.0)), 0.0);
    assert_eq!(formulas::lambda(a, grazing), f64::INFINITY);
    assert_eq!(formulas::g1(a, grazing), 0.0);
    assert_eq!(formulas::lambda(a, nan), 0.0);
    for f in [formulas::d(a, nan), formulas::g1(a, nan), formulas::g2(a, nan, nan), formulas::d_visible(a, nan, nan)] {
        assert!(!f.is_nan());
    }
}

/// The conductor's `eval` (`F = 1`) against its `f64` twin at the same (widened) directions:
/// `f |wi.z| = D |wi.z| / (2 (|wi.z| so + |wo.z| si))` from the normalized half vector.
#[test]
fn conductor_eval_rounds_within_a_few_eps_of_its_f64_twin() {
    let mut worst = 0.0f64;
    let mut compared = 0;
    for (ax, ay) in alpha_pairs().into_iter().filter(|&(x, y)| x.max(y) >= DELTA_ALPHA) {
        let brdf = GgxConductor::new(ax, ay, Fresnel::One);
        let (a, dirs) = (widened(&brdf.distribution), dirs32());
        for &wo in &dirs {
            for &wi in &dirs {
                let (f64_value, _) = reflection(a, V64::from(wo), V64::from(wi));
                let got = brdf.eval(wo, wi);
                assert!(got.x == got.y && got.y == got.z, "F = 1 gives grey: {got}");
                if f64_value > 1e-30 {
                    worst = worst.max(eps_error(got.x, f64_value));
                    compared += 1;
                }
            }
        }
    }
    println!("conductor eval (F = 1) vs f64 twin over {compared} pairs: worst error {worst:.2} f32 eps");
    assert!(compared > 50_000, "{compared}");
    assert!(worst <= 12.0, "{worst} eps");
}
