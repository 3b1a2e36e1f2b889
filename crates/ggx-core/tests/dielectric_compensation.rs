//! Energy compensation of the rough dielectric (`GgxDielectricMs`, Turquin 2019) and of the
//! plastic's coat (`energy_dielectric`): the tables against an independent f64 model, the white
//! furnace from both sides with and without compensation, the plastic's energy balance, the
//! sampler's consistency, the bit-identity of `compensation = 0`, and the reciprocity the scale
//! gives up.
//!
//! Albedos of ggx-core's BSDFs are quadratures of `eval` over the visible normals `wm` of `wo`:
//! `integral f |wi.z| dwi = integral D_wo(wm) sum_lobes P_lobe eval(wi) / pdf(wi) dwm`, `P_lobe` =
//! `F` or `1 - F`, `wi = reflect` or `refract` (the pdf carries the Jacobian `dwm / dwi` and
//! `P_lobe`). Rules: the VNDF sampler's unit square (24 x 12 panels of 5-point Gauss-Legendre;
//! the table generator uses at most 16 x 8), and, from the denser side at alpha >= 0.1, polar
//! coordinates around `wo` cut at the critical cosine (16 panels per piece and for the azimuth;
//! the generator uses 12 for the azimuth and fewer per piece). Their own error is below 1e-3.
//! The table check uses `support/dielectric_ref.rs`, an f64 model written without ggx-core,
//! and an adaptive quadrature over stretched slopes.

mod support;
mod util;

use ggx_core::energy_dielectric::{
    ETA_TABLE_MAX, coat_albedo, coat_average_albedo, dielectric_albedo, plastic_base_weight,
};
use ggx_core::fresnel::fresnel_dielectric;
use ggx_core::{
    Fresnel, GgxConductor, GgxDielectric, GgxDielectricMs, Sampling, TransportMode, Vec2, Vec3, reflect, refract,
};
use support::dielectric_ref::RefDielectric;
use support::quadrature::{AdaptiveTolerance, Rect, gauss_legendre_5x5, integrate_adaptive};
use util::Uniforms;

const GL5_NODES: [f64; 5] = [-0.906179845938664, -0.5384693101056831, 0.0, 0.5384693101056831, 0.906179845938664];
const GL5_WEIGHTS: [f64; 5] =
    [0.23692688505618908, 0.47862867049936647, 128.0 / 225.0, 0.47862867049936647, 0.23692688505618908];

const IMP: TransportMode = TransportMode::Importance;
const RAD: TransportMode = TransportMode::Radiance;

/// Composite 5-point Gauss-Legendre nodes and weights on `[0, 1]`.
fn rule(panels: usize) -> Vec<(f64, f64)> {
    let h = 1.0 / panels as f64;
    (0..panels)
        .flat_map(|p| {
            GL5_NODES.iter().zip(&GL5_WEIGHTS).map(move |(&t, &w)| ((p as f64 + 0.5 * (t + 1.0)) * h, 0.5 * h * w))
        })
        .collect()
}

/// [`rule`] on `[a, b]` after `x = a + (b - a) (3 t^2 - 2 t^3)` (square-root edges at both ends
/// become smooth).
fn smooth_rule(a: f64, b: f64, panels: usize) -> Vec<(f64, f64)> {
    rule(panels)
        .into_iter()
        .map(|(t, w)| (a + (b - a) * t * t * (3.0 - 2.0 * t), w * (b - a) * 6.0 * t * (1.0 - t)))
        .collect()
}

/// `sum_lobes P_lobe eval / pdf` for one visible normal (importance mode); a lobe whose
/// direction leaves its hemisphere (a reflection below the horizon, which `eval` would read as
/// a transmission through another normal) contributes nothing, as in the sampler.
fn lobes(m: &GgxDielectricMs, wo: Vec3, wm: Vec3) -> f64 {
    let eta = m.dielectric.eta();
    let c = wo.dot(wm);
    if !(c * wo.z > 0.0) {
        return 0.0;
    }
    let f = fresnel_dielectric(c, eta) as f64;
    let ratio = |wi: Option<Vec3>, same_side: bool| {
        let Some(wi) = wi else { return 0.0 };
        if !((wi.z * wo.z > 0.0) == same_side && wi.z != 0.0) {
            return 0.0;
        }
        let pdf = m.pdf(wo, wi, Sampling::Vndf, IMP) as f64;
        if pdf > 0.0 { m.eval(wo, wi, IMP).x as f64 / pdf } else { 0.0 }
    };
    f * ratio(Some(reflect(wo, wm)), true) + (1.0 - f) * ratio(refract(wo, wm, eta), false)
}

