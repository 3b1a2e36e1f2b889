//! The sampling routines under test and the checks applied to every sample they return.

use super::grid::Case;
use super::tally::{Check, Example, Tally};
use ggx_core::math::normalize_or_zero;
use ggx_core::{Fresnel, GgxConductor, Sampling, TrowbridgeReitz, Vec2, Vec3};

/// Largest accepted `| |w| - 1 |` of a returned direction.
pub const UNIT_TOLERANCE: f32 = 1e-5;
/// Slack on the analytic weight bound `weight <= F <= 1`.
pub const BOUND_SLACK: f32 = 1e-5;
/// Largest relative difference between `weight` and `eval / pdf` (and between the sample's
/// pdf and `pdf()`) that counts as agreement.
pub const WEIGHT_TOLERANCE: f32 = 1e-3;
/// `weight` is compared with `eval / pdf` only where `pdf > PDF_FLOOR`.
pub const PDF_FLOOR: f32 = 1e-3;

/// The Fresnel models every technique runs with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FresnelChoice {
    /// `F = 1`.
    One,
    /// A copper-like conductor, `eta = (0.2, 0.92, 1.1)`, `k = (3.9, 2.45, 2.2)`.
    Conductor,
}

impl FresnelChoice {
    /// The model.
    pub fn fresnel(self) -> Fresnel {
        match self {
            FresnelChoice::One => Fresnel::One,
            FresnelChoice::Conductor => {
                Fresnel::Conductor { eta: Vec3::new(0.2, 0.92, 1.1), k: Vec3::new(3.9, 2.45, 2.2) }
            }
        }
    }

    fn name(self) -> &'static str {
        match self {
            FresnelChoice::One => "F=1",
            FresnelChoice::Conductor => "conductor",
        }
    }
}

/// A raw microfacet-normal sampler of [`TrowbridgeReitz`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NormalSampler {
    /// `sample_wm_ndf`, density `D(wm) wm.z`.
    Ndf,
    /// `sample_wm_vndf`, density `D_wo(wm)`.
    Vndf,
    /// `sample_wm_spherical_caps`, density `D_wo(wm)`.
    SphericalCaps,
    /// `sample_wm_bounded`; its density is checked with `pdf_wi_bounded` (that of the
    /// reflected direction, positive exactly where `D(wm)` is).
    Bounded,
}

impl NormalSampler {
    #[inline]
    fn sample(self, d: &TrowbridgeReitz, wo: Vec3, u: Vec2) -> Vec3 {
        match self {
            NormalSampler::Ndf => d.sample_wm_ndf(u),
            NormalSampler::Vndf => d.sample_wm_vndf(wo, u),
            NormalSampler::SphericalCaps => d.sample_wm_spherical_caps(wo, u),
            NormalSampler::Bounded => d.sample_wm_bounded(wo, u),
        }
    }

    #[inline]
    fn pdf(self, d: &TrowbridgeReitz, wo: Vec3, wm: Vec3) -> f32 {
        match self {
            NormalSampler::Ndf => d.pdf_wm_ndf(wm),
            NormalSampler::Vndf | NormalSampler::SphericalCaps => d.d_visible(wo, wm),
            NormalSampler::Bounded => d.pdf_wi_bounded(wo, wm),
        }
    }

    fn name(self) -> &'static str {
        match self {
            NormalSampler::Ndf => "wm_ndf",
            NormalSampler::Vndf => "wm_vndf",
            NormalSampler::SphericalCaps => "wm_spherical_caps",
            NormalSampler::Bounded => "wm_bounded",
        }
    }
}

/// One routine under test.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// `GgxConductor::sample` with a technique and a Fresnel model.
    Brdf(Sampling, FresnelChoice),
    /// A raw `TrowbridgeReitz::sample_wm_*`.
    Normal(NormalSampler),
}

impl Method {
    /// Every technique with both Fresnel models, then the four raw normal samplers.
    pub fn all() -> Vec<Method> {
        let brdf = Sampling::ALL
            .into_iter()
            .flat_map(|s| [FresnelChoice::One, FresnelChoice::Conductor].map(|f| Method::Brdf(s, f)));
        let normal = [NormalSampler::Ndf, NormalSampler::Vndf, NormalSampler::SphericalCaps, NormalSampler::Bounded];
        brdf.chain(normal.map(Method::Normal)).collect()
    }

