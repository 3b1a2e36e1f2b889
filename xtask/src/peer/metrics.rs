//! The numbers of the peer comparison, from the measured ladders and the two references: pure
//! functions, unit-tested.
//!
//! Every time here is the steady-state time of a rung, [`Rung::steady_seconds`]: its wall
//! clock less the JIT compilation that happened during it (Mitsuba's LLVM variant compiles a
//! kernel the first time it meets it; that cost is reported on its own).
//!
//! * Throughput: camera samples per second, `sum(samples) / sum(seconds)` over the upper rungs
//!   (spp >= top / 8), where fixed costs per render are small.
//! * Efficiency: `relMSE x seconds`, constant for an unbiased Monte Carlo estimator once its
//!   error falls as 1/spp; the median over the upper rungs. The efficiency ratio of a
//!   configuration to ggx's baseline is `(relMSE s)_ggx / (relMSE s)_config`: above 1 the
//!   configuration reaches a given error sooner.
//! * relMSE at equal time: read off each relMSE-against-time curve at the baseline's top-rung
//!   time ([`crate::bench::interp::y_at`]).
//! * Agreement of the converged references: ratio of the means per channel and of luminance,
//!   the same per region of a grid, and relMSE between them beside the noise floor expected
//!   from the two references' own noise.

use ggx_film::Vec3;

use crate::bench::interp::{Estimate, y_at};

/// One rendered rung.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rung {
    /// Samples per pixel.
    pub spp: u32,
    /// Render time in seconds (JIT compilation included where it happened).
    pub seconds: f64,
    /// Of which JIT compilation (Mitsuba's LLVM variant; 0 otherwise).
    pub jit_seconds: f64,
    /// Camera samples traced.
    pub camera_samples: u64,
    /// relMSE against the renderer's own reference.
    pub rel_mse: f64,
    /// relMSE without the worst 1 % of pixels ([`crate::bench::robust::trimmed_rel_mse`]).
    pub rel_mse_trimmed: f64,
}

impl Rung {
    /// `seconds - jit_seconds`: the render without JIT compilation (at least 1 µs).
    pub fn steady_seconds(&self) -> f64 {
        (self.seconds - self.jit_seconds.max(0.0)).max(1e-6)
    }

    /// Camera samples per steady-state second (0 for a non-positive time).
    pub fn samples_per_second(&self) -> f64 {
        if self.seconds > 0.0 { self.camera_samples as f64 / self.steady_seconds() } else { 0.0 }
    }
}

/// The rungs with `spp >= top / 8` (all of them when that leaves none).
fn upper(rungs: &[Rung]) -> Vec<Rung> {
    let top = rungs.iter().map(|r| r.spp).max().unwrap_or(0);
    let kept: Vec<Rung> = rungs.iter().copied().filter(|r| r.spp.saturating_mul(8) >= top).collect();
    if kept.is_empty() { rungs.to_vec() } else { kept }
}

/// `sum(camera samples) / sum(seconds)` over the upper rungs; 0 without time.
pub fn throughput(rungs: &[Rung]) -> f64 {
    let r = upper(rungs);
    let seconds: f64 = r.iter().map(Rung::steady_seconds).sum();
    let samples: f64 = r.iter().map(|r| r.camera_samples as f64).sum();
    if seconds > 0.0 { samples / seconds } else { 0.0 }
}

/// The median of `relMSE x seconds` over the upper rungs (NaN without rungs).
pub fn efficiency(rungs: &[Rung]) -> f64 {
    let mut v: Vec<f64> = upper(rungs).iter().map(|r| r.rel_mse * r.steady_seconds()).collect();
    median(&mut v)
}

/// The median of `v` (mean of the middle two for an even count; NaN when empty).
pub fn median(v: &mut [f64]) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 { v[n / 2] } else { 0.5 * (v[n / 2 - 1] + v[n / 2]) }
}

