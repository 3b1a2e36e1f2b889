//! `GltfMetalRough`, the glTF 2.0 metallic-roughness BRDF, against the specification.
//!
//! * Albedo `E(wo) = integral f |wi.z| dwi` three ways: (a) an f64 quadrature of the spec's
//!   formulas written here independently (anisotropic `D`, Smith `Lambda`, height-correlated
//!   `G2`, Schlick, `fresnel_mix`, `mix`), (b) the same quadrature of `GltfMetalRough::eval`,
//!   (c) the mean of `sample` weights. (a) and (b) agree to [`QUADRATURE_F32_TOL`]; (c) lies
//!   within a Sidak-corrected two-sided z-test at significance 0.01 of (a). Quadrature over the
//!   half vector (`dwi = 4 |wo.wm| dwm`, nodes crowded at the pole where the lobe sits),
//!   [`N_THETA`] x [`N_PHI`] nodes.
//! * White furnace: metallic 1 with a white base is the single-scattering GGX lobe with `F = 1`
//!   bit for bit, its albedo `E(mu) < 1`. No metal's albedo exceeds one, nor any material's at
//!   normal incidence; the spec's dielectric does exceed one at oblique views (its
//!   `fresnel_mix` is not energy conserving), in the f64 reference as in `eval`.
//! * Contract: `weight == eval / pdf` and `pdf == pdf()` of every sample; the pdf integrates to
//!   the rate at which `sample` returns `Some`; delta samples carry `p_s` and `F / p_s`.
//! * Chi-square of the mixture sampler (support/chi2.rs).
//! * Any f32 in every constructor argument, field and direction: no panic, no NaN.

mod support;
mod util;

use ggx_core::metal_rough::{DEFAULT_IOR, clamp_ior, dielectric_f0};
use ggx_core::{
    Bxdf, BxdfFlags, DELTA_ALPHA, Fresnel, GgxConductor, GltfMetalRough, Sampling, TransportMode, Vec2, Vec3, warp,
};
use proptest::prelude::*;
use proptest::test_runner::RngSeed;
use support::albedo::{AlbedoChecks, dir64, dot, mean_and_error, normalize};
use support::chi2::{Chi2Config, chi2_test, integrate_cells, sidak_significance};
use util::hostile::{any_f32, direction, ok, ok3, vec3};
use util::{Uniforms, random_metal_rough, wo_at};

// ---------------------------------------------------------------------------------------------
// The specification in f64
// ---------------------------------------------------------------------------------------------

/// A glTF material: core parameters plus `KHR_materials_ior` and `KHR_materials_specular`.
#[derive(Clone, Copy, Debug)]
struct Params {
    base: [f64; 3],
    metallic: f64,
    /// glTF roughness along x and y (`alpha = roughness^2`).
    roughness: (f64, f64),
    ior: f64,
    specular_color: [f64; 3],
    specular_weight: f64,
}

impl Params {
    fn core(base: [f64; 3], metallic: f64, roughness: f64) -> Self {
        Params {
            base,
            metallic,
            roughness: (roughness, roughness),
            ior: 1.5,
            specular_color: [1.0; 3],
            specular_weight: 1.0,
        }
    }

    /// The alphas as ggx-core receives them (f32 `roughness^2`), in f64.
    fn alphas(&self) -> (f64, f64) {
        let a = |r: f64| ((r as f32) * (r as f32)) as f64;
        (a(self.roughness.0), a(self.roughness.1))
    }

