//! Slice (structure-of-arrays) versions of the hot functions. Each lane runs the scalar
//! path's own functions ([`GgxConductor::eval`]'s and [`GgxConductor::pdf`]'s bodies,
//! [`TrowbridgeReitz::d`], Heitz's and the spherical-cap visible-normal samplers and the
//! reflection step of [`GgxConductor::sample`]), written branch-free (selects only, no calls
//! into libm: the polynomial [`crate::math::sincos_2pi`]) so that LLVM auto-vectorizes the
//! loops; slices are re-sliced to one common length so bounds checks vanish. One source, so every lane is the
//! scalar result bit for bit (the tests check it over hostile input).
//!
//! With the `std` feature, [`d`], [`sample_vndf`], [`sample`], [`eval`] and [`pdf`] pick the
//! widest vector ISA of the CPU at run time (`pulp`'s dispatch: x86-64-v4 with AVX-512, v3 with
//! AVX2, else the baseline) and compile the same loop for it; the `*_portable` functions are the
//! loops at the build's baseline ISA (what the dispatching functions run without `std`). Every
//! lane is bit-identical whichever ISA runs it: Rust never contracts `a * b + c` into a fused
//! multiply-add, and `sqrt` and `/` are correctly rounded at every width.
//!
//! Lanes whose sample is invalid (below the horizon, back-facing normal, degenerate input)
//! get a zero direction, weight and pdf instead of an `Option`.
//!
//! ```
//! use ggx_core::batch::{self, Vec3Slices, Vec3SlicesMut};
//! use ggx_core::{Fresnel, GgxConductor, Sampling, Vec2, Vec3};
//!
//! // Four views (tangent space, +z up), one per lane, and two random numbers per lane.
//! let (wo_x, wo_y, wo_z) = ([0.0, 0.3, -0.5, 0.0], [0.0, 0.1, 0.2, 0.6], [1.0, 0.9, 0.8, -0.8]);
//! let (u0, u1) = ([0.1, 0.5, 0.9, 0.3], [0.7, 0.2, 0.4, 0.6]);
//! let gold = Fresnel::Conductor { eta: Vec3::new(0.143, 0.374, 1.442), k: Vec3::new(3.983, 2.385, 1.603) };
//! let brdf = GgxConductor::isotropic(0.3, gold);
//! let (mut wi, mut weight, mut pdf) = ([[0.0f32; 4]; 3], [[0.0f32; 4]; 3], [0.0f32; 4]);
//! let [wx, wy, wz] = &mut wi;
//! let [fx, fy, fz] = &mut weight;
//! let wo = Vec3Slices { x: &wo_x, y: &wo_y, z: &wo_z };
//! let valid = batch::sample(
//!     &brdf,
//!     wo,
//!     &u0,
//!     &u1,
//!     Sampling::Vndf,
//!     Vec3SlicesMut { x: wx, y: wy, z: wz },
//!     Vec3SlicesMut { x: fx, y: fy, z: fz },
//!     &mut pdf,
//! );
//! // The last view is below the horizon: its lane is zero.
//! assert_eq!(valid, 3);
//! assert_eq!((wi[0][3], wi[1][3], wi[2][3], pdf[3]), (0.0, 0.0, 0.0, 0.0));
//! // Each lane is the scalar sampler's result, bit for bit.
//! for i in 0..3 {
//!     let wo = Vec3::new(wo_x[i], wo_y[i], wo_z[i]);
//!     let s = brdf.sample(wo, Vec2::new(u0[i], u1[i]), Sampling::Vndf).unwrap();
//!     assert_eq!(Vec3::new(wi[0][i], wi[1][i], wi[2][i]), s.wi);
//!     assert_eq!(Vec3::new(weight[0][i], weight[1][i], weight[2][i]), s.weight);
//!     assert_eq!(pdf[i], s.pdf);
//! }
//! // The density of those pairs, without sampling: `GgxConductor::pdf`, the same bits.
//! let mut density = [0.0f32; 4];
//! batch::pdf(&brdf, wo, Vec3Slices { x: &wi[0], y: &wi[1], z: &wi[2] }, &mut density);
//! assert_eq!(density[..3], pdf[..3]);
//! ```

use crate::conductor::formulas::{half_terms, pdf_vndf_of};
use crate::conductor::{Reflected, reflect_about};
use crate::fresnel::kind;
use crate::{GgxConductor, Sampling, TrowbridgeReitz};
use glam::{Vec2, Vec3};

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

/// One batch loop: [`dispatched`] runs it for the CPU's widest ISA, [`portable`] at the
/// build's baseline.
trait BatchLoop {
    /// What the loop returns.
    type Output;
    /// The loop, `#[inline(always)]` so that it is compiled for the caller's ISA; `ROUND`: the
    /// ISA has SSE4.1's rounding instruction (`math::sincos_2pi_with`).
    fn run<const ROUND: bool>(self) -> Self::Output;
}

/// `l` compiled for the widest ISA of this CPU (`pulp`'s dispatch) with `std`, else at the
/// baseline.
#[inline(always)]
fn dispatched<L: BatchLoop>(l: L) -> L::Output {
    #[cfg(feature = "std")]
    {
        pulp::Arch::new().dispatch(Dispatch(l))
    }
    #[cfg(not(feature = "std"))]
    {
        l.run::<false>()
    }
}

/// `l` at the build's baseline ISA.
#[inline(always)]
fn portable<L: BatchLoop>(l: L) -> L::Output {
    l.run::<false>()
}

