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
    /// Guide table over `cdf` (`guide_table`): `n` starting segments, one per `1/n` of `u`.
    pub guide: Vec<u32>,
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
        let cdf: Vec<f32> = cdf.iter().map(|&c| if acc > 0.0 { (c / acc).min(1.0) as f32 } else { 0.0 }).collect();
        let guide = guide_table(&cdf, n);
        Self { func, cdf, integral: acc as f32, guide }
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
    #[inline(always)]
    pub fn sample_discrete(&self, u: f32) -> Option<(usize, f32, f32)> {
        let (i, du) = invert_cdf(&self.cdf, &self.guide, u)?;
        Some((i, self.pmf(i), du))
    }

    /// Samples `x` in `[0, 1)` with density `pdf(x) = func[i] / integral`, `i = floor(x n)`.
    /// Returns `(x, pdf, i)`, or `None` when empty.
    pub fn sample_continuous(&self, u: f32) -> Option<(f32, f32, usize)> {
        let (i, du) = invert_cdf(&self.cdf, &self.guide, u)?;
        let x = ((i as f32 + du) / self.len() as f32).min(ONE_MINUS_EPSILON);
        Some((x, self.func[i] / self.integral, i))
    }

    /// Probability of segment `i` (0 when out of range).
    #[inline]
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
/// `u` inside it in `[0, 1)`; `None` for an empty table. `guide` ([`guide_table`]) gives the
/// search its starting segment; any guide (even an empty or wrong one) gives the same segment
/// as a binary search over `cdf`, which is what the GPU kernel runs.
#[inline(always)]
fn invert_cdf(cdf: &[f32], guide: &[u32], u: f32) -> Option<(usize, f32)> {
    let n = cdf.len().checked_sub(1).filter(|&n| n > 0)?;
    let u = clamp_u(u);
    let i = find_segment(cdf, guide, n, u);
    Some((i, segment_offset(cdf, i, u)))
}

/// `u` clamped to `[0, 1)`, NaN to 0.
#[inline(always)]
fn clamp_u(u: f32) -> f32 {
    if u.is_nan() { 0.0 } else { u.clamp(0.0, ONE_MINUS_EPSILON) }
}

/// The offset of `u` inside segment `i` in `[0, 1)` (the middle of a zero-width one).
#[inline(always)]
fn segment_offset(cdf: &[f32], i: usize, u: f32) -> f32 {
    let width = cdf[i + 1] - cdf[i];
    if width > 0.0 { ((u - cdf[i]) / width).clamp(0.0, ONE_MINUS_EPSILON) } else { 0.5 }
}

/// The last segment `i < n` with `cdf[i] <= u` for `u` in `[0, 1)`, which is
/// `cdf.partition_point(|c| c <= u) - 1` capped at `n - 1` (cdf non-decreasing from 0). Starts
/// at `guide[floor(u K)]` and walks down, then up, to it: with [`guide_table`]'s `K = n`
/// entries the walk takes about one step on average (the cutpoint method, Chen & Asau 1974;
/// Devroye 1986, 3.2.4) where the binary search takes `log2 n` dependent loads.
#[inline]
fn find_segment(cdf: &[f32], guide: &[u32], n: usize, u: f32) -> usize {
    walk_to_segment(cdf, n, u, guide_start(guide, n, u))
}

/// The guide's starting segment for `u` (0 without a guide), below `n`.
#[inline(always)]
fn guide_start(guide: &[u32], n: usize, u: f32) -> usize {
    let k = ((u * guide.len() as f32) as usize).min(guide.len().saturating_sub(1));
    guide.get(k).map_or(0, |&g| (g as usize).min(n - 1))
}

/// [`find_segment`]'s walk from segment `start`, down then up.
#[inline(always)]
fn walk_to_segment(cdf: &[f32], n: usize, u: f32, start: usize) -> usize {
    let mut i = start;
    while i > 0 && cdf[i] > u {
        i -= 1;
    }
    while i + 1 < n && cdf[i + 1] <= u {
        i += 1;
    }
    i
}

