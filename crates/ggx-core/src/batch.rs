//! Slice (structure-of-arrays) versions of the hot functions, written so that LLVM
//! auto-vectorizes them: no branches in the loop bodies (selects only), no calls into
//! libm (the polynomial [`crate::math::sincos_2pi`]), and slices re-sliced to one common
//! length so bounds checks vanish.
//!
//! With the `std` feature, [`sample_vndf`] and [`eval`] pick the widest vector ISA of the CPU
//! at run time (`pulp`'s dispatch: x86-64-v4 with AVX-512, v3 with AVX2, else the baseline) and
//! compile the same loop for it; [`sample_vndf_portable`] and [`eval_portable`] are the loops at
//! the build's baseline ISA (what the dispatching functions run without `std`). Every lane is
//! bit-identical whichever ISA runs it: Rust never contracts `a * b + c` into a fused
//! multiply-add, and `sqrt` and `/` are correctly rounded at every width.
//!
//! Lanes whose sample is invalid (below the horizon, back-facing normal, degenerate input)
//! get a zero direction and a zero pdf instead of an `Option`.

use crate::fresnel::kind;
use crate::math::{ONE_MINUS_EPSILON, sincos_2pi_with};
use crate::{GgxConductor, TrowbridgeReitz};

/// Three equally long slices holding the x, y and z components of directions.
#[derive(Clone, Copy)]
pub struct Vec3Slices<'a> {
    /// x components.
    pub x: &'a [f32],
    /// y components.
    pub y: &'a [f32],
    /// z components.
    pub z: &'a [f32],
}

/// Mutable counterpart of [`Vec3Slices`].
pub struct Vec3SlicesMut<'a> {
    /// x components.
    pub x: &'a mut [f32],
    /// y components.
    pub y: &'a mut [f32],
    /// z components.
    pub z: &'a mut [f32],
}

#[inline(always)]
fn rsqrt_or_zero(len2: f32) -> f32 {
    let r = 1.0 / crate::math::sqrt(len2);
    if len2 > 1e-30 && len2 < f32::INFINITY { r } else { 0.0 }
}

/// Visible-normal sampling of reflected directions for a batch (spherical caps, Dupuy &
/// Benyoub 2023, the same density as Heitz 2018): for each lane `i`, `wo[i]` (unit, tangent
/// space) and `u0[i], u1[i]` give `wi[i]` and its density `pdf[i] = D(wm) / (2 (wo.z + so))`.
/// Processes `min` of all slice lengths and returns how many lanes got a valid sample.
/// Any input gives a finite `wi` (the reflection of `wo`, so unit only for a unit `wo`) and a
/// finite pdf `>= 0`; lanes past the common length are left untouched. A delta lobe is not
/// sampled here (every lane gets zero, as `GgxConductor::pdf` is zero for it): sample mirrors
/// with [`GgxConductor::sample`].
pub fn sample_vndf(
    dist: &TrowbridgeReitz,
    wo: Vec3Slices,
    u0: &[f32],
    u1: &[f32],
    wi: Vec3SlicesMut,
    pdf: &mut [f32],
) -> usize {
    #[cfg(feature = "std")]
    {
        pulp::Arch::new().dispatch(SampleVndf { dist, wo, u0, u1, wi, pdf })
    }
    #[cfg(not(feature = "std"))]
    {
        sample_vndf_lanes::<false>(dist, wo, u0, u1, wi, pdf)
    }
}

/// [`sample_vndf`] at the build's baseline ISA, without run-time dispatch; the same lanes bit for bit.
pub fn sample_vndf_portable(
    dist: &TrowbridgeReitz,
    wo: Vec3Slices,
    u0: &[f32],
    u1: &[f32],
    wi: Vec3SlicesMut,
    pdf: &mut [f32],
) -> usize {
    sample_vndf_lanes::<false>(dist, wo, u0, u1, wi, pdf)
}