/// A [`BatchLoop`] for `pulp`'s dispatch.
#[cfg(feature = "std")]
struct Dispatch<L>(L);

#[cfg(feature = "std")]
impl<L: BatchLoop> pulp::WithSimd for Dispatch<L> {
    type Output = L::Output;

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) -> L::Output {
        // Every dispatched ISA but the scalar fallback has SSE4.1's rounding instruction.
        if S::IS_SCALAR { self.0.run::<false>() } else { self.0.run::<true>() }
    }
}

/// The length every slice of a loop is cut to: the shortest.
#[inline(always)]
fn common_len<const N: usize>(lens: [usize; N]) -> usize {
    lens.into_iter().min().unwrap_or(0)
}

/// `D(wm)` for a batch of microfacet normals (Trowbridge & Reitz 1975; Walter et al. 2007 eq.
/// 33): [`TrowbridgeReitz::d`]'s values bit for bit, for any input (zero where `wm.z <= 0`).
/// Processes `min` of all lengths.
pub fn d(dist: &TrowbridgeReitz, wm: Vec3Slices, out: &mut [f32]) {
    dispatched(D { dist, wm, out })
}

/// [`d`] at the build's baseline ISA, without run-time dispatch; the same lanes bit for bit.
pub fn d_portable(dist: &TrowbridgeReitz, wm: Vec3Slices, out: &mut [f32]) {
    portable(D { dist, wm, out })
}

/// The arguments of [`d`].
struct D<'a, 'b> {
    dist: &'a TrowbridgeReitz,
    wm: Vec3Slices<'a>,
    out: &'b mut [f32],
}

impl BatchLoop for D<'_, '_> {
    type Output = ();

    #[inline(always)]
    fn run<const ROUND: bool>(self) {
        let n = common_len([self.wm.x.len(), self.wm.y.len(), self.wm.z.len(), self.out.len()]);
        let (x, y, z, out) = (&self.wm.x[..n], &self.wm.y[..n], &self.wm.z[..n], &mut self.out[..n]);
        for i in 0..n {
            out[i] = self.dist.d(Vec3::new(x[i], y[i], z[i]));
        }
    }
}

/// Visible-normal sampling of reflected directions for a batch, by `sampling`:
/// [`Sampling::Vndf`] (Heitz 2018) or [`Sampling::SphericalCaps`] (Dupuy & Benyoub 2023), the
/// same density. For each lane `i`, `wo[i]` (tangent space, normalized as
/// [`GgxConductor::sample`] does) and `u0[i], u1[i]` give `wi[i]` and its density
/// `pdf[i] = D(wm) / (2 (wo.z + so))`: exactly the `wi` and `pdf` of
/// `GgxConductor::sample(wo[i], (u0[i], u1[i]), sampling)` with this distribution, bit for bit,
/// and zeros where that returns `None`. Processes `min` of all slice lengths and returns how
/// many lanes got a valid sample. Any input gives a finite `wi` (unit where valid) and a finite
/// pdf `>= 0`; lanes past the common length are left untouched. A delta lobe is not sampled
/// here (every lane gets zero, as `GgxConductor::pdf` is zero for it): sample mirrors with
/// [`GgxConductor::sample`]; nor are the other techniques (every lane zero).
pub fn sample_vndf(
    dist: &TrowbridgeReitz,
    wo: Vec3Slices,
    u0: &[f32],
    u1: &[f32],
    sampling: Sampling,
    wi: Vec3SlicesMut,
    pdf: &mut [f32],
) -> usize {
    dispatched(Sample { dist, wo, u0, u1, sampling, wi, pdf, weights: NoWeights })
}

/// [`sample_vndf`] at the build's baseline ISA, without run-time dispatch; the same lanes bit for bit.
pub fn sample_vndf_portable(
    dist: &TrowbridgeReitz,
    wo: Vec3Slices,
    u0: &[f32],
    u1: &[f32],
    sampling: Sampling,
    wi: Vec3SlicesMut,
    pdf: &mut [f32],
) -> usize {
    portable(Sample { dist, wo, u0, u1, sampling, wi, pdf, weights: NoWeights })
}

/// [`sample_vndf`] with each sample's weight `f |wi.z| / pdf = F(wo . wm) G2 / G1(wo)` (Heitz
/// 2018 eq. 19) written to `weight` as RGB: lane `i` is `GgxConductor::sample(wo[i], (u0[i],
/// u1[i]), sampling)`'s `wi`, `weight` and `pdf` bit for bit ([`Sampling::Vndf`] or
/// [`Sampling::SphericalCaps`]), and zeros where that returns `None` or a delta sample (a lobe
/// below [`crate::DELTA_ALPHA`] is not sampled here, nor are the other techniques). Processes
/// `min` of all lengths and returns how many lanes got a valid sample; every output is finite
/// for any input.
#[allow(clippy::too_many_arguments)]
pub fn sample(
    brdf: &GgxConductor,
    wo: Vec3Slices,
    u0: &[f32],
    u1: &[f32],
    sampling: Sampling,
    wi: Vec3SlicesMut,
    weight: Vec3SlicesMut,
    pdf: &mut [f32],
) -> usize {
    dispatched(SampleWeighted { brdf, wo, u0, u1, sampling, wi, weight, pdf })
}

