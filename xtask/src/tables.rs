//! `cargo xtask tables`: the energy-compensation tables of ggx-core's conductor (Kulla & Conty
//! 2017), written to `crates/ggx-core/src/energy_tables.rs`; the same command writes the
//! dielectric's and the plastic coat's tables ([`crate::tables_dielectric`]).
//!
//! * `E(mu, alpha)`, the directional albedo of the `F = 1` single-scattering GGX conductor,
//!   on a [`N`] x [`N`] grid: rows at `alpha = ggx_core::energy::row_alpha(j / (N - 1))`
//!   (quarter roots of alpha from `DELTA_ALPHA` to 1), columns at `mu =
//!   ggx_core::energy::column_mu(i / (N - 1)) = (i / (N - 1))^4` (the `mu = 0` column is
//!   evaluated at [`MU_MIN`]). Quarter roots rather than `mu`: `E` dips near `mu ~ alpha` and
//!   climbs back to 1 as `mu -> 0` (height-correlated `G2 / G1(wo) -> 1`); near a mirror that
//!   dip is a function of `mu / alpha`, which equal power maps on both axes resolve evenly (a
//!   `sqrt(alpha)` x `sqrt(mu)` grid left 3.3 % furnace error at alpha 0.002, mu 0.003).
//! * `E_avg(alpha) = 2 integral_0^1 E(mu) mu dmu`, same roughness nodes, integrated exactly
//!   over the table's own interpolant (see [`interpolant_average`]; close to the
//!   fine quadrature [`average_albedo`], `average_matches_a_fine_quadrature`).
//!
//! Everything is computed from ggx-core itself: `E(mu) = integral f(wo, wi) |wi.z| dwi` as a
//! quadrature of `GgxConductor::eval / GgxConductor::pdf` over the VNDF sampler's unit square
//! (the change of variables `u -> wi` of `GgxConductor::sample`, whose integrand `G2 / G1` is
//! smooth and vanishes continuously at the horizon; see [`albedo`] for the substitution that
//! keeps it smooth near `u.x = 1`), composite 5-point Gauss-Legendre with 2 [`PANELS`] x
//! [`PANELS`] panels, summed in f64; `E_avg` by composite Gauss-Legendre over
//! `sqrt(mu)` ([`PANELS_MU`] panels). Deterministic: every sum runs in a fixed order on one thread (rows
//! run in parallel), and values are printed with Rust's shortest round-trip formatting, so a
//! rerun reproduces the file byte for byte (`committed_tables_are_up_to_date`).

use ggx_core::energy::{column_mu, row_alpha};
use ggx_core::{Fresnel, GgxConductor, Sampling, Vec2, Vec3};
use rayon::prelude::*;
use std::path::PathBuf;

/// Grid size of both tables.
pub const N: usize = 48;
/// Gauss-Legendre panels over `v = u.y` of the sampler's unit square (twice as many over `s`).
pub const PANELS: usize = 16;
/// Gauss-Legendre panels over `sqrt(mu)` for `E_avg`.
#[cfg(test)]
pub const PANELS_MU: usize = 8;
/// The cosine at which the `mu = 0` column is evaluated (the limit `mu -> 0+`).
pub const MU_MIN: f32 = 1e-7;

/// Nodes of the 5-point Gauss-Legendre rule on `[-1, 1]`.
const GL5_NODES: [f64; 5] = [-0.906179845938664, -0.5384693101056831, 0.0, 0.5384693101056831, 0.906179845938664];
/// Weights of the 5-point Gauss-Legendre rule on `[-1, 1]` (they sum to 2).
const GL5_WEIGHTS: [f64; 5] =
    [0.23692688505618908, 0.47862867049936647, 128.0 / 225.0, 0.47862867049936647, 0.23692688505618908];

/// Nodes and weights of the composite 5-point Gauss-Legendre rule with `panels` panels on `[0, 1]`.
pub(crate) fn composite_gl(panels: usize) -> Vec<(f64, f64)> {
    let h = 1.0 / panels as f64;
    (0..panels)
        .flat_map(|p| {
            GL5_NODES.iter().zip(&GL5_WEIGHTS).map(move |(&t, &w)| ((p as f64 + 0.5 * (t + 1.0)) * h, 0.5 * h * w))
        })
        .collect()
}

/// `E(mu, alpha) = integral f(wo, wi) |wi.z| dwi` of the `F = 1` conductor, `wo = (sqrt(1 -
/// mu^2), 0, mu)`: the sum over the composite rule's nodes of `eval(wo, wi) / pdf(wo, wi)`
/// with `wi` from `sample(wo, u, Vndf)` (0 where it returns `None`), `u = (1 - (1 - s)^2, v)`:
/// the substitution removes the square-root singularity of the VNDF map at `u.x -> 1`
/// (`nh.z = sqrt(1 - u.x) = 1 - s`), where the horizon cut of the lobe lies (`u.x ~ 0.99` at
/// alpha 0.1). A mirror lobe (`is_delta`) returns its sample weight (1).
pub fn albedo(mu: f32, alpha: f32) -> f64 {
    albedo_with(mu, alpha, PANELS)
}