    /// Table label, e.g. `vndf/conductor` or `wm_bounded`.
    pub fn name(self) -> String {
        match self {
            Method::Brdf(s, f) => format!("{}/{}", s.name(), f.name()),
            Method::Normal(n) => n.name().into(),
        }
    }

    /// True where the weight has the analytic bound `weight <= F(wo . wm) <= 1`: visible
    /// normals (VNDF, spherical caps) give `F G2 / G1(wo)`, bounded VNDF a ratio below one.
    /// NDF, cosine and uniform weights have no bound of 1 and are not checked.
    pub fn has_unit_bound(self) -> bool {
        matches!(self, Method::Brdf(Sampling::Vndf | Sampling::SphericalCaps | Sampling::Bounded, _))
    }

    /// The bound column of the table.
    pub fn bound(self) -> &'static str {
        match self {
            Method::Normal(_) => "-",
            _ if self.has_unit_bound() => "w<=F",
            // Delta lobes (any technique) are still checked for weight == F <= 1.
            _ => "none",
        }
    }

    /// True when the method's output depends on `u` for this case: not for a view at or
    /// below the horizon (rejected up front) and not for a delta lobe (the mirror); the raw
    /// NDF sampler ignores the view. Only such cases get random samples beyond the u grid.
    pub fn uses_u(self, case: &Case) -> bool {
        match self {
            Method::Normal(NormalSampler::Ndf) => true,
            Method::Normal(_) => case.wo.z > 0.0,
            Method::Brdf(..) => {
                case.wo.z > 0.0 && !GgxConductor::new(case.alpha.0, case.alpha.1, Fresnel::One).is_delta()
            }
        }
    }

    /// A checker for this method on one case.
    pub fn checker(self, case: &Case) -> Checker {
        let (ax, ay) = case.alpha;
        let fresnel = match self {
            Method::Brdf(_, f) => f.fresnel(),
            Method::Normal(_) => Fresnel::One,
        };
        Checker { method: self, wo: case.wo, brdf: GgxConductor::new(ax, ay, fresnel) }
    }
}

/// Draws and checks samples of one method for one case.
pub struct Checker {
    method: Method,
    wo: Vec3,
    brdf: GgxConductor,
}

impl Checker {
    /// Draws the sample for `u`, checks it and counts the outcome in `t`; `id` identifies
    /// the sample in examples.
    #[inline]
    pub fn check(&self, u: Vec2, id: u64, t: &mut Tally) {
        t.samples += 1;
        match self.method {
            Method::Brdf(sampling, _) => self.check_brdf(sampling, u, id, t),
            Method::Normal(sampler) => self.check_normal(sampler, u, id, t),
        }
    }