/// [`sample`] at the build's baseline ISA, without run-time dispatch; the same lanes bit for bit.
#[allow(clippy::too_many_arguments)]
pub fn sample_portable(
    brdf: &GgxConductor,
    wo: Vec3Slices,
    u0: &[f32],
    u1: &[f32],
    sampling: Sampling,
    wi: Vec3SlicesMut,
    weight: Vec3SlicesMut,
    pdf: &mut [f32],
) -> usize {
    portable(SampleWeighted { brdf, wo, u0, u1, sampling, wi, weight, pdf })
}

/// Where a sampling loop puts each lane's weight.
trait Weights {
    /// Lanes it holds.
    fn len(&self) -> usize;
    /// Cuts it to `n <= len()` lanes.
    fn truncate(&mut self, n: usize);
    /// The weight of a reflected sample: `F(cos_om) * scale`.
    fn of(&self, r: &Reflected) -> Vec3;
    /// Stores lane `i`'s weight.
    fn set(&mut self, i: usize, w: Vec3);
}

/// No weights: [`sample_vndf`].
struct NoWeights;

impl Weights for NoWeights {
    #[inline(always)]
    fn len(&self) -> usize {
        usize::MAX
    }

    #[inline(always)]
    fn truncate(&mut self, _n: usize) {}

    #[inline(always)]
    fn of(&self, _r: &Reflected) -> Vec3 {
        Vec3::ONE
    }

    #[inline(always)]
    fn set(&mut self, _i: usize, _w: Vec3) {}
}

/// RGB weights with the Fresnel term `fresnel(cos_om)`: [`sample`].
struct RgbWeights<'b, F> {
    fresnel: F,
    out: Vec3SlicesMut<'b>,
}

impl<F: Fn(f32) -> Vec3> Weights for RgbWeights<'_, F> {
    #[inline(always)]
    fn len(&self) -> usize {
        common_len([self.out.x.len(), self.out.y.len(), self.out.z.len()])
    }

    #[inline(always)]
    fn truncate(&mut self, n: usize) {
        let out = &mut self.out;
        out.x = &mut core::mem::take(&mut out.x)[..n];
        out.y = &mut core::mem::take(&mut out.y)[..n];
        out.z = &mut core::mem::take(&mut out.z)[..n];
    }

    #[inline(always)]
    fn of(&self, r: &Reflected) -> Vec3 {
        (self.fresnel)(r.cos_om) * r.scale
    }

    #[inline(always)]
    fn set(&mut self, i: usize, w: Vec3) {
        self.out.x[i] = w.x;
        self.out.y[i] = w.y;
        self.out.z[i] = w.z;
    }
}

/// The arguments of [`sample`].
struct SampleWeighted<'a, 'b> {
    brdf: &'a GgxConductor,
    wo: Vec3Slices<'a>,
    u0: &'a [f32],
    u1: &'a [f32],
    sampling: Sampling,
    wi: Vec3SlicesMut<'b>,
    weight: Vec3SlicesMut<'b>,
    pdf: &'b mut [f32],
}

impl BatchLoop for SampleWeighted<'_, '_> {
    type Output = usize;

    /// The loop with the Fresnel term's kind chosen once for the batch (branch-free lanes):
    /// `FresnelParams::eval` of that kind, the same function, so the same bits.
    #[inline(always)]
    fn run<const ROUND: bool>(self) -> usize {
        let f = self.brdf.fresnel;
        match f.kind {
            kind::SCHLICK => self.with_fresnel::<ROUND>(|c| f.eval_as(kind::SCHLICK, c)),
            kind::CONDUCTOR => self.with_fresnel::<ROUND>(|c| f.eval_as(kind::CONDUCTOR, c)),
            kind::DIELECTRIC => self.with_fresnel::<ROUND>(|c| f.eval_as(kind::DIELECTRIC, c)),
            // kind::ONE and any unknown kind: F = 1.
            _ => self.with_fresnel::<ROUND>(|c| f.eval_as(kind::ONE, c)),
        }
    }
}

impl SampleWeighted<'_, '_> {
    /// [`Sample`]'s loop with RGB weights of the Fresnel term `fresnel(cos(wo, wm))`.
    #[inline(always)]
    fn with_fresnel<const ROUND: bool>(self, fresnel: impl Fn(f32) -> Vec3) -> usize {
        let Self { brdf, wo, u0, u1, sampling, wi, weight, pdf } = self;
        let weights = RgbWeights { fresnel, out: weight };
        Sample { dist: &brdf.distribution, wo, u0, u1, sampling, wi, pdf, weights }.run::<ROUND>()
    }
}

/// The sampling loop of [`sample_vndf`] and [`sample`].
struct Sample<'a, 'b, W> {
    dist: &'a TrowbridgeReitz,
    wo: Vec3Slices<'a>,
    u0: &'a [f32],
    u1: &'a [f32],
    sampling: Sampling,
    wi: Vec3SlicesMut<'b>,
    pdf: &'b mut [f32],
    weights: W,
}

impl<W: Weights> BatchLoop for Sample<'_, '_, W> {
    type Output = usize;

    /// The loop with the visible-normal sampler chosen once for the batch (branch-free lanes).
    #[inline(always)]
    fn run<const ROUND: bool>(self) -> usize {
        match self.sampling {
            Sampling::Vndf => self.lanes::<ROUND, true>(),
            _ => self.lanes::<ROUND, false>(),
        }
    }
}

