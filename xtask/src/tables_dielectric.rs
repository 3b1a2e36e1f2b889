//! `cargo xtask tables` (second file): the energy-compensation tables of ggx-core's rough
//! dielectric (Turquin 2019) and of the plastic's coat (Kulla & Conty 2017), written to
//! `crates/ggx-core/src/energy_dielectric_tables.rs`.
//!
//! Every table has [`N_ETA`] slices of index `eta = ggx_core::energy_dielectric::slice_eta(k /
//! (N_ETA - 1))` (from 1 to 3, `sqrt((eta - 1) / (eta + 1))` spaced), [`N_ALPHA`] rows and
//! [`N_MU`] columns on the conductor's quarter-root axes (`energy::row_alpha`,
//! `energy::column_mu`; the `mu = 0` column at [`MU_MIN`]):
//!
//! * `E_T_OUTSIDE`, `E_T_INSIDE`: `E_T = integral f |wi.z| dwi` of `GgxDielectric::isotropic(alpha,
//!   eta)` in importance mode, reflection plus transmission, for `wo = (sqrt(1 - mu^2), 0, mu)`
//!   (outside: `eta' = eta`) and `wo = (sqrt(1 - mu^2), 0, -mu)` (inside the denser medium:
//!   `eta' = 1 / eta`). As an integral over the visible normals `wm` of `wo`, with the lobe
//!   choice `u_lobe` integrated analytically, `E_T = integral D_wo(wm) (F G2(wo, wr) / G1(wo) +
//!   (1 - F) G2(wo, wt) / G1(wo)) dwm` ([`lobes`]: `F = fresnel_dielectric(wo.wm)`, `wr =
//!   reflect`, `wt = refract`, the expectation of `GgxDielectric::sample`'s weight, which is
//!   `eval / pdf`). Two rules ([`dielectric_albedo`]): the VNDF sampler's unit square (as the
//!   conductor's tables), and, from inside at `alpha >=` [`POLAR_ALPHA_MIN`], polar coordinates
//!   around `wo` whose pieces end at the critical cosine. There `1 - F` has a square-root edge
//!   (`1 - F ~ cos_t`), a curve across the unit square where a fixed rule converges only as
//!   `h^1.5` (2.4e-3 error left with 32 x 16 panels, 1.3e-2 with 16 x 8); on a piece boundary
//!   with a smoothstep substitution the error is below 1e-3 for less work ([`polar_albedo`]; what
//!   remains are the kinks where the reflected or refracted direction crosses the horizon,
//!   curves in any coordinates, worst at alpha 1 and grazing). Doubling every panel count moves
//!   no value by more than 3.8e-5 outside and for the coat, 7.6e-4 inside
//!   (`quadrature_is_converged`): far below the tables' interpolation error (4.5e-3, see
//!   ggx-core's `tests/dielectric_compensation.rs`).
//! * `E_R`: the albedo of `GgxConductor::isotropic(alpha, Fresnel::Dielectric { eta })` from
//!   outside (the coat), by the conductor tables' own rule (`tables::conductor_albedo`).
//! * `E_R_AVG[k][j] = 2 integral_0^1 E_R(mu) mu dmu` of the row as the lookup interpolates it
//!   (`tables::interpolant_average`), so that a plastic's base weight integrates to exactly
//!   `1 - E_R(mu_o)`.
//!
//! Sums in f64 of ggx-core's f32 functions; values above 1 (quadrature noise, at most 2.3e-4;
//! the importance albedo cannot exceed 1) are stored as 1. Deterministic like the conductor's
//! tables: fixed-order sums per row, rows in parallel, shortest round-trip printing, so a rerun
//! reproduces the file byte for byte (`committed_dielectric_tables_are_up_to_date`).

use crate::tables::{MU_MIN, composite_gl, conductor_albedo, interpolant_average};
use ggx_core::energy::{column_mu, row_alpha};
use ggx_core::energy_dielectric::slice_eta;
use ggx_core::fresnel::fresnel_dielectric;
use ggx_core::math::normalize_or_zero;
use ggx_core::{Fresnel, GgxConductor, GgxDielectric, Vec2, Vec3, reflect, refract};
use rayon::prelude::*;
use std::path::PathBuf;

