//! Runs every method over every case of its family on all cores: the family's whole u grid
//! on every case, then random points from a [`CounterRng`] on the cases where the output
//! depends on `u`, as many as it takes to reach the per-method sample budget. Deterministic
//! apart from timings.

use super::grid::{Case, Family, Point};
use super::method::Method;
use super::tally::Tally;
use ggx_core::CounterRng;
use rayon::prelude::*;
use std::ops::Range;
use std::time::Instant;

/// What the sweep runs: cases, methods, the u grids and each method's random points per case.
pub struct Plan {
    /// The cases of every [`Family`], in [`Family::ALL`] order (conductor cases first, so
    /// their indices, and random streams, are those of a conductor-only sweep).
    pub cases: Vec<Case>,
    /// Every method of [`Method::all`].
    pub methods: Vec<Method>,
    /// Per family, in [`Family::ALL`] order: the range of its cases in `cases`.
    pub ranges: Vec<Range<usize>>,
    /// Per family, in [`Family::ALL`] order: the u grid of [`Family::points`], run on the
    /// cases where [`Method::uses_u`].
    pub grids: Vec<Vec<Point>>,
    /// Per family, in [`Family::ALL`] order: the grid of [`Family::fixed_points`], run on
    /// the other cases.
    pub fixed: Vec<Vec<Point>>,
    /// Per method: random points on each case where [`Method::uses_u`].
    pub random: Vec<u64>,
}

impl Plan {
    /// The plan that gives every method at least `samples` samples (at least the grids on
    /// every case of its family, whatever `samples` says).
    pub fn new(samples: u64) -> Plan {
        let (mut cases, mut ranges, mut grids, mut fixed) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for family in Family::ALL {
            let start = cases.len();
            cases.extend(family.cases());
            ranges.push(start..cases.len());
            grids.push(family.points());
            fixed.push(family.fixed_points());
        }
        let methods = Method::all();
        let mut plan = Plan { cases, methods, ranges, grids, fixed, random: Vec::new() };
        plan.random = (0..plan.methods.len())
            .map(|m| {
                let grid_total: u64 = plan.cases_of(m).map(|c| plan.grid_for(m, c).len() as u64).sum();
                let u_cases = plan.cases_of(m).filter(|&c| plan.methods[m].uses_u(&plan.cases[c])).count() as u64;
                samples.saturating_sub(grid_total).div_ceil(u_cases.max(1))
            })
            .collect();
        plan
    }

    /// Index of a family in [`Family::ALL`].
    fn family_index(family: Family) -> usize {
        Family::ALL.iter().position(|&f| f == family).unwrap_or(0)
    }

    /// The cases method `m` runs on: indices into `cases`.
    pub fn cases_of(&self, m: usize) -> Range<usize> {
        self.ranges[Self::family_index(self.methods[m].family())].clone()
    }

    /// The grid method `m` runs on case `c`: its family's u grid where [`Method::uses_u`],
    /// else its fixed grid.
    pub fn grid_for(&self, m: usize, c: usize) -> &[Point] {
        let family = Self::family_index(self.methods[m].family());
        if self.methods[m].uses_u(&self.cases[c]) { &self.grids[family] } else { &self.fixed[family] }
    }

    /// Random points of method `m` on case `c`.
    fn random_for(&self, m: usize, c: usize) -> u64 {
        if self.methods[m].uses_u(&self.cases[c]) { self.random[m] } else { 0 }
    }

    /// Samples method `m` draws over all its cases.
    #[cfg(test)]
    pub fn samples_of(&self, m: usize) -> u64 {
        self.cases_of(m).map(|c| self.grid_for(m, c).len() as u64 + self.random_for(m, c)).sum()
    }

    /// Runs method `m` on case `c`: the grid, then the random points of stream
    /// `CounterRng::new(c, m)` (`u`, then `u_lobe` for the dielectric).
    fn run_one(&self, m: usize, c: usize) -> Tally {
        let start = Instant::now();
        let checker = self.methods[m].checker(&self.cases[c]);
        let mut t = Tally::default();
        let base = (c as u64) << 32;
        let grid = self.grid_for(m, c);
        for (i, &p) in grid.iter().enumerate() {
            checker.check(p, base | i as u64, &mut t);
        }
        let mut rng = CounterRng::new(c as u32, m as u32);
        let first = grid.len() as u64;
        let dielectric = self.methods[m].family() == Family::Dielectric;
        for i in 0..self.random_for(m, c) {
            let u = rng.next_vec2();
            let u_lobe = if dielectric { rng.next_f32() } else { 0.0 };
            checker.check(Point { u, u_lobe }, base | (first + i), &mut t);
        }
        t.nanos = start.elapsed().as_nanos() as u64;
        t
    }

    /// One tally per method, over every case of its family, computed on rayon's global pool.
    pub fn run(&self) -> Vec<Tally> {
        let empty = || vec![Tally::default(); self.methods.len()];
        let merge = |mut a: Vec<Tally>, b: Vec<Tally>| {
            a.iter_mut().zip(&b).for_each(|(a, b)| a.merge(b));
            a
        };
        let items: Vec<(usize, usize)> =
            (0..self.methods.len()).flat_map(|m| self.cases_of(m).map(move |c| (m, c))).collect();
        items
            .into_par_iter()
            .fold(empty, |mut acc, (m, c)| {
                acc[m].merge(&self.run_one(m, c));
                acc
            })
            .reduce(empty, merge)
    }
}

#[cfg(test)]
mod tests {
    use super::super::tally::Check;
    use super::*;

    #[test]
    fn plan_meets_the_budget_and_a_tiny_sweep_is_clean() {
        let plan = Plan::new(0);
        assert!(plan.random.iter().all(|&r| r == 0));
        let plan = Plan::new(1_000_000);
        for m in 0..plan.methods.len() {
            let total = plan.samples_of(m);
            assert!(total >= 1_000_000, "{}: {total}", plan.methods[m].name());
        }
        // One case: deterministic, and clean.
        let t = plan.run_one(1, 700);
        assert_eq!(t.samples, plan.grid_for(1, 700).len() as u64 + plan.random_for(1, 700));
        assert_eq!(plan.run_one(1, 700).counts, t.counts);
        assert_eq!(t.counts, [0; Check::COUNT]);
        // A dielectric method runs on the dielectric cases only, which follow the conductor's.
        let d = plan.methods.iter().position(|m| m.family() == Family::Dielectric).unwrap();
        let cases = plan.cases_of(d);
        assert_eq!(cases.start, plan.ranges[0].end);
        assert!(plan.cases[cases.clone()].iter().all(|c| c.eta.is_some()));
        assert!(plan.cases[plan.ranges[0].clone()].iter().all(|c| c.eta.is_none()));
        for c in [cases.start, cases.start + 700, cases.end - 1] {
            let t = plan.run_one(d, c);
            assert_eq!(t.samples, plan.grid_for(d, c).len() as u64 + plan.random_for(d, c));
            assert_eq!(t.counts, [0; Check::COUNT]);
        }
        // Delta cases (the first alpha pairs) get the lobe grid only, rough ones the u grid.
        assert_eq!(plan.grid_for(d, cases.start).len(), plan.fixed[1].len());
        assert_eq!(plan.grid_for(d, cases.end - 1).len(), plan.grids[1].len());
    }
}