impl<W: Weights> Sample<'_, '_, W> {
    /// The lanes, their normals from Heitz's sampler (`HEITZ`) or the spherical caps; a
    /// technique other than those two fills every lane with zeros, as a delta lobe does.
    #[inline(always)]
    fn lanes<const ROUND: bool, const HEITZ: bool>(self) -> usize {
        let Self { dist, wo, u0, u1, sampling, wi, pdf, mut weights } = self;
        let n = common_len([
            wo.x.len(),
            wo.y.len(),
            wo.z.len(),
            u0.len(),
            u1.len(),
            wi.x.len(),
            wi.y.len(),
            wi.z.len(),
            pdf.len(),
            weights.len(),
        ]);
        let (ox, oy, oz, u0, u1) = (&wo.x[..n], &wo.y[..n], &wo.z[..n], &u0[..n], &u1[..n]);
        let (ix, iy, iz, pdf) = (&mut wi.x[..n], &mut wi.y[..n], &mut wi.z[..n], &mut pdf[..n]);
        weights.truncate(n);
        let refused = dist.is_effectively_smooth() || !matches!(sampling, Sampling::Vndf | Sampling::SphericalCaps);
        // The valid lanes are counted in u32 per chunk: a usize counter makes LLVM pick 8-lane
        // vectors on AVX-512 (16 i64 lanes take two registers), a u32 one 16 lanes (+40-60 %).
        let mut valid = 0usize;
        let mut start = 0;
        while start < n {
            let end = n.min(start.saturating_add(COUNT_CHUNK));
            let mut count = 0u32;
            for i in start..end {
                let wo = crate::math::normalize_or_zero(Vec3::new(ox[i], oy[i], oz[i]));
                let u = Vec2::new(u0[i], u1[i]);
                let wm = if HEITZ {
                    dist.sample_wm_vndf_with::<ROUND>(wo, u)
                } else {
                    dist.sample_wm_spherical_caps_with::<ROUND>(wo, u)
                };
                let r = reflect_about(dist, wo, wm, if HEITZ { Sampling::Vndf } else { Sampling::SphericalCaps });
                let w = weights.of(&r);
                // reflect_about's pdf is 0 for every invalid lane (wm = 0 where wo.z <= 0);
                // GgxConductor::sample also refuses a non-finite weight.
                let ok = !refused && r.pdf > 0.0 && w.is_finite();
                ix[i] = if ok { r.wi.x } else { 0.0 };
                iy[i] = if ok { r.wi.y } else { 0.0 };
                iz[i] = if ok { r.wi.z } else { 0.0 };
                pdf[i] = if ok { r.pdf } else { 0.0 };
                weights.set(i, if ok { w } else { Vec3::ZERO });
                count += ok as u32;
            }
            valid += count as usize;
            start = end;
        }
        valid
    }
}

/// Lanes per `u32` count in [`Sample`]'s loop (far below `u32::MAX`); the tests use a
/// small chunk so that their batches cross chunk boundaries.
const COUNT_CHUNK: usize = if cfg!(test) { 1000 } else { 1 << 20 };

/// `f(wo, wi) |wi.z|` for a batch, written to `out` as RGB: [`GgxConductor::eval`]'s values
/// bit for bit, for any input. Processes `min` of all lengths.
pub fn eval(brdf: &GgxConductor, wo: Vec3Slices, wi: Vec3Slices, out: Vec3SlicesMut) {
    dispatched(Eval { brdf, wo, wi, out })
}

/// [`eval`] at the build's baseline ISA, without run-time dispatch; the same lanes bit for bit.
pub fn eval_portable(brdf: &GgxConductor, wo: Vec3Slices, wi: Vec3Slices, out: Vec3SlicesMut) {
    portable(Eval { brdf, wo, wi, out })
}

/// The arguments of [`eval`].
struct Eval<'a, 'b> {
    brdf: &'a GgxConductor,
    wo: Vec3Slices<'a>,
    wi: Vec3Slices<'a>,
    out: Vec3SlicesMut<'b>,
}

impl BatchLoop for Eval<'_, '_> {
    type Output = ();

    /// [`eval_lanes`] with the Fresnel term's kind chosen once for the batch, so that each loop
    /// is branch-free: `FresnelParams::eval` of that kind (the same function, so the same bits).
    #[inline(always)]
    fn run<const ROUND: bool>(self) {
        let Self { brdf, wo, wi, out } = self;
        let f = brdf.fresnel;
        match f.kind {
            kind::SCHLICK => eval_lanes(brdf, wo, wi, out, |c| f.eval_as(kind::SCHLICK, c)),
            kind::CONDUCTOR => eval_lanes(brdf, wo, wi, out, |c| f.eval_as(kind::CONDUCTOR, c)),
            kind::DIELECTRIC => eval_lanes(brdf, wo, wi, out, |c| f.eval_as(kind::DIELECTRIC, c)),
            // kind::ONE and any unknown kind: F = 1.
            _ => eval_lanes(brdf, wo, wi, out, |c| f.eval_as(kind::ONE, c)),
        }
    }
}