/// [`albedo`] with `2 panels` x `panels` Gauss-Legendre panels (`s` x `v`).
fn albedo_with(mu: f32, alpha: f32, panels: usize) -> f64 {
    conductor_albedo(&GgxConductor::isotropic(alpha, Fresnel::One), mu, panels)
}

/// `integral f(wo, wi) |wi.z| dwi` (red channel) of any conductor, `wo = (sqrt(1 - mu^2), 0,
/// mu)`, by the rule of [`albedo`] with `2 panels` x `panels` panels; also the plastic coat's
/// `E_R` (`tables_dielectric.rs`).
pub(crate) fn conductor_albedo(brdf: &GgxConductor, mu: f32, panels: usize) -> f64 {
    let mu = mu.max(MU_MIN).min(1.0);
    let wo = Vec3::new((1.0 - mu * mu).max(0.0).sqrt(), 0.0, mu);
    if brdf.is_delta() {
        return brdf.sample(wo, Vec2::splat(0.5), Sampling::Vndf).map_or(0.0, |s| s.weight.x as f64);
    }
    let (rule_s, rule_v) = (composite_gl(2 * panels), composite_gl(panels));
    let mut sum = 0.0f64;
    for &(s, ws) in &rule_s {
        let ux = 1.0 - (1.0 - s) * (1.0 - s);
        let jac = 2.0 * (1.0 - s);
        let mut row = 0.0f64;
        for &(v, wv) in &rule_v {
            if let Some(smp) = brdf.sample(wo, Vec2::new(ux as f32, v as f32), Sampling::Vndf) {
                let pdf = brdf.pdf(wo, smp.wi, Sampling::Vndf) as f64;
                if pdf > 0.0 {
                    row += wv * brdf.eval(wo, smp.wi).x as f64 / pdf;
                }
            }
        }
        sum += ws * jac * row;
    }
    sum
}

/// `E_avg(alpha) = 2 integral_0^1 E(mu, alpha) mu dmu = integral_0^1 E(x^2, alpha) 4 x^3 dx`
/// by the composite rule over `x = sqrt(mu)` (smooth where `E` dips at grazing).
#[cfg(test)]
fn average_albedo(alpha: f32) -> f64 {
    composite_gl(PANELS_MU).into_iter().map(|(x, w)| 4.0 * w * x * x * x * albedo((x * x) as f32, alpha)).sum()
}

/// `2 integral_0^1 E_lin(mu) mu dmu = integral_0^1 E_lin(x) 8 x^7 dx` of the piecewise-linear
/// interpolant in `x = mu^(1/4)` of one table row (nodes at `x = i / (len - 1)`), exactly
/// (5-point Gauss-Legendre per cell, a degree-8 integrand): the `E_avg` the lookup is
/// consistent with, so that the multiple-scattering lobe built from the interpolated `E`
/// integrates to exactly `F_ms (1 - E(mu_o))` and the furnace error is the interpolation error
/// of `E(mu_o)` alone. Also the coat's `E_R_avg` (`tables_dielectric.rs`).
pub(crate) fn interpolant_average(e: &[f32]) -> f64 {
    let n = e.len();
    let h = 1.0 / (n - 1) as f64;
    let mut sum = 0.0f64;
    for i in 0..n - 1 {
        let (a, b) = (e[i] as f64, e[i + 1] as f64);
        for (&t, &w) in GL5_NODES.iter().zip(&GL5_WEIGHTS) {
            let f = 0.5 * (t + 1.0);
            let x = (i as f64 + f) * h;
            sum += 0.5 * h * w * (a + f * (b - a)) * 8.0 * x.powi(7);
        }
    }
    sum
}

/// One row of the tables: `(E(mu_i, alpha_j) for every i, E_avg(alpha_j))`, `E_avg` the
/// [`interpolant_average`] of the row.
fn row(j: usize) -> ([f32; N], f32) {
    let alpha = row_alpha(j as f32 / (N - 1) as f32);
    let mut e = [0.0f32; N];
    for (i, v) in e.iter_mut().enumerate() {
        *v = albedo(column_mu(i as f32 / (N - 1) as f32), alpha) as f32;
    }
    (e, interpolant_average(&e) as f32)
}

