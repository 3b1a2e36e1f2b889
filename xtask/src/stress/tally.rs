//! Per-method counts of what went wrong, with reproducible examples: the first sample of
//! each kind of failure and the worst disagreements between `weight` and `eval / pdf`.

use ggx_core::{Vec2, Vec3};

/// How many worst weight disagreements each tally keeps.
pub const WORST: usize = 3;

/// What an accepted sample can get wrong; indexes [`Tally::counts`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Check {
    /// NaN or infinity in the direction, weight or pdf.
    NonFinite,
    /// Direction whose length is off 1 by more than [`super::method::UNIT_TOLERANCE`].
    NonUnit,
    /// Accepted although `wi.z <= 0` (normal samplers: `wm.z < 0`), or although the view
    /// itself is at or below the horizon. Dielectric: `wi` on the wrong side for the lobe
    /// `u_lobe` selects (reflection keeps `wo`'s side, transmission crosses), or `wi.z = 0`.
    BelowHorizon,
    /// A finite pdf `<= 0`, or a weight channel `<= 0` (dielectric: `< 0`).
    NonPositive,
    /// Weight above its analytic bound (see [`super::method::Method::bound`]).
    OverBound,
    /// `weight != eval / pdf` (delta lobes: weight, pdf or direction off the delta convention).
    WeightMismatch,
    /// The sample's pdf differs from `pdf()` (`GgxConductor::pdf`, `GgxDielectric::pdf`) for
    /// the same pair.
    PdfMismatch,
    /// Normal samplers only: a returned normal whose own density is 0 (back-facing to the
    /// view, or horizontal). Reported, never fails: `GgxConductor::sample` rejects them.
    ZeroDensity,
}

impl Check {
    /// Number of checks.
    pub const COUNT: usize = 8;
    /// Every check, in column order.
    pub const ALL: [Check; Check::COUNT] = [
        Check::NonFinite,
        Check::NonUnit,
        Check::BelowHorizon,
        Check::NonPositive,
        Check::OverBound,
        Check::WeightMismatch,
        Check::PdfMismatch,
        Check::ZeroDensity,
    ];

    /// Column header.
    pub fn label(self) -> &'static str {
        match self {
            Check::NonFinite => "nan/inf",
            Check::NonUnit => "non-unit",
            Check::BelowHorizon => "below-hz",
            Check::NonPositive => "w|p<=0",
            Check::OverBound => "over-bnd",
            Check::WeightMismatch => "w!=f/p",
            Check::PdfMismatch => "p!=pdf()",
            Check::ZeroDensity => "p(wm)=0",
        }
    }

    /// Share of a method's samples above which the check fails the run: 0 (any occurrence)
    /// for invalid samples, `mismatch_share` for the weight and pdf disagreements, `None`
    /// (never) for [`Check::ZeroDensity`].
    pub fn fail_share(self, mismatch_share: f64) -> Option<f64> {
        match self {
            Check::WeightMismatch | Check::PdfMismatch => Some(mismatch_share),
            Check::ZeroDensity => None,
            _ => Some(0.0),
        }
    }
}

/// One sample with its inputs and outputs, enough to reproduce and judge it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Example {
    /// `case index << 32 | sample index within the case`: orders examples deterministically.
    pub id: u64,
    /// Random numbers passed to the sampler.
    pub u: Vec2,
    /// The lobe choice passed to the dielectric (0, unused, for the other methods).
    pub u_lobe: f32,
    /// Returned direction (`wm` for the normal samplers).
    pub wi: Vec3,
    /// Returned weight (zero for the normal samplers).
    pub weight: Vec3,
    /// Returned pdf (normal samplers: the density of the returned normal).
    pub pdf: f32,
    /// What the weight should be: `eval / pdf`, or the delta convention's weight.
    pub want: Vec3,
    /// Relative error of `weight` against `want` (NaN where not compared).
    pub error: f32,
}

impl Example {
    /// Index of the case in [`super::grid::cases`].
    pub fn case(&self) -> usize {
        (self.id >> 32) as usize
    }
}

