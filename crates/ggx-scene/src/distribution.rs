//! Piecewise-constant 1D and 2D distributions over flat `f32` tables (GPU-uploadable), after
//! pbrt's `Distribution1D` / `Distribution2D` (Pharr, Jakob & Humphreys, PBR 3rd ed., 13.3
//! and 14.2.4).

use glam::Vec2;

/// Largest `f32` below 1, so that sampled coordinates stay in `[0, 1)`.
const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

/// A piecewise-constant density on `[0, 1)` with `n` equal segments of weight `func[i]`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Distribution1D {
    /// Non-negative segment weights (all ones when the input summed to zero).
    pub func: Vec<f32>,
    /// `n + 1` cumulative values, `cdf[0] = 0`, `cdf[n] = 1`.
    pub cdf: Vec<f32>,
    /// `integral = sum(func) / n`, the integral of the step function over `[0, 1)`.
    pub integral: f32,
}

impl Distribution1D {
    /// Builds the distribution of `weights`; negative or NaN weights count as zero, and
    /// all-zero weights give the uniform distribution.
    pub fn new(weights: &[f32]) -> Self {
        let mut func: Vec<f32> = weights.iter().map(|&w| if w > 0.0 { w.min(f32::MAX) } else { 0.0 }).collect();
        if !func.iter().any(|&w| w > 0.0) {
            func.fill(1.0);
        }
        let n = func.len();
        // cdf[i] = sum_{j<i} func[j] / n, accumulated in f64 for long tables.
        let mut acc = 0.0f64;
        let mut cdf = Vec::with_capacity(n + 1);
        cdf.push(0.0f64);
        for &f in &func {
            acc += f64::from(f) / n as f64;
            cdf.push(acc);
        }
        let cdf = cdf.iter().map(|&c| if acc > 0.0 { (c / acc).min(1.0) as f32 } else { 0.0 }).collect();
        Self { func, cdf, integral: acc as f32 }
    }

    /// Number of segments.
    pub fn len(&self) -> usize {
        self.func.len()
    }

    /// `true` for a distribution with no segments (nothing can be sampled).
    pub fn is_empty(&self) -> bool {
        self.func.is_empty()
    }

    /// Picks a segment with probability `pmf = func[i] / sum(func)` by inverting the CDF at
    /// `u` in `[0, 1)`. Returns `(index, pmf, u remapped to [0, 1) inside the segment)`, or
    /// `None` when empty.
    pub fn sample_discrete(&self, u: f32) -> Option<(usize, f32, f32)> {
        let (i, du) = invert_cdf(&self.cdf, u)?;
        Some((i, self.pmf(i), du))
    }

    /// Samples `x` in `[0, 1)` with density `pdf(x) = func[i] / integral`, `i = floor(x n)`.
    /// Returns `(x, pdf, i)`, or `None` when empty.
    pub fn sample_continuous(&self, u: f32) -> Option<(f32, f32, usize)> {
        let (i, du) = invert_cdf(&self.cdf, u)?;
        let x = ((i as f32 + du) / self.len() as f32).min(ONE_MINUS_EPSILON);
        Some((x, self.func[i] / self.integral, i))
    }

    /// Probability of segment `i` (0 when out of range).
    pub fn pmf(&self, i: usize) -> f32 {
        self.func.get(i).map_or(0.0, |f| f / (self.integral * self.len() as f32))
    }

    /// Density at `x` in `[0, 1)` (0 outside).
    pub fn pdf(&self, x: f32) -> f32 {
        if !(0.0..1.0).contains(&x) {
            return 0.0;
        }
        let i = ((x * self.len() as f32) as usize).min(self.len().saturating_sub(1));
        self.func.get(i).map_or(0.0, |f| f / self.integral)
    }
}

/// Segment `i` with `cdf[i] <= u < cdf[i + 1]` (never a zero-width one) and the offset of
/// `u` inside it in `[0, 1)`; `None` for an empty table.
fn invert_cdf(cdf: &[f32], u: f32) -> Option<(usize, f32)> {
    let n = cdf.len().checked_sub(1).filter(|&n| n > 0)?;
    let u = if u.is_nan() { 0.0 } else { u.clamp(0.0, ONE_MINUS_EPSILON) };
    let i = cdf.partition_point(|&c| c <= u).saturating_sub(1).min(n - 1);
    let width = cdf[i + 1] - cdf[i];
    let du = if width > 0.0 { ((u - cdf[i]) / width).clamp(0.0, ONE_MINUS_EPSILON) } else { 0.5 };
    Some((i, du))
}

