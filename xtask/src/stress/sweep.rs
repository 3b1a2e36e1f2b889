//! Runs every method over every case on all cores: the whole u grid on every case, then
//! random points from a [`CounterRng`] on the cases where the output depends on `u`, as many
//! as it takes to reach the per-method sample budget. Deterministic apart from timings.

use super::grid::{self, Case};
use super::method::Method;
use super::tally::Tally;
use ggx_core::{CounterRng, Vec2};
use rayon::prelude::*;
use std::time::Instant;

/// What the sweep runs: cases, methods, the u grid and each method's random points per case.
pub struct Plan {
    /// Every case of [`grid::cases`].
    pub cases: Vec<Case>,
    /// Every method of [`Method::all`].
    pub methods: Vec<Method>,
    /// The u grid of [`grid::u_grid`].
    pub grid: Vec<Vec2>,
    /// Per method: random points on each case where [`Method::uses_u`].
    pub random: Vec<u64>,
}

impl Plan {
    /// The plan that gives every method at least `samples` samples (at least the u grid on
    /// every case, whatever `samples` says).
    pub fn new(samples: u64) -> Plan {
        let (cases, methods, grid) = (grid::cases(), Method::all(), grid::u_grid());
        let grid_total = (cases.len() * grid.len()) as u64;
        let random = methods
            .iter()
            .map(|m| {
                let u_cases = cases.iter().filter(|c| m.uses_u(c)).count() as u64;
                samples.saturating_sub(grid_total).div_ceil(u_cases.max(1))
            })
            .collect();
        Plan { cases, methods, grid, random }
    }

    /// Random points of method `m` on case `c`.
    fn random_for(&self, m: usize, c: usize) -> u64 {
        if self.methods[m].uses_u(&self.cases[c]) { self.random[m] } else { 0 }
    }

    /// Runs method `m` on case `c`: the grid, then the random points of stream
    /// `CounterRng::new(c, m)`.
    fn run_one(&self, m: usize, c: usize) -> Tally {
        let start = Instant::now();
        let checker = self.methods[m].checker(&self.cases[c]);
        let mut t = Tally::default();
        let base = (c as u64) << 32;
        for (i, &u) in self.grid.iter().enumerate() {
            checker.check(u, base | i as u64, &mut t);
        }
        let mut rng = CounterRng::new(c as u32, m as u32);
        let first = self.grid.len() as u64;
        for i in 0..self.random_for(m, c) {
            checker.check(rng.next_vec2(), base | (first + i), &mut t);
        }
        t.nanos = start.elapsed().as_nanos() as u64;
        t
    }

    /// One tally per method, over every case, computed on rayon's global pool.
    pub fn run(&self) -> Vec<Tally> {
        let empty = || vec![Tally::default(); self.methods.len()];
        let merge = |mut a: Vec<Tally>, b: Vec<Tally>| {
            a.iter_mut().zip(&b).for_each(|(a, b)| a.merge(b));
            a
        };
        (0..self.methods.len() * self.cases.len())
            .into_par_iter()
            .fold(empty, |mut acc, item| {
                let (m, c) = (item / self.cases.len(), item % self.cases.len());
                acc[m].merge(&self.run_one(m, c));
                acc
            })
            .reduce(empty, merge)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plan_meets_the_budget_and_a_tiny_sweep_is_clean() {
        let plan = Plan::new(0);
        assert!(plan.random.iter().all(|&r| r == 0));
        let plan = Plan::new(1_000_000);
        for m in 0..plan.methods.len() {
            let total: u64 = (0..plan.cases.len()).map(|c| plan.grid.len() as u64 + plan.random_for(m, c)).sum();
            assert!(total >= 1_000_000, "{}: {total}", plan.methods[m].name());
        }
        // The u grid alone on a handful of cases: deterministic, and mergeable in any order.
        let t = plan.run_one(1, 700);
        assert_eq!(t.samples, plan.grid.len() as u64 + plan.random_for(1, 700));
        assert_eq!(plan.run_one(1, 700).counts, t.counts);
    }
}