/// The loop of [`eval`] with the Fresnel term `fresnel(cos(wo, wm))`, inlined into each ISA's
/// context.
#[inline(always)]
fn eval_lanes(brdf: &GgxConductor, wo: Vec3Slices, wi: Vec3Slices, out: Vec3SlicesMut, fresnel: impl Fn(f32) -> Vec3) {
    let n = common_len([
        wo.x.len(),
        wo.y.len(),
        wo.z.len(),
        wi.x.len(),
        wi.y.len(),
        wi.z.len(),
        out.x.len(),
        out.y.len(),
        out.z.len(),
    ]);
    let (ox, oy, oz) = (&wo.x[..n], &wo.y[..n], &wo.z[..n]);
    let (ix, iy, iz) = (&wi.x[..n], &wi.y[..n], &wi.z[..n]);
    let (rx, ry, rz) = (&mut out.x[..n], &mut out.y[..n], &mut out.z[..n]);
    for i in 0..n {
        let wo = Vec3::new(ox[i], oy[i], oz[i]);
        let wi = Vec3::new(ix[i], iy[i], iz[i]);
        let v = brdf.eval_with(wo, wi, &fresnel);
        rx[i] = v.x;
        ry[i] = v.y;
        rz[i] = v.z;
    }
}

/// The visible-normal density of reflecting `wo` into `wi` for a batch, `D_wo(wm) / (4 wo.wm) =
/// D(wm) / (2 (wo.z + so))` (Heitz 2018 eq. 17; the density of [`sample_vndf`] and [`sample`]):
/// [`GgxConductor::pdf`]`(wo, wi, Sampling::Vndf)`'s values bit for bit, for any input (zero
/// below either horizon, on a back-facing half vector and for a delta lobe). Processes `min` of
/// all lengths.
pub fn pdf(brdf: &GgxConductor, wo: Vec3Slices, wi: Vec3Slices, out: &mut [f32]) {
    dispatched(Pdf { brdf, wo, wi, out })
}

/// [`pdf`] at the build's baseline ISA, without run-time dispatch; the same lanes bit for bit.
pub fn pdf_portable(brdf: &GgxConductor, wo: Vec3Slices, wi: Vec3Slices, out: &mut [f32]) {
    portable(Pdf { brdf, wo, wi, out })
}

/// The arguments of [`pdf`].
struct Pdf<'a, 'b> {
    brdf: &'a GgxConductor,
    wo: Vec3Slices<'a>,
    wi: Vec3Slices<'a>,
    out: &'b mut [f32],
}

impl BatchLoop for Pdf<'_, '_> {
    type Output = ();

