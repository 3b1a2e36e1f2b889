//! Normalization by f64 quadrature: the projected area of the microsurface is one,
//! `integral D(wm) wm.z dwm = 1`, and the visible normals are a distribution,
//! `integral D_wo(wm) dwm = 1`, within 1e-3 for alpha in [0.05, 1] and anisotropic pairs.

mod util;

use ggx_core::TrowbridgeReitz;
use util::{INCIDENCES_DEG, alpha_pairs, hemisphere_integral, wo_at};

#[test]
fn projected_area_is_one() {
    let mut pairs = alpha_pairs();
    pairs.extend([(0.2, 0.2), (0.5, 0.5), (0.9, 0.9), (0.1, 1.0)]);
    for (ax, ay) in pairs {
        let d = TrowbridgeReitz::new(ax, ay);
        let integral = hemisphere_integral(4000, 512, |wm| d.d(wm) as f64 * wm.z as f64);
        println!("alpha ({ax}, {ay}): |integral D cos - 1| = {:.2e}", (integral - 1.0).abs());
        assert!((integral - 1.0).abs() < 1e-3, "alpha ({ax}, {ay}): {integral}");
    }
}

#[test]
fn visible_normals_integrate_to_one() {
    let mut worst = 0.0f64;
    for (ax, ay) in alpha_pairs() {
        let d = TrowbridgeReitz::new(ax, ay);
        for inc in INCIDENCES_DEG {
            let wo = wo_at(inc);
            let integral = hemisphere_integral(3000, 1024, |wm| d.d_visible(wo, wm) as f64);
            worst = worst.max((integral - 1.0).abs());
            assert!((integral - 1.0).abs() < 1e-3, "alpha ({ax}, {ay}) at {inc} deg: {integral}");
        }
    }
    println!("35 configurations: worst |integral D_wo - 1| = {worst:.2e}");
}
