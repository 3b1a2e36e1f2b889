//! Shared helpers of the ggx-core integration tests: the parameter grid of the issue,
//! directions from angles, an f64 hemisphere quadrature and a small deterministic RNG.
#![allow(dead_code)]

use ggx_core::{GltfMetalRough, Vec2, Vec3};
use rand_core::{Rng, SeedableRng};

/// Isotropic alphas of the test grid.
pub const ALPHAS: [f32; 5] = [0.05, 0.1, 0.3, 0.7, 1.0];
/// Incidence angles of the test grid, degrees.
pub const INCIDENCES_DEG: [f32; 5] = [0.0, 30.0, 60.0, 80.0, 89.0];

/// Every (alpha_x, alpha_y) of the grid: the isotropic ones plus two anisotropic pairs.
pub fn alpha_pairs() -> Vec<(f32, f32)> {
    let mut v: Vec<(f32, f32)> = ALPHAS.iter().map(|&a| (a, a)).collect();
    v.push((0.05, 0.5));
    v.push((0.5, 0.05));
    v
}

/// Unit direction at polar angle `theta` (radians) and azimuth `phi`.
pub fn dir(theta: f64, phi: f64) -> Vec3 {
    Vec3::new((theta.sin() * phi.cos()) as f32, (theta.sin() * phi.sin()) as f32, theta.cos() as f32)
}

/// View direction for an incidence in degrees; the azimuth is off-axis (0.7 rad) so that
/// anisotropic lobes are tested away from their symmetry planes.
pub fn wo_at(incidence_deg: f32) -> Vec3 {
    dir((incidence_deg as f64).to_radians(), 0.7)
}

/// Integral of `f(w)` over the upper hemisphere in f64, with nodes concentrated near the
/// pole: `theta = (pi / 2) x^2`, midpoint rule in `x` (n_theta nodes) and `phi` (n_phi).
pub fn hemisphere_integral(n_theta: usize, n_phi: usize, f: impl Fn(Vec3) -> f64) -> f64 {
    let (pi, tau) = (std::f64::consts::PI, std::f64::consts::TAU);
    let mut total = 0.0;
    for i in 0..n_theta {
        let x = (i as f64 + 0.5) / n_theta as f64;
        let theta = 0.5 * pi * x * x;
        let jac = pi * x / n_theta as f64 * theta.sin(); // dtheta/dx dx * sin(theta)
        let mut row = 0.0;
        for j in 0..n_phi {
            let phi = (j as f64 + 0.5) / n_phi as f64 * tau;
            row += f(dir(theta, phi));
        }
        total += row * jac * tau / n_phi as f64;
    }
    total
}

/// Deterministic uniform pairs in [0, 1)^2.
pub struct Uniforms(rand_pcg::Pcg64);

impl Uniforms {
    /// Generator for a seed.
    pub fn new(seed: u64) -> Self {
        Self(rand_pcg::Pcg64::seed_from_u64(seed))
    }
    /// Next pair, 24-bit resolution like the sample sequences.
    pub fn next(&mut self) -> Vec2 {
        let mut f = || (self.0.next_u32() >> 8) as f32 * (1.0 / 16_777_216.0);
        Vec2::new(f(), f())
    }
}

/// `v` in [0, 1) mapped so that the edges are over-represented: below 0.15 -> 0, above 0.85 -> 1,
/// linear in between.
pub fn edge(v: f32) -> f32 {
    if v < 0.15 {
        0.0
    } else if v > 0.85 {
        1.0
    } else {
        (v - 0.15) / 0.7
    }
}

/// A random glTF metal-rough material: any base colour, metallic and specular weight in [0, 1]
/// with the edges 0 and 1 over-represented ([`edge`]), roughness from mirror to 1 (anisotropic
/// half of the time), ior in [1, 3] or 0, specular colour up to 2.
pub fn random_metal_rough(u: &mut Uniforms) -> GltfMetalRough {
    let mut x = || u.next().x;
    let base = Vec3::new(edge(x()), x(), x());
    let metallic = edge(x());
    let sw = edge(x());
    let r = edge(x());
    let (ax, ay) = if x() < 0.5 { (r * r, r * r) } else { (r * r, x() * x()) };
    let ior = if x() < 0.1 { 0.0 } else { 1.0 + 2.0 * x() };
    GltfMetalRough::new(base, metallic, ax, ay, ior, Vec3::new(2.0 * x(), 2.0 * x(), x()), sw)
}

/// proptest strategies for hostile inputs, shared by the glTF BRDF tests (`metal_rough.rs`,
/// `clearcoat.rs`).
pub mod hostile {
    use ggx_core::math::ONE_MINUS_EPSILON;
    use ggx_core::{Vec2, Vec3, warp};
    use proptest::prelude::*;

    /// Any bits, the unit ranges, and the special values (NaN, infinities, zeros, subnormals,
    /// `1 - ulp`, the delta threshold's neighbours).
    pub fn any_f32() -> impl Strategy<Value = f32> {
        prop_oneof![
            3 => proptest::num::f32::ANY,
            2 => -1.0f32..=1.0,
            2 => 0.0f32..=3.0,
            2 => prop::sample::select(vec![
                0.0, -0.0, 1.0, -1.0, ONE_MINUS_EPSILON, -ONE_MINUS_EPSILON, 1e-45, -1e-45, f32::MIN_POSITIVE,
                f32::NAN, f32::INFINITY, f32::NEG_INFINITY, f32::MAX, f32::MIN, 1e-7, 1e-20, 0.5, 1e-4, 1e-3,
                9.99e-4, 1.5, 0.05, 0.95,
            ]),
        ]
    }

    /// Three [`any_f32`].
    pub fn vec3() -> impl Strategy<Value = Vec3> {
        (any_f32(), any_f32(), any_f32()).prop_map(|(x, y, z)| Vec3::new(x, y, z))
    }

    /// A direction: any bits, uniform on the hemisphere, or grazing down to cos 1e-7.
    pub fn direction() -> impl Strategy<Value = Vec3> {
        prop_oneof![
            3 => vec3(),
            3 => (0.0f32..1.0, 0.0f32..1.0).prop_map(|(a, b)| warp::sample_uniform_hemisphere(Vec2::new(a, b))),
            2 => (-7.0f32..0.0, 0.0f32..6.3).prop_map(|(e, phi)| {
                let z = 10f32.powf(e);
                let r = (1.0 - z * z).sqrt();
                Vec3::new(r * phi.cos(), r * phi.sin(), z)
            }),
        ]
    }

    /// Finite and not negative.
    pub fn ok(x: f32) -> bool {
        x.is_finite() && x >= 0.0
    }

    /// [`ok`] in every component.
    pub fn ok3(v: Vec3) -> bool {
        ok(v.x) && ok(v.y) && ok(v.z)
    }
}