    #[inline(always)]
    fn run<const ROUND: bool>(self) {
        let Self { brdf, wo, wi, out } = self;
        let n = common_len([wo.x.len(), wo.y.len(), wo.z.len(), wi.x.len(), wi.y.len(), wi.z.len(), out.len()]);
        let (ox, oy, oz) = (&wo.x[..n], &wo.y[..n], &wo.z[..n]);
        let (ix, iy, iz, out) = (&wi.x[..n], &wi.y[..n], &wi.z[..n], &mut out[..n]);
        let (a, delta) = (brdf.distribution.widths(), brdf.is_delta());
        for i in 0..n {
            let t = half_terms(a, Vec3::new(ox[i], oy[i], oz[i]).into(), Vec3::new(ix[i], iy[i], iz[i]).into());
            // GgxConductor::pdf's branches as selects: its density is 0 for a delta lobe.
            out[i] = if delta { 0.0 } else { pdf_vndf_of(&t) };
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Fresnel;
    use crate::math::ONE_MINUS_EPSILON;
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

    /// Hostile lanes: NaN, infinities, zeros, subnormals, values just below one, huge values.
    const HOSTILE: [f32; 8] = [f32::NAN, f32::INFINITY, -f32::INFINITY, 0.0, -0.0, 1e-40, ONE_MINUS_EPSILON, 3e38];

    /// Every Fresnel kind, and a raw Schlick that is `-0.0` at normal incidence (the clamp must
    /// give `+0.0` in every lane: `max(-0.0, 0.0)` gave either zero).
    const FRESNELS: [Fresnel; 5] = [
        Fresnel::One,
        Fresnel::Schlick { f0: Vec3::new(0.9, 0.6, 0.3) },
        Fresnel::Conductor { eta: Vec3::new(0.2, 0.9, 1.1), k: Vec3::new(3.9, 2.4, 2.2) },
        Fresnel::Dielectric { eta: 1.5 },
        Fresnel::SchlickF90 { f0: Vec3::new(-0.0, -0.0, -0.0), f90: Vec3::new(-1.0, -1.0, -1.0) },
    ];

    /// `n` views and random pairs for the samplers, with hostile views and numbers in lanes
    /// 100-187 and grazing and non-unit views in lanes 200 and 201.
    fn sampling_lanes(n: usize) -> (Vec<Vec3>, Vec<Vec2>) {
        let (mut wo, mut u) = lanes(n);
        for (i, &x) in HOSTILE.iter().enumerate() {
            wo[100 + i] = Vec3::new(x, 0.3, 0.5);
            wo[120 + i] = Vec3::new(0.1, 0.2, x);
            wo[140 + i] = Vec3::new(0.6, 0.8, 0.0) * (1.0 + x);
            u[160 + i] = Vec2::new(x, 0.4);
            u[180 + i] = Vec2::new(0.7, x);
        }
        wo[200] = Vec3::new(1.0, 0.0, 1e-7);
        wo[201] = Vec3::new(0.0, 3.0, 4.0);
        (wo, u)
    }

    /// The x, y and z columns of `v`.
    fn columns(v: &[Vec3]) -> [Vec<f32>; 3] {
        [v.iter().map(|w| w.x).collect(), v.iter().map(|w| w.y).collect(), v.iter().map(|w| w.z).collect()]
    }

    /// Every lane of `sample_vndf` is `GgxConductor::sample(.., sampling)`'s `wi` and pdf bit
    /// for bit (zeros where it returns `None` or a delta), Heitz's sampler and the spherical
    /// caps, over the whole alpha range and hostile lanes: the batch runs the scalar path's own
    /// functions.
    #[test]
    fn batch_sampling_is_the_scalar_visible_normal_sampler_bit_for_bit() {
        for sampling in [Sampling::Vndf, Sampling::SphericalCaps] {
            batch_sampling_matches(sampling);
        }
    }

    fn batch_sampling_matches(sampling: Sampling) {
        let (wo, u) = sampling_lanes(4096);
        // The whole alpha range: deltas (below 1e-3, where the scalar pdf is 0), the threshold,
        // near-mirrors, anisotropic and rough lobes.
        let alphas = [(1e-4f32, 1e-4f32), (5e-4, 9e-4), (9.99e-4, 9.99e-4), (1e-3, 1e-3), (0.0011, 0.0011)];
        let bits = |v: Vec3| v.to_array().map(f32::to_bits);
        for (ax, ay) in alphas.into_iter().chain([(0.01, 0.002), (0.3, 0.3), (0.05, 0.5), (1.0, 1.0)]) {
            let brdf = GgxConductor::new(ax, ay, Fresnel::One);
            let [x, y, z] = columns(&wo);
            let (u0, u1): (Vec<f32>, Vec<f32>) = (u.iter().map(|v| v.x).collect(), u.iter().map(|v| v.y).collect());
            let (mut rx, mut ry, mut rz, mut pdf) =
                (std::vec![9.0; 4096], std::vec![9.0; 4096], std::vec![9.0; 4096], std::vec![9.0; 4096]);
            let valid = sample_vndf(
                &brdf.distribution,
                Vec3Slices { x: &x, y: &y, z: &z },
                &u0,
                &u1,
                sampling,
                Vec3SlicesMut { x: &mut rx, y: &mut ry, z: &mut rz },
                &mut pdf,
            );
            let mut scalar_valid = 0;
            for i in 0..4096 {
                let s = brdf.sample(wo[i], u[i], sampling).filter(|s| !s.is_delta);
                let (want_wi, want_pdf) = s.map_or((Vec3::ZERO, 0.0), |s| (s.wi, s.pdf));
                scalar_valid += s.is_some() as usize;
                let got = Vec3::new(rx[i], ry[i], rz[i]);
                assert_eq!(
                    (bits(got), pdf[i].to_bits()),
                    (bits(want_wi), want_pdf.to_bits()),
                    "{sampling:?} {ax} {ay} lane {i}: wo {:?} u {:?}: {got:?} {} vs {want_wi:?} {want_pdf}",
                    wo[i],
                    u[i],
                    pdf[i]
                );
                if s.is_some() {
                    assert_eq!(brdf.pdf(wo[i], want_wi, sampling).to_bits(), want_pdf.to_bits(), "lane {i}");
                }
            }
            assert_eq!(valid, scalar_valid, "{ax} {ay}");
            if brdf.is_delta() {
                assert_eq!(valid, 0, "{ax} {ay}: a delta lobe");
            } else {
                assert!(valid > 2000, "{ax} {ay}: {valid} valid lanes");
            }
        }
    }

    /// The dispatched loops (the widest ISA of this CPU) give the baseline loops' lanes bit for
    /// bit, every batch function: over the alpha range, every Fresnel kind, and hostile lanes (NaN, infinities, zero,
    /// subnormal, non-unit, below the horizon).
    #[test]
    fn dispatched_lanes_are_the_portable_lanes_bit_for_bit() {
        let (mut wo, u) = lanes(1000);
        let mut wi: Vec<Vec3> = u.iter().map(|&v| crate::warp::sample_cosine_hemisphere(v)).collect();
        for (i, &x) in HOSTILE.iter().enumerate() {
            wo[5 + i] = Vec3::new(x, 0.3, 0.5);
            wo[20 + i] = Vec3::new(0.1, 0.2, x);
            wi[40 + i] = Vec3::new(0.2, x, 0.4);
            wi[60 + i] = Vec3::new(x, x, x);
        }
        let (mut u0, mut u1): (Vec<f32>, Vec<f32>) = (u.iter().map(|v| v.x).collect(), u.iter().map(|v| v.y).collect());
        for (i, &x) in HOSTILE.iter().enumerate() {
            (u0[80 + i], u1[90 + i]) = (x, x);
        }
        let [ox, oy, oz] = columns(&wo);
        let [ix, iy, iz] = columns(&wi);
        let bits = |v: &[f32]| -> Vec<u32> { v.iter().map(|x| x.to_bits()).collect() };
        let alphas =
            [(1e-4f32, 1e-4f32), (9.99e-4, 5e-4), (1e-3, 1e-3), (0.01, 0.002), (0.3, 0.3), (0.05, 0.5), (1.0, 1.0)];
        let techniques = [Sampling::Vndf, Sampling::SphericalCaps, Sampling::SphericalCaps];
        for ((ax, ay), sampling) in alphas.into_iter().zip(techniques.into_iter().cycle()) {
            for fresnel in FRESNELS {
                let brdf = GgxConductor::new(ax, ay, fresnel);
                let run = |portable: bool| {
                    let mut r =
                        [std::vec![0.0f32; 1000], std::vec![0.0; 1000], std::vec![0.0; 1000], std::vec![0.0; 1000]];
                    let [rx, ry, rz, pdf] = &mut r;
                    let o = Vec3Slices { x: &ox, y: &oy, z: &oz };
                    let out = Vec3SlicesMut { x: rx, y: ry, z: rz };
                    let valid = if portable {
                        sample_vndf_portable(&brdf.distribution, o, &u0, &u1, sampling, out, pdf)
                    } else {
                        sample_vndf(&brdf.distribution, o, &u0, &u1, sampling, out, pdf)
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
                    // The weighted sampler, the pdf of the pairs and D of the wi lanes as normals.
                    let mut w = [
                        std::vec![0.0f32; 1000],
                        std::vec![0.0; 1000],
                        std::vec![0.0; 1000],
                        std::vec![0.0; 1000],
                        std::vec![0.0; 1000],
                        std::vec![0.0; 1000],
                        std::vec![0.0; 1000],
                        std::vec![0.0; 1000],
                        std::vec![0.0; 1000],
                    ];
                    let [sx, sy, sz, wx, wy, wz, sp, pp, dd] = &mut w;
                    let s_wi = Vec3SlicesMut { x: sx, y: sy, z: sz };
                    let s_w = Vec3SlicesMut { x: wx, y: wy, z: wz };
                    let weighted = if portable {
                        let v = sample_portable(&brdf, o, &u0, &u1, sampling, s_wi, s_w, sp);
                        pdf_portable(&brdf, o, i, pp);
                        d_portable(&brdf.distribution, i, dd);
                        v
                    } else {
                        let v = sample(&brdf, o, &u0, &u1, sampling, s_wi, s_w, sp);
                        super::pdf(&brdf, o, i, pp);
                        d(&brdf.distribution, i, dd);
                        v
                    };
                    let all: Vec<Vec<u32>> = r.iter().chain(&e).chain(&w).map(|v| bits(v)).collect();
                    assert!(
                        r.iter().chain(&e).chain(&w).flatten().all(|x| x.is_finite()),
                        "{ax} {ay} {fresnel:?}: finite lanes"
                    );
                    (valid, weighted, all)
                };
                assert_eq!(run(false), run(true), "{ax} {ay} {fresnel:?} {sampling:?}");
            }
        }
    }

    /// Every lane of `eval` is `GgxConductor::eval`'s value bit for bit, for every Fresnel kind,
    /// over the alpha range and hostile lanes (non-unit, grazing, back-facing half vectors).
    #[test]
    fn batch_eval_is_the_scalar_eval_bit_for_bit() {
        let (mut wo, u) = lanes(2048);
        let mut wi: Vec<Vec3> = u.iter().map(|&v| crate::warp::sample_cosine_hemisphere(v)).collect();
        // Grazing pairs where wo ~ -wi: the half vector is back-facing after rounding.
        wi[3] = Vec3::new(-wo[3].x, -wo[3].y, 1e-7).normalize();
        wi[4] = Vec3::new(1.0, 0.0, 1e-30);
        wi[5] = Vec3::new(0.0, 3.0, 4.0);
        // Normal incidence: the Fresnel term's argument is exactly 1.
        (wo[7], wi[7], wo[100], wi[100]) = (Vec3::Z, Vec3::Z, Vec3::Z, Vec3::Z);
        for (i, &x) in HOSTILE.iter().enumerate() {
            wo[10 + i] = Vec3::new(x, 0.3, 0.5);
            wi[30 + i] = Vec3::new(0.2, x, 0.4);
            wi[50 + i] = Vec3::splat(x);
        }
        let [ox, oy, oz] = columns(&wo);
        let [ix, iy, iz] = columns(&wi);
        for (ax, ay) in [(0.2f32, 0.6f32), (1e-4, 1e-4), (9e-4, 5e-4), (1e-3, 1e-3), (0.004, 0.02), (1.0, 1.0)] {
            for fresnel in FRESNELS {
                let brdf = GgxConductor::new(ax, ay, fresnel);
                let (mut r, mut g, mut b) = (std::vec![9.0; 2048], std::vec![9.0; 2048], std::vec![9.0; 2048]);
                eval(
                    &brdf,
                    Vec3Slices { x: &ox, y: &oy, z: &oz },
                    Vec3Slices { x: &ix, y: &iy, z: &iz },
                    Vec3SlicesMut { x: &mut r, y: &mut g, z: &mut b },
                );
                let mut nonzero = 0;
                for i in 0..2048 {
                    let s = brdf.eval(wo[i], wi[i]);
                    let v = Vec3::new(r[i], g[i], b[i]);
                    assert_eq!(
                        v.to_array().map(f32::to_bits),
                        s.to_array().map(f32::to_bits),
                        "{ax} {ay} {fresnel:?} lane {i}: {v:?} vs {s:?}"
                    );
                    nonzero += (s != Vec3::ZERO) as usize;
                }
                // The raw Schlick term is <= 0 everywhere: every lane is zero.
                let black = matches!(fresnel, Fresnel::SchlickF90 { .. });
                assert_eq!(nonzero > 1500, !brdf.is_delta() && !black, "{ax} {ay}: {nonzero} non-zero lanes");
            }
        }
    }

    /// Every lane of `sample` is `GgxConductor::sample(.., sampling)`'s `wi`, weight and pdf
    /// bit for bit (zeros where it returns `None` or a delta), Heitz's sampler and the
    /// spherical caps, for every Fresnel kind, over the alpha range and hostile lanes; the other
    /// techniques are refused, every lane zero.
    #[test]
    fn batch_weighted_sampling_is_the_scalar_sampler_bit_for_bit() {
        for sampling in Sampling::ALL {
            batch_weighted_sampling_matches(sampling);
        }
    }

    fn batch_weighted_sampling_matches(sampling: Sampling) {
        let batched = matches!(sampling, Sampling::Vndf | Sampling::SphericalCaps);
        let (wo, u) = sampling_lanes(3000);
        let [x, y, z] = columns(&wo);
        let (u0, u1): (Vec<f32>, Vec<f32>) = (u.iter().map(|v| v.x).collect(), u.iter().map(|v| v.y).collect());
        let bits = |v: Vec3| v.to_array().map(f32::to_bits);
        for (ax, ay) in
            [(1e-4f32, 1e-4f32), (9.99e-4, 5e-4), (1e-3, 1e-3), (0.01, 0.002), (0.3, 0.3), (0.05, 0.5), (1.0, 1.0)]
        {
            for fresnel in FRESNELS {
                let brdf = GgxConductor::new(ax, ay, fresnel);
                let mut o = [(); 7].map(|_| std::vec![9.0f32; 3000]);
                let [rx, ry, rz, wx, wy, wz, pdf] = &mut o;
                let valid = sample(
                    &brdf,
                    Vec3Slices { x: &x, y: &y, z: &z },
                    &u0,
                    &u1,
                    sampling,
                    Vec3SlicesMut { x: rx, y: ry, z: rz },
                    Vec3SlicesMut { x: wx, y: wy, z: wz },
                    pdf,
                );
                let mut scalar_valid = 0;
                for i in 0..3000 {
                    let s = brdf.sample(wo[i], u[i], sampling).filter(|s| !s.is_delta && batched);
                    let (want_wi, want_w, want_pdf) =
                        s.map_or((Vec3::ZERO, Vec3::ZERO, 0.0), |s| (s.wi, s.weight, s.pdf));
                    scalar_valid += s.is_some() as usize;
                    let (got_wi, got_w) = (Vec3::new(rx[i], ry[i], rz[i]), Vec3::new(wx[i], wy[i], wz[i]));
                    assert_eq!(
                        (bits(got_wi), bits(got_w), pdf[i].to_bits()),
                        (bits(want_wi), bits(want_w), want_pdf.to_bits()),
                        "{sampling:?} {ax} {ay} {fresnel:?} lane {i}: wo {:?} u {:?}",
                        wo[i],
                        u[i]
                    );
                }
                assert_eq!(valid, scalar_valid, "{sampling:?} {ax} {ay} {fresnel:?}");
                assert_eq!(valid > 1500, batched && !brdf.is_delta(), "{sampling:?} {ax} {ay}: {valid} valid lanes");
            }
        }
    }

    /// Every lane of `pdf` is `GgxConductor::pdf(.., Vndf)` (whose match arm `SphericalCaps`
    /// shares) and every lane of `d` is `TrowbridgeReitz::d`, bit for bit, over the
    /// alpha range and hostile lanes (grazing, back-facing half vectors, below the horizon).
    #[test]
    fn batch_pdf_and_d_are_the_scalar_functions_bit_for_bit() {
        let (mut wo, u) = lanes(2048);
        let mut wi: Vec<Vec3> = u.iter().map(|&v| crate::warp::sample_cosine_hemisphere(v)).collect();
        wi[3] = Vec3::new(-wo[3].x, -wo[3].y, 1e-7).normalize();
        wi[4] = Vec3::new(1.0, 0.0, 1e-30);
        wi[5] = Vec3::new(0.0, 3.0, 4.0);
        wi[6] = Vec3::new(0.1, 0.2, -0.9);
        for (i, &x) in HOSTILE.iter().enumerate() {
            wo[10 + i] = Vec3::new(x, 0.3, 0.5);
            wi[30 + i] = Vec3::new(0.2, x, 0.4);
            wi[50 + i] = Vec3::splat(x);
        }
        let [ox, oy, oz] = columns(&wo);
        let [ix, iy, iz] = columns(&wi);
        for (ax, ay) in [(0.2f32, 0.6f32), (1e-4, 1e-4), (9e-4, 5e-4), (1e-3, 1e-3), (0.004, 0.02), (1.0, 1.0)] {
            let brdf = GgxConductor::new(ax, ay, Fresnel::One);
            let (mut p, mut dd) = (std::vec![9.0; 2048], std::vec![9.0; 2048]);
            pdf(&brdf, Vec3Slices { x: &ox, y: &oy, z: &oz }, Vec3Slices { x: &ix, y: &iy, z: &iz }, &mut p);
            // The wi lanes as microfacet normals (some below the horizon: D = 0 there).
            d(&brdf.distribution, Vec3Slices { x: &ix, y: &iy, z: &iz }, &mut dd);
            let mut positive = 0;
            for i in 0..2048 {
                let want = brdf.pdf(wo[i], wi[i], Sampling::Vndf);
                assert_eq!(p[i].to_bits(), want.to_bits(), "{ax} {ay} lane {i}: {} vs {want}", p[i]);
                let want_d = brdf.distribution.d(wi[i]);
                assert_eq!(dd[i].to_bits(), want_d.to_bits(), "{ax} {ay} lane {i}: D {} vs {want_d}", dd[i]);
                positive += (want > 0.0) as usize;
            }
            assert_eq!(positive > 1500, !brdf.is_delta(), "{ax} {ay}: {positive} positive lanes");
        }
    }
}