/// Columns (`mu`) of every table.
pub const N_MU: usize = 32;
/// Rows (`alpha`) of every table.
pub const N_ALPHA: usize = 32;
/// Slices (`eta`) of every table.
pub const N_ETA: usize = 12;
/// Gauss-Legendre panels over `v = u.y` of the VNDF square (twice as many over `s`), outside
/// and for the coat.
pub const PANELS: usize = 4;
/// The same from inside below [`POLAR_ALPHA_MIN`] (the critical-angle edge crosses the lobe).
pub const PANELS_INSIDE: usize = 8;
/// Gauss-Legendre panels of the polar rule ([`polar_albedo`]): over the azimuth, and per unit
/// length of each piece of `c` (at least 2 per piece).
pub const POLAR_PANELS: usize = 12;
/// From this alpha up the inside table uses the polar rule; below it the visible normals are
/// too concentrated for a rule that is not warped by the VNDF.
pub const POLAR_ALPHA_MIN: f32 = 0.1;

/// `F w_r + (1 - F) w_t` for one visible normal `wm` of `wo`: the weights `G2(wo, wi) /
/// G1(wo)` (at most 1, as `GgxDielectric::sample` clamps them) of the reflected and the
/// refracted direction, each 0 when its direction leaves its lobe's hemisphere (or under total
/// internal reflection), mixed by the probabilities `F = fresnel_dielectric(wo.wm, eta)` and
/// `1 - F` with which the sampler picks them: the sampler's weight averaged over `u_lobe`.
fn lobes(b: &GgxDielectric, wo: Vec3, wm: Vec3) -> f64 {
    let d = &b.distribution;
    let eta = b.eta();
    let cos_om = wo.dot(wm);
    if !(cos_om * wo.z > 0.0) {
        return 0.0;
    }
    let f = fresnel_dielectric(cos_om, eta);
    let g1 = d.g1(wo);
    let weight = |wi: Vec3| f64::from((d.g2(wo, wi) / g1).min(1.0));
    let wr = normalize_or_zero(reflect(wo, wm));
    let r = if wr.z * wo.z > 0.0 { f64::from(f) * weight(wr) } else { 0.0 };
    let t = match refract(wo, wm, eta).map(normalize_or_zero) {
        Some(wt) if wt.z * wo.z < 0.0 => f64::from(1.0 - f) * weight(wt),
        _ => 0.0,
    };
    r + t
}

/// `E_T` over the VNDF sampler's unit square: `sum w [lobes](wm(u))`, `wm =
/// sample_wm_vndf(sign(wo.z) wo, u)`, `u = (1 - (1 - s)^2, v)` (the substitution of the
/// conductor's tables, smooth where the map has `sqrt(1 - u.x)`), composite 5-point
/// Gauss-Legendre with `2 panels` x `panels` panels.
fn vndf_albedo(b: &GgxDielectric, wo: Vec3, panels: usize) -> f64 {
    let wv = if wo.z < 0.0 { -wo } else { wo };
    let rule_v = composite_gl(panels);
    let mut sum = 0.0f64;
    for (s, ws) in composite_gl(2 * panels) {
        let ux = (1.0 - (1.0 - s) * (1.0 - s)) as f32;
        let mut row = 0.0f64;
        for &(v, wv_) in &rule_v {
            row += wv_ * lobes(b, wo, b.distribution.sample_wm_vndf(wv, Vec2::new(ux, v as f32)));
        }
        sum += ws * 2.0 * (1.0 - s) * row;
    }
    sum
}

/// Composite `panels`-panel Gauss-Legendre on `[a, b]` after the smoothstep substitution `x = a
/// + (b - a) (3 t^2 - 2 t^3)`, whose Jacobian `6 t (1 - t)` vanishes at both ends: a
/// square-root edge there (`sqrt(x - a) ~ t`) becomes smooth.
fn smoothstep_rule(a: f64, b: f64, panels: usize) -> Vec<(f64, f64)> {
    composite_gl(panels)
        .into_iter()
        .map(|(t, w)| (a + (b - a) * t * t * (3.0 - 2.0 * t), w * (b - a) * 6.0 * t * (1.0 - t)))
        .collect()
}