/// Guide table of `buckets` entries over a CDF of `n + 1` values: entry `k` is the segment
/// that [`find_segment`] returns at `u = k / buckets` (by binary search).
pub fn guide_table(cdf: &[f32], buckets: usize) -> Vec<u32> {
    let n = cdf.len().saturating_sub(1);
    if n == 0 {
        return Vec::new();
    }
    (0..buckets)
        .map(|k| {
            let u = k as f32 / buckets as f32;
            cdf.partition_point(|&c| c <= u).saturating_sub(1).min(n - 1) as u32
        })
        .collect()
}

/// Samples or lookups per pass of the batched table reads ([`Distribution2D::sample_cells`],
/// `EnvMap`'s `*_batch` lookups): a camera packet's paths.
pub const LOOKUP_BATCH: usize = 16;

/// A row [`Distribution2D::sample`] picked, and the sampled `y` in it.
#[derive(Clone, Copy)]
struct SampledRow {
    y: f32,
    row: usize,
}

/// A column search's state after the guide: the row, its segment count, the clamped `u` and
/// the guide's segment.
#[derive(Clone, Copy)]
struct ColumnStart {
    row: SampledRow,
    n: usize,
    u: f32,
    start: usize,
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
    /// Row-major guide tables over the conditional CDFs (`guide_table`), `width` per row.
    pub conditional_guide: Vec<u32>,
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
        let mut conditional_guide = Vec::with_capacity(h * w);
        let mut row_integrals = Vec::with_capacity(h);
        for row in func.chunks_exact(w) {
            let d = Distribution1D::new(row);
            conditional_cdf.extend_from_slice(&d.cdf);
            conditional_guide.extend_from_slice(&d.guide);
            row_integrals.push(if row.iter().any(|&x| x > 0.0) { d.integral } else { 0.0 });
        }
        let marginal = Distribution1D::new(&row_integrals);
        Some(Self { width, height, func, conditional_cdf, conditional_guide, marginal })
    }

    /// Samples a point with density [`Self::pdf`]: `u.y` picks the row, `u.x` the column.
    /// Returns `(point in [0, 1)^2, pdf, [column, row])`.
    pub fn sample(&self, u: Vec2) -> (Vec2, f32, [u32; 2]) {
        match self.sample_row(u.y).and_then(|r| self.start_column(r, u.x)) {
            Some(start) => {
                let (p, [col, row]) = self.finish_column(start);
                (p, self.cell_pdf(col as usize, row as usize), [col, row])
            }
            None => (Vec2::ZERO, 0.0, [0, 0]),
        }
    }

    /// [`Self::sample`]'s point and cell, without its density.
    pub fn sample_cell(&self, u: Vec2) -> (Vec2, [u32; 2]) {
        match self.sample_row(u.y).and_then(|r| self.start_column(r, u.x)) {
            Some(start) => self.finish_column(start),
            None => (Vec2::ZERO, [0, 0]),
        }
    }

    /// [`Self::sample_cell`] of each of `us` into `out` (the shorter length of the two), the same
    /// bits, in three passes over up to [`LOOKUP_BATCH`] samples at a time: every row, then
    /// every row's guide entry, then every walk of the rows' CDFs. The reads of a pass do not
    /// wait for one another, so the cache misses of a large table (a map's conditional CDFs
    /// and guides are megabytes) overlap instead of following one by one.
    pub fn sample_cells(&self, us: &[Vec2], out: &mut [(Vec2, [u32; 2])]) {
        for (us, out) in us.chunks(LOOKUP_BATCH).zip(out.chunks_mut(LOOKUP_BATCH)) {
            let mut rows = [None; LOOKUP_BATCH];
            for (r, u) in rows.iter_mut().zip(us) {
                *r = self.sample_row(u.y);
            }
            let mut starts = [None; LOOKUP_BATCH];
            for ((s, r), u) in starts.iter_mut().zip(rows).zip(us) {
                *s = r.and_then(|r| self.start_column(r, u.x));
            }
            for (o, s) in out.iter_mut().zip(starts).take(us.len()) {
                *o = s.map_or((Vec2::ZERO, [0, 0]), |s| self.finish_column(s));
            }
        }
    }

    /// The row `u_y` picks and the sampled `y`.
    #[inline(always)]
    fn sample_row(&self, u_y: f32) -> Option<SampledRow> {
        let (y, _, row) = self.marginal.sample_continuous(u_y)?;
        Some(SampledRow { y, row })
    }

    /// Row `row`'s conditional CDF and guide table (empty outside the grid).
    #[inline(always)]
    fn row_tables(&self, row: usize) -> (&[f32], &[u32]) {
        let w = self.width as usize;
        let cdf = self.conditional_cdf.get(row * (w + 1)..(row + 1) * (w + 1)).unwrap_or_default();
        let guide = self.conditional_guide.get(row * w..(row + 1) * w).unwrap_or_default();
        (cdf, guide)
    }

    /// Where inverting the row's CDF at `u_x` starts: the guide's segment (`invert_cdf`'s first
    /// half); `None` for an empty row.
    #[inline(always)]
    fn start_column(&self, row: SampledRow, u_x: f32) -> Option<ColumnStart> {
        let (cdf, guide) = self.row_tables(row.row);
        let n = cdf.len().checked_sub(1).filter(|&n| n > 0)?;
        let u = clamp_u(u_x);
        Some(ColumnStart { row, n, u, start: guide_start(guide, n, u) })
    }

    /// The walk from the guide's segment to the column, and the point (`invert_cdf`'s second
    /// half).
    #[inline(always)]
    fn finish_column(&self, s: ColumnStart) -> (Vec2, [u32; 2]) {
        let (cdf, _) = self.row_tables(s.row.row);
        let col = walk_to_segment(cdf, s.n, s.u, s.start);
        let du = segment_offset(cdf, col, s.u);
        let x = ((col as f32 + du) / self.width as f32).min(ONE_MINUS_EPSILON);
        (Vec2::new(x, s.row.y), [col as u32, s.row.row as u32])
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

    /// The segment of a plain binary search, as the GPU kernel finds it.
    fn binary_search(cdf: &[f32], u: f32) -> usize {
        let n = cdf.len() - 1;
        let u = if u.is_nan() { 0.0 } else { u.clamp(0.0, ONE_MINUS_EPSILON) };
        cdf.partition_point(|&c| c <= u).saturating_sub(1).min(n - 1)
    }

    /// The guided search returns the binary search's segment for every `u`, whatever the guide
    /// (the table's, none, or one pointing at the wrong end), over tables with zero-weight
    /// runs, spikes and one segment, at every bucket edge and its neighbouring floats.
    #[test]
    fn guided_search_finds_the_binary_search_segment() {
        let spike: Vec<f32> = (0..300).map(|i| if i == 123 { 1e6 } else { (i % 7) as f32 }).collect();
        let tables: [Vec<f32>; 5] = [
            std::vec![1.0],
            std::vec![0.0, 0.0, 5.0, 0.0],
            spike,
            (0..64).map(|i| (i * i) as f32).collect(),
            std::vec![1e-30, 1.0, 1e-30, 0.0, 2.0],
        ];
        let hostile = [f32::NAN, -1.0, 0.0, 1e-40, 0.5, ONE_MINUS_EPSILON, 1.0, f32::INFINITY];
        for weights in &tables {
            let d = Distribution1D::new(weights);
            let n = d.len();
            let mut us: Vec<f32> = hostile.to_vec();
            for k in 0..=n {
                let edge = k as f32 / n as f32;
                us.extend([edge, edge.next_down(), edge.next_up()]);
            }
            us.extend(d.cdf.iter().flat_map(|&c| [c, c.next_down(), c.next_up()]));
            us.extend((0..5000).map(|i| (i as f32 * 0.618_034).fract()));
            let wrong = std::vec![n as u32 - 1; n];
            for &u in &us {
                let expected = binary_search(&d.cdf, u);
                let u = if u.is_nan() { 0.0 } else { u.clamp(0.0, ONE_MINUS_EPSILON) };
                for guide in [&d.guide[..], &[], &wrong[..], &[0]] {
                    assert_eq!(find_segment(&d.cdf, guide, n, u), expected, "{weights:?} u {u} guide {guide:?}");
                }
            }
        }
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
