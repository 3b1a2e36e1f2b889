//! The sampling routines under test and the checks applied to every sample they return.

use super::grid::{Case, Family, Point};
use super::tally::{Check, Example, Tally};
use ggx_core::fresnel::fresnel_dielectric;
use ggx_core::math::{normalize_or_zero, sanitize_u};
use ggx_core::{
    BsdfSample, Bxdf, Fresnel, GgxConductor, GgxDielectric, Sampling, TransportMode, TrowbridgeReitz, Vec2, Vec3,
    refract,
};

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
    /// `GgxDielectric::sample` with a technique and a transport mode (over the dielectric
    /// cases, [`Family::Dielectric`]).
    Dielectric(Sampling, TransportMode),
}

impl Method {
    /// The techniques `GgxDielectric::sample` accepts (it refuses cosine and uniform;
    /// bounded samples spherical caps).
    pub const DIELECTRIC_SAMPLINGS: [Sampling; 4] =
        [Sampling::Ndf, Sampling::Vndf, Sampling::SphericalCaps, Sampling::Bounded];

    /// Every technique with both Fresnel models, the four raw normal samplers, then every
    /// dielectric technique in both transport modes.
    pub fn all() -> Vec<Method> {
        let brdf = Sampling::ALL
            .into_iter()
            .flat_map(|s| [FresnelChoice::One, FresnelChoice::Conductor].map(|f| Method::Brdf(s, f)));
        let normal = [NormalSampler::Ndf, NormalSampler::Vndf, NormalSampler::SphericalCaps, NormalSampler::Bounded];
        let dielectric = Method::DIELECTRIC_SAMPLINGS
            .into_iter()
            .flat_map(|s| [TransportMode::Radiance, TransportMode::Importance].map(|m| Method::Dielectric(s, m)));
        brdf.chain(normal.map(Method::Normal)).chain(dielectric).collect()
    }

    /// The cases the method runs on.
    pub fn family(self) -> Family {
        match self {
            Method::Dielectric(..) => Family::Dielectric,
            _ => Family::Conductor,
        }
    }

    /// Table label, e.g. `vndf/conductor`, `wm_bounded` or `dielectric/vndf/radiance`.
    pub fn name(self) -> String {
        match self {
            Method::Brdf(s, f) => format!("{}/{}", s.name(), f.name()),
            Method::Normal(n) => n.name().into(),
            Method::Dielectric(s, m) => format!("dielectric/{}/{}", s.name(), mode_name(m)),
        }
    }

    /// True where the weight has an analytic bound: for the conductor `weight <= F(wo . wm)
    /// <= 1` (visible normals, VNDF and spherical caps, give `F G2 / G1(wo)`, bounded VNDF a
    /// ratio below one), for the dielectric `weight <= s`, `s = 1 / eta'^2` for transmitted
    /// radiance and 1 otherwise (`min(G2 / G1(wo), 1) s` for visible normals and bounded,
    /// which samples spherical caps). NDF, cosine and uniform weights have no such bound.
    pub fn has_unit_bound(self) -> bool {
        matches!(
            self,
            Method::Brdf(Sampling::Vndf | Sampling::SphericalCaps | Sampling::Bounded, _)
                | Method::Dielectric(Sampling::Vndf | Sampling::SphericalCaps | Sampling::Bounded, _)
        )
    }

    /// The bound column of the table.
    pub fn bound(self) -> &'static str {
        match self {
            Method::Normal(_) => "-",
            Method::Dielectric(..) if self.has_unit_bound() => "w<=s",
            _ if self.has_unit_bound() => "w<=F",
            // Delta lobes (any technique) are still checked for weight == F <= 1 (conductor)
            // or weight == s (dielectric).
            _ => "none",
        }
    }

    /// True when the method's output depends on `u` for this case: not for a view at or
    /// below the horizon (conductor) or on it (dielectric), rejected up front, and not for a
    /// delta lobe (the mirror, or the dielectric's mirror or refraction, which depend on
    /// `u_lobe` alone); the raw NDF sampler ignores the view. Only such cases get random
    /// samples beyond the u grid.
    pub fn uses_u(self, case: &Case) -> bool {
        match self {
            Method::Normal(NormalSampler::Ndf) => true,
            Method::Normal(_) => case.wo.z > 0.0,
            Method::Brdf(..) => {
                case.wo.z > 0.0 && !GgxConductor::new(case.alpha.0, case.alpha.1, Fresnel::One).is_delta()
            }
            Method::Dielectric(..) => case.wo.z != 0.0 && !dielectric_of(case).is_delta(),
        }
    }

    /// A checker for this method on one case.
    pub fn checker(self, case: &Case) -> Checker {
        let (ax, ay) = case.alpha;
        let fresnel = match self {
            Method::Brdf(_, f) => f.fresnel(),
            _ => Fresnel::One,
        };
        Checker { method: self, wo: case.wo, brdf: GgxConductor::new(ax, ay, fresnel), dielectric: dielectric_of(case) }
    }
}