/// `E_T` in polar coordinates around the visible side `wv = (s, 0, mu)` of `wo` (in the
/// `xz`-plane): `wm = c wv + sqrt(1 - c^2) (cos phi t1 + sin phi y)`, `t1 = (-mu, 0, s)`, so that
/// `dwm = dc dphi` and `E_T = 2 integral integral D_wv(wm) [lobes](wm) dphi dc` (`D_wv` =
/// `d_visible`; the lobe is symmetric in `phi`). The `phi` range is where `wm.z > 0` (`D`
/// drops to 0 there): `cos phi > -c mu / (sqrt(1 - c^2) s)`, from 0 to its closed-form end. The
/// `c` axis is cut at the critical cosine `sqrt(1 - eta'^2)` (`eta' < 1`), at `c = s` (where the
/// `phi` range starts to shrink) and at `c = mu` (the peak of `D`, `wm = z`); each piece gets
/// [`smoothstep_rule`] with `ceil(panels * length)` panels (at least 2), the `phi` range `panels`.
fn polar_albedo(b: &GgxDielectric, wo: Vec3, panels: usize) -> f64 {
    let wv = if wo.z < 0.0 { -wo } else { wo };
    let (s, mu) = (f64::from(wv.x), f64::from(wv.z));
    let eta = f64::from(b.eta());
    let etap = if wo.z > 0.0 { eta } else { 1.0 / eta };
    let mut cuts = vec![0.0, 1.0, s, mu];
    if etap < 1.0 {
        cuts.push((1.0 - etap * etap).sqrt());
    }
    cuts.sort_by(f64::total_cmp);
    cuts.dedup();
    let mut sum = 0.0f64;
    for piece in cuts.windows(2) {
        let c_panels = ((panels as f64 * (piece[1] - piece[0])).ceil() as usize).max(2);
        for (c, wc) in smoothstep_rule(piece[0], piece[1], c_panels) {
            let sn = (1.0 - c * c).max(0.0).sqrt();
            let phi_max = if sn * s > 0.0 { (-c * mu / (sn * s)).max(-1.0).acos() } else { std::f64::consts::PI };
            let mut row = 0.0f64;
            for (phi, wp) in smoothstep_rule(0.0, phi_max, panels) {
                let (sp, cp) = phi.sin_cos();
                let m = [c * s - sn * cp * mu, sn * sp, c * mu + sn * cp * s];
                let wm = normalize_or_zero(Vec3::new(m[0] as f32, m[1] as f32, m[2] as f32));
                if wm.z > 0.0 {
                    row += wp * f64::from(b.distribution.d_visible(wv, wm)) * lobes(b, wo, wm);
                }
            }
            sum += wc * 2.0 * row;
        }
    }
    sum
}

/// `E_T(mu, alpha)` of `GgxDielectric::isotropic(alpha, eta)` seen from outside (`eta' = eta`)
/// or from inside (`eta' = 1 / eta`), `mu` clamped to `[MU_MIN, 1]`: [`vndf_albedo`] with
/// [`PANELS`] outside, from inside [`polar_albedo`] with [`POLAR_PANELS`] at `alpha >=`
/// [`POLAR_ALPHA_MIN`] and [`vndf_albedo`] with [`PANELS_INSIDE`] below. A smooth interface
/// (never a table row) keeps everything: 1.
pub fn dielectric_albedo(mu: f32, alpha: f32, eta: f32, inside: bool) -> f64 {
    dielectric_albedo_with(mu, alpha, eta, inside, 1)
}

/// [`dielectric_albedo`] with every panel count multiplied by `refine`.
fn dielectric_albedo_with(mu: f32, alpha: f32, eta: f32, inside: bool, refine: usize) -> f64 {
    let b = GgxDielectric::isotropic(alpha, eta);
    if b.is_delta() {
        return 1.0;
    }
    let mu = mu.max(MU_MIN).min(1.0);
    let s = (1.0 - mu * mu).max(0.0).sqrt();
    let wo = Vec3::new(s, 0.0, if inside { -mu } else { mu });
    if !inside {
        vndf_albedo(&b, wo, PANELS * refine)
    } else if alpha >= POLAR_ALPHA_MIN {
        polar_albedo(&b, wo, POLAR_PANELS * refine)
    } else {
        vndf_albedo(&b, wo, PANELS_INSIDE * refine)
    }
}

