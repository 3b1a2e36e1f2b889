//! The four microfacet-normal samplers ([`ggx_core::distribution::samplers`], one source over
//! `Lanes`) run in `f64`: each density is held to the Jacobian of its own map, measured by
//! central differences, which checks sampler and pdf against each other without a histogram;
//! and the `f32` methods are held to their `f64` twin at the same inputs, which bounds their
//! rounding error.

use ggx_core::distribution::formulas::{Widths, d_visible};
use ggx_core::distribution::samplers::{
    pdf_wi_bounded, pdf_wm_ndf, sample_wm_bounded, sample_wm_ndf, sample_wm_spherical_caps, sample_wm_vndf,
};
use ggx_core::lanes::{Lanes, Vec3Lanes};
use ggx_core::{ALPHA_MAX, ALPHA_MIN, TrowbridgeReitz, Vec2, Vec3};
use glam::Vec3A;

type V64 = Vec3Lanes<f64>;

/// The four samplers by name, each with the density of the normal it returns.
const SAMPLERS: [&str; 4] = ["ndf", "vndf", "spherical_caps", "bounded"];

fn sample64(name: &str, a: Widths<f64>, wo: V64, u0: f64, u1: f64) -> V64 {
    match name {
        "ndf" => sample_wm_ndf(a, u0, u1),
        "vndf" => sample_wm_vndf(a, wo, u0, u1),
        "spherical_caps" => sample_wm_spherical_caps(a, wo, u0, u1),
        _ => sample_wm_bounded(a, wo, u0, u1),
    }
}

/// Density of the normal `wm` each sampler returns: `D(wm) wm.z`, `D_wo(wm)`, and for the
/// bounded sampler its reflected-direction density times the Jacobian `4 wo . wm`.
fn density64(name: &str, a: Widths<f64>, wo: V64, wm: V64) -> f64 {
    match name {
        "ndf" => pdf_wm_ndf(a, wm),
        "vndf" | "spherical_caps" => d_visible(a, wo, wm),
        _ => pdf_wi_bounded(a, wo, wm) * 4.0 * wo.dot(wm),
    }
}

fn sample32(name: &str, t: &TrowbridgeReitz, wo: Vec3, u: Vec2) -> Vec3 {
    match name {
        "ndf" => t.sample_wm_ndf(u),
        "vndf" => t.sample_wm_vndf(wo, u),
        "spherical_caps" => t.sample_wm_spherical_caps(wo, u),
        _ => t.sample_wm_bounded(wo, u),
    }
}

fn len(v: V64) -> f64 {
    v.dot(v).sqrt()
}

fn dir64(theta_deg: f64, phi: f64) -> V64 {
    let t = theta_deg.to_radians();
    V64::new(t.sin() * phi.cos(), t.sin() * phi.sin(), t.cos())
}

/// Views from the pole (where the VNDF sampler takes its other basis) to 89.9 degrees.
fn views() -> Vec<V64> {
    let mut v = vec![dir64(0.0, 0.0)];
    for theta in [20.0, 50.0, 75.0, 88.0, 89.9] {
        v.extend([dir64(theta, 0.3), dir64(theta, 2.1)]);
    }
    v
}

/// `1 / |dwm/du0 x dwm/du1|`: the solid-angle density of the map `u -> wm` at `u`, by central
/// differences of step `h` (truncation error `O(h^2)`, rounding `O(1e-16 / h)`).
fn jacobian_density(f: impl Fn(f64, f64) -> V64, u0: f64, u1: f64, h: f64) -> f64 {
    let d0 = (f(u0 + h, u1) - f(u0 - h, u1)).scale(1.0 / (2.0 * h));
    let d1 = (f(u0, u1 + h) - f(u0, u1 - h)).scale(1.0 / (2.0 * h));
    1.0 / len(d0.cross(d1))
}