/// relMSE of the curve `(steady seconds, relMSE)` of the upper rungs at `seconds` (log-log
/// interpolation, `≈` beyond the last rung with relMSE ∝ 1/time). The small rungs are left
/// out: their times are dominated by fixed costs and need not grow with spp.
pub fn rel_mse_at(rungs: &[Rung], seconds: f64) -> Estimate {
    let points: Vec<(f64, f64)> = upper(rungs).iter().map(|r| (r.steady_seconds(), r.rel_mse)).collect();
    y_at(&points, seconds)
}

/// Expected relMSE between two independent converged references from their own noise: each
/// contributes its ladder's top-rung relMSE scaled by `top_spp / ref_spp` (relMSE ∝ 1/spp).
pub fn noise_floor(a_top: (u32, f64), b_top: (u32, f64), ref_spp: u32) -> f64 {
    let scaled = |(spp, rel): (u32, f64)| rel * f64::from(spp) / f64::from(ref_spp.max(1));
    scaled(a_top) + scaled(b_top)
}

/// The agreement of two converged images of the same scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Agreement {
    /// `mean(a) / mean(b)` for R, G, B and Rec. 709 luminance.
    pub mean_ratio: [f64; 4],
    /// Luminance `mean(a) / mean(b)` per grid region, row-major from the top left (NaN where
    /// `b`'s region is black).
    pub regions: Vec<f64>,
    /// Grid `(rows, columns)`.
    pub grid: (usize, usize),
    /// relMSE between the images (`ggx_film::compare`, `b` as the reference).
    pub rel_mse: f64,
    /// The same without the worst 1 % of pixels.
    pub rel_mse_trimmed: f64,
}

impl Agreement {
    /// The region ratio farthest from 1 (NaN regions skipped; 1 when none is finite).
    pub fn worst_region(&self) -> f64 {
        self.regions
            .iter()
            .copied()
            .filter(|r| r.is_finite())
            .fold(1.0, |w, r| if (r - 1.0).abs() > (w - 1.0).abs() { r } else { w })
    }
}

/// Rec. 709 luminance of `p` in f64.
fn luminance(p: Vec3) -> f64 {
    0.2126 * f64::from(p.x) + 0.7152 * f64::from(p.y) + 0.0722 * f64::from(p.z)
}

