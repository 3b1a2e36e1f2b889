//! The parameter grid of the stress sweep: alphas from 1e-7 to 1 with anisotropy up to
//! 1:100, views from the normal to below the horizon (for the dielectric: on both sides, and
//! around the critical angle of each index of refraction), and random numbers that include
//! the extremes `0` and `1 - ulp` on purpose.

use core::f64::consts::FRAC_PI_2;
use ggx_core::math::ONE_MINUS_EPSILON;
use ggx_core::{ETA_MAX, ETA_MIN, Vec2, Vec3, clamp_eta};

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

/// Relative indices of refraction (`eta_t / eta_i`, the `-z` side over the `+z` side) of the
/// dielectric cases: glass seen from the air and the air seen from glass, water, diamond, and
/// the two clamp bounds [`ETA_MIN`] and [`ETA_MAX`], where `1 / eta'^2` reaches `1e4`.
pub const ETAS: [f32; 6] = [1.5, 1.0 / 1.5, 1.33, 2.4, ETA_MIN, ETA_MAX];
/// Azimuths of the dielectric views: the first and last of [`AZIMUTHS`] (on the x axis, and
/// in the third quadrant), to keep the number of cases (x 6 etas x 2 sides) moderate.
pub const DIELECTRIC_AZIMUTHS: [f64; 2] = [AZIMUTHS[0], AZIMUTHS[3]];
/// Relative offsets of `sin theta` around the critical angle (`sin theta_c = eta'`): just
/// below (refraction possible at the macro normal) and just above (total internal reflection).
pub const CRITICAL_OFFSETS: [f64; 2] = [-1e-3, 1e-3];
/// The lobe choices `u_lobe` of the dielectric u grid: exactly 0, the smallest 24-bit step,
/// about `F` at normal incidence on glass (0.04) and its complement, a half, and `1 - ulp`.
pub const U_LOBE_VALUES: [f32; 7] = [0.0, 1.0 / 16_777_216.0, 0.04, 0.5, 0.96, 1.0 - 1e-6, ONE_MINUS_EPSILON];

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

/// Cosines of the dielectric views for one `eta`: the normal, `1 - ulp`, 0.9, 0.5, 86 and 89
/// degrees, 1e-3 and 1e-7, each on both sides, `+0` and `-0`, then the critical angle region on the side where total internal reflection happens
/// (inside, `wo.z < 0`, for `eta > 1`; outside for `eta < 1`; none for `eta = 1`): the f32
/// nearest the critical cosine `sqrt(1 - eta'^2)` and its two neighbours, and `sin theta`
/// [`CRITICAL_OFFSETS`] off.
pub fn dielectric_cos_thetas(eta: f32) -> Vec<f32> {
    let deg = |d: f64| d.to_radians().cos() as f32;
    let positive = [1.0, ONE_MINUS_EPSILON, 0.9, 0.5, deg(86.0), deg(89.0), 1e-3, 1e-7];
    let mut cos = positive.to_vec();
    cos.extend(positive.map(|c| -c));
    cos.extend([0.0, -0.0]);
    let eta = clamp_eta(eta) as f64;
    if eta != 1.0 {
        let (sin_c, side) = if eta > 1.0 { (1.0 / eta, -1.0f32) } else { (eta, 1.0) };
        let cos_of = |s: f64| (1.0 - s * s).max(0.0).sqrt() as f32;
        let c = cos_of(sin_c);
        cos.extend([c.next_down(), c, c.next_up().min(1.0)].map(|c| side * c));
        cos.extend(CRITICAL_OFFSETS.map(|o| side * cos_of(sin_c * (1.0 + o))));
    }
    cos
}

/// Every pair of [`U_VALUES`], row-major (`u.x` outer).
pub fn u_grid() -> Vec<Vec2> {
    U_VALUES.iter().flat_map(|&x| U_VALUES.iter().map(move |&y| Vec2::new(x, y))).collect()
}

/// The random numbers of one sample: `u` picks the microfacet normal, `u_lobe` the
/// dielectric's lobe (reflection or transmission; ignored by the other methods).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Point {
    /// The 2D sample of the normal.
    pub u: Vec2,
    /// The lobe choice.
    pub u_lobe: f32,
}

/// The BSDF a case is built for: which grid of views and u points it uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Family {
    /// `GgxConductor` and the raw normal samplers: [`cases`], [`u_grid`].
    Conductor,
    /// `GgxDielectric`: [`dielectric_cases`], [`dielectric_points`] (and [`lobe_points`]).
    Dielectric,
}

impl Family {
    /// Both families, in the order of the plan's cases.
    pub const ALL: [Family; 2] = [Family::Conductor, Family::Dielectric];

    /// The family's cases.
    pub fn cases(self) -> Vec<Case> {
        match self {
            Family::Conductor => cases(),
            Family::Dielectric => dielectric_cases(),
        }
    }

    /// The u grid run on every case of the family where `u` matters (see
    /// `Method::uses_u`).
    pub fn points(self) -> Vec<Point> {
        match self {
            Family::Conductor => u_grid().into_iter().map(|u| Point { u, u_lobe: 0.0 }).collect(),
            Family::Dielectric => dielectric_points(),
        }
    }