    fn brdf(&self) -> GltfMetalRough {
        let v = |c: [f64; 3]| Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32);
        let (ax, ay) = self.alphas();
        GltfMetalRough::new(
            v(self.base),
            self.metallic as f32,
            ax as f32,
            ay as f32,
            self.ior as f32,
            v(self.specular_color),
            self.specular_weight as f32,
        )
    }

    fn is_delta(&self) -> bool {
        let (ax, ay) = self.alphas();
        ax.max(ay) < DELTA_ALPHA as f64
    }

    /// `f0 = min(((ior - 1) / (ior + 1))^2 specular_color, 1)` (KHR_materials_specular).
    fn f0(&self) -> [f64; 3] {
        let r = (self.ior - 1.0) / (self.ior + 1.0);
        self.specular_color.map(|c| (r * r * c).min(1.0))
    }

    /// `D(m) = 1 / (pi ax ay (x^2/ax^2 + y^2/ay^2 + z^2)^2)` (Walter et al. 2007, anisotropic).
    fn d(&self, m: [f64; 3]) -> f64 {
        if m[2] <= 0.0 {
            return 0.0;
        }
        let (ax, ay) = self.alphas();
        let t = (m[0] / ax).powi(2) + (m[1] / ay).powi(2) + m[2] * m[2];
        1.0 / (std::f64::consts::PI * ax * ay * t * t)
    }

    /// `Lambda(w) = (sqrt(1 + (ax^2 x^2 + ay^2 y^2) / z^2) - 1) / 2` (Heitz 2014 eq. 86).
    fn lambda(&self, w: [f64; 3]) -> f64 {
        let (ax, ay) = self.alphas();
        let q = ((ax * w[0]).powi(2) + (ay * w[1]).powi(2)) / (w[2] * w[2]);
        ((1.0 + q).sqrt() - 1.0) / 2.0
    }

    /// The specular lobe's and the diffuse lobe's weights at `cos = |wo.h|` (glTF 2.0
    /// Appendix B: `fresnel_mix` with KHR_materials_specular, `conductor_fresnel`, `mix`).
    fn weights(&self, cos: f64) -> ([f64; 3], f64) {
        let x = (1.0 - cos).powi(5);
        let f0 = self.f0();
        let fr_d = f0.map(|f| f + (1.0 - f) * x);
        let fr_max = fr_d.iter().copied().fold(0.0, f64::max);
        let m = self.metallic;
        let sw = self.specular_weight;
        let spec = std::array::from_fn(|k| (1.0 - m) * sw * fr_d[k] + m * (self.base[k] + (1.0 - self.base[k]) * x));
        (spec, (1.0 - m) * (1.0 - sw * fr_max))
    }

    /// `f(wo, wi)` (without the cosine) for directions above the horizon; the specular lobe
    /// left out when it is a mirror.
    fn f(&self, wo: [f64; 3], wi: [f64; 3]) -> [f64; 3] {
        let h = normalize([wo[0] + wi[0], wo[1] + wi[1], wo[2] + wi[2]]);
        let (spec, diffuse) = self.weights(dot(wo, h).abs());
        let specular_brdf = if self.is_delta() {
            0.0
        } else {
            self.d(h) / (1.0 + self.lambda(wo) + self.lambda(wi)) / (4.0 * wo[2] * wi[2])
        };
        std::array::from_fn(|k| spec[k] * specular_brdf + diffuse * self.base[k] / std::f64::consts::PI)
    }
}

/// Largest `|(a) - (b)|` (absolute, per channel; albedos are at most about 1): what the f32
/// evaluation at f32-rounded nodes may add to the f64 reference on the same nodes.
const QUADRATURE_F32_TOL: f64 = 2e-5;

/// The view directions of the albedo tests (degrees; azimuth 0.7 rad, `util::wo_at`).
const VIEWS_DEG: [f64; 4] = [0.0, 45.0, 75.0, 88.0];

/// Directional albedo by quadrature over the half vector: (a) the f64 spec formulas at f64
/// nodes, (b) `GltfMetalRough::eval` at the same nodes rounded to f32, `wi = reflect(wo, wm)`;
/// `E = integral f(wo, wi) wi.z 4 (wo.wm) dwm` over `wo.wm > 0` (every `wi` above the horizon
/// once). Nodes: `theta = (pi / 2) x^2`, midpoint rule in `x` and `phi`, as `util::hemisphere_integral`.
/// The mirror lobe of a delta material is added in closed form (`specular_fresnel(wo.z)`,
/// `G2 = D = 1` in the limit) to both.
fn albedo_quadrature(p: &Params, inc_deg: f64) -> ([f64; 3], [f64; 3]) {
    let brdf = p.brdf();
    let wo = wo_at(inc_deg as f32);
    let wo64 = dir64(inc_deg.to_radians(), 0.7);
    let (mut a, mut b) = support::albedo::albedo_quadrature(wo64, wo, |wo, wi| p.f(wo, wi), |wo, wi| brdf.eval(wo, wi));
    if p.is_delta() {
        let (spec, _) = p.weights(wo64[2]);
        let s = brdf.specular_fresnel(wo.z);
        for k in 0..3 {
            a[k] += spec[k];
            b[k] += s[k] as f64;
        }
    }
    (a, b)
}

/// Mean and standard error of the sample weights (per channel, `None` as 0) over `n` draws.
fn albedo_monte_carlo(brdf: &GltfMetalRough, wo: Vec3, sampling: Sampling, n: usize, seed: u64) -> [(f64, f64); 3] {
    let mut u = Uniforms::new(seed);
    mean_and_error(n, || {
        let uv = u.next();
        let u_lobe = u.next().x;
        brdf.sample(wo, uv, u_lobe, sampling).map_or(Vec3::ZERO, |s| s.weight)
    })
}