/// A piecewise-constant density on `[0, 1)^2` over a `width x height` grid: the marginal
/// distribution over rows, then the conditional distribution within the chosen row.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Distribution2D {
    /// Columns.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// Row-major cell weights, `width * height` (all ones when the input summed to zero).
    pub func: Vec<f32>,
    /// Row-major conditional CDFs, `(width + 1)` values per row.
    pub conditional_cdf: Vec<f32>,
    /// Distribution over rows; `marginal.func[r]` is row `r`'s integral and
    /// `marginal.integral` the integral over the whole square.
    pub marginal: Distribution1D,
}

impl Distribution2D {
    /// Builds the distribution of a row-major `width x height` table of weights. Returns
    /// `None` when the sizes do not match or are zero.
    pub fn new(width: u32, height: u32, weights: &[f32]) -> Option<Self> {
        let (w, h) = (width as usize, height as usize);
        if w == 0 || h == 0 || weights.len() != w.checked_mul(h)? {
            return None;
        }
        let mut func: Vec<f32> = weights.iter().map(|&x| if x > 0.0 { x.min(f32::MAX) } else { 0.0 }).collect();
        if !func.iter().any(|&x| x > 0.0) {
            func.fill(1.0);
        }
        let mut conditional_cdf = Vec::with_capacity(h * (w + 1));
        let mut row_integrals = Vec::with_capacity(h);
        for row in func.chunks_exact(w) {
            let d = Distribution1D::new(row);
            conditional_cdf.extend_from_slice(&d.cdf);
            row_integrals.push(if row.iter().any(|&x| x > 0.0) { d.integral } else { 0.0 });
        }
        let marginal = Distribution1D::new(&row_integrals);
        Some(Self { width, height, func, conditional_cdf, marginal })
    }

    /// Samples a point with density [`Self::pdf`]: `u.y` picks the row, `u.x` the column.
    /// Returns `(point in [0, 1)^2, pdf, [column, row])`.
    pub fn sample(&self, u: Vec2) -> (Vec2, f32, [u32; 2]) {
        let w = self.width as usize;
        let Some((y, _, row)) = self.marginal.sample_continuous(u.y) else { return (Vec2::ZERO, 0.0, [0, 0]) };
        let cdf = &self.conditional_cdf[row * (w + 1)..(row + 1) * (w + 1)];
        let Some((col, du)) = invert_cdf(cdf, u.x) else { return (Vec2::ZERO, 0.0, [0, 0]) };
        let x = ((col as f32 + du) / w as f32).min(ONE_MINUS_EPSILON);
        (Vec2::new(x, y), self.cell_pdf(col, row), [col as u32, row as u32])
    }

    /// Density at `p` in `[0, 1)^2`: `func[cell] / integral` (0 outside).
    pub fn pdf(&self, p: Vec2) -> f32 {
        if !(0.0..1.0).contains(&p.x) || !(0.0..1.0).contains(&p.y) {
            return 0.0;
        }
        let col = ((p.x * self.width as f32) as usize).min(self.width as usize - 1);
        let row = ((p.y * self.height as f32) as usize).min(self.height as usize - 1);
        self.cell_pdf(col, row)
    }

    /// Density inside cell `(column, row)`.
    pub fn cell_pdf(&self, col: usize, row: usize) -> f32 {
        self.func.get(row * self.width as usize + col).map_or(0.0, |f| f / self.marginal.integral)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn discrete_sampling_follows_weights_and_skips_zeros() {
        let d = Distribution1D::new(&[1.0, 0.0, 3.0]);
        assert_eq!(d.sample_discrete(0.0).map(|s| s.0), Some(0));
        assert_eq!(d.sample_discrete(0.25).map(|s| s.0), Some(2));
        assert_eq!(d.sample_discrete(0.9999).map(|s| (s.0, s.1)), Some((2, 0.75)));
        assert_eq!(d.pmf(1), 0.0);
        assert!((d.pdf(0.1) - 0.75).abs() < 1e-6);
        assert!(Distribution1D::new(&[]).sample_discrete(0.5).is_none());
        assert_eq!(Distribution1D::new(&[0.0, 0.0]).pmf(1), 0.5);
    }

    #[test]
    fn sampled_pdf_matches_pdf() {
        let weights: Vec<f32> = (0..12).map(|i| ((i * 7) % 5) as f32).collect();
        let d = Distribution2D::new(4, 3, &weights).unwrap();
        for i in 0..1000 {
            let u = Vec2::new((i as f32 * 0.618_034).fract(), (i as f32 * 0.754_878).fract());
            let (p, pdf, _) = d.sample(u);
            assert!(pdf > 0.0);
            assert!((pdf - d.pdf(p)).abs() <= 1e-5 * pdf, "{p} {pdf} {}", d.pdf(p));
        }
    }
}