/// The generated source file.
pub fn generate() -> String {
    let rows: Vec<([f32; N], f32)> = (0..N).into_par_iter().map(row).collect();
    let mut s = String::new();
    s += "//! Energy-compensation tables of the GGX conductor (Kulla & Conty 2017).\n";
    s += "//!\n";
    s += "//! GENERATED by `cargo xtask tables` (xtask/src/tables.rs), do not edit: a test there\n";
    s += "//! regenerates them and fails when this file differs.\n";
    s += "//!\n";
    s += "//! `E[j][i]` is the directional albedo `integral f |wi.z| dwi` of `GgxConductor` with\n";
    s += "//! `Fresnel::One` at `alpha = energy::row_alpha(j / (N - 1))` (quarter roots of alpha from\n";
    s += "//! `DELTA_ALPHA` to 1) and `mu = wo.z = energy::column_mu(i / (N - 1)) = (i / (N - 1))^4`\n";
    s += &format!("//! (the `mu = 0` column at `mu = {MU_MIN:e}`); `E_AVG[j] = 2 integral E(mu) mu dmu`.\n");
    s += &format!(
        "//! Quadrature: composite 5-point Gauss-Legendre, {} x {PANELS} panels over the VNDF sampler's\n",
        2 * PANELS
    );
    s += "//! unit square, summed in f64; `E_AVG` integrates the bilinear interpolant exactly.\n\n";
    s += "/// Number of nodes per axis of both tables.\n";
    s += &format!("pub const N: usize = {N};\n\n");
    s += "/// `E(mu, alpha)`: row `j` is `alpha = row_alpha(j / (N - 1))`, column `i` is `mu = (i / (N - 1))^4`.\n";
    s += "#[rustfmt::skip]\n";
    s += "pub const E: [[f32; N]; N] = [\n";
    for (e, _) in &rows {
        let vals: Vec<String> = e.iter().map(|v| format!("{v:?}")).collect();
        s += &format!("    [{}],\n", vals.join(", "));
    }
    s += "];\n\n";
    s += "/// `E_avg(alpha) = 2 integral_0^1 E(mu, alpha) mu dmu` at `alpha = row_alpha(j / (N - 1))`.\n";
    s += "#[rustfmt::skip]\n";
    s += "pub const E_AVG: [f32; N] = [\n";
    for (_, a) in &rows {
        s += &format!("    {a:?},\n");
    }
    s += "];\n";
    s
}

/// Where the tables live.
pub fn path() -> PathBuf {
    crate::render::workspace_root().join("crates/ggx-core/src/energy_tables.rs")
}

/// `cargo xtask tables [--check]`: writes both table files (this one and
/// [`crate::tables_dielectric`]'s), or with `--check` fails when a committed file differs from
/// a fresh generation.
pub fn run(args: &[String]) -> Result<(), String> {
    let check = match args {
        [] => false,
        [a] if a == "--check" => true,
        _ => return Err(format!("tables: unexpected arguments {args:?} (usage: tables [--check])")),
    };
    let files = [(path(), generate()), (crate::tables_dielectric::path(), crate::tables_dielectric::generate())];
    let mut stale = vec![];
    for (path, text) in files {
        if check {
            let old = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
            if old != text {
                stale.push(path.display().to_string());
            } else {
                eprintln!("{} is up to date", path.display());
            }
        } else {
            std::fs::write(&path, text).map_err(|e| format!("{}: {e}", path.display()))?;
            eprintln!("wrote {}", path.display());
        }
    }
    if stale.is_empty() { Ok(()) } else { Err(format!("out of date: {}; run `cargo xtask tables`", stale.join(", "))) }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Fails when the committed tables differ from a fresh generation (byte for byte, so every
    /// value bit for bit): someone edited the file by hand, or changed ggx-core's `eval`,
    /// `pdf` or sampler without rerunning `cargo xtask tables`.
    #[test]
    fn committed_tables_are_up_to_date() {
        let committed = std::fs::read_to_string(path()).expect("read energy_tables.rs");
        let fresh = generate();
        if committed != fresh {
            let diff = committed.lines().zip(fresh.lines()).position(|(a, b)| a != b);
            panic!("energy_tables.rs is out of date (first differing line {diff:?}): run `cargo xtask tables`");
        }
    }

    /// `E_avg` of the interpolant agrees with a fine quadrature of `E` over `mu`.
    #[test]
    fn average_matches_a_fine_quadrature() {
        let mut worst = 0.0f64;
        for j in [0usize, 3, 8, 12, 20, N - 1] {
            let (_, avg) = row(j);
            worst = worst.max((avg as f64 - average_albedo(row_alpha(j as f32 / (N - 1) as f32))).abs());
        }
        println!("worst |E_avg(interpolant) - E_avg(quadrature)| = {worst:.2e}");
        assert!(worst < 2e-4);
    }

    /// The quadrature is converged: doubling the panels moves no sampled `E` by more than 1e-4.
    #[test]
    fn quadrature_is_converged() {
        let near_mirror = [(0.003f32, 0.002f32), (1e-4, 0.0011), (1e-6, 0.001), (0.01, 0.005)];
        for (mu, alpha) in
            [(1.0f32, 0.01f32), (0.5, 0.25), (0.05, 1.0), (0.01, 0.5), (0.2, 0.0025)].into_iter().chain(near_mirror)
        {
            let (coarse, fine) = (albedo(mu, alpha), albedo_with(mu, alpha, 2 * PANELS));
            assert!((coarse - fine).abs() < 1e-4, "mu {mu} alpha {alpha}: {coarse} vs {fine}");
        }
    }
}