/// Compares `a` with `b` (`width x height`, row-major): mean ratios, a `rows x cols` grid of
/// luminance ratios (region `(i, j)` covers rows `[i h / rows, (i + 1) h / rows)` and likewise
/// for columns), relMSE; `Err` when the sizes differ.
pub fn agreement(
    a: &[Vec3],
    b: &[Vec3],
    width: usize,
    height: usize,
    grid: (usize, usize),
) -> Result<Agreement, String> {
    if a.len() != b.len() || a.len() != width * height || width == 0 || height == 0 {
        return Err(format!("images of {} and {} pixels for {width}x{height}", a.len(), b.len()));
    }
    let sums = |img: &[Vec3]| {
        let mut s = [0.0f64; 4];
        for p in img {
            s[0] += f64::from(p.x);
            s[1] += f64::from(p.y);
            s[2] += f64::from(p.z);
            s[3] += luminance(*p);
        }
        s
    };
    let (sa, sb) = (sums(a), sums(b));
    let ratio = |x: f64, y: f64| if y > 0.0 { x / y } else { f64::NAN };
    let mean_ratio = [0, 1, 2, 3].map(|c| ratio(sa[c], sb[c]));
    let (rows, cols) = (grid.0.clamp(1, height), grid.1.clamp(1, width));
    let mut regions = Vec::with_capacity(rows * cols);
    for i in 0..rows {
        for j in 0..cols {
            let (y0, y1) = (i * height / rows, (i + 1) * height / rows);
            let (x0, x1) = (j * width / cols, (j + 1) * width / cols);
            let (mut la, mut lb) = (0.0, 0.0);
            for y in y0..y1 {
                for x in x0..x1 {
                    la += luminance(a[y * width + x]);
                    lb += luminance(b[y * width + x]);
                }
            }
            regions.push(ratio(la, lb));
        }
    }
    let rel_mse = ggx_film::compare(a, b, 1.0).map_err(|e| e.to_string())?.rel_mse;
    let rel_mse_trimmed = crate::bench::robust::trimmed_rel_mse(a, b, crate::bench::robust::TRIM);
    Ok(Agreement { mean_ratio, regions, grid: (rows, cols), rel_mse, rel_mse_trimmed })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rung(spp: u32, seconds: f64, rel_mse: f64) -> Rung {
        Rung { spp, seconds, jit_seconds: 0.0, camera_samples: u64::from(spp) * 100, rel_mse, rel_mse_trimmed: rel_mse }
    }

    #[test]
    fn throughput_and_efficiency_use_the_upper_rungs() {
        // 1/spp error, time linear in spp plus a fixed 1 s that only the small rungs feel.
        let rungs: Vec<Rung> =
            [1u32, 2, 4, 8, 16, 32, 64].iter().map(|&s| rung(s, 1.0 + f64::from(s), 1.0 / f64::from(s))).collect();
        // Rungs 8..64: 120 spp x 100 samples over 124 s.
        assert!((throughput(&rungs) - 12000.0 / 124.0).abs() < 1e-9);
        // relMSE x s at 8, 16, 32, 64: 9/8, 17/16, 33/32, 65/64; median = (17/16 + 33/32) / 2.
        assert!((efficiency(&rungs) - 0.5 * (17.0 / 16.0 + 33.0 / 32.0)).abs() < 1e-12);
        assert_eq!(throughput(&[]), 0.0);
        assert!(efficiency(&[]).is_nan());
        assert_eq!(median(&mut [3.0, 1.0, 2.0]), 2.0);
    }

    #[test]
    fn jit_time_is_left_out() {
        let mut r = rung(8, 2.0, 0.1);
        r.jit_seconds = 1.5;
        assert_eq!(r.steady_seconds(), 0.5);
        assert_eq!(r.samples_per_second(), 1600.0);
        assert_eq!(throughput(&[r]), 1600.0);
        assert!((efficiency(&[r]) - 0.05).abs() < 1e-15);
    }

    #[test]
    fn rel_mse_at_time_interpolates_and_extrapolates() {
        let rungs = [rung(1, 1.0, 1.0), rung(2, 2.0, 0.5), rung(4, 4.0, 0.25)];
        assert_eq!(rel_mse_at(&rungs, 2.0), Estimate::Interpolated(0.5));
        match rel_mse_at(&rungs, 8.0) {
            Estimate::Extrapolated(v) => assert!((v - 0.125).abs() < 1e-12),
            other => panic!("{other:?}"),
        }
        assert_eq!(rel_mse_at(&rungs, 0.5), Estimate::BelowRange);
        assert!((noise_floor((256, 1e-3), (256, 2e-3), 4096) - 3e-3 / 16.0).abs() < 1e-15);
    }

    #[test]
    fn agreement_of_scaled_images() {
        let (w, h) = (4, 2);
        let b: Vec<Vec3> = (0..w * h).map(|i| Vec3::splat(1.0 + i as f32)).collect();
        let mut a = b.clone();
        // The right half 10 % brighter, in red only.
        for y in 0..h {
            for x in 2..4 {
                a[y * w + x].x *= 1.1;
            }
        }
        let g = agreement(&a, &b, w, h, (1, 2)).unwrap();
        assert_eq!(g.grid, (1, 2));
        assert!((g.regions[0] - 1.0).abs() < 1e-12);
        assert!((g.regions[1] - 1.0).abs() > 0.01 && g.regions[1] > 1.0);
        assert!((g.mean_ratio[1] - 1.0).abs() < 1e-12 && g.mean_ratio[0] > 1.0);
        assert_eq!(g.worst_region(), g.regions[1]);
        assert!(g.rel_mse > 0.0 && g.rel_mse_trimmed <= g.rel_mse);
        assert_eq!(agreement(&b, &b, w, h, (4, 4)).unwrap().rel_mse, 0.0);
        assert!(agreement(&a, &b[1..], w, h, (1, 1)).is_err());
        let black = vec![Vec3::ZERO; w * h];
        assert!(agreement(&b, &black, w, h, (1, 1)).unwrap().regions[0].is_nan());
    }
}