/// `E_R(mu, alpha, eta)`: the coat's albedo, `GgxConductor::isotropic(alpha, Fresnel::Dielectric
/// { eta })` from outside, by the conductor tables' rule with [`PANELS`].
pub fn coat_albedo(mu: f32, alpha: f32, eta: f32) -> f64 {
    conductor_albedo(&GgxConductor::isotropic(alpha, Fresnel::Dielectric { eta }), mu, PANELS)
}

/// The three tables.
#[derive(Clone, Copy, PartialEq)]
enum Which {
    /// `E_T_OUTSIDE`.
    Outside,
    /// `E_T_INSIDE`.
    Inside,
    /// `E_R`.
    Coat,
}

/// Row `j` of slice `k` of a table, stored as f32 (the albedos clamped to at most 1).
fn row(which: Which, k: usize, j: usize) -> [f32; N_MU] {
    let eta = slice_eta(k as f32 / (N_ETA - 1) as f32);
    let alpha = row_alpha(j as f32 / (N_ALPHA - 1) as f32);
    let mut r = [0.0f32; N_MU];
    for (i, v) in r.iter_mut().enumerate() {
        let mu = column_mu(i as f32 / (N_MU - 1) as f32);
        let e = match which {
            Which::Outside => dielectric_albedo(mu, alpha, eta, false),
            Which::Inside => dielectric_albedo(mu, alpha, eta, true),
            Which::Coat => coat_albedo(mu, alpha, eta),
        };
        *v = e.min(1.0) as f32;
    }
    r
}

/// Appends `name`, a `[[[f32; N_MU]; N_ALPHA]; N_ETA]` table, one line per row and a comment
/// with the index of each slice.
fn write_table(s: &mut String, doc: &str, name: &str, rows: &[[f32; N_MU]]) {
    *s += &format!("/// {doc}\n#[rustfmt::skip]\npub static {name}: [[[f32; N_MU]; N_ALPHA]; N_ETA] = [\n");
    for (k, slice) in rows.chunks(N_ALPHA).enumerate() {
        *s += &format!("    // k = {k}: eta = {:?}\n    [\n", slice_eta(k as f32 / (N_ETA - 1) as f32));
        for r in slice {
            let vals: Vec<String> = r.iter().map(|v| format!("{v:?}")).collect();
            *s += &format!("        [{}],\n", vals.join(", "));
        }
        *s += "    ],\n";
    }
    *s += "];\n";
}