/// The dielectric of a case (`eta = 1` for a conductor case, where it is unused).
fn dielectric_of(case: &Case) -> GgxDielectric {
    GgxDielectric::new(case.alpha.0, case.alpha.1, case.eta.unwrap_or(1.0))
}

/// `radiance` or `importance`.
pub fn mode_name(mode: TransportMode) -> &'static str {
    match mode {
        TransportMode::Radiance => "radiance",
        TransportMode::Importance => "importance",
    }
}

/// What a delta sample must be, by the BSDF's delta convention.
struct DeltaWant {
    /// The direction: the mirror, or the refracted direction.
    wi: Vec3,
    /// The weight.
    weight: Vec3,
    /// The pdf: 1 (conductor), or the probability of the lobe (dielectric).
    pdf: f32,
    /// Largest valid weight channel.
    bound: f32,
}

/// A BSDF under test: ggx-core's [`Bxdf`] interface plus what the shared checks of
/// [`Checker::check_bsdf`] need to know about it.
trait Subject: Bxdf {
    /// A valid weight may be 0 (the dielectric's `G2` can underflow at grazing `wi`; the
    /// conductor's weights are positive).
    const ZERO_WEIGHT_OK: bool;
    /// True when `sample` returns a delta lobe.
    fn is_delta(&self) -> bool;
    /// True when an accepted sample lies where its lobe puts it, never on the surface.
    fn side_ok(&self, n: Vec3, p: Point, sampling: Sampling, s: &BsdfSample) -> bool;
    /// The delta convention for the normalized view `n` and the lobe choice `u_lobe`.
    fn delta_want(&self, n: Vec3, u_lobe: f32, mode: TransportMode) -> DeltaWant;
    /// The per-channel bound of a rough sample's weight (for [`Method::has_unit_bound`]) and
    /// the largest value that bound itself may take.
    fn rough_bound(&self, n: Vec3, s: &BsdfSample, mode: TransportMode) -> (Vec3, f32);
}

impl Subject for GgxConductor {
    const ZERO_WEIGHT_OK: bool = false;

    fn is_delta(&self) -> bool {
        GgxConductor::is_delta(self)
    }

    fn side_ok(&self, n: Vec3, _: Point, _: Sampling, s: &BsdfSample) -> bool {
        s.wi.z > 0.0 && n.z > 0.0
    }

    fn delta_want(&self, n: Vec3, _: f32, _: TransportMode) -> DeltaWant {
        // eval and pdf are 0 by contract: the weight is F(wo.z), the pdf 1, wi the mirror.
        DeltaWant { wi: Vec3::new(-n.x, -n.y, n.z), weight: self.fresnel.eval(n.z), pdf: 1.0, bound: 1.0 }
    }

    fn rough_bound(&self, n: Vec3, s: &BsdfSample, _: TransportMode) -> (Vec3, f32) {
        (self.fresnel.eval(n.dot(normalize_or_zero(n + s.wi))), 1.0)
    }
}

/// `1 / eta'^2` for transmitted radiance, else 1; `eta' = eta` seen from `+z`, `1 / eta` from
/// `-z`.
fn transport_scale(eta: f32, n: Vec3, transmitted: bool, mode: TransportMode) -> f32 {
    let etap = if n.z > 0.0 { eta } else { 1.0 / eta };
    if transmitted && mode == TransportMode::Radiance { 1.0 / (etap * etap) } else { 1.0 }
}

impl Subject for GgxDielectric {
    const ZERO_WEIGHT_OK: bool = true;

    fn is_delta(&self) -> bool {
        GgxDielectric::is_delta(self)
    }

