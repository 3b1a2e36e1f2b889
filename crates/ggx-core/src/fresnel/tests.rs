use super::*;

/// f64 reference of the dielectric Fresnel equations.
fn dielectric_f64(cos_i: f64, eta: f64) -> f64 {
    let (cos_i, eta) = if cos_i < 0.0 { (-cos_i, 1.0 / eta) } else { (cos_i, eta) };
    let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    let rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    0.5 * (rs * rs + rp * rp)
}

/// f64 reference of the conductor reflectance, Born & Wolf's real-valued form
/// (a^2 + b^2 = sqrt((n^2 - k^2 - sin^2)^2 + 4 n^2 k^2)).
fn conductor_f64(cos_i: f64, n: f64, k: f64) -> f64 {
    let s2 = 1.0 - cos_i * cos_i;
    let t0 = n * n - k * k - s2;
    let a2b2 = (t0 * t0 + 4.0 * n * n * k * k).sqrt();
    let a = (0.5 * (a2b2 + t0)).max(0.0).sqrt();
    let t1 = a2b2 + cos_i * cos_i;
    let t2 = 2.0 * cos_i * a;
    let rs = (t1 - t2) / (t1 + t2);
    let t3 = cos_i * cos_i * a2b2 + s2 * s2;
    let t4 = t2 * s2;
    let rp = rs * (t3 - t4) / (t3 + t4);
    0.5 * (rp + rs)
}

#[test]
fn dielectric_matches_f64_inside_and_outside() {
    for eta in [1.0f32, 1.33, 1.5, 2.4] {
        for i in -100..=100 {
            let c = i as f32 / 100.0;
            let f = fresnel_dielectric(c, eta) as f64;
            let r = dielectric_f64(c as f64, eta as f64);
            assert!((f - r).abs() < 2e-6, "cos {c} eta {eta}: {f} vs {r}");
        }
    }
    // Glass at normal incidence: ((1.5 - 1) / (1.5 + 1))^2 = 0.04.
    assert!((fresnel_dielectric(1.0, 1.5) - 0.04).abs() < 1e-6);
    // Total internal reflection from inside beyond the critical angle (41.8 degrees).
    assert_eq!(fresnel_dielectric(-0.5, 1.5), 1.0);
    assert_eq!(fresnel_dielectric(0.0, 1.5), 1.0);
}

#[test]
fn conductor_matches_f64_and_reduces_to_dielectric_without_absorption() {
    let metals = [(0.143f32, 3.983f32), (0.2, 3.9), (1.1, 2.6), (2.5, 0.1)];
    for (n, k) in metals {
        for i in 0..=100 {
            let c = i as f32 / 100.0;
            let f = fresnel_complex(c, n, k) as f64;
            let r = conductor_f64(c as f64, n as f64, k as f64);
            assert!((f - r).abs() < 1e-5, "cos {c} n {n} k {k}: {f} vs {r}");
        }
    }
    for i in 1..=100 {
        let c = i as f32 / 100.0;
        assert!((fresnel_complex(c, 1.5, 0.0) - fresnel_dielectric(c, 1.5)).abs() < 1e-5);
    }
    assert!((fresnel_complex(0.0, 0.2, 3.9) - 1.0).abs() < 1e-6);
}

#[test]
fn schlick_interpolates_between_f0_and_f90() {
    let f0 = Vec3::new(0.04, 0.5, 1.0);
    assert_eq!(fresnel_schlick(1.0, f0, Vec3::ONE), f0);
    assert_eq!(fresnel_schlick(0.0, f0, Vec3::ONE), Vec3::ONE);
    assert_eq!(fresnel_schlick(-3.0, f0, Vec3::splat(0.5)), Vec3::splat(0.5));
    let m = 0.5f32.powi(5);
    assert!((fresnel_schlick(0.5, f0, Vec3::ONE) - (f0 + (Vec3::ONE - f0) * m)).length() < 1e-7);
}