/// `integral eval(wo, wi) dwi` over the VNDF sampler's unit square, `u.x = 1 - (1 - s)^2`.
fn albedo_vndf(m: &GgxDielectricMs, wo: Vec3) -> f64 {
    let wv = if wo.z < 0.0 { -wo } else { wo };
    let rule_v = rule(12);
    let mut sum = 0.0;
    for (s, ws) in rule(24) {
        let ux = (1.0 - (1.0 - s) * (1.0 - s)) as f32;
        for &(v, wv_) in &rule_v {
            let wm = m.dielectric.distribution.sample_wm_vndf(wv, Vec2::new(ux, v as f32));
            sum += ws * 2.0 * (1.0 - s) * wv_ * lobes(m, wo, wm);
        }
    }
    sum
}

/// `integral eval(wo, wi) dwi` in polar coordinates `(c, phi)` around the visible side `wv` of
/// `wo` (`wo` in the `xz`-plane): `dwm = dc dphi`, `phi` up to where `wm.z = 0`, `c` cut at the
/// critical cosine, at `c = sin(theta_v)` and at the peak `c = wv.z`.
fn albedo_polar(m: &GgxDielectricMs, wo: Vec3) -> f64 {
    let wv = if wo.z < 0.0 { -wo } else { wo };
    let (s, mu) = (wv.x as f64, wv.z as f64);
    let eta = m.dielectric.eta() as f64;
    let etap = if wo.z > 0.0 { eta } else { 1.0 / eta };
    let mut cuts = vec![0.0, 1.0, s, mu];
    if etap < 1.0 {
        cuts.push((1.0 - etap * etap).sqrt());
    }
    cuts.sort_by(f64::total_cmp);
    cuts.dedup();
    let mut sum = 0.0;
    for piece in cuts.windows(2) {
        for (c, wc) in smooth_rule(piece[0], piece[1], 16) {
            let sn = (1.0 - c * c).max(0.0).sqrt();
            let phi_max = if sn * s > 0.0 { (-c * mu / (sn * s)).max(-1.0).acos() } else { std::f64::consts::PI };
            for (phi, wp) in smooth_rule(0.0, phi_max, 16) {
                let (sp, cp) = phi.sin_cos();
                let wm = Vec3::new((c * s - sn * cp * mu) as f32, (sn * sp) as f32, (c * mu + sn * cp * s) as f32);
                if wm.z > 0.0 {
                    sum += 2.0 * wc * wp * m.dielectric.distribution.d_visible(wv, wm) as f64 * lobes(m, wo, wm);
                }
            }
        }
    }
    sum
}

/// The albedo of `m` for `wo` (importance mode): the polar rule from the denser side from alpha
/// 0.1 up (where the critical-angle edge crosses the lobe), the VNDF square otherwise; a smooth
/// interface keeps everything.
fn albedo(m: &GgxDielectricMs, wo: Vec3) -> f64 {
    if m.dielectric.is_delta() {
        return 1.0;
    }
    let eta = m.dielectric.eta();
    let denser = if wo.z > 0.0 { eta < 1.0 } else { eta > 1.0 };
    let (ax, ay) = m.dielectric.distribution.alphas();
    if denser && ax.min(ay) >= 0.1 { albedo_polar(m, wo) } else { albedo_vndf(m, wo) }
}

/// View direction at cosine `mu` (sign: side), in the `xz`-plane.
fn wo_mu(mu: f32) -> Vec3 {
    Vec3::new((1.0 - mu * mu).max(0.0).sqrt(), 0.0, mu)
}

/// Alphas from `DELTA_ALPHA` to 1.
const ALPHAS: [f32; 12] = [0.001, 0.002, 0.005, 0.01, 0.02, 0.05, 0.1, 0.2, 0.35, 0.5, 0.75, 1.0];
/// View cosines from normal incidence to grazing.
const MUS: [f32; 12] = [1.0, 0.9, 0.75, 0.6, 0.45, 0.3, 0.2, 0.1, 0.05, 0.03, 0.02, 0.01];