    /// The lobe is recomputed from the inputs, independently of the returned direction: the
    /// normal the technique draws from `u` (visible normals of `sign(wo.z) wo`, or the NDF;
    /// bounded samples spherical caps), reflection where `u_lobe < F(wo . wm)`; reflection
    /// must stay on `wo`'s side, transmission cross it, and `wi.z = 0` is never valid. A
    /// sample the drawn normal cannot give (facing away from `wo`) fails too.
    fn side_ok(&self, n: Vec3, p: Point, sampling: Sampling, s: &BsdfSample) -> bool {
        let eta = self.eta();
        let reflected = if GgxDielectric::is_delta(self) {
            sanitize_u(p.u_lobe) < fresnel_dielectric(n.z, eta)
        } else {
            let d = &self.distribution;
            let wv = if n.z < 0.0 { -n } else { n };
            let wm = match sampling {
                Sampling::Ndf => d.sample_wm_ndf(p.u),
                Sampling::Vndf => d.sample_wm_vndf(wv, p.u),
                _ => d.sample_wm_spherical_caps(wv, p.u),
            };
            let cos_om = n.dot(wm);
            if !(cos_om * n.z > 0.0) {
                return false;
            }
            sanitize_u(p.u_lobe) < fresnel_dielectric(cos_om, eta)
        };
        let side = s.wi.z * n.z;
        s.wi.z != 0.0 && if reflected { side > 0.0 } else { side < 0.0 }
    }

    fn delta_want(&self, n: Vec3, u_lobe: f32, mode: TransportMode) -> DeltaWant {
        // eval and pdf are 0 by contract: the mirror with pdf F(wo.z) and weight 1, or the
        // refracted direction with pdf 1 - F and weight 1 / eta'^2 (radiance) or 1.
        let eta = self.eta();
        let f = fresnel_dielectric(n.z, eta);
        let reflected = sanitize_u(u_lobe) < f;
        let (wi, pdf) = if reflected {
            (Vec3::new(-n.x, -n.y, n.z), f)
        } else {
            (refract(n, Vec3::Z, eta).map_or(Vec3::ZERO, normalize_or_zero), 1.0 - f)
        };
        let scale = transport_scale(eta, n, !reflected, mode);
        DeltaWant { wi, weight: Vec3::splat(scale), pdf, bound: scale }
    }

    fn rough_bound(&self, n: Vec3, s: &BsdfSample, mode: TransportMode) -> (Vec3, f32) {
        let scale = transport_scale(self.eta(), n, s.is_transmission(n), mode);
        (Vec3::splat(scale), scale)
    }
}

/// Draws and checks samples of one method for one case.
pub struct Checker {
    method: Method,
    wo: Vec3,
    brdf: GgxConductor,
    dielectric: GgxDielectric,
}

impl Checker {
    /// Draws the sample for `p`, checks it and counts the outcome in `t`; `id` identifies
    /// the sample in examples.
    #[inline]
    pub fn check(&self, p: Point, id: u64, t: &mut Tally) {
        t.samples += 1;
        match self.method {
            // The conductor ignores the mode.
            Method::Brdf(sampling, _) => self.check_bsdf(&self.brdf, sampling, TransportMode::Radiance, p, id, t),
            Method::Normal(sampler) => self.check_normal(sampler, p.u, id, t),
            Method::Dielectric(sampling, mode) => self.check_bsdf(&self.dielectric, sampling, mode, p, id, t),
        }
    }