/// The generated source file.
pub fn generate() -> String {
    let jobs: Vec<(Which, usize, usize)> = [Which::Outside, Which::Inside, Which::Coat]
        .into_iter()
        .flat_map(|w| (0..N_ETA).flat_map(move |k| (0..N_ALPHA).map(move |j| (w, k, j))))
        .collect();
    let rows: Vec<[f32; N_MU]> = jobs.into_par_iter().map(|(w, k, j)| row(w, k, j)).collect();
    let per_table = N_ETA * N_ALPHA;
    let (outside, inside, coat) = (&rows[..per_table], &rows[per_table..2 * per_table], &rows[2 * per_table..]);
    let mut s = String::new();
    s += &format!(
        r#"//! Energy-compensation tables of the GGX dielectric (Turquin 2019) and of the plastic's coat
//! (Kulla & Conty 2017); read by `energy_dielectric`.
//!
//! GENERATED by `cargo xtask tables` (xtask/src/tables_dielectric.rs), do not edit: a test there
//! regenerates them and fails when this file differs.
//!
//! `T[k][j][i]`, flat `(k * N_ALPHA + j) * N_MU + i`, is at
//! * `eta = energy_dielectric::slice_eta(k / (N_ETA - 1))`: 1 to 3, spaced in `sqrt((eta - 1) / (eta + 1))`;
//! * `alpha = energy::row_alpha(j / (N_ALPHA - 1))`: quarter roots from `DELTA_ALPHA` to 1;
//! * `mu = energy::column_mu(i / (N_MU - 1)) = (i / (N_MU - 1))^4` (the `mu = 0` column at `mu = {MU_MIN:e}`).
//!
//! Statics (one copy each; the accessors of `energy_dielectric` lend them as flat `&'static [f32]`):
//! * `E_T_OUTSIDE`, `E_T_INSIDE`: `integral f |wi.z| dwi` (reflection + transmission, importance mode)
//!   of `GgxDielectric::isotropic(alpha, eta)` for `wo.z = mu` (outside, `eta' = eta`) and `wo.z = -mu`
//!   (inside the denser medium, `eta' = 1 / eta`);
//! * `E_R`: `integral f |wi.z| dwi` of the coat, `GgxConductor::isotropic(alpha, Fresnel::Dielectric {{ eta }})`;
//!   `E_R_AVG[k][j] = 2 integral E_R(mu) mu dmu` of the row's interpolant, exactly.
//!
//! Quadrature in f64 of ggx-core's f32 code, composite 5-point Gauss-Legendre: the VNDF square with
//! {s} x {PANELS} panels ({s_in} x {PANELS_INSIDE} inside below alpha {POLAR_ALPHA_MIN}), polar coordinates
//! around `wo` inside from alpha {POLAR_ALPHA_MIN} ({POLAR_PANELS} azimuth panels).

"#,
        s = 2 * PANELS,
        s_in = 2 * PANELS_INSIDE
    );
    s += "/// Columns (`mu`) of every table.\n";
    s += &format!("pub const N_MU: usize = {N_MU};\n");
    s += "/// Rows (`alpha`) of every table.\n";
    s += &format!("pub const N_ALPHA: usize = {N_ALPHA};\n");
    s += "/// Slices (`eta`) of every table.\n";
    s += &format!("pub const N_ETA: usize = {N_ETA};\n\n");
    write_table(&mut s, "`E_T(mu, alpha, eta' = eta)`: `wo` outside the denser medium.", "E_T_OUTSIDE", outside);
    s += "\n";
    write_table(&mut s, "`E_T(mu, alpha, eta' = 1 / eta)`: `wo` inside the denser medium.", "E_T_INSIDE", inside);
    s += "\n";
    write_table(&mut s, "`E_R(mu, alpha, eta)`: the coat, `wo` outside.", "E_R", coat);
    s += "\n/// `E_R_avg(alpha, eta) = 2 integral_0^1 E_R(mu, alpha, eta) mu dmu`, `[k][j]` as `E_R`.\n";
    s += "#[rustfmt::skip]\npub static E_R_AVG: [[f32; N_ALPHA]; N_ETA] = [\n";
    for slice in coat.chunks(N_ALPHA) {
        let vals: Vec<String> = slice.iter().map(|r| format!("{:?}", interpolant_average(r) as f32)).collect();
        s += &format!("    [{}],\n", vals.join(", "));
    }
    s += "];\n";
    s
}

/// Where the tables live.
pub fn path() -> PathBuf {
    crate::render::workspace_root().join("crates/ggx-core/src/energy_dielectric_tables.rs")
}

#[cfg(test)]
mod tests {
    use super::*;
    use ggx_core::{Sampling, TransportMode};

    /// Fails when the committed tables differ from a fresh generation (byte for byte): someone
    /// edited the file, or changed ggx-core's dielectric, Fresnel, sampler or axes without
    /// rerunning `cargo xtask tables`.
    #[test]
    fn committed_dielectric_tables_are_up_to_date() {
        let committed = std::fs::read_to_string(path()).expect("read energy_dielectric_tables.rs");
        let fresh = generate();
        if committed != fresh {
            let diff = committed.lines().zip(fresh.lines()).position(|(a, b)| a != b);
            panic!(
                "energy_dielectric_tables.rs is out of date (first differing line {diff:?}): run `cargo xtask tables`"
            );
        }
    }