/// White furnace: in importance mode the compensated albedo is 1 within 1 % for water, glass
/// and diamond-like indices and their inverses, seen from both sides (the nine (eta, side)
/// pairs cover both tables and both ways `compensation_scale` reaches them), for every alpha
/// from `DELTA_ALPHA` to 1 and every view from normal incidence to `mu = 0.01`. Without
/// compensation the loss is large (asserted, so the test can tell).
#[test]
fn white_furnace_is_one_within_one_percent_from_both_sides() {
    let mut cases = vec![];
    for eta in [1.33f32, 1.5, 2.4] {
        cases.push((eta, 1.0f32));
        cases.push((eta, -1.0));
        cases.push((1.0 / eta, 1.0));
    }
    let (mut worst, mut worst_ss) = ((0.0f64, 0.0, 0.0, 0.0, 0.0), (0.0f64, 0.0, 0.0, 0.0, 0.0));
    let mut failures = vec![];
    for (eta, side) in cases {
        for alpha in ALPHAS {
            let ms = GgxDielectricMs::new(GgxDielectric::isotropic(alpha, eta));
            let ss = GgxDielectricMs { compensation: 0, ..ms };
            for mu in MUS {
                let wo = wo_mu(mu) * Vec3::new(1.0, 1.0, side);
                let e = albedo(&ms, wo);
                let loss = 1.0 - e / ms.compensation_scale(wo) as f64;
                let err = (e - 1.0).abs();
                if err > worst.0 {
                    worst = (err, eta, side, alpha, mu);
                }
                if loss > worst_ss.0 {
                    worst_ss = (loss, eta, side, alpha, mu);
                }
                if err >= 0.01 {
                    failures.push(format!("eta {eta} side {side} alpha {alpha} mu {mu}: {e}"));
                }
                if alpha == 1.0 && mu == 1.0 {
                    let e_ss = albedo(&ss, wo);
                    println!("alpha 1, mu 1, eta {eta:.4} side {side:+}: uncompensated {e_ss:.4}, compensated {e:.5}");
                }
            }
        }
    }
    println!(
        "compensated: worst |albedo - 1| = {:.2e} at eta {}, side {:+}, alpha {}, mu {}",
        worst.0, worst.1, worst.2, worst.3, worst.4
    );
    println!(
        "uncompensated: worst loss 1 - E_T = {:.3} at eta {}, side {:+}, alpha {}, mu {}",
        worst_ss.0, worst_ss.1, worst_ss.2, worst_ss.3, worst_ss.4
    );
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert!(worst_ss.0 > 0.3, "the uncompensated loss should be large: {worst_ss:?}");
}