const ORANGE: [f64; 3] = [0.8, 0.5, 0.2];
const WHITE: [f64; 3] = [1.0; 3];
const ROUGHNESS: [f64; 6] = [0.05, 0.1, 0.3, 0.5, 0.8, 1.0];
/// Samples per Monte Carlo estimate.
const MC_SAMPLES: usize = 200_000;
/// What the z-test forgives before dividing by the sample's standard error, which misses two
/// things: the f32 rounding of the weights (a few ulp of an albedo of at most about 2; a
/// mirror's weights are all alike, sigma 0) and events too rare to be drawn at all. A lobe with
/// a tiny alpha loses about `alpha^2` of its energy below the horizon (at normal incidence, the
/// normals tilted beyond 45 degrees): a probability near 1 / MC_SAMPLES, where the sample
/// variance of runs without such an event is far below the true one. Events of probability
/// below 3 / MC_SAMPLES go unseen in 95 % of runs (rule of three); their weight is at most 2.
const MC_ALLOWANCE: f64 = 1e-6 + 3.0 * 2.0 / MC_SAMPLES as f64;

/// Checks (a) ~ (b), (c) ~ (a) for every material at every view in [`VIEWS_DEG`], and
/// `E <= 1` for metals and at normal incidence, with the Sidak threshold over every (material, view, channel, technique).
fn check_albedos(name: &str, materials: &[Params], samplings: &[Sampling]) {
    let mut checks = AlbedoChecks::new(name, materials.len() * VIEWS_DEG.len() * 3 * samplings.len());
    for (i, p) in materials.iter().enumerate() {
        let brdf = p.brdf();
        for (j, inc) in VIEWS_DEG.into_iter().enumerate() {
            let (a, b) = albedo_quadrature(p, inc);
            let wo = wo_at(inc as f32);
            let mut line = format!(
                "{name} base {:?} m {} r {:?} ior {} sc {:?} sw {} p_s {:.3} {inc:>2} deg: E = [{:.5}, {:.5}, {:.5}]",
                p.base,
                p.metallic,
                p.roughness,
                p.ior,
                p.specular_color,
                p.specular_weight,
                brdf.specular_probability(),
                a[0],
                a[1],
                a[2]
            );
            // The spec's metal never gains energy; its dielectric does at oblique views (see
            // `the_spec_dielectric_gains_energy_at_grazing_views`), never at normal incidence.
            checks.quadrature(&line, a, b, QUADRATURE_F32_TOL, p.metallic == 1.0 || inc == 0.0);
            for (t, &sampling) in samplings.iter().enumerate() {
                let seed = ((i * 16 + j) * 8 + t) as u64 ^ 0x6c74_6600;
                let mc = albedo_monte_carlo(&brdf, wo, sampling, MC_SAMPLES, seed);
                checks.monte_carlo(&line, sampling.name(), mc, a, MC_ALLOWANCE);
                line += &format!("  {}: {:.5}", sampling.name(), mc[0].0);
            }
            println!("{line}");
        }
    }
    checks.finish();
}

fn core_materials(metallic: f64) -> Vec<Params> {
    ROUGHNESS.iter().flat_map(|&r| [ORANGE, WHITE].map(|base| Params::core(base, metallic, r))).collect()
}

#[test]
fn albedo_matches_the_spec_dielectric() {
    check_albedos("metallic 0", &core_materials(0.0), &[Sampling::Vndf]);
}

#[test]
fn albedo_matches_the_spec_half_metal() {
    check_albedos("metallic 0.5", &core_materials(0.5), &[Sampling::Vndf]);
}

#[test]
fn albedo_matches_the_spec_metal() {
    check_albedos("metallic 1", &core_materials(1.0), &[Sampling::Vndf]);
}

/// KHR_materials_ior and KHR_materials_specular (coloured, above-one and zero specular colours,
/// weights, ior 1.0, 1.33, 2.4 and 0), anisotropic lobes, every technique.
#[test]
fn albedo_matches_the_spec_with_extensions_and_every_technique() {
    let p = |base, metallic, roughness, ior, specular_color, specular_weight| Params {
        base,
        metallic,
        roughness,
        ior,
        specular_color,
        specular_weight,
    };
    let materials = [
        p(ORANGE, 0.0, (0.4, 0.4), 1.33, [1.0, 0.5, 2.0], 0.7),
        p([0.2, 0.9, 0.4], 0.3, (0.2, 0.7), 2.4, [1.0; 3], 1.0),
        p(WHITE, 0.0, (0.7, 0.25), 1.0, [1.0; 3], 1.0),
        p(ORANGE, 0.0, (0.3, 0.3), 0.0, [1.0, 0.8, 0.6], 0.5),
        p(WHITE, 0.0, (0.5, 0.5), 1.5, [0.0; 3], 0.0),
        p([0.9, 0.6, 0.3], 0.8, (0.15, 0.15), 1.5, [6.0, 1.0, 0.0], 0.4),
    ];
    check_albedos("extensions", &materials, &Sampling::ALL);
}