    fn check_brdf(&self, sampling: Sampling, u: Vec2, id: u64, t: &mut Tally) {
        let (brdf, wo) = (&self.brdf, self.wo);
        let Some(s) = brdf.sample(wo, u, sampling) else {
            t.rejected += 1;
            return;
        };
        let example = |want: Vec3, error: f32| Example { id, u, wi: s.wi, weight: s.weight, pdf: s.pdf, want, error };
        if !(s.wi.is_finite() && s.weight.is_finite() && s.pdf.is_finite()) {
            t.flag(Check::NonFinite, || example(Vec3::ZERO, f32::NAN));
            return;
        }
        if (s.wi.length() - 1.0).abs() > UNIT_TOLERANCE {
            t.flag(Check::NonUnit, || example(Vec3::ZERO, f32::NAN));
        }
        if !(s.wi.z > 0.0 && wo.z > 0.0) {
            t.flag(Check::BelowHorizon, || example(Vec3::ZERO, f32::NAN));
        }
        if !(s.pdf > 0.0 && s.weight.min_element() > 0.0) {
            t.flag(Check::NonPositive, || example(Vec3::ZERO, f32::NAN));
        }
        t.max_weight = t.max_weight.max(s.weight.max_element());
        let n = normalize_or_zero(wo);
        if s.is_delta || brdf.is_delta() {
            // eval and pdf are 0 by contract: the weight is F(wo.z), the pdf 1, wi the mirror.
            let f = brdf.fresnel.eval(n.z);
            let error = rel_error(s.weight, f);
            t.compared += 1;
            t.offer_error(error, || example(f, error));
            let mirror = Vec3::new(-n.x, -n.y, n.z);
            let exact = s.is_delta && brdf.is_delta() && s.pdf == 1.0 && s.wi == mirror;
            if !(exact && error <= WEIGHT_TOLERANCE) {
                t.flag(Check::WeightMismatch, || example(f, error));
            }
            if s.weight.max_element() > 1.0 + BOUND_SLACK {
                t.flag(Check::OverBound, || example(f, error));
            }
            return;
        }
        if self.method.has_unit_bound() {
            let f = brdf.fresnel.eval(n.dot(normalize_or_zero(n + s.wi)));
            if (s.weight - f).max_element() > BOUND_SLACK || f.max_element() > 1.0 + BOUND_SLACK {
                t.flag(Check::OverBound, || example(f, f32::NAN));
            }
        }
        let pdf = brdf.pdf(wo, s.wi, sampling);
        if pdf > PDF_FLOOR {
            let want = brdf.eval(wo, s.wi) / pdf;
            let error = rel_error(s.weight, want);
            t.compared += 1;
            t.offer_error(error, || example(want, error));
            if !(error <= WEIGHT_TOLERANCE) {
                t.flag(Check::WeightMismatch, || example(want, error));
            }
            let pdf_error = rel_error(Vec3::splat(s.pdf), Vec3::splat(pdf));
            if !(pdf_error <= WEIGHT_TOLERANCE) {
                t.flag(Check::PdfMismatch, || example(Vec3::splat(pdf), pdf_error));
            }
        }
    }

    fn check_normal(&self, sampler: NormalSampler, u: Vec2, id: u64, t: &mut Tally) {
        let (d, wo) = (&self.brdf.distribution, self.wo);
        let wm = sampler.sample(d, wo, u);
        if wm == Vec3::ZERO {
            t.rejected += 1;
            return;
        }
        let pdf = sampler.pdf(d, wo, wm);
        let example = || Example { id, u, wi: wm, weight: Vec3::ZERO, pdf, want: Vec3::ZERO, error: f32::NAN };
        if !(wm.is_finite() && pdf.is_finite()) {
            t.flag(Check::NonFinite, example);
            return;
        }
        if (wm.length() - 1.0).abs() > UNIT_TOLERANCE {
            t.flag(Check::NonUnit, example);
        }
        // wm.z = 0 is allowed by the samplers' contract (its density, 0, is caught below).
        let view_ok = wo.z > 0.0 || sampler == NormalSampler::Ndf;
        if !(wm.z >= 0.0 && view_ok) {
            t.flag(Check::BelowHorizon, example);
        }
        if !(pdf > 0.0) {
            t.flag(Check::ZeroDensity, example);
        }
    }
}

/// Largest relative difference over the channels, `|got - want| / |want|`: 0 where they
/// are equal, infinite where only `want` is 0 or either is NaN.
pub fn rel_error(got: Vec3, want: Vec3) -> f32 {
    let mut worst = 0.0f32;
    for i in 0..3 {
        let (g, w) = (got[i], want[i]);
        let e = if g == w { 0.0 } else { (g - w).abs() / w.abs() };
        worst = if e <= f32::MAX { worst.max(e) } else { f32::INFINITY };
    }
    worst
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rel_error_is_relative_and_never_nan() {
        assert_eq!(rel_error(Vec3::ONE, Vec3::ONE), 0.0);
        assert!((rel_error(Vec3::new(1.0, 2.0, 3.3), Vec3::new(1.0, 2.0, 3.0)) - 0.1).abs() < 1e-6);
        assert_eq!(rel_error(Vec3::X, Vec3::ZERO), f32::INFINITY);
        assert_eq!(rel_error(Vec3::ZERO, Vec3::ZERO), 0.0);
        assert_eq!(rel_error(Vec3::splat(f32::NAN), Vec3::ONE), f32::INFINITY);
    }

    #[test]
    fn every_technique_and_normal_sampler_is_covered() {
        let methods = Method::all();
        assert_eq!(methods.len(), 2 * Sampling::ALL.len() + 4);
        for s in Sampling::ALL {
            assert!(methods.contains(&Method::Brdf(s, FresnelChoice::Conductor)), "{s:?}");
        }
    }
}