/// Anisotropic lobes read the isotropic tables at the RMS alpha (`energy::effective_alpha`, as
/// the conductor), which cannot follow the albedo's dependence on the view azimuth. Measured
/// for glass, views at azimuths 0, 45 and 90 degrees from the `alpha_x` axis and `mu` from 0.01
/// to 1: from outside the furnace is within 2.6 % (alphas (0.3, 0.6)) to 7.2 % ((0.05, 0.5));
/// from inside, where total internal reflection makes the albedo depend on the azimuth most,
/// it is off by 16 % at (0.1, 0.4) and 38 % at (0.25, 1), at grazing across the long axis.
/// (Projected or geometric-mean alphas are worse outside and no better inside.) Each bound is
/// its measured worst plus about 10 %.
#[test]
fn anisotropic_furnace_error_is_bounded() {
    // (alpha_x, alpha_y, bound outside, bound inside) on |albedo - 1|.
    const PAIRS: [(f32, f32, f64, f64); 4] =
        [(0.1, 0.4, 0.045, 0.18), (0.3, 0.6, 0.029, 0.195), (0.05, 0.5, 0.08, 0.25), (0.25, 1.0, 0.058, 0.42)];
    let mut failures = vec![];
    for (ax, ay, bound_out, bound_in) in PAIRS {
        let ms = GgxDielectricMs::new(GgxDielectric::new(ax, ay, 1.5));
        for (side, bound) in [(1.0f32, bound_out), (-1.0, bound_in)] {
            let mut worst = (0.0f64, 0.0f32, 0.0f32);
            for phi in [0.0f32, std::f32::consts::FRAC_PI_4, std::f32::consts::FRAC_PI_2] {
                for mu in [0.01f32, 0.1, 0.3, 0.6, 1.0] {
                    let s = (1.0 - mu * mu).sqrt();
                    let wo = Vec3::new(s * phi.cos(), s * phi.sin(), side * mu);
                    let err = (albedo_vndf(&ms, wo) - 1.0).abs();
                    if err > worst.0 {
                        worst = (err, phi, mu);
                    }
                }
            }
            println!(
                "a=({ax},{ay}), eta 1.5, side {side:+}: worst |albedo - 1| = {:.3} at azimuth {}, mu {} (bound {bound})",
                worst.0, worst.1, worst.2
            );
            if worst.0 >= bound {
                failures.push(format!("a=({ax},{ay}) side {side}: {:.3e} >= {bound}", worst.0));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// `(E_R, E_T)`: the reflected and total importance albedo of the f64 reference model for `wo`,
/// by adaptive quadrature over stretched slopes (`t` in [0, 1), `phi` in [0, 2 pi)).
fn reference_albedo(r: &RefDielectric, wo: Vec3) -> (f64, f64) {
    const TOL: AdaptiveTolerance = AdaptiveTolerance { rel: 1e-5, abs: 1e-8, max_depth: 10 };
    let wo = [wo.x as f64, wo.y as f64, wo.z as f64];
    let mut lobe_sums = [0.0f64; 2];
    for (lobe, total) in lobe_sums.iter_mut().enumerate() {
        for i in 0..8 {
            for j in 0..16 {
                let tau = std::f64::consts::TAU;
                let rect =
                    Rect::new(i as f64 / 8.0, (i + 1) as f64 / 8.0, j as f64 / 16.0 * tau, (j + 1) as f64 / 16.0 * tau);
                let f = |rc: &Rect| {
                    gauss_legendre_5x5(
                        rc,
                        |t| t,
                        |p| p,
                        |t, p| {
                            let (a, b) = r.albedo_integrand(wo, t, p, false);
                            if lobe == 0 { a } else { b }
                        },
                    )
                };
                *total += integrate_adaptive(rect, None, TOL, f).value;
            }
        }
    }
    (lobe_sums[0], lobe_sums[0] + lobe_sums[1])
}

/// Tables against the independent f64 model at points between the nodes of every axis (mu,
/// alpha and eta off-grid): `|E_T(table) - E_T|` and `|E_R(table) - E_R|` are the interpolation
/// error (plus the generator's quadrature error, below 2e-4). Measured worst: see the output;
/// bounded at 1 % for `E_T` from both sides and 0.6 % for `E_R` absolute.
#[test]
fn tables_match_an_independent_model_between_the_nodes() {
    let mus = [0.013f32, 0.07, 0.33, 0.62, 0.87];
    let alphas = [0.0013f32, 0.013, 0.13, 0.37, 0.83];
    let etas = [1.17f32, 1.33, 1.5, 2.4, 2.9];
    let none = (0.0f64, 0.0f32, 0.0f32, 0.0f32);
    let (mut worst_out, mut worst_in, mut worst_coat) = (none, none, none);
    for eta in etas {
        for alpha in alphas {
            let r = RefDielectric { ax: alpha as f64, ay: alpha as f64, eta: eta as f64 };
            for mu in mus {
                let (e_r, e_t) = reference_albedo(&r, wo_mu(mu));
                let (_, e_t_in) = reference_albedo(&r, wo_mu(mu) * Vec3::new(1.0, 1.0, -1.0));
                let d_out = (dielectric_albedo(mu, alpha, eta) as f64 - e_t).abs();
                let d_in = (dielectric_albedo(mu, alpha, 1.0 / eta) as f64 - e_t_in).abs();
                let d_coat = (coat_albedo(mu, alpha, eta) as f64 - e_r).abs();
                for (w, d) in [(&mut worst_out, d_out), (&mut worst_in, d_in), (&mut worst_coat, d_coat)] {
                    if d > w.0 {
                        *w = (d, mu, alpha, eta);
                    }
                }
            }
        }
    }
    for (name, w) in [("E_T outside", worst_out), ("E_T inside ", worst_in), ("E_R (coat) ", worst_coat)] {
        println!("worst |{name} - table| = {:.2e} at mu {}, alpha {}, eta {}", w.0, w.1, w.2, w.3);
    }
    assert!(worst_out.0 < 0.01 && worst_in.0 < 0.01 && worst_coat.0 < 0.006);
}

/// `integral f |wi.z| dwi` of the coat (`GgxConductor` with the dielectric Fresnel term) by a
/// fine quadrature over the VNDF square (48 x 24 panels).
fn coat_albedo_quadrature(alpha: f32, eta: f32, mu: f32) -> f64 {
    let c = GgxConductor::isotropic(alpha, Fresnel::Dielectric { eta });
    let wo = wo_mu(mu);
    if c.is_delta() {
        return c.sample(wo, Vec2::splat(0.5), Sampling::Vndf).map_or(0.0, |s| s.weight.x as f64);
    }
    let mut sum = 0.0;
    for (s, ws) in rule(48) {
        let ux = (1.0 - (1.0 - s) * (1.0 - s)) as f32;
        for (v, wv) in rule(24) {
            if let Some(smp) = c.sample(wo, Vec2::new(ux, v as f32), Sampling::Vndf) {
                let pdf = c.pdf(wo, smp.wi, Sampling::Vndf) as f64;
                if pdf > 0.0 {
                    sum += ws * 2.0 * (1.0 - s) * wv * c.eval(wo, smp.wi).x as f64 / pdf;
                }
            }
        }
    }
    sum
}

/// The plastic's energy balance with a white base: the coat's albedo (a fine quadrature of
/// `GgxConductor`, not the table) plus the base's, `integral plastic_base_weight(mu_o, mu_i)
/// mu_i / pi dwi = 2 integral w mu_i dmu_i` (exact per table cell: the lookup is linear in
/// `mu_i^(1/4)` there), is 1 within 1 % for water, glass and diamond-like coats, every alpha
/// and every view down to `mu = 0.01`. The base integral equals `1 - E_R(mu_o)` of the table to
/// rounding (checked), so the balance is off only by the table's interpolation error.
#[test]
fn plastic_with_a_white_base_keeps_all_energy() {
    let n_cells = ggx_core::energy_dielectric_tables::N_MU - 1;
    let mut worst = (0.0f64, 0.0f32, 0.0f32, 0.0f32);
    let mut worst_consistency = 0.0f64;
    for eta in [1.33f32, 1.5, 2.4] {
        for alpha in ALPHAS {
            for mu in MUS {
                let base: f64 = rule(n_cells)
                    .into_iter()
                    .map(|(x, w)| {
                        let mu_i = (x * x) * (x * x);
                        w * 8.0 * x.powi(7) * plastic_base_weight(mu, mu_i as f32, alpha, eta) as f64
                    })
                    .sum();
                worst_consistency = worst_consistency.max((base - (1.0 - coat_albedo(mu, alpha, eta) as f64)).abs());
                let total = coat_albedo_quadrature(alpha, eta, mu) + base;
                if (total - 1.0).abs() > worst.0 {
                    worst = ((total - 1.0).abs(), eta, alpha, mu);
                }
            }
        }
    }
    println!("plastic: worst |E_R + base - 1| = {:.2e} at eta {}, alpha {}, mu {}", worst.0, worst.1, worst.2, worst.3);
    println!("plastic: worst |base - (1 - E_R(table))| = {worst_consistency:.2e}");
    assert!(worst.0 < 0.01 && worst_consistency < 1e-5, "{worst:?} {worst_consistency}");
}

/// `E_R_avg` is the average of the interpolated `E_R` at off-grid alpha and eta too
/// (interpolation is linear in the table entries).
#[test]
fn coat_average_is_the_average_of_the_lookup() {
    let n_cells = ggx_core::energy_dielectric_tables::N_MU - 1;
    for (alpha, eta) in [(0.0013f32, 1.17f32), (0.13, 1.33), (0.37, 2.9), (0.83, 1.5), (1.0, 3.0)] {
        let avg: f64 = rule(n_cells)
            .into_iter()
            .map(|(x, w)| w * 8.0 * x.powi(7) * coat_albedo(((x * x) * (x * x)) as f32, alpha, eta) as f64)
            .sum();
        let table = coat_average_albedo(alpha, eta) as f64;
        assert!((avg - table).abs() < 2e-6, "alpha {alpha} eta {eta}: {avg} vs {table}");
    }
}

/// Dielectrics of the sampler tests: rough and near-mirror, both index orders.
fn dielectrics() -> Vec<GgxDielectricMs> {
    [(0.05f32, 0.05f32, 1.5f32), (0.3, 0.3, 1.33), (1.0, 1.0, 2.4), (0.1, 0.5, 1.5), (0.3, 0.3, 1.0 / 1.5)]
        .into_iter()
        .map(|(ax, ay, eta)| GgxDielectricMs::new(GgxDielectric::new(ax, ay, eta)))
        .collect()
}

/// `weight == eval / pdf` (to 1e-5 relative) and `pdf == pdf()` (bit for bit) for every
/// technique, both transport modes and both sides; compensated weights exceed the
/// uncompensated ones by exactly `compensation_scale`.
#[test]
fn sample_weight_and_pdf_agree_with_eval_and_pdf() {
    let (mut checked, mut worst) = (0u64, 0.0f32);
    for ms in dielectrics() {
        let ss = ms.dielectric;
        for inc in [0.0f32, 45.0, 80.0, 89.0] {
            for side in [1.0f32, -1.0] {
                let wo = util::wo_at(inc) * Vec3::new(1.0, 1.0, side);
                let scale = ms.compensation_scale(wo);
                for sampling in [Sampling::Vndf, Sampling::SphericalCaps, Sampling::Bounded, Sampling::Ndf] {
                    for mode in [IMP, RAD] {
                        let mut u = Uniforms::new(checked);
                        for _ in 0..300 {
                            let (uu, ul) = (u.next(), u.next().x);
                            let s = ms.sample(wo, uu, ul, sampling, mode);
                            let s0 = ss.sample(wo, uu, ul, sampling, mode);
                            assert_eq!(s.map(|s| (s.wi, s.pdf)), s0.map(|s| (s.wi, s.pdf)));
                            let (Some(s), Some(s0)) = (s, s0) else { continue };
                            assert_eq!(s.weight, s0.weight * scale);
                            let pdf = ms.pdf(wo, s.wi, sampling, mode);
                            assert_eq!(s.pdf, pdf);
                            let expect = ms.eval(wo, s.wi, mode) / pdf;
                            let e = ((s.weight - expect).abs() / expect.abs().max(Vec3::splat(1e-6))).max_element();
                            worst = worst.max(e);
                            assert!(e < 1e-5, "{sampling:?} {mode:?}: weight {} vs {expect}", s.weight);
                            checked += 1;
                        }
                    }
                }
            }
        }
    }
    println!("{checked} samples, worst relative |weight - eval / pdf| = {worst:.2e}");
    assert!(checked > 10_000);
}

/// `compensation = 0` (and a smooth interface, whatever `compensation`) is exactly
/// `GgxDielectric`, bit for bit, in every method.
#[test]
fn without_compensation_it_is_the_dielectric() {
    let mut u = Uniforms::new(11);
    for (alpha, eta) in [(0.0f32, 1.5f32), (0.3, 1.5), (1.0, 1.0 / 2.4)] {
        let d = GgxDielectric::isotropic(alpha, eta);
        let mut off = GgxDielectricMs::new(d);
        if alpha > 0.0 {
            off.compensation = 0;
        }
        assert!(!off.is_compensated());
        for _ in 0..2000 {
            let sphere = |u: Vec2, side: f32| ggx_core::warp::sample_uniform_hemisphere(u) * Vec3::new(1.0, 1.0, side);
            let wo = sphere(u.next(), if u.next().x < 0.5 { 1.0 } else { -1.0 });
            let wi = sphere(u.next(), if u.next().x < 0.5 { 1.0 } else { -1.0 });
            let (uu, ul) = (u.next(), u.next().x);
            for mode in [IMP, RAD] {
                let bits = |v: Vec3| v.to_array().map(f32::to_bits);
                assert_eq!(bits(off.eval(wo, wi, mode)), bits(d.eval(wo, wi, mode)));
                assert_eq!(
                    off.pdf(wo, wi, Sampling::Vndf, mode).to_bits(),
                    d.pdf(wo, wi, Sampling::Vndf, mode).to_bits()
                );
                assert_eq!(off.sample(wo, uu, ul, Sampling::Vndf, mode), d.sample(wo, uu, ul, Sampling::Vndf, mode));
            }
        }
    }
}

/// Monte Carlo furnace through the sampler: the mean importance weight is 1 within 4 standard
/// errors plus 1 % (sampling, pdf, eval and the scale agree on the integral), from both sides.
#[test]
fn sampler_estimates_unit_albedo() {
    for (alpha, eta, inc, side) in
        [(0.3f32, 1.5f32, 30.0f32, 1.0f32), (1.0, 1.5, 0.0, -1.0), (1.0, 2.4, 80.0, 1.0), (0.6, 1.33, 60.0, -1.0)]
    {
        let ms = GgxDielectricMs::new(GgxDielectric::isotropic(alpha, eta));
        let wo = util::wo_at(inc) * Vec3::new(1.0, 1.0, side);
        let mut u = Uniforms::new(alpha.to_bits() as u64 ^ inc.to_bits() as u64);
        let n = 200_000;
        let (mut s1, mut s2) = (0.0f64, 0.0f64);
        for _ in 0..n {
            let ul = u.next().x;
            let w = ms.sample(wo, u.next(), ul, Sampling::Vndf, IMP).map_or(0.0, |s| s.weight.x as f64);
            s1 += w;
            s2 += w * w;
        }
        let mean = s1 / n as f64;
        let sigma = ((s2 / n as f64 - mean * mean).max(0.0) / n as f64).sqrt();
        println!("alpha {alpha} eta {eta} inc {inc} side {side:+}: mean weight {mean:.5} +- {sigma:.1e}");
        assert!((mean - 1.0).abs() < 4.0 * sigma + 0.01, "alpha {alpha} eta {eta} inc {inc} side {side}: {mean}");
    }
}

/// What the scale costs: the single-scattering dielectric is reciprocal in the adjoint sense,
/// `f_rad(wo, wi) / |wi.z| = f_imp(wi, wo) / |wo.z|` (checked, to f32 rounding), and the compensated one
/// breaks it by exactly `E_T(wi) / E_T(wo)`, the ratio of the two directions' albedos. The
/// deviation `|ratio - 1|` is printed per alpha (it grows with roughness: the inside albedo
/// drops under total internal reflection) and bounded by its measured worst.
#[test]
fn reciprocity_deviation_is_the_albedo_ratio() {
    let mut u = Uniforms::new(5);
    let mut overall = 0.0f32;
    for alpha in [0.05f32, 0.3, 1.0] {
        let ms = GgxDielectricMs::new(GgxDielectric::isotropic(alpha, 1.5));
        let mut worst = 0.0f32;
        for _ in 0..5000 {
            let side = |x: f32| if x < 0.5 { 1.0 } else { -1.0 };
            let wo = ggx_core::warp::sample_uniform_hemisphere(u.next()) * Vec3::new(1.0, 1.0, side(u.next().x));
            let wi = ggx_core::warp::sample_uniform_hemisphere(u.next()) * Vec3::new(1.0, 1.0, side(u.next().x));
            let (a0, b0) =
                (ms.dielectric.eval(wo, wi, RAD).x / wi.z.abs(), ms.dielectric.eval(wi, wo, IMP).x / wo.z.abs());
            if !(a0 > 1e-3 && b0 > 1e-3) {
                continue;
            }
            // f32 rounding: 1 - F is ill-conditioned near the critical angle (see dielectric_ref.rs).
            assert!((a0 / b0 - 1.0).abs() < 1e-2, "single scattering: {a0} vs {b0} for {wo} {wi}");
            let (a, b) = (ms.eval(wo, wi, RAD).x / wi.z.abs(), ms.eval(wi, wo, IMP).x / wo.z.abs());
            let ratio = a / b;
            let expect = ms.compensation_scale(wo) / ms.compensation_scale(wi);
            assert!((ratio / expect / (a0 / b0) - 1.0).abs() < 1e-5, "{ratio} vs {expect}");
            worst = worst.max((ratio - 1.0).abs().max((1.0 / ratio - 1.0).abs()));
        }
        println!("alpha {alpha}, eta 1.5: worst reciprocity deviation max(r, 1/r) - 1 = {worst:.3}");
        overall = overall.max(worst);
    }
    assert!(overall > 0.1 && overall < 3.0, "{overall}");
}

/// Indices beyond the tables read the last slice: `eta' = 5` is `eta' = 3`, and `1/5` is `1/3`.
#[test]
fn indices_beyond_the_tables_are_clamped() {
    for (mu, alpha) in [(0.3f32, 0.2f32), (1.0, 1.0), (0.02, 0.01)] {
        assert_eq!(dielectric_albedo(mu, alpha, 5.0), dielectric_albedo(mu, alpha, ETA_TABLE_MAX));
        assert_eq!(dielectric_albedo(mu, alpha, 0.2), dielectric_albedo(mu, alpha, 1.0 / ETA_TABLE_MAX));
        assert_eq!(coat_albedo(mu, alpha, 7.0), coat_albedo(mu, alpha, ETA_TABLE_MAX));
    }
}