/// Counts of one method over any number of samples; tallies of disjoint samples merge.
#[derive(Clone, Debug, Default)]
pub struct Tally {
    /// Samples drawn.
    pub samples: u64,
    /// Samples the method rejected (`None`, or a zero normal).
    pub rejected: u64,
    /// Accepted samples whose weight was compared with `eval / pdf` (or `F`).
    pub compared: u64,
    /// Failures per [`Check`], in [`Check::ALL`] order.
    pub counts: [u64; Check::COUNT],
    /// The failing sample with the lowest id, per [`Check`].
    pub first: [Option<Example>; Check::COUNT],
    /// The [`WORST`] largest weight errors among the compared samples, largest first.
    pub worst: Vec<Example>,
    /// Largest weight channel of any finite accepted sample.
    pub max_weight: f32,
    /// Thread time spent, nanoseconds.
    pub nanos: u64,
}

impl Tally {
    /// Counts a failure; `example` is only called to keep the first occurrence.
    #[inline]
    pub fn flag(&mut self, check: Check, example: impl FnOnce() -> Example) {
        let i = check as usize;
        self.counts[i] += 1;
        if self.first[i].is_none() {
            self.first[i] = Some(example());
        }
    }

    /// Offers a compared sample's weight error to the worst list.
    #[inline]
    pub fn offer_error(&mut self, error: f32, example: impl FnOnce() -> Example) {
        if self.worst.len() == WORST && !(error > self.worst[WORST - 1].error) {
            return;
        }
        let e = example();
        insert_worst(&mut self.worst, e);
    }

    /// Count of one check.
    pub fn count(&self, check: Check) -> u64 {
        self.counts[check as usize]
    }

    /// Adds the counts of disjoint samples; examples stay those with the lowest ids.
    pub fn merge(&mut self, other: &Tally) {
        self.samples += other.samples;
        self.rejected += other.rejected;
        self.compared += other.compared;
        for i in 0..Check::COUNT {
            self.counts[i] += other.counts[i];
            self.first[i] = match (self.first[i], other.first[i]) {
                (Some(a), Some(b)) => Some(if b.id < a.id { b } else { a }),
                (a, b) => a.or(b),
            };
        }
        for &e in &other.worst {
            insert_worst(&mut self.worst, e);
        }
        self.max_weight = self.max_weight.max(other.max_weight);
        self.nanos += other.nanos;
    }
}

/// Inserts into a list sorted by error (largest first, ties by lowest id), keeping [`WORST`].
fn insert_worst(worst: &mut Vec<Example>, e: Example) {
    let pos = worst.iter().position(|w| e.error > w.error || (e.error == w.error && e.id < w.id));
    worst.insert(pos.unwrap_or(worst.len()), e);
    worst.truncate(WORST);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn example(id: u64, error: f32) -> Example {
        Example { id, u: Vec2::ZERO, u_lobe: 0.0, wi: Vec3::Z, weight: Vec3::ONE, pdf: 1.0, want: Vec3::ONE, error }
    }

    #[test]
    fn merge_keeps_lowest_ids_and_largest_errors_whatever_the_order() {
        let mut a = Tally::default();
        let mut b = Tally::default();
        a.flag(Check::NonUnit, || example(7, 0.0));
        b.flag(Check::NonUnit, || example(3, 0.0));
        b.flag(Check::NonUnit, || example(1, 0.0)); // not the first one b saw: dropped
        for (id, err) in [(1, 0.5), (2, 0.1), (3, 0.9)] {
            a.offer_error(err, || example(id, err));
        }
        for (id, err) in [(4, 0.7), (5, 0.9), (6, 0.05)] {
            b.offer_error(err, || example(id, err));
        }
        let (mut ab, mut ba) = (a.clone(), b.clone());
        ab.merge(&b);
        ba.merge(&a);
        for t in [ab, ba] {
            assert_eq!(t.count(Check::NonUnit), 3);
            assert_eq!(t.first[Check::NonUnit as usize].map(|e| e.id), Some(3));
            assert_eq!(t.worst.iter().map(|e| e.id).collect::<Vec<_>>(), [3, 5, 4]);
        }
    }
}