/// The arguments of [`sample_vndf`], for `pulp`'s dispatch.
#[cfg(feature = "std")]
struct SampleVndf<'a, 'b> {
    dist: &'a TrowbridgeReitz,
    wo: Vec3Slices<'a>,
    u0: &'a [f32],
    u1: &'a [f32],
    wi: Vec3SlicesMut<'b>,
    pdf: &'b mut [f32],
}

#[cfg(feature = "std")]
impl pulp::WithSimd for SampleVndf<'_, '_> {
    type Output = usize;

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) -> usize {
        // Every dispatched ISA but the scalar fallback has SSE4.1's rounding instruction.
        if S::IS_SCALAR {
            sample_vndf_lanes::<false>(self.dist, self.wo, self.u0, self.u1, self.wi, self.pdf)
        } else {
            sample_vndf_lanes::<true>(self.dist, self.wo, self.u0, self.u1, self.wi, self.pdf)
        }
    }
}

/// The loop of [`sample_vndf`], inlined into each ISA's context; `ROUND`: floors by the
/// rounding instruction (`math::sincos_2pi_with`), for ISAs that have one.
#[inline(always)]
fn sample_vndf_lanes<const ROUND: bool>(
    dist: &TrowbridgeReitz,
    wo: Vec3Slices,
    u0: &[f32],
    u1: &[f32],
    wi: Vec3SlicesMut,
    pdf: &mut [f32],
) -> usize {
    let n = [wo.x.len(), wo.y.len(), wo.z.len(), u0.len(), u1.len(), wi.x.len(), wi.y.len(), wi.z.len(), pdf.len()]
        .into_iter()
        .min()
        .unwrap_or(0);
    let (ox, oy, oz, u0, u1) = (&wo.x[..n], &wo.y[..n], &wo.z[..n], &u0[..n], &u1[..n]);
    let (ix, iy, iz, pdf) = (&mut wi.x[..n], &mut wi.y[..n], &mut wi.z[..n], &mut pdf[..n]);
    let (ax, ay) = dist.alphas();
    let inv_pi_axay = 1.0 / (core::f32::consts::PI * ax * ay);
    let delta = dist.is_effectively_smooth();
    let mut valid = 0usize;
    for i in 0..n {
        let (wx, wy, wz) = (ox[i], oy[i], oz[i]);
        // Stretched view direction; its length never below |wo.z| (TrowbridgeReitz::stretched_len).
        let (sx, sy) = (ax * wx, ay * wy);
        let so = crate::math::sqrt(sx * sx + sy * sy + wz * wz).max(wz.abs());
        let inv = rsqrt_or_zero(so * so);
        let (vx, vy, vz) = (sx * inv, sy * inv, wz * inv);
        // Uniform point on the cap z in [-vz, 1].
        let a = u0[i].max(0.0).min(ONE_MINUS_EPSILON);
        let b = u1[i].max(0.0).min(ONE_MINUS_EPSILON);
        let (sin_phi, cos_phi) = sincos_2pi_with::<ROUND>(a);
        let t = (1.0 - b) * (1.0 + vz);
        let z = t - vz;
        let st = crate::math::sqrt((1.0 - z * z).max(0.0));
        // z + vz is exactly t (no cancellation), as in TrowbridgeReitz::sample_cap.
        let (hx, hy, hz) = (st * cos_phi + vx, st * sin_phi + vy, t);
        // Unstretch and normalize.
        let (mx, my, mz) = (ax * hx, ay * hy, hz.max(0.0));
        let minv = rsqrt_or_zero(mx * mx + my * my + mz * mz);
        let (mx, my, mz) = (mx * minv, my * minv, mz * minv);
        // Reflect.
        let c = wx * mx + wy * my + wz * mz;
        let (rx, ry, rz) = (2.0 * c * mx - wx, 2.0 * c * my - wy, 2.0 * c * mz - wz);
        // The density at the half vector of the returned pair, as GgxConductor::sample does,
        // so pdf[i] == GgxConductor::pdf(wo, wi) even for near-mirror lobes.
        let (hx, hy, hz) = (wx + rx, wy + ry, wz + rz);
        let hinv = rsqrt_or_zero(hx * hx + hy * hy + hz * hz);
        let (mx, my, mz) = (hx * hinv, hy * hinv, hz * hinv);
        // D(wm) / (2 (wo.z + so)).
        let (tx, ty) = (mx / ax, my / ay);
        let t = tx * tx + ty * ty + mz * mz;
        let p = inv_pi_axay / (t * t) / (2.0 * (wz + so));
        let cos_om = wx * mx + wy * my + wz * mz;
        let ok = !delta && wz > 0.0 && c > 0.0 && cos_om > 0.0 && rz > 0.0 && p > 0.0 && p < f32::INFINITY;
        ix[i] = if ok { rx } else { 0.0 };
        iy[i] = if ok { ry } else { 0.0 };
        iz[i] = if ok { rz } else { 0.0 };
        pdf[i] = if ok { p } else { 0.0 };
        valid += ok as usize;
    }
    valid
}

