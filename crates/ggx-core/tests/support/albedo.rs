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