#[test]
fn f64_sampler_densities_are_the_jacobians_of_their_maps() {
    let alphas = [(0.02, 0.02), (0.05, 0.5), (0.3, 0.3), (0.5, 0.05), (0.9, 0.999), (1.0, 1.0)];
    let grid: Vec<f64> = (0..12).map(|i| 0.04 + 0.08 * i as f64).collect();
    let mut worst = [0.0f64; 4];
    let mut checked = 0;
    for (ax, ay) in alphas {
        let a = Widths { x: ax, y: ay, isotropic: ax == ay };
        for wo in views() {
            for (k, name) in SAMPLERS.iter().enumerate() {
                for &u0 in &grid {
                    for &u1 in &grid {
                        let wm = sample64(name, a, wo, u0, u1);
                        assert!((len(wm) - 1.0).abs() < 1e-14, "{name} {ax} {ay} {wo:?} {u0} {u1}: {wm:?}");
                        let want = density64(name, a, wo, wm);
                        let got = jacobian_density(|x, y| sample64(name, a, wo, x, y), u0, u1, 1e-6);
                        let err = (got - want).abs() / want;
                        assert!(want > 0.0 && err < 1e-6, "{name} {ax} {ay} {wo:?} u = ({u0}, {u1}): {got} vs {want}");
                        worst[k] = worst[k].max(err);
                        checked += 1;
                    }
                }
            }
        }
    }
    println!(
        "density vs Jacobian, worst relative error over {checked} samples (ndf, vndf, caps, bounded): {:?}",
        worst.map(|e| format!("{e:.1e}"))
    );
}

/// `max_i |v_i - w_i|` in units of `f32::EPSILON`: unit vectors, so absolute.
fn eps_distance(v: V64, w: V64) -> f64 {
    let e = [v.x - w.x, v.y - w.y, v.z - w.z];
    e.iter().fold(0.0f64, |m, x| m.max(x.abs())) / f64::from(f32::EPSILON)
}

/// The `f32` neighbours of `x`, one ulp down and up.
fn ulp_neighbours(x: f32) -> [f32; 2] {
    let next = |x: f32, up: bool| {
        if x == 0.0 {
            return if up { f32::from_bits(1) } else { -f32::from_bits(1) };
        }
        let b = x.to_bits();
        f32::from_bits(if (x > 0.0) == up { b + 1 } else { b - 1 })
    };
    [next(x, false), next(x, true)]
}

/// How far the exact (`f64`) map moves, in `f32` epsilons, when one of its `f32` inputs
/// (`u0`, `u1`, a component of `wo`) moves by one ulp: the map's own sensitivity at this
/// point, the least error any `f32` algorithm whose inputs are rounded can promise.
fn ulp_sensitivity(name: &str, a: Widths<f64>, wo: Vec3, u: Vec2, at: V64) -> f64 {
    let eval = |wo: Vec3, u: Vec2| sample64(name, a, V64::from(wo), f64::from(u.x), f64::from(u.y));
    let mut k = 0.0f64;
    for i in 0..5 {
        let x = if i < 2 { u[i] } else { wo[i - 2] };
        for y in ulp_neighbours(x) {
            let (mut wo, mut u) = (wo, u);
            if i < 2 {
                u[i] = y
            } else {
                wo[i - 2] = y
            }
            k = k.max(eps_distance(eval(wo, u), at));
        }
    }
    k
}