/// `f(wo, wi) |wi.z|` for a batch, written to `out` as RGB; the same values as
/// [`GgxConductor::eval`] (for unit inputs, up to rounding). Processes `min` of all lengths.
pub fn eval(brdf: &GgxConductor, wo: Vec3Slices, wi: Vec3Slices, out: Vec3SlicesMut) {
    #[cfg(feature = "std")]
    {
        pulp::Arch::new().dispatch(Eval { brdf, wo, wi, out })
    }
    #[cfg(not(feature = "std"))]
    {
        eval_fresnel(brdf, wo, wi, out)
    }
}

/// [`eval`] at the build's baseline ISA, without run-time dispatch; the same lanes bit for bit.
pub fn eval_portable(brdf: &GgxConductor, wo: Vec3Slices, wi: Vec3Slices, out: Vec3SlicesMut) {
    eval_fresnel(brdf, wo, wi, out)
}

/// The arguments of [`eval`], for `pulp`'s dispatch.
#[cfg(feature = "std")]
struct Eval<'a, 'b> {
    brdf: &'a GgxConductor,
    wo: Vec3Slices<'a>,
    wi: Vec3Slices<'a>,
    out: Vec3SlicesMut<'b>,
}

#[cfg(feature = "std")]
impl pulp::WithSimd for Eval<'_, '_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) {
        eval_fresnel(self.brdf, self.wo, self.wi, self.out)
    }
}

/// [`eval_lanes`] with the Fresnel term's kind chosen once for the batch, so that each loop is
/// branch-free: `FresnelParams::eval` of that kind (the same function, so the same bits).
#[inline(always)]
fn eval_fresnel(brdf: &GgxConductor, wo: Vec3Slices, wi: Vec3Slices, out: Vec3SlicesMut) {
    let f = brdf.fresnel;
    match f.kind {
        kind::SCHLICK => eval_lanes(brdf, wo, wi, out, |c| f.eval_as(kind::SCHLICK, c)),
        kind::CONDUCTOR => eval_lanes(brdf, wo, wi, out, |c| f.eval_as(kind::CONDUCTOR, c)),
        kind::DIELECTRIC => eval_lanes(brdf, wo, wi, out, |c| f.eval_as(kind::DIELECTRIC, c)),
        // kind::ONE and any unknown kind: F = 1.
        _ => eval_lanes(brdf, wo, wi, out, |c| f.eval_as(kind::ONE, c)),
    }
}