    /// The checks of every BSDF sample, conductor and dielectric alike.
    fn check_bsdf<B: Subject>(
        &self,
        bsdf: &B,
        sampling: Sampling,
        mode: TransportMode,
        p: Point,
        id: u64,
        t: &mut Tally,
    ) {
        let wo = self.wo;
        let Some(s) = bsdf.sample(wo, p.u, p.u_lobe, sampling, mode) else {
            t.rejected += 1;
            return;
        };
        let example = |want: Vec3, error: f32| Example {
            id,
            u: p.u,
            u_lobe: p.u_lobe,
            wi: s.wi,
            weight: s.weight,
            pdf: s.pdf,
            want,
            error,
        };
        if !(s.wi.is_finite() && s.weight.is_finite() && s.pdf.is_finite()) {
            t.flag(Check::NonFinite, || example(Vec3::ZERO, f32::NAN));
            return;
        }
        if (s.wi.length() - 1.0).abs() > UNIT_TOLERANCE {
            t.flag(Check::NonUnit, || example(Vec3::ZERO, f32::NAN));
        }
        let n = normalize_or_zero(wo);
        if !bsdf.side_ok(n, p, sampling, &s) {
            t.flag(Check::BelowHorizon, || example(Vec3::ZERO, f32::NAN));
        }
        let weight_ok = if B::ZERO_WEIGHT_OK { s.weight.min_element() >= 0.0 } else { s.weight.min_element() > 0.0 };
        if !(s.pdf > 0.0 && weight_ok) {
            t.flag(Check::NonPositive, || example(Vec3::ZERO, f32::NAN));
        }
        t.max_weight = t.max_weight.max(s.weight.max_element());
        if s.is_delta || bsdf.is_delta() {
            let want = bsdf.delta_want(n, p.u_lobe, mode);
            let error = rel_error(s.weight, want.weight);
            t.compared += 1;
            t.offer_error(error, || example(want.weight, error));
            let exact = s.is_delta && bsdf.is_delta() && s.pdf == want.pdf && s.wi == want.wi;
            if !(exact && error <= WEIGHT_TOLERANCE) {
                t.flag(Check::WeightMismatch, || example(want.weight, error));
            }
            if s.weight.max_element() > want.bound * (1.0 + BOUND_SLACK) {
                t.flag(Check::OverBound, || example(want.weight, error));
            }
            return;
        }
        if self.method.has_unit_bound() {
            let (bound, limit) = bsdf.rough_bound(n, &s, mode);
            if (s.weight - bound).max_element() > BOUND_SLACK * limit || bound.max_element() > limit + BOUND_SLACK {
                t.flag(Check::OverBound, || example(bound, f32::NAN));
            }
        }
        let pdf = bsdf.pdf(wo, s.wi, sampling, mode);
        if pdf > PDF_FLOOR {
            let want = bsdf.eval(wo, s.wi, mode) / pdf;
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
        let example =
            || Example { id, u, u_lobe: 0.0, wi: wm, weight: Vec3::ZERO, pdf, want: Vec3::ZERO, error: f32::NAN };
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
    fn dielectric_delta_convention_and_side_check() {
        let glass = GgxDielectric::isotropic(1e-7, 1.5);
        let n = Vec3::Z;
        // Normal incidence on glass: F = 0.04.
        let r = glass.delta_want(n, 0.0, TransportMode::Radiance);
        assert_eq!((r.wi, r.weight, r.bound), (Vec3::Z, Vec3::ONE, 1.0));
        assert!((r.pdf - 0.04).abs() < 1e-6);
        let t = glass.delta_want(n, 0.5, TransportMode::Radiance);
        assert_eq!(t.wi, -Vec3::Z);
        assert!((t.weight.x - 1.0 / 2.25).abs() < 1e-6 && (t.pdf - 0.96).abs() < 1e-6);
        assert_eq!(glass.delta_want(n, 0.5, TransportMode::Importance).weight, Vec3::ONE);
        // From inside, radiance is scaled by eta'^2 = 1 / 1.5^2 the other way.
        let inside = glass.delta_want(-n, 0.5, TransportMode::Radiance);
        assert!((inside.weight.x - 2.25).abs() < 1e-5 && inside.wi == Vec3::Z);
        // The side check follows u_lobe, not the returned direction.
        let p = |u_lobe| Point { u: Vec2::ZERO, u_lobe };
        let s = |wi| BsdfSample { wi, weight: Vec3::ONE, pdf: 1.0, is_delta: true };
        assert!(glass.side_ok(n, p(0.0), Sampling::Vndf, &s(Vec3::Z)));
        assert!(!glass.side_ok(n, p(0.5), Sampling::Vndf, &s(Vec3::Z)), "reflected where it should transmit");
        assert!(glass.side_ok(n, p(0.5), Sampling::Vndf, &s(-Vec3::Z)));
        assert!(!glass.side_ok(n, p(0.0), Sampling::Vndf, &s(Vec3::X)), "wi.z = 0");
    }

    #[test]
    fn every_technique_and_normal_sampler_is_covered() {
        let methods = Method::all();
        assert_eq!(methods.len(), 2 * Sampling::ALL.len() + 4 + 2 * Method::DIELECTRIC_SAMPLINGS.len());
        for s in Sampling::ALL {
            assert!(methods.contains(&Method::Brdf(s, FresnelChoice::Conductor)), "{s:?}");
        }
        for s in Method::DIELECTRIC_SAMPLINGS {
            for m in [TransportMode::Radiance, TransportMode::Importance] {
                assert!(methods.contains(&Method::Dielectric(s, m)), "{s:?} {m:?}");
            }
        }
    }
}
