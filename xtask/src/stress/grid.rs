//! The parameter grid of the stress sweep: alphas from 1e-7 to 1 with anisotropy up to
//! 1:100, views from the normal to below the horizon, and random numbers that include the
//! extremes `0` and `1 - ulp` on purpose.

use core::f64::consts::FRAC_PI_2;
use ggx_core::math::ONE_MINUS_EPSILON;
use ggx_core::{Vec2, Vec3};

/// Number of log-spaced alphas from [`ALPHA_LO`] to 1 (half a decade apart).
pub const ALPHA_COUNT: usize = 15;
/// Smallest alpha of the sweep, far below `ggx_core::ALPHA_MIN`, so clamping and the delta
/// (mirror) path are exercised.
pub const ALPHA_LO: f32 = 1e-7;
/// Divisors `(dx, dy)` applied to each alpha `a`: the pairs `(a, a)`, `(a, a/10)`,
/// `(a, a/100)` and `(a/100, a)`, passed unclamped to the constructors (which clamp).
pub const ANISOTROPY: [(f32, f32); 4] = [(1.0, 1.0), (1.0, 10.0), (1.0, 100.0), (100.0, 1.0)];
/// Azimuths of the view directions, radians: on both tangent axes, off-axis, and in the
/// third quadrant (negative x and y).
pub const AZIMUTHS: [f64; 4] = [0.0, 0.7, FRAC_PI_2, 3.9];
/// The one-dimensional random numbers whose square is the u grid: exactly 0, the smallest
/// 24-bit step, 1 - ulp (`0x3f7fffff`), the quarter turns where `sincos_2pi` switches
/// quadrant, and a few ordinary values.
pub const U_VALUES: [f32; 12] =
    [0.0, 1.0 / 16_777_216.0, 1e-6, 1e-3, 0.125, 0.25, 0.3, 0.5, 0.75, 0.999, 1.0 - 1e-6, ONE_MINUS_EPSILON];

/// `n >= 2` values from `lo` to `hi`, evenly spaced in `log`, with both endpoints exact.
pub fn log_spaced(lo: f32, hi: f32, n: usize) -> Vec<f32> {
    let (l, h) = ((lo as f64).ln(), (hi as f64).ln());
    (0..n)
        .map(|i| match i {
            0 => lo,
            _ if i + 1 == n => hi,
            _ => (l + (h - l) * i as f64 / (n - 1) as f64).exp() as f32,
        })
        .collect()
}

/// The sweep's alphas: [`ALPHA_COUNT`] values from [`ALPHA_LO`] to 1.
pub fn alphas() -> Vec<f32> {
    log_spaced(ALPHA_LO, 1.0, ALPHA_COUNT)
}

/// Every `(alpha_x, alpha_y)` of the sweep: each alpha with each [`ANISOTROPY`] ratio.
pub fn alpha_pairs() -> Vec<(f32, f32)> {
    alphas().into_iter().flat_map(|a| ANISOTROPY.map(|(dx, dy)| (a / dx, a / dy))).collect()
}

/// Cosines of the view angle: the normal, `1 - ulp`, ordinary angles, 86 and 89 degrees,
/// grazing down to 1e-7, exactly on the horizon (`+0` and `-0`) and below it.
pub fn cos_thetas() -> Vec<f32> {
    let deg = |d: f64| d.to_radians().cos() as f32;
    vec![
        1.0,
        ONE_MINUS_EPSILON,
        0.9,
        0.5,
        0.1,
        deg(86.0),
        deg(89.0),
        1e-2,
        1e-3,
        1e-4,
        1e-5,
        1e-6,
        1e-7,
        0.0,
        -0.0,
        -1e-7,
        -0.5,
        -1.0,
    ]
}

/// Unit direction with `z = cos_theta` exactly and azimuth `phi` (radians); the tangential
/// part is computed in f64 so the direction is unit to within an f32 rounding.
pub fn view(cos_theta: f32, phi: f64) -> Vec3 {
    let c = cos_theta as f64;
    let s = (1.0 - c * c).max(0.0).sqrt();
    Vec3::new((s * phi.cos()) as f32, (s * phi.sin()) as f32, cos_theta)
}

/// Every pair of [`U_VALUES`], row-major (`u.x` outer).
pub fn u_grid() -> Vec<Vec2> {
    U_VALUES.iter().flat_map(|&x| U_VALUES.iter().map(move |&y| Vec2::new(x, y))).collect()
}

/// One point of the sweep: an alpha pair (as passed to the constructors) and a view.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Case {
    /// `(alpha_x, alpha_y)` before the core clamps them.
    pub alpha: (f32, f32),
    /// `wo.z`, as listed in [`cos_thetas`].
    pub cos_theta: f32,
    /// Azimuth of `wo`, radians.
    pub phi: f64,
    /// The view direction.
    pub wo: Vec3,
}

/// Every alpha pair with every view: [`alpha_pairs`] x [`cos_thetas`] x [`AZIMUTHS`].
pub fn cases() -> Vec<Case> {
    let cos = cos_thetas();
    let mut cases = Vec::new();
    for alpha in alpha_pairs() {
        for &cos_theta in &cos {
            for phi in AZIMUTHS {
                cases.push(Case { alpha, cos_theta, phi, wo: view(cos_theta, phi) });
            }
        }
    }
    cases
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn alphas_span_1e_7_to_1_exactly_and_log_evenly() {
        let a = alphas();
        assert_eq!(a.len(), ALPHA_COUNT);
        assert_eq!(a[0], 1e-7);
        assert_eq!(a[ALPHA_COUNT - 1], 1.0);
        assert!(a.contains(&1e-3), "the delta threshold itself is on the grid");
        for w in a.windows(2) {
            let ratio = w[1] as f64 / w[0] as f64;
            assert!((ratio - 10f64.sqrt()).abs() < 1e-5, "{w:?}");
        }
        let pairs = alpha_pairs();
        assert_eq!(pairs.len(), 4 * ALPHA_COUNT);
        assert!(pairs.contains(&(1.0, 0.01)) && pairs.contains(&(0.01, 1.0)));
    }

    #[test]
    fn u_grid_holds_zero_and_one_minus_ulp() {
        let grid = u_grid();
        assert_eq!(grid.len(), U_VALUES.len() * U_VALUES.len());
        assert!(grid.contains(&Vec2::new(0.0, 0.0)));
        let last = grid[grid.len() - 1];
        assert_eq!((last.x.to_bits(), last.y.to_bits()), (0x3f7f_ffff, 0x3f7f_ffff));
        assert!(grid.iter().all(|u| (0.0..1.0).contains(&u.x) && (0.0..1.0).contains(&u.y)));
    }

    #[test]
    fn views_are_unit_and_reach_below_the_horizon() {
        let cos = cos_thetas();
        for needle in [1.0, ONE_MINUS_EPSILON, 0.5, 1e-7, -1.0] {
            assert!(cos.contains(&needle), "{needle}");
        }
        assert!(cos.iter().any(|c| c.to_bits() == 0) && cos.iter().any(|c| c.to_bits() == (-0.0f32).to_bits()));
        for case in cases() {
            assert_eq!(case.wo.z.to_bits(), case.cos_theta.to_bits());
            assert!((case.wo.length() - 1.0).abs() < 1e-6, "{case:?}");
        }
    }
}