#[test]
fn params_round_trip_and_evaluate_like_the_enum() {
    let all = [
        Fresnel::One,
        Fresnel::Schlick { f0: Vec3::new(0.9, 0.6, 0.3) },
        Fresnel::SchlickF90 { f0: Vec3::splat(0.04), f90: Vec3::splat(0.7) },
        Fresnel::Conductor { eta: Vec3::new(0.2, 0.9, 1.1), k: Vec3::new(3.9, 2.4, 2.2) },
        Fresnel::Dielectric { eta: 1.5 },
    ];
    for f in all {
        assert_eq!(FresnelParams::from(f).to_fresnel(), f);
        assert_eq!(core::mem::size_of::<FresnelParams>(), 48);
        for c in [-1.0f32, 0.0, 0.3, 1.0, 2.0, f32::NAN, f32::INFINITY] {
            let v = f.eval(c);
            assert!(v.cmpge(Vec3::ZERO).all() && v.cmple(Vec3::ONE).all(), "{f:?} {c} -> {v}");
        }
    }
    let garbage = FresnelParams { kind: 99, eta: f32::NAN, pad: [0; 2], a: [f32::NAN; 4], b: [f32::INFINITY; 4] };
    assert_eq!(garbage.eval(0.5), Vec3::ONE);
    let nan = FresnelParams::from(Fresnel::Conductor { eta: Vec3::NAN, k: Vec3::NAN });
    assert!(nan.eval(0.5).is_finite());
}

/// The conductor kind evaluates the three channels as `Vec3A` lanes: each lane is the scalar
/// `fresnel_complex` bit for bit, over metals, dielectric-like and hostile parameters.
#[test]
fn conductor_rgb_lanes_are_the_scalar_function_bit_for_bit() {
    let odd = [0.0f32, -0.0, 1e-40, -1e-40, 1e-20, 0.5, 1.0, -2.0, 3e38, f32::INFINITY, -f32::INFINITY, f32::NAN];
    let mut cosines: std::vec::Vec<f32> = (0..=64).map(|i| i as f32 / 64.0).collect();
    cosines.extend(odd);
    let metals = [(0.143f32, 3.983f32), (0.2, 3.9), (1.1, 2.6), (2.5, 0.1), (0.2, 0.0), (1.0, 0.0)];
    let mut params: std::vec::Vec<(f32, f32)> = metals.to_vec();
    params.extend(odd.iter().flat_map(|&x| [(x, 1.0), (1.0, x), (x, x)]));
    for chunk in params.chunks(3) {
        let at = |i: usize| chunk.get(i).copied().unwrap_or((1.5, 0.0));
        let eta = Vec3::new(at(0).0, at(1).0, at(2).0);
        let k = Vec3::new(at(0).1, at(1).1, at(2).1);
        for &c in &cosines {
            let lanes = formulas::fresnel_complex_rgb(c, eta, k);
            for ch in 0..3 {
                let scalar = fresnel_complex(c, eta[ch], k[ch]);
                assert_eq!(lanes[ch].to_bits(), scalar.to_bits(), "cos {c} eta {} k {}", eta[ch], k[ch]);
            }
        }
    }
}