/// Below `DELTA_ALPHA` the specular lobe is a mirror: `eval` keeps the diffuse lobe, `sample`
/// returns the mirror with weight `specular_fresnel(wo.z) / p_s`, and the albedo is the
/// diffuse quadrature plus the mirror's reflectance.
#[test]
fn albedo_with_a_mirror_specular_lobe() {
    let materials: Vec<Params> = [0.0, 0.02, 0.03]
        .into_iter()
        .flat_map(|r| [(ORANGE, 0.0), (WHITE, 0.5), ([0.3, 0.6, 0.9], 1.0)].map(|(b, m)| Params::core(b, m, r)))
        .collect();
    for p in &materials {
        assert!(p.is_delta() && p.brdf().is_delta(), "{p:?}");
    }
    check_albedos("mirror", &materials, &[Sampling::Vndf, Sampling::Cosine]);
}

/// Metallic 1 with a white base is GgxConductor with `F = 1`, bit for bit; its albedo is the
/// single-scattering `E(mu) < 1` (ggx-core's table within its interpolation error), and it
/// loses more energy as roughness grows.
#[test]
fn white_metal_is_the_single_scattering_furnace() {
    for r in [0.05f32, 0.1, 0.3, 0.5, 0.8, 1.0] {
        let alpha = r * r;
        let metal = GltfMetalRough::core(Vec3::ONE, 1.0, alpha);
        let conductor = GgxConductor::isotropic(alpha, Fresnel::One);
        assert_eq!(metal.specular_probability(), 1.0);
        let mut u = Uniforms::new(r.to_bits() as u64);
        for _ in 0..20_000 {
            let wo = warp::sample_cosine_hemisphere(u.next());
            let wi = warp::sample_uniform_hemisphere(u.next());
            assert_eq!(metal.eval(wo, wi), conductor.eval(wo, wi), "r {r} wo {wo} wi {wi}");
            for s in Sampling::ALL {
                assert_eq!(metal.pdf(wo, wi, s), conductor.pdf(wo, wi, s));
            }
        }
        let mut last = 1.0f64;
        for inc in [0.0, 45.0, 75.0, 88.0] {
            let (a, b) = albedo_quadrature(&Params::core(WHITE, 1.0, r as f64), inc);
            let mu = (inc as f32).to_radians().cos();
            let table = ggx_core::energy::albedo(mu, alpha) as f64;
            println!("roughness {r} {inc:>2} deg: E = {:.6} (f32 eval {:.6}), table {table:.6}", a[0], b[0]);
            assert!(a[0] < 1.0 && a[0] > 0.3, "roughness {r} {inc} deg: {}", a[0]);
            assert!(a == [a[0]; 3] && (a[0] - b[0]).abs() < QUADRATURE_F32_TOL);
            assert!((a[0] - table).abs() < 5e-3, "roughness {r} {inc} deg: quadrature {} vs table {table}", a[0]);
            if inc == 0.0 {
                assert!(a[0] <= last);
                last = a[0];
            }
        }
    }
}

