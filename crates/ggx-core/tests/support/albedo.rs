//! Directional albedo of a reflection-only BRDF by quadrature over the half vector, shared by
//! the glTF BRDF tests (`metal_rough.rs`, `clearcoat.rs`): an f64 reference formula at f64
//! nodes beside a ggx-core `eval` at the same nodes rounded to f32.

use ggx_core::{Vec3, reflect};

/// `a . b` in f64.
pub fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// `v / |v|` in f64.
pub fn normalize(v: [f64; 3]) -> [f64; 3] {
    let l = dot(v, v).sqrt();
    v.map(|x| x / l)
}

/// The unit direction at polar angle `theta`, azimuth `phi`, in f64.
pub fn dir64(theta: f64, phi: f64) -> [f64; 3] {
    [theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos()]
}

/// Nodes of the half-vector quadrature.
pub const N_THETA: usize = 1500;
/// Azimuthal nodes of the half-vector quadrature.
pub const N_PHI: usize = 512;

/// `E(wo) = integral f(wo, wi) wi.z dwi` two ways, over the half vector (`wi = reflect(wo, wm)`,
/// `E = integral f wi.z 4 (wo.wm) dwm` over `wo.wm > 0`, every `wi` above the horizon once;
/// nodes `theta = (pi / 2) x^2`, midpoint rule in `x` and `phi`): (a) `f64_f` (`f` without the
/// cosine) at the f64 nodes around `wo64`, (b) `eval32` (`f |wi.z|`, a ggx-core `eval`) at the
/// same nodes rounded to f32 around `wo`.
pub fn albedo_quadrature(
    wo64: [f64; 3],
    wo: Vec3,
    f64_f: impl Fn([f64; 3], [f64; 3]) -> [f64; 3],
    eval32: impl Fn(Vec3, Vec3) -> Vec3,
) -> ([f64; 3], [f64; 3]) {
    let (pi, tau) = (std::f64::consts::PI, std::f64::consts::TAU);
    let (mut a, mut b) = ([0.0f64; 3], [0.0f64; 3]);
    for i in 0..N_THETA {
        let x = (i as f64 + 0.5) / N_THETA as f64;
        let theta = 0.5 * pi * x * x;
        let weight = pi * x / N_THETA as f64 * theta.sin() * tau / N_PHI as f64;
        for j in 0..N_PHI {
            let phi = (j as f64 + 0.5) / N_PHI as f64 * tau;
            let wm64 = dir64(theta, phi);
            let c = dot(wo64, wm64);
            if c > 0.0 {
                let wi64 = std::array::from_fn(|k| 2.0 * c * wm64[k] - wo64[k]);
                if wi64[2] > 0.0 {
                    let f = f64_f(wo64, wi64);
                    for k in 0..3 {
                        a[k] += f[k] * wi64[2] * 4.0 * c * weight;
                    }
                }
            }
            let wm = Vec3::new((theta.sin() * phi.cos()) as f32, (theta.sin() * phi.sin()) as f32, theta.cos() as f32);
            let c = wo.dot(wm);
            if c > 0.0 {
                let e = eval32(wo, reflect(wo, wm));
                for k in 0..3 {
                    b[k] += e[k] as f64 * 4.0 * c as f64 * weight;
                }
            }
        }
    }
    (a, b)
}

/// Mean and standard error of each channel of `n` sample weights drawn by `draw` (a Monte
/// Carlo estimate of the directional albedo).
pub fn mean_and_error(n: usize, mut draw: impl FnMut() -> Vec3) -> [(f64, f64); 3] {
    let (mut sum, mut sum2) = ([0.0f64; 3], [0.0f64; 3]);
    for _ in 0..n {
        let w = draw();
        for k in 0..3 {
            sum[k] += w[k] as f64;
            sum2[k] += (w[k] as f64).powi(2);
        }
    }
    std::array::from_fn(|k| {
        let mean = sum[k] / n as f64;
        (mean, ((sum2[k] / n as f64 - mean * mean).max(0.0) / n as f64).sqrt())
    })
}

/// The albedo checks of a material grid, collected over every (material, view): (a) the f64
/// quadrature against (b) the f32 `eval` at the same nodes, `E <= 1` where the model conserves
/// energy, and (c) each technique's Monte Carlo estimate against (a) by a z-test at the Sidak
/// threshold over `tests` comparisons; [`AlbedoChecks::finish`] prints the worst values and
/// fails with every failure.
pub struct AlbedoChecks {
    name: String,
    tests: usize,
    significance: f64,
    worst_f32: f64,
    worst_z: f64,
    max_albedo: f64,
    failures: Vec<String>,
}

impl AlbedoChecks {
    /// Checks named `name` over `tests` Monte Carlo comparisons (materials x views x channels x
    /// techniques).
    pub fn new(name: &str, tests: usize) -> Self {
        let significance = super::chi2::sidak_significance(0.01, tests);
        let failures = Vec::new();
        Self { name: name.to_owned(), tests, significance, worst_f32: 0.0, worst_z: 0.0, max_albedo: 0.0, failures }
    }

    /// (a) `a` against (b) `b` within `tolerance` per channel, and `a <= 1 + 1e-4` when `bounded`;
    /// `line` names the material and view.
    pub fn quadrature(&mut self, line: &str, a: [f64; 3], b: [f64; 3], tolerance: f64, bounded: bool) {
        for k in 0..3 {
            let d = (a[k] - b[k]).abs();
            self.worst_f32 = self.worst_f32.max(d);
            self.max_albedo = self.max_albedo.max(a[k]);
            if d > tolerance {
                self.failures.push(format!("{line}: channel {k} f64 {} vs f32 eval {} (diff {d:.2e})", a[k], b[k]));
            }
            if bounded && a[k] > 1.0 + 1e-4 {
                self.failures.push(format!("{line}: channel {k} albedo {} above one", a[k]));
            }
        }
    }

    /// (c) the estimate `mc` of `technique` against `a`, forgiving `allowance` before dividing by
    /// the standard error.
    pub fn monte_carlo(&mut self, line: &str, technique: &str, mc: [(f64, f64); 3], a: [f64; 3], allowance: f64) {
        for k in 0..3 {
            let (mean, sigma) = mc[k];
            let z = ((mean - a[k]).abs() - allowance).max(0.0) / sigma;
            let z = if z.is_nan() { 0.0 } else { z };
            self.worst_z = self.worst_z.max(z);
            if super::chi2::chi2_survival(z * z, 1.0) < self.significance {
                self.failures.push(format!(
                    "{line}: {technique} channel {k} Monte Carlo {mean} +- {sigma:.2e} vs {} (z = {z:.2})",
                    a[k]
                ));
            }
        }
    }

    /// Prints the summary and fails with every failure.
    pub fn finish(self) {
        println!(
            "{}: {} comparisons, worst |f64 - f32| {:.2e}, worst z {:.2}, largest albedo {:.5}",
            self.name, self.tests, self.worst_f32, self.worst_z, self.max_albedo
        );
        assert!(self.failures.is_empty(), "{}", self.failures.join("\n"));
    }
}