    /// The grid run on the cases where `u` does not matter: the conductor's whole u grid
    /// again (as the sweep always did), the dielectric's [`lobe_points`] (its delta interface
    /// depends on `u_lobe` alone, and a view on the surface is rejected up front).
    pub fn fixed_points(self) -> Vec<Point> {
        match self {
            Family::Conductor => self.points(),
            Family::Dielectric => lobe_points(),
        }
    }
}

/// Every [`U_LOBE_VALUES`] with `u = (0, 0)` and with `u = (1 - ulp, 1 - ulp)`.
pub fn lobe_points() -> Vec<Point> {
    let corners = [Vec2::ZERO, Vec2::splat(ONE_MINUS_EPSILON)];
    corners.into_iter().flat_map(|u| U_LOBE_VALUES.map(|u_lobe| Point { u, u_lobe })).collect()
}

/// The dielectric u grid: [`u_grid`] with `u_lobe` cycling through [`U_LOBE_VALUES`] (7 is
/// prime to 12, so every `u.x` and every `u.y` of the grid meets every `u_lobe`, and
/// `u = (0, 0)` gets `u_lobe = 0`).
pub fn dielectric_points() -> Vec<Point> {
    let lobes = U_LOBE_VALUES.len();
    u_grid().into_iter().enumerate().map(|(i, u)| Point { u, u_lobe: U_LOBE_VALUES[i % lobes] }).collect()
}

/// One point of the sweep: an alpha pair (as passed to the constructors), a view and, for the
/// dielectric, a relative index of refraction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Case {
    /// `(alpha_x, alpha_y)` before the core clamps them.
    pub alpha: (f32, f32),
    /// `wo.z`, as listed in [`cos_thetas`] (or [`dielectric_cos_thetas`]).
    pub cos_theta: f32,
    /// Azimuth of `wo`, radians.
    pub phi: f64,
    /// The view direction.
    pub wo: Vec3,
    /// The dielectric's `eta` as passed to `GgxDielectric::new`; `None` for conductor cases.
    pub eta: Option<f32>,
}

/// Every alpha pair with every view: [`alpha_pairs`] x [`cos_thetas`] x [`AZIMUTHS`].
pub fn cases() -> Vec<Case> {
    let cos = cos_thetas();
    let mut cases = Vec::new();
    for alpha in alpha_pairs() {
        for &cos_theta in &cos {
            for phi in AZIMUTHS {
                cases.push(Case { alpha, cos_theta, phi, wo: view(cos_theta, phi), eta: None });
            }
        }
    }
    cases
}

/// Every alpha pair with every eta and that eta's views: [`alpha_pairs`] x [`ETAS`] x
/// [`dielectric_cos_thetas`] x [`DIELECTRIC_AZIMUTHS`].
pub fn dielectric_cases() -> Vec<Case> {
    let mut cases = Vec::new();
    for alpha in alpha_pairs() {
        for eta in ETAS {
            for cos_theta in dielectric_cos_thetas(eta) {
                for phi in DIELECTRIC_AZIMUTHS {
                    cases.push(Case { alpha, cos_theta, phi, wo: view(cos_theta, phi), eta: Some(eta) });
                }
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
    fn dielectric_views_cover_both_sides_and_the_critical_angle() {
        for eta in ETAS {
            let cos = dielectric_cos_thetas(eta);
            for c in [1.0, ONE_MINUS_EPSILON, 1e-7] {
                assert!(cos.contains(&c) && cos.contains(&-c), "{eta} {c}");
            }
            assert!(cos.iter().any(|c| c.to_bits() == 0) && cos.iter().any(|c| c.to_bits() == (-0.0f32).to_bits()));
            // The critical cosines lie on the side of total internal reflection, around
            // sqrt(1 - eta'^2), eta' = min(eta, 1 / eta).
            let etap = (eta as f64).min(1.0 / eta as f64);
            let critical = &cos[cos.len() - 5..];
            let side = if eta > 1.0 { -1.0 } else { 1.0 };
            for &c in critical {
                assert!(c * side > 0.0, "{eta} {c}");
                assert!(((c.abs() as f64) - (1.0 - etap * etap).sqrt()).abs() < 2e-3, "{eta} {c}");
            }
        }
        assert_eq!(dielectric_cos_thetas(1.0).len(), 18, "no critical angle at eta = 1");
        let cases = dielectric_cases();
        assert!(cases.iter().all(|c| c.eta.is_some() && (c.wo.length() - 1.0).abs() < 1e-6));
        assert_eq!(cases.len(), alpha_pairs().len() * 6 * 23 * DIELECTRIC_AZIMUTHS.len());
    }

    #[test]
    fn dielectric_points_hold_every_u_lobe_with_every_u_value() {
        let points = dielectric_points();
        assert_eq!(points.len(), U_VALUES.len() * U_VALUES.len());
        for lobe in U_LOBE_VALUES {
            for v in U_VALUES {
                assert!(points.iter().any(|p| p.u.x == v && p.u_lobe == lobe), "x {v} lobe {lobe}");
                assert!(points.iter().any(|p| p.u.y == v && p.u_lobe == lobe), "y {v} lobe {lobe}");
            }
        }
        assert!(U_LOBE_VALUES.contains(&0.0) && U_LOBE_VALUES.contains(&ONE_MINUS_EPSILON));
        assert_eq!(lobe_points().len(), 2 * U_LOBE_VALUES.len());
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