    /// [`lobes`] is the sampler's weight averaged over `u_lobe`: for random `u`, `F w(u_lobe <
    /// F) + (1 - F) w(u_lobe > F)` from `GgxDielectric::sample` (with `F` from its own normal)
    /// agrees to rounding, from both sides, for every rule's alphas.
    #[test]
    fn lobes_are_the_samplers_expected_weight() {
        let mut worst = 0.0f64;
        let mut state = 0x1234_5678u32;
        let mut next = || {
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (state >> 8) as f32 / 16_777_216.0
        };
        for (alpha, eta) in [(0.01f32, 1.5f32), (0.3, 1.33), (1.0, 2.4), (0.05, 3.0)] {
            let b = GgxDielectric::isotropic(alpha, eta);
            for mu in [0.02f32, 0.3, 0.8, 1.0] {
                let s = (1.0 - mu * mu).sqrt();
                for wo in [Vec3::new(s, 0.0, mu), Vec3::new(s, 0.0, -mu)] {
                    let wv = if wo.z < 0.0 { -wo } else { wo };
                    for _ in 0..2000 {
                        let u = Vec2::new(next(), next());
                        let wm = b.distribution.sample_wm_vndf(wv, u);
                        let f = fresnel_dielectric(wo.dot(wm), eta);
                        let w = |ul: f32| {
                            b.sample(wo, u, ul, Sampling::Vndf, TransportMode::Importance).map_or(0.0, |x| x.weight.x)
                        };
                        let sampled = f64::from(f) * f64::from(w(0.5 * f))
                            + f64::from(1.0 - f) * f64::from(w(f + 0.5 * (1.0 - f)));
                        worst = worst.max((sampled - lobes(&b, wo, wm)).abs());
                    }
                }
            }
        }
        println!("worst |lobes - expected sample weight| = {worst:.2e}");
        assert!(worst < 1e-5, "{worst}");
    }

    /// The rules are converged: doubling every panel count moves no sampled value by more than
    /// 1e-4 (`E_T` outside: measured 3.8e-5; `E_R`: 3.8e-5), or 1e-3 from inside (7.6e-4 at
    /// alpha 1, mu 0.05, eta 1.09, where the polar rule meets the horizon kinks); points at
    /// near-mirror grazing, the critical angle and rough lobes at both ends of the index range.
    #[test]
    fn quadrature_is_converged() {
        let points = [
            (1.0f32, 0.01f32, 1.5f32),
            (0.5, 0.25, 1.5),
            (0.05, 1.0, 1.5),
            (0.01, 0.5, 2.4),
            (0.2, 0.0025, 1.33),
            (0.003, 0.002, 1.5),
            (0.01, 0.005, 1.5),
            (0.74, 0.05, 1.5),
            (0.75, 0.1, 1.5),
            (0.3, 1.0, 3.0),
            (1.0, 0.5, 3.0),
            (0.05, 1.0, 1.09),
        ];
        let mut worst = [0.0f64; 3];
        for (mu, alpha, eta) in points {
            for (t, inside) in [(0, false), (1, true)] {
                let (coarse, fine) =
                    (dielectric_albedo(mu, alpha, eta, inside), dielectric_albedo_with(mu, alpha, eta, inside, 2));
                worst[t] = worst[t].max((coarse - fine).abs());
                let bound = if inside { 1e-3 } else { 1e-4 };
                assert!(
                    (coarse - fine).abs() < bound,
                    "mu {mu} alpha {alpha} eta {eta} inside {inside}: {coarse} vs {fine}"
                );
            }
            let brdf = GgxConductor::isotropic(alpha, Fresnel::Dielectric { eta });
            let (coarse, fine) = (coat_albedo(mu, alpha, eta), conductor_albedo(&brdf, mu, 2 * PANELS));
            worst[2] = worst[2].max((coarse - fine).abs());
            assert!((coarse - fine).abs() < 1e-4, "coat mu {mu} alpha {alpha} eta {eta}: {coarse} vs {fine}");
        }
        println!("worst change on doubling: outside {:.1e}, inside {:.1e}, coat {:.1e}", worst[0], worst[1], worst[2]);
    }
}