/// The `f32` samplers against their `f64` twin at the same (widened) inputs, down to alpha
/// 1e-4, views at 89.9 degrees and `u` at `1 - 2^-24`. Written without cancellation, 99.9 % of
/// the samples are within 8 eps (with `1 - z^2` and `1 - p1^2 - p2^2` as printed they
/// measured 1e5 to 1e6 eps); every error is within 16 eps (measured: 10.9) plus 24 times the
/// map's own one-ulp sensitivity, which is large only at the maps' singular points (normals
/// at the horizon, the cap's rim opposite `vh`), where rounding the inputs to `f32` alone
/// moves the exact result as far. (The 16 eps are the caps' own sum `vh + c` where it nearly
/// cancels: two unit-sized terms, each rounded, give a short `h`.)
#[test]
fn f32_samplers_round_within_a_few_eps_of_their_f64_twin() {
    let alphas = [
        (ALPHA_MIN, ALPHA_MIN),
        (ALPHA_MAX, ALPHA_MAX),
        (ALPHA_MIN, ALPHA_MAX),
        (0.05, 0.05),
        (0.3, 0.3),
        (0.05, 0.5),
        (0.002, 0.7),
    ];
    let grid: Vec<f32> = (0..=32).map(|i| (i as f32 / 32.0).min(ggx_core::math::ONE_MINUS_EPSILON)).collect();
    let mut worst = [0.0f64; 4];
    let mut worst_conditioned = [0.0f64; 4];
    let mut all = vec![Vec::new(); 4];
    for (ax, ay) in alphas {
        let t = TrowbridgeReitz::new(ax, ay);
        let w = t.widths();
        let a = Widths { x: f64::from(w.x), y: f64::from(w.y), isotropic: w.isotropic };
        for wo in views() {
            let wo32 = Vec3::new(wo.x as f32, wo.y as f32, wo.z as f32);
            for (k, name) in SAMPLERS.iter().enumerate() {
                for &u0 in &grid {
                    for &u1 in &grid {
                        let u = Vec2::new(u0, u1);
                        let got = sample32(name, &t, wo32, u);
                        let want = sample64(name, a, V64::from(wo32), f64::from(u0), f64::from(u1));
                        let e = eps_distance(V64::from(got), want);
                        worst[k] = worst[k].max(e);
                        all[k].push(e);
                        if e > 8.0 {
                            let sensitivity = ulp_sensitivity(name, a, wo32, u, want);
                            let beyond = e - 24.0 * sensitivity;
                            assert!(beyond <= 16.0, "{name} {t:?} {wo32:?} {u:?}: {e} eps, sensitivity {sensitivity}");
                            worst_conditioned[k] = worst_conditioned[k].max(beyond);
                        }
                    }
                }
            }
        }
    }
    let p999: Vec<f64> = all
        .iter_mut()
        .map(|v| {
            v.sort_by(f64::total_cmp);
            v[v.len() * 999 / 1000]
        })
        .collect();
    println!(
        "f32 vs f64 samplers, eps (ndf, vndf, caps, bounded): 99.9th percentile {p999:.2?}, worst {worst:.0?}, \
         worst of error - 24 x one-ulp sensitivity {worst_conditioned:.2?}"
    );
    for k in 0..4 {
        assert!(p999[k] <= 8.0, "{}: {} eps at the 99.9th percentile", SAMPLERS[k], p999[k]);
    }
}

#[test]
fn f64_samplers_keep_the_special_values() {
    let a = Widths { x: 0.3, y: 0.1, isotropic: false };
    let (zero, up) = (V64::new(0.0, 0.0, 0.0), V64::new(0.0, 0.0, 1.0));
    for wo in [V64::new(0.6, 0.0, -0.8), V64::new(1.0, 0.0, 0.0), V64::new(0.0, 0.0, f64::NAN), zero] {
        for name in &SAMPLERS[1..] {
            assert_eq!(sample64(name, a, wo, 0.3, 0.7), zero, "{name} {wo:?}");
        }
        assert_eq!(pdf_wi_bounded(a, wo, up), 0.0);
    }
    // NaN and out-of-range numbers are sanitized into [0, 1 - 2^-24], as in f32.
    for name in SAMPLERS {
        assert_eq!(sample64(name, a, up, f64::NAN, -1.0), sample64(name, a, up, 0.0, 0.0), "{name}");
        let wm = sample64(name, a, dir64(40.0, 1.0), f64::INFINITY, 2.0);
        assert!((len(wm) - 1.0).abs() < 1e-14, "{name} {wm:?}");
    }
    assert_eq!(pdf_wm_ndf(a, V64::new(1.0, 0.0, 0.0)), 0.0);
}

#[test]
fn sincos_lanes_agree() {
    let mut worst = 0.0f64;
    for i in 0..=100_000u32 {
        let u = i as f32 / 100_000.0 * 3.0 - 1.5;
        let (s, c) = u.sincos_2pi_with::<false>();
        let (s64, c64) = f64::from(u).sincos_2pi_with::<false>();
        let x = std::f64::consts::TAU * f64::from(u);
        assert!((s64 - x.sin()).abs() < 1e-14 && (c64 - x.cos()).abs() < 1e-14, "{u}");
        worst = worst.max((f64::from(s) - s64).abs()).max((f64::from(c) - c64).abs());
        let v = Vec3A::new(u, -u, u * 0.5);
        let (sv, cv) = v.sincos_2pi_with::<true>();
        for (lane, x) in [u, -u, u * 0.5].into_iter().enumerate() {
            let (s, c) = x.sincos_2pi_with::<false>();
            assert_eq!((sv[lane].to_bits(), cv[lane].to_bits()), (s.to_bits(), c.to_bits()), "{x}");
        }
    }
    assert!(worst < 2e-7, "f32 vs f64 sincos: {worst}");
    for u in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, 1e300, 5.0] {
        let (s, c) = u.sincos_2pi_with::<false>();
        assert!(s == 0.0 && c == 1.0, "{u}: {s} {c}");
    }
}