/// Every `Lanes` operation on `Vec3A` is the `f32` operation in each lane, bit for bit.
#[test]
fn vec3a_lanes_are_f32_lanes() {
    use crate::lanes::Lanes;
    use glam::Vec3A;
    let values = [0.0f32, -0.0, 1e-40, -1.5, 2.0, 0.25, 3e38, f32::INFINITY, -f32::INFINITY, f32::NAN, -f32::NAN];
    for (i, &a0) in values.iter().enumerate() {
        for &b0 in &values {
            let (a1, b1) = (values[(i + 3) % values.len()], b0 * 0.5);
            let (a2, b2) = (b0, a0);
            let (a, b) = (Vec3A::new(a0, a1, a2), Vec3A::new(b0, b1, b2));
            let (sa, sb) = ([a0, a1, a2], [b0, b1, b2]);
            // NaN results compare as one value: Rust leaves a NaN's sign and payload unspecified
            // (constant folding and the hardware may differ).
            let canon = |x: f32| if x.is_nan() { f32::NAN.to_bits() } else { x.to_bits() };
            let bits = |v: Vec3A| [canon(v.x), canon(v.y), canon(v.z)];
            let each =
                |f: &dyn Fn(f32, f32) -> f32| [canon(f(sa[0], sb[0])), canon(f(sa[1], sb[1])), canon(f(sa[2], sb[2]))];
            assert_eq!(bits(Lanes::sqrt(a)), each(&|x, _| Lanes::sqrt(x)));
            assert_eq!(bits(Lanes::abs(a)), each(&|x, _| Lanes::abs(x)));
            assert_eq!(bits(Lanes::copysign(a, b)), each(&|x, y| Lanes::copysign(x, y)));
            assert_eq!(bits(a / b), each(&|x, y| x / y));
            let select = |m: glam::BVec3A| Vec3A::select(m, Vec3A::ONE, Vec3A::ZERO);
            let pick = |m: fn(f32, f32) -> bool| each(&|x, y| if m(x, y) { 1.0 } else { 0.0 });
            assert_eq!(bits(select(Lanes::eq(a, b))), pick(<f32 as Lanes>::eq));
            assert_eq!(bits(select(Lanes::ge(a, b))), pick(<f32 as Lanes>::ge));
            assert_eq!(bits(select(Lanes::gt(a, b))), pick(<f32 as Lanes>::gt));
            assert_eq!(bits(select(Lanes::is_finite(a))), pick(|x, _| Lanes::is_finite(x)));
            assert_eq!(bits(Lanes::max(a, b)), each(&|x, y| Lanes::max(x, y)));
            assert_eq!(bits(Lanes::min(a, b)), each(&|x, y| Lanes::min(x, y)));
            assert_eq!(bits(Lanes::finite_or_zero(a)), each(&|x, _| Lanes::finite_or_zero(x)));
            let n = <Vec3A as Lanes>::normalize_or_zero(crate::lanes::Vec3Lanes::new(a, b, a * b));
            for lane in 0..3 {
                let v = glam::Vec3::new(sa[lane], sb[lane], sa[lane] * sb[lane]);
                let m = crate::math::normalize_or_zero(v);
                assert_eq!(
                    [canon(n.x[lane]), canon(n.y[lane]), canon(n.z[lane])],
                    [canon(m.x), canon(m.y), canon(m.z)]
                );
            }
            assert_eq!(bits(<Vec3A as Lanes>::from_f64(core::f64::consts::PI)), [core::f32::consts::PI.to_bits(); 3]);
            assert_eq!(bits(select(Lanes::is_nan(a))), pick(|x, _| Lanes::is_nan(x)));
            assert_eq!(
                bits(<Vec3A as Lanes>::select(Lanes::ge(a, b), a, b)),
                each(&|x, y| Lanes::select(x >= y, x, y))
            );
        }
    }
}

/// An unphysical `eta` near `-1 + 0i` makes the denominators cancel: the result is 1, not
/// infinite (the contract fuzz's witness) nor huge rounding noise (4e14 at cos 0.3), in the
/// scalar function and on RGB lanes.
#[test]
fn conductor_with_a_vanishing_denominator_is_one() {
    let cases =
        [(1.0f32, -1.0f32, 0.0f32), (0.3, -1.0, 0.0), (0.1, -1.0, 0.0), (0.625_026_17, -0.999_999_94, 3.537_849_6e-23)];
    for (c, eta, k) in cases {
        assert_eq!(fresnel_complex(c, eta, k), 1.0, "{c} {eta} {k}: {}", fresnel_complex(c, eta, k));
        let rgb = formulas::fresnel_complex_rgb(c, Vec3::splat(eta), Vec3::splat(k));
        assert_eq!(rgb, Vec3::ONE, "{c} {eta} {k}");
    }
}
