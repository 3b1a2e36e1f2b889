//! Adaptive tensor-product Gauss-Legendre quadrature over rectangles.
//!
//! Used by the chi-square test to integrate very peaked pdfs over the
//! (theta, phi) cells of the histogram.

/// Positive nodes of the 5-point Gauss-Legendre rule on `[-1, 1]`
/// (the rule is symmetric and also has a node at 0).
const GL5_POS_NODES: [f64; 2] = [0.5384693101056831, 0.906179845938664];

/// Nodes of the 5-point Gauss-Legendre rule on `[-1, 1]`.
pub const GL5_NODES: [f64; 5] = [-GL5_POS_NODES[1], -GL5_POS_NODES[0], 0.0, GL5_POS_NODES[0], GL5_POS_NODES[1]];

/// Weights of the 5-point Gauss-Legendre rule on `[-1, 1]` (they sum to 2).
pub const GL5_WEIGHTS: [f64; 5] =
    [0.23692688505618908, 0.47862867049936647, 128.0 / 225.0, 0.47862867049936647, 0.23692688505618908];

/// An axis-aligned rectangle `[x0, x1] x [y0, y1]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rect {
    /// Lower bound of the first coordinate.
    pub x0: f64,
    /// Upper bound of the first coordinate.
    pub x1: f64,
    /// Lower bound of the second coordinate.
    pub y0: f64,
    /// Upper bound of the second coordinate.
    pub y1: f64,
}

impl Rect {
    /// Creates the rectangle `[x0, x1] x [y0, y1]`.
    pub fn new(x0: f64, x1: f64, y0: f64, y1: f64) -> Self {
        Self { x0, x1, y0, y1 }
    }

    /// Splits the rectangle at its center into its four quadrants.
    pub fn quadrants(&self) -> [Rect; 4] {
        let xm = 0.5 * (self.x0 + self.x1);
        let ym = 0.5 * (self.y0 + self.y1);
        [
            Rect::new(self.x0, xm, self.y0, ym),
            Rect::new(xm, self.x1, self.y0, ym),
            Rect::new(self.x0, xm, ym, self.y1),
            Rect::new(xm, self.x1, ym, self.y1),
        ]
    }
}

/// Integrates `f` over `rect` with the 5x5 tensor-product Gauss-Legendre rule
/// (exact for polynomials of degree 9 in each variable).
///
/// `prep_x` and `prep_y` map each node coordinate to per-node data (for example
/// `sin_cos`) so that expensive per-coordinate work is done 5 + 5 times instead
/// of 25 times; `f` then receives the prepared data of one node pair.
pub fn gauss_legendre_5x5<A: Copy, B: Copy>(
    rect: &Rect,
    prep_x: impl Fn(f64) -> A,
    prep_y: impl Fn(f64) -> B,
    mut f: impl FnMut(A, B) -> f64,
) -> f64 {
    let (hx, cx) = (0.5 * (rect.x1 - rect.x0), 0.5 * (rect.x1 + rect.x0));
    let (hy, cy) = (0.5 * (rect.y1 - rect.y0), 0.5 * (rect.y1 + rect.y0));
    let xs = GL5_NODES.map(|t| prep_x(cx + hx * t));
    let ys = GL5_NODES.map(|t| prep_y(cy + hy * t));
    let mut sum = 0.0;
    for (&x, &wx) in xs.iter().zip(&GL5_WEIGHTS) {
        let mut row = 0.0;
        for (&y, &wy) in ys.iter().zip(&GL5_WEIGHTS) {
            row += wy * f(x, y);
        }
        sum += wx * row;
    }
    sum * hx * hy
}

/// Accuracy goals of [`integrate_adaptive`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AdaptiveTolerance {
    /// A region is accepted when its coarse and refined estimates differ by at
    /// most `max(rel * |refined|, abs)`.
    pub rel: f64,
    /// Absolute tolerance per region, see [`AdaptiveTolerance::rel`].
    pub abs: f64,
    /// Maximum subdivision depth; regions at this depth are accepted even if
    /// they did not converge (and counted in [`AdaptiveResult::unconverged`]).
    pub max_depth: u32,
}

/// Result of [`integrate_adaptive`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct AdaptiveResult {
    /// The integral estimate.
    pub value: f64,
    /// How many times the fixed rule was applied.
    pub rule_applications: u64,
    /// How many regions were accepted at the depth cap without meeting the
    /// tolerance.
    pub unconverged: u64,
}

/// Integrates over `rect` adaptively: the fixed `rule` (which integrates one
/// rectangle) is applied to a region and to its four quadrants; when the two
/// estimates agree within `tol` the quadrant sum is accepted, otherwise the
/// quadrants are refined in turn (explicit stack, no recursion).
///
/// `coarse` may pass an already known `rule(rect)` to save one application.
pub fn integrate_adaptive(
    rect: Rect,
    coarse: Option<f64>,
    tol: AdaptiveTolerance,
    mut rule: impl FnMut(&Rect) -> f64,
) -> AdaptiveResult {
    let mut result = AdaptiveResult::default();
    let coarse = coarse.unwrap_or_else(|| {
        result.rule_applications += 1;
        rule(&rect)
    });
    let mut stack = vec![(rect, coarse, 0u32)];
    while let Some((region, coarse, depth)) = stack.pop() {
        let quads = region.quadrants();
        let parts = quads.map(|q| rule(&q));
        result.rule_applications += 4;
        let fine: f64 = parts.iter().sum();
        let converged = (fine - coarse).abs() <= (tol.rel * fine.abs()).max(tol.abs);
        if converged || depth + 1 >= tol.max_depth || !fine.is_finite() {
            result.value += fine;
            if !converged {
                result.unconverged += 1;
            }
        } else {
            for (q, p) in quads.into_iter().zip(parts) {
                stack.push((q, p, depth + 1));
            }
        }
    }
    result
}