/// The spec's `fresnel_mix` weighs the diffuse lobe by `1 - F(|wo.h|)` at the half vector of
/// each diffuse direction (far from grazing, so about `1 - f0`), while the specular lobe around
/// the mirror direction gets `F(|wo.h|)` with `|wo.h| ~ wo.z` (near 1 at grazing views): at
/// oblique views the two add up to more than one. Not an implementation error: the f64
/// reference of the formulas shows the same albedo, the metal (no `fresnel_mix`) does not.
#[test]
fn the_spec_dielectric_gains_energy_at_grazing_views() {
    for (roughness, inc, at_least) in [(0.3, 88.0, 1.3), (0.5, 75.0, 1.05), (0.1, 45.0, 1.0001), (0.3, 0.0, 0.0)] {
        let (a, b) = albedo_quadrature(&Params::core(WHITE, 0.0, roughness), inc);
        let (metal, _) = albedo_quadrature(&Params::core(WHITE, 1.0, roughness), inc);
        println!(
            "white dielectric roughness {roughness} at {inc} deg: E = {:.5} (eval {:.5}), metal {:.5}",
            a[0], b[0], metal[0]
        );
        assert!((a[0] - b[0]).abs() < QUADRATURE_F32_TOL);
        assert!(metal[0] < 1.0);
        if inc == 0.0 {
            assert!(a[0] < 1.0, "{}", a[0]);
        } else {
            assert!(a[0] > at_least, "{}", a[0]);
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Contract
// ---------------------------------------------------------------------------------------------

/// A random view: cosine-weighted, a tenth of the time grazing (cos down to 1e-6).
fn random_wo(u: &mut Uniforms) -> Vec3 {
    let v = u.next();
    if v.x < 0.1 {
        let z = 10f32.powf(-6.0 * u.next().x);
        let r = (1.0 - z * z).sqrt();
        Vec3::new(r * (6.3 * v.y).cos(), r * (6.3 * v.y).sin(), z)
    } else {
        warp::sample_cosine_hemisphere(u.next())
    }
}

fn close(a: f32, b: f32, rel: f32) -> bool {
    (a - b).abs() <= rel * a.abs().max(b.abs()) + 1e-30
}

#[test]
fn samples_agree_with_eval_and_pdf() {
    let mut u = Uniforms::new(0x6d72);
    let (mut delta, mut total) = (0usize, 0usize);
    let mut worst = 0.0f32;
    for _ in 0..2_000 {
        let brdf = random_metal_rough(&mut u);
        let p = brdf.specular_probability();
        assert!((0.0..=1.0).contains(&p));
        for _ in 0..20 {
            let wo = random_wo(&mut u);
            for s in Sampling::ALL {
                let (uv, u_lobe) = (u.next(), u.next().x);
                let Some(bs) = brdf.sample(wo, uv, u_lobe, s) else { continue };
                total += 1;
                assert!((bs.wi.length() - 1.0).abs() < 1e-5 && bs.wi.z > 0.0, "{bs:?}");
                assert!(bs.weight.is_finite() && bs.weight.min_element() >= 0.0, "{bs:?}");
                // The same call through the trait.
                let t = Bxdf::sample(&brdf, wo, uv, u_lobe, s, TransportMode::Importance);
                assert_eq!(t, Some(bs));
                if bs.is_delta {
                    delta += 1;
                    assert!(brdf.is_delta() && u_lobe < p, "{brdf:?}");
                    assert_eq!(bs.wi, Vec3::new(-wo.x, -wo.y, wo.z));
                    assert_eq!(bs.pdf, p);
                    assert_eq!(bs.weight, brdf.specular_fresnel(wo.z) / p);
                    assert!(bs.mis_pdf().is_infinite());
                    continue;
                }
                let pdf = brdf.pdf(wo, bs.wi, s);
                assert!(close(bs.pdf, pdf, 1e-6), "pdf {} vs pdf() {pdf}", bs.pdf);
                let f = brdf.eval(wo, bs.wi);
                for k in 0..3 {
                    let expected = f[k] / pdf;
                    let err = (bs.weight[k] - expected).abs() / expected.max(1e-20);
                    worst = worst.max(err);
                    assert!(close(bs.weight[k], expected, 1e-5), "{brdf:?} {s:?} wo {wo} weight {bs:?} vs {expected}");
                }
            }
        }
    }
    println!("{total} samples ({delta} delta), worst relative |weight - eval / pdf| {worst:.2e}");
    assert!(delta > 1000 && total > 200_000);
}

/// The density integrates (adaptively over the chi-square test's cells, to 1e-7) to the
/// probability that `sample` returns a non-delta `Some`: the missing mass is the specular
/// sampler's directions below the horizon plus the mirror lobe's `p_s`. Within 4 binomial
/// sigma plus 1e-5; at most 1 + 1e-5.
#[test]
fn pdf_integrates_to_the_rate_of_returned_samples() {
    let materials = [
        Params::core(ORANGE, 0.0, 0.5),
        Params::core(ORANGE, 0.5, 1.0),
        Params::core(WHITE, 1.0, 0.3),
        Params::core(ORANGE, 0.0, 0.02),
        Params { specular_weight: 0.0, ..Params::core(ORANGE, 0.0, 0.5) },
        Params { roughness: (0.9, 0.2), ..Params::core(ORANGE, 0.3, 0.5) },
    ];
    let n = 400_000;
    for (i, p) in materials.iter().enumerate() {
        let brdf = p.brdf();
        for inc in [0.0f32, 60.0, 85.0] {
            let wo = wo_at(inc);
            for s in [Sampling::Vndf, Sampling::Ndf, Sampling::Bounded, Sampling::Uniform] {
                let integral = integrate_cells(51, 101, |wi| brdf.pdf(wo, wi, s) as f64).total();
                let mut u = Uniforms::new(i as u64 * 64 + inc as u64 + s as u64 * 4096);
                let kept =
                    (0..n).filter(|_| brdf.sample(wo, u.next(), u.next().x, s).is_some_and(|b| !b.is_delta)).count();
                let rate = kept as f64 / n as f64;
                let sigma = (rate * (1.0 - rate) / n as f64).sqrt();
                println!("{p:?} {inc} deg {s:?}: integral {integral:.5}, rate {rate:.5} +- {sigma:.1e}");
                assert!(integral <= 1.0 + 1e-5, "{integral}");
                assert!((integral - rate).abs() <= 4.0 * sigma + 1e-5, "{p:?} {inc} {s:?}: {integral} vs {rate}");
                if p.specular_weight == 0.0 && p.metallic == 0.0 {
                    assert!((integral - 1.0).abs() < 1e-5, "cosine lobe alone: {integral}");
                }
            }
        }
    }
}

#[test]
fn constructor_defaults_clamps_and_lobe_probability() {
    // Defaults: f0 = 0.04.
    let core = GltfMetalRough::core(Vec3::splat(0.5), 0.0, 0.25);
    for f in core.f0 {
        assert!((f - 0.04).abs() < 1e-7, "{f}");
    }
    assert_eq!(core.specular_weight, 1.0);
    assert_eq!(dielectric_f0(DEFAULT_IOR, Vec3::ONE), dielectric_f0(f32::NAN, Vec3::splat(f32::INFINITY)));
    // KHR_materials_ior: 0 means f0 = 1 (times the specular colour); below 1 clamps to 1.
    assert_eq!(dielectric_f0(0.0, Vec3::new(1.0, 0.5, 3.0)), Vec3::new(1.0, 0.5, 1.0));
    assert_eq!(dielectric_f0(0.5, Vec3::ONE), Vec3::ZERO);
    assert_eq!(clamp_ior(-0.0), 0.0);
    assert_eq!(clamp_ior(-2.0), 1.0);
    assert_eq!(clamp_ior(f32::NEG_INFINITY), DEFAULT_IOR);
    assert_eq!(clamp_ior(1e30), ggx_core::ETA_MAX);
    assert_eq!(
        dielectric_f0(1.5, Vec3::new(-1.0, 100.0, f32::NAN)),
        Vec3::new(0.0, 1.0, dielectric_f0(1.5, Vec3::ONE).z)
    );
    // Sanitized inputs.
    let odd = GltfMetalRough::new(
        Vec3::new(f32::NAN, -1.0, 7.0),
        f32::INFINITY,
        f32::NAN,
        2.0,
        f32::NAN,
        Vec3::splat(f32::NAN),
        -3.0,
    );
    assert_eq!(odd.base_color, [1.0, 0.0, 1.0]);
    assert_eq!((odd.metallic, odd.specular_weight), (1.0, 0.0));
    assert_eq!((odd.distribution.alpha_x, odd.distribution.alpha_y), (ggx_core::ALPHA_MIN, 1.0));
    // Lobe probabilities: exactly 1 or 0 where a lobe is absent, else within [0.1, 0.9].
    assert_eq!(GltfMetalRough::core(Vec3::splat(0.5), 1.0, 0.3).specular_probability(), 1.0);
    assert_eq!(GltfMetalRough::core(Vec3::ZERO, 0.0, 0.3).specular_probability(), 1.0);
    let diffuse_only = GltfMetalRough::new(Vec3::ONE, 0.0, 0.3, 0.3, 1.5, Vec3::ONE, 0.0);
    assert_eq!(diffuse_only.specular_probability(), 0.0);
    let black = GltfMetalRough::new(Vec3::ZERO, 0.0, 0.3, 0.3, 1.5, Vec3::ONE, 0.0);
    assert_eq!(black.specular_probability(), 0.0);
    assert_eq!(GltfMetalRough::new(Vec3::ONE, 0.0, 0.3, 0.3, 0.0, Vec3::ONE, 1.0).specular_probability(), 1.0);
    let mut u = Uniforms::new(7);
    for _ in 0..10_000 {
        let b = random_metal_rough(&mut u);
        let p = b.specular_probability();
        assert!(p == 0.0 || p == 1.0 || (0.1..=0.9).contains(&p), "{b:?}");
        let has_specular = b.metallic > 0.0 || b.specular_weight > 0.0;
        let has_diffuse = b.metallic < 1.0 && b.base_color.iter().any(|&c| c > 0.0) && b.diffuse_weight(1.0) > 0.0;
        assert_eq!(p > 0.0, has_specular, "{b:?}");
        if has_specular {
            assert_eq!(p < 1.0, has_diffuse, "{b:?}");
        }
    }
    // A plastic-like dielectric samples its diffuse base most of the time.
    let p = GltfMetalRough::core(Vec3::new(0.8, 0.5, 0.2), 0.0, 0.25).specular_probability();
    assert!((0.1..0.2).contains(&p), "{p}");
}

#[test]
fn layout_flags_and_two_sided_convention() {
    assert_eq!(size_of::<GltfMetalRough>(), 48);
    assert_eq!(size_of::<GltfMetalRough>() % 16, 0);
    assert_eq!(align_of::<GltfMetalRough>(), 4);
    assert_eq!(std::mem::offset_of!(GltfMetalRough, metallic), 12);
    assert_eq!(std::mem::offset_of!(GltfMetalRough, f0), 16);
    assert_eq!(std::mem::offset_of!(GltfMetalRough, specular_weight), 28);
    assert_eq!(std::mem::offset_of!(GltfMetalRough, distribution), 32);
    assert_eq!(std::mem::offset_of!(GltfMetalRough, p_specular), 40);
    let b = GltfMetalRough::core(Vec3::new(0.8, 0.5, 0.2), 0.3, 0.2);
    let words: &[u32] = bytemuck::cast_slice(std::slice::from_ref(&b));
    assert_eq!(words.len(), 12);
    assert_eq!(bytemuck::pod_read_unaligned::<GltfMetalRough>(bytemuck::bytes_of(&b)), b);

    let (r, g, s) = (BxdfFlags::REFLECTION, BxdfFlags::GLOSSY, BxdfFlags::SPECULAR);
    assert_eq!(b.flags(), r.union(g));
    assert_eq!(GltfMetalRough::core(Vec3::ONE, 1.0, 0.0).flags(), r.union(s));
    assert_eq!(GltfMetalRough::core(Vec3::ONE, 0.5, 0.0).flags(), r.union(g).union(s));
    let diffuse_mirror = GltfMetalRough::new(Vec3::ONE, 0.0, 0.0, 0.0, 1.5, Vec3::ONE, 0.0);
    assert_eq!(diffuse_mirror.flags(), r.union(g));
    assert!(!b.flags().is_transmissive());

    // Reflection only, wo above the horizon: like GgxConductor, nothing below.
    let (wo, wi) = (Vec3::new(0.3, 0.1, 0.9).normalize(), Vec3::new(-0.4, 0.2, 0.8).normalize());
    assert!(b.eval(wo, wi).min_element() > 0.0 && b.pdf(wo, wi, Sampling::Vndf) > 0.0);
    let flip = |v: Vec3| Vec3::new(v.x, v.y, -v.z);
    for (o, i) in [(flip(wo), wi), (wo, flip(wi)), (flip(wo), flip(wi)), (Vec3::X, wi), (wo, Vec3::X)] {
        assert_eq!(b.eval(o, i), Vec3::ZERO);
        assert_eq!(b.pdf(o, i, Sampling::Vndf), 0.0);
    }
    assert!(b.sample(flip(wo), Vec2::splat(0.3), 0.5, Sampling::Vndf).is_none());
    assert!(b.sample(Vec3::X, Vec2::splat(0.3), 0.05, Sampling::Vndf).is_none());
    // Unnormalized input is normalized first.
    let scaled = b.eval(wo * 3.0, wi * 0.25);
    assert!((scaled - b.eval(wo, wi)).abs().max_element() < 1e-6, "{scaled}");
    // Reciprocal: h and |wo.h| = |wi.h| are symmetric in wo, wi, so f(wo, wi) = f(wi, wo).
    let (f1, f2) = (b.eval(wo, wi) / wi.z, b.eval(wi, wo) / wo.z);
    assert!((f1 - f2).abs().max_element() < 1e-5 * f1.max_element(), "{f1} {f2}");
}

// ---------------------------------------------------------------------------------------------
// Chi-square of the sampler
// ---------------------------------------------------------------------------------------------

/// Goodness of fit of the mixture sampler against `pdf` (support/chi2.rs): `u_lobe` from its own
/// generator; a delta sample counts as lost, whose expected rate is the mass `pdf` lacks
/// (`p_s` for a mirror lobe, plus the specular sampler's directions below the horizon).
#[test]
fn chi2_of_the_mixture_sampler() {
    let configs: Vec<(Params, Sampling)> = vec![
        (Params::core(ORANGE, 0.0, 0.5), Sampling::Vndf),
        (Params::core(ORANGE, 0.5, 0.3), Sampling::Vndf),
        (Params::core(WHITE, 0.0, 0.7), Sampling::SphericalCaps),
        (Params::core([0.9, 0.6, 0.3], 1.0, 0.6), Sampling::Bounded),
        (Params { roughness: (0.3, 0.8), ..Params::core(ORANGE, 0.3, 0.5) }, Sampling::Vndf),
        (Params { specular_weight: 0.0, ..Params::core(ORANGE, 0.0, 0.5) }, Sampling::Vndf),
        (Params::core(ORANGE, 0.4, 0.02), Sampling::Vndf),
        (Params { ior: 2.4, ..Params::core(WHITE, 0.0, 0.4) }, Sampling::Ndf),
    ];
    let views = [20.0f32, 70.0];
    let significance = sidak_significance(0.01, configs.len() * views.len());
    let mut failures = Vec::new();
    for (i, (p, s)) in configs.iter().enumerate() {
        let brdf = p.brdf();
        for (j, inc) in views.into_iter().enumerate() {
            let wo = wo_at(inc);
            let seed = (i * 8 + j) as u64;
            let mut lobe = Uniforms::new(seed ^ 0x10be);
            let cfg = Chi2Config { seed, ..Chi2Config::default() };
            let outcome = chi2_test(
                &cfg,
                |u| brdf.sample(wo, u, lobe.next().x, *s).filter(|b| !b.is_delta).map(|b| b.wi),
                |wi| brdf.pdf(wo, wi, *s) as f64,
            );
            let line = format!("{p:?} {s:?} {inc} deg: {}", outcome.summary());
            println!("{line}");
            if !outcome.passes(significance) {
                failures.push(line);
            }
        }
    }
    assert!(failures.is_empty(), "chi-square failures:\n{}", failures.join("\n"));
}

// ---------------------------------------------------------------------------------------------
// Any f32 in
// ---------------------------------------------------------------------------------------------

/// Through the constructor from any arguments, or any bits in every field.
fn material() -> impl Strategy<Value = GltfMetalRough> {
    prop_oneof![
        (vec3(), any_f32(), any_f32(), any_f32(), any_f32(), vec3(), any_f32())
            .prop_map(|(b, m, ax, ay, ior, sc, sw)| GltfMetalRough::new(b, m, ax, ay, ior, sc, sw)),
        prop::array::uniform12(any_f32())
            .prop_map(|f| bytemuck::cast::<[u32; 12], GltfMetalRough>(f.map(f32::to_bits))),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 10_000,
        rng_seed: RngSeed::Fixed(0x676c_7466),
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn never_produces_invalid_values(
        b in material(), wo in direction(), wi in direction(), u in (any_f32(), any_f32()), u_lobe in any_f32(),
        c in any_f32(),
    ) {
        let u = Vec2::new(u.0, u.1);
        prop_assert!(ok3(b.eval(wo, wi)), "eval {:?}", b.eval(wo, wi));
        prop_assert!(ok3(b.specular_fresnel(c)) && b.specular_fresnel(c).max_element() <= 1.0 + 1e-6);
        prop_assert!(ok(b.diffuse_weight(c)) && b.diffuse_weight(c) <= 1.0);
        let p = b.specular_probability();
        prop_assert!((0.0..=1.0).contains(&p));
        let flags = b.flags();
        prop_assert!(flags.contains(BxdfFlags::REFLECTION) && !flags.is_transmissive());
        for s in Sampling::ALL {
            let pdf = b.pdf(wo, wi, s);
            prop_assert!(ok(pdf), "pdf {s:?} {pdf}");
            // eval_pdf is eval and pdf bit for bit, inherent and through the trait.
            let bits = |(f, p): (Vec3, f32)| (f.to_array().map(f32::to_bits), p.to_bits());
            prop_assert_eq!(bits(b.eval_pdf(wo, wi, s)), bits((b.eval(wo, wi), pdf)), "{:?}", s);
            prop_assert_eq!(bits(Bxdf::eval_pdf(&b, wo, wi, s, TransportMode::Radiance)), bits((b.eval(wo, wi), pdf)));
            if let Some(bs) = b.sample(wo, u, u_lobe, s) {
                prop_assert!((bs.wi.length() - 1.0).abs() < 1e-5, "{s:?} |wi| = {}", bs.wi.length());
                prop_assert!(bs.wi.z > 0.0, "{s:?} below horizon {:?}", bs.wi);
                prop_assert!(ok3(bs.weight), "{s:?} weight {:?}", bs.weight);
                prop_assert!(bs.pdf > 0.0 && bs.pdf.is_finite(), "{s:?} pdf {}", bs.pdf);
                prop_assert!(!bs.is_delta || flags.is_delta());
            }
        }
    }

    #[test]
    fn constructor_stores_fields_in_range(
        base in vec3(), m in any_f32(), ax in any_f32(), ay in any_f32(), ior in any_f32(), sc in vec3(), sw in any_f32(),
    ) {
        let b = GltfMetalRough::new(base, m, ax, ay, ior, sc, sw);
        let unit = |x: f32| (0.0..=1.0).contains(&x);
        prop_assert!(b.base_color.into_iter().chain(b.f0).chain([b.metallic, b.specular_weight, b.p_specular]).all(unit));
        prop_assert_eq!(b.distribution, ggx_core::TrowbridgeReitz::new(ax, ay));
        prop_assert_eq!(b.pad, 0);
        let i = clamp_ior(ior);
        prop_assert!(i == 0.0 || (1.0..=ggx_core::ETA_MAX).contains(&i));
    }
}