/// The loop of [`eval`] with the Fresnel term `fresnel(cos(wo, wm))`, inlined into each ISA's
/// context.
#[inline(always)]
fn eval_lanes(
    brdf: &GgxConductor,
    wo: Vec3Slices,
    wi: Vec3Slices,
    out: Vec3SlicesMut,
    fresnel: impl Fn(f32) -> glam::Vec3,
) {
    let n =
        [wo.x.len(), wo.y.len(), wo.z.len(), wi.x.len(), wi.y.len(), wi.z.len(), out.x.len(), out.y.len(), out.z.len()]
            .into_iter()
            .min()
            .unwrap_or(0);
    let (ox, oy, oz) = (&wo.x[..n], &wo.y[..n], &wo.z[..n]);
    let (ix, iy, iz) = (&wi.x[..n], &wi.y[..n], &wi.z[..n]);
    let (rx, ry, rz) = (&mut out.x[..n], &mut out.y[..n], &mut out.z[..n]);
    let (ax, ay) = brdf.distribution.alphas();
    let (ax2, ay2) = (ax * ax, ay * ay);
    let inv_pi_axay = 1.0 / (core::f32::consts::PI * ax * ay);
    let delta = brdf.is_delta();
    for i in 0..n {
        let (a, b, c) = (ox[i], oy[i], oz[i]);
        let (e, f, g) = (ix[i], iy[i], iz[i]);
        let (hx, hy, hz) = (a + e, b + f, c + g);
        let hinv = rsqrt_or_zero(hx * hx + hy * hy + hz * hz);
        let (mx, my, mz) = (hx * hinv, hy * hinv, hz * hinv);
        let t = mx * mx / ax2 + my * my / ay2 + mz * mz;
        let dm = inv_pi_axay / (t * t);
        // Stretched lengths never below |w.z| (TrowbridgeReitz::stretched_len).
        let so = crate::math::sqrt(c * c + ax2 * a * a + ay2 * b * b).max(c.abs());
        let si = crate::math::sqrt(g * g + ax2 * e * e + ay2 * f * f).max(g.abs());
        let v = dm * g / (2.0 * (g * so + c * si));
        // wo.wm > 0: a back-facing half vector (rounding where wo ~ -wi) reflects nothing.
        let cos_om = a * mx + b * my + c * mz;
        let ok = !delta && c > 0.0 && g > 0.0 && cos_om > 0.0 && v < f32::INFINITY;
        let v = if ok { v } else { 0.0 };
        let fr = fresnel(cos_om);
        rx[i] = fr.x * v;
        ry[i] = fr.y * v;
        rz[i] = fr.z * v;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Fresnel, Sampling};
    use glam::{Vec2, Vec3};
    use std::vec::Vec;

    fn lanes(n: usize) -> (Vec<Vec3>, Vec<Vec2>) {
        use rand_core::{Rng, SeedableRng};
        let mut rng = rand_pcg::Pcg32::seed_from_u64(34);
        let mut next = move || Vec2::new(rng.next_u32() as f32 / 4294967296.0, rng.next_u32() as f32 / 4294967296.0);
        let mut wo = Vec::new();
        let mut u = Vec::new();
        for i in 0..n {
            let w = crate::warp::sample_uniform_hemisphere(next());
            wo.push(if i % 17 == 0 { Vec3::new(w.x, w.y, -w.z) } else { w });
            u.push(next());
        }
        u[1] = Vec2::new(0.0, 0.0);
        u[2] = Vec2::new(ONE_MINUS_EPSILON, ONE_MINUS_EPSILON);
        (wo, u)
    }

    #[test]
    fn batch_sampling_matches_scalar_spherical_caps() {
        let (wo, u) = lanes(4096);
        // The whole alpha range: deltas (below 1e-3, where the scalar pdf is 0), the threshold,
        // near-mirrors, anisotropic and rough lobes.
        let alphas = [(1e-4f32, 1e-4f32), (5e-4, 9e-4), (9.99e-4, 9.99e-4), (1e-3, 1e-3), (0.0011, 0.0011)];
        for (ax, ay) in alphas.into_iter().chain([(0.01, 0.002), (0.3, 0.3), (0.05, 0.5), (1.0, 1.0)]) {
            let brdf = GgxConductor::new(ax, ay, Fresnel::One);
            let (x, y, z): (Vec<f32>, Vec<f32>, Vec<f32>) =
                (wo.iter().map(|w| w.x).collect(), wo.iter().map(|w| w.y).collect(), wo.iter().map(|w| w.z).collect());
            let (u0, u1): (Vec<f32>, Vec<f32>) = (u.iter().map(|v| v.x).collect(), u.iter().map(|v| v.y).collect());
            let (mut rx, mut ry, mut rz, mut pdf) =
                (std::vec![0.0; 4096], std::vec![0.0; 4096], std::vec![0.0; 4096], std::vec![0.0; 4096]);
            let valid = sample_vndf(
                &brdf.distribution,
                Vec3Slices { x: &x, y: &y, z: &z },
                &u0,
                &u1,
                Vec3SlicesMut { x: &mut rx, y: &mut ry, z: &mut rz },
                &mut pdf,
            );
            let mut scalar_valid = 0;
            for i in 0..4096 {
                let s = brdf.sample(wo[i], u[i], Sampling::SphericalCaps).filter(|s| !s.is_delta);
                if brdf.is_delta() {
                    assert_eq!((rx[i], ry[i], rz[i], pdf[i]), (0.0, 0.0, 0.0, 0.0), "{ax} {ay} lane {i}: a delta lobe");
                }
                if let Some(s) = s {
                    assert_eq!(brdf.pdf(wo[i], s.wi, Sampling::SphericalCaps) > 0.0, pdf[i] > 0.0, "lane {i}");
                    scalar_valid += 1;
                    let b = Vec3::new(rx[i], ry[i], rz[i]);
                    assert!((s.wi - b).length() < 1e-4, "{ax} {ay} lane {i}: {:?} vs {b:?}", s.wi);
                    assert!((s.pdf - pdf[i]).abs() <= 1e-4 * s.pdf, "{ax} {ay} lane {i}: {} vs {}", s.pdf, pdf[i]);
                } else {
                    assert!(pdf[i] == 0.0 || pdf[i] < 1e-6, "lane {i} valid only in batch");
                }
            }
            assert!(valid.abs_diff(scalar_valid) <= 4, "{valid} vs {scalar_valid}");
        }
    }

    /// The dispatched loops (the widest ISA of this CPU) give the baseline loops' lanes bit for
    /// bit: over the alpha range, every Fresnel kind, and hostile lanes (NaN, infinities, zero,
    /// subnormal, non-unit, below the horizon).
    #[test]
    fn dispatched_lanes_are_the_portable_lanes_bit_for_bit() {
        let (mut wo, u) = lanes(1000);
        let mut wi: Vec<Vec3> = u.iter().map(|&v| crate::warp::sample_cosine_hemisphere(v)).collect();
        let hostile = [f32::NAN, f32::INFINITY, -f32::INFINITY, 0.0, -0.0, 1e-40, 1.0 - f32::EPSILON / 2.0, 3e38];
        for (i, &x) in hostile.iter().enumerate() {
            wo[5 + i] = Vec3::new(x, 0.3, 0.5);
            wo[20 + i] = Vec3::new(0.1, 0.2, x);
            wi[40 + i] = Vec3::new(0.2, x, 0.4);
            wi[60 + i] = Vec3::new(x, x, x);
        }
        let (mut u0, mut u1): (Vec<f32>, Vec<f32>) = (u.iter().map(|v| v.x).collect(), u.iter().map(|v| v.y).collect());
        for (i, &x) in hostile.iter().enumerate() {
            (u0[80 + i], u1[90 + i]) = (x, x);
        }
        let col = |v: &Vec<Vec3>, f: fn(&Vec3) -> f32| -> Vec<f32> { v.iter().map(f).collect() };
        let (ox, oy, oz) = (col(&wo, |w| w.x), col(&wo, |w| w.y), col(&wo, |w| w.z));
        let (ix, iy, iz) = (col(&wi, |w| w.x), col(&wi, |w| w.y), col(&wi, |w| w.z));
        let bits = |v: &[f32]| -> Vec<u32> { v.iter().map(|x| x.to_bits()).collect() };
        let fresnels = [
            Fresnel::One,
            Fresnel::Schlick { f0: Vec3::new(0.9, 0.6, 0.3) },
            Fresnel::Conductor { eta: Vec3::new(0.2, 0.9, 1.1), k: Vec3::new(3.9, 2.4, 2.2) },
            Fresnel::Dielectric { eta: 1.5 },
        ];
        let alphas =
            [(1e-4f32, 1e-4f32), (9.99e-4, 5e-4), (1e-3, 1e-3), (0.01, 0.002), (0.3, 0.3), (0.05, 0.5), (1.0, 1.0)];
        for (ax, ay) in alphas {
            for fresnel in fresnels {
                let brdf = GgxConductor::new(ax, ay, fresnel);
                let run = |portable: bool| {
                    let mut r =
                        [std::vec![0.0f32; 1000], std::vec![0.0; 1000], std::vec![0.0; 1000], std::vec![0.0; 1000]];
                    let [rx, ry, rz, pdf] = &mut r;
                    let o = Vec3Slices { x: &ox, y: &oy, z: &oz };
                    let out = Vec3SlicesMut { x: rx, y: ry, z: rz };
                    let valid = if portable {
                        sample_vndf_portable(&brdf.distribution, o, &u0, &u1, out, pdf)
                    } else {
                        sample_vndf(&brdf.distribution, o, &u0, &u1, out, pdf)
                    };
                    let mut e = [std::vec![0.0f32; 1000], std::vec![0.0; 1000], std::vec![0.0; 1000]];
                    let [ex, ey, ez] = &mut e;
                    let i = Vec3Slices { x: &ix, y: &iy, z: &iz };
                    let out = Vec3SlicesMut { x: ex, y: ey, z: ez };
                    if portable {
                        eval_portable(&brdf, o, i, out)
                    } else {
                        eval(&brdf, o, i, out)
                    }
                    let all: Vec<Vec<u32>> = r.iter().chain(&e).map(|v| bits(v)).collect();
                    assert!(r.iter().chain(&e).flatten().all(|x| x.is_finite()), "{ax} {ay} {fresnel:?}: finite lanes");
                    (valid, all)
                };
                assert_eq!(run(false), run(true), "{ax} {ay} {fresnel:?}");
            }
        }
    }

    #[test]
    fn batch_eval_matches_scalar() {
        for (ax, ay) in [(0.2f32, 0.6f32), (1e-4, 1e-4), (9e-4, 5e-4), (1e-3, 1e-3), (0.004, 0.02), (1.0, 1.0)] {
            batch_eval_matches_scalar_at(ax, ay);
        }
    }

    fn batch_eval_matches_scalar_at(ax: f32, ay: f32) {
        let (wo, u) = lanes(2048);
        let mut wi: Vec<Vec3> = u.iter().map(|&v| crate::warp::sample_cosine_hemisphere(v)).collect();
        // Grazing pairs where wo ~ -wi: the half vector is back-facing after rounding.
        wi[3] = Vec3::new(-wo[3].x, -wo[3].y, 1e-7).normalize();
        wi[4] = Vec3::new(1.0, 0.0, 1e-30);
        let brdf = GgxConductor::new(
            ax,
            ay,
            Fresnel::Conductor { eta: Vec3::new(0.2, 0.9, 1.1), k: Vec3::new(3.9, 2.4, 2.2) },
        );
        let col = |v: &Vec<Vec3>, f: fn(&Vec3) -> f32| -> Vec<f32> { v.iter().map(f).collect() };
        let (ox, oy, oz) = (col(&wo, |w| w.x), col(&wo, |w| w.y), col(&wo, |w| w.z));
        let (ix, iy, iz) = (col(&wi, |w| w.x), col(&wi, |w| w.y), col(&wi, |w| w.z));
        let (mut r, mut g, mut b) = (std::vec![0.0; 2048], std::vec![0.0; 2048], std::vec![0.0; 2048]);
        eval(
            &brdf,
            Vec3Slices { x: &ox, y: &oy, z: &oz },
            Vec3Slices { x: &ix, y: &iy, z: &iz },
            Vec3SlicesMut { x: &mut r, y: &mut g, z: &mut b },
        );
        for i in 0..2048 {
            let s = brdf.eval(wo[i], wi[i]);
            let v = Vec3::new(r[i], g[i], b[i]);
            assert!((s - v).length() <= 1e-4 * s.length().max(1e-3), "{ax} {ay} lane {i}: {s:?} vs {v:?}");
        }
    }
}
