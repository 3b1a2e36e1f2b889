//! Reading a measured error curve between its points: linear interpolation in log-log space
//! (Monte Carlo error curves are close to straight lines there), and beyond the measured range
//! an extrapolation with the Monte Carlo rate `error ∝ 1 / x` from the last point, marked as
//! such. Below the first point nothing is extrapolated: less than one rung is not a render.

/// A value read off a curve, with how it was obtained.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Estimate {
    /// On or between measured points (log-log linear).
    Interpolated(f64),
    /// Already reached at the first point: the value is an upper bound.
    AtMost(f64),
    /// Beyond the measured range, from the last point with slope -1 in log-log.
    Extrapolated(f64),
    /// Below the first measured point (e.g. a time budget shorter than the 1-spp render).
    BelowRange,
    /// No valid point (positive and finite) to read from.
    Unavailable,
}

impl Estimate {
    /// Formats the value with `f`, prefixed `≤ ` for a bound and `≈ ` for an extrapolation.
    pub fn show(&self, f: impl Fn(f64) -> String) -> String {
        match *self {
            Estimate::Interpolated(v) => f(v),
            Estimate::AtMost(v) => format!("≤ {}", f(v)),
            Estimate::Extrapolated(v) => format!("≈ {}", f(v)),
            Estimate::BelowRange => "n/a (< 1st rung)".into(),
            Estimate::Unavailable => "n/a".into(),
        }
    }
}

/// True for a point usable in log space.
fn valid(&(x, y): &(f64, f64)) -> bool {
    x > 0.0 && y > 0.0 && x.is_finite() && y.is_finite()
}

/// Log-log linear interpolation: `y` at `x` on the line through `a` and `b` (`a.0 != b.0`).
fn loglog(a: (f64, f64), b: (f64, f64), x: f64) -> f64 {
    let t = (x.ln() - a.0.ln()) / (b.0.ln() - a.0.ln());
    (a.1.ln() + t * (b.1.ln() - a.1.ln())).exp()
}

/// The `x` (e.g. time) from which a curve of `(x, y)` points in measurement order (spp
/// increasing) stays at `y <= target`: interpolated in log-log between the last point above the
/// target and the next one (a noisy early dip below the target does not count);
/// [`Estimate::AtMost`] the first `x` when no point is above it; extrapolated from the last
/// point with `y ∝ 1/x` when the last point is still above it.
pub fn x_to_reach(points: &[(f64, f64)], target: f64) -> Estimate {
    let points: Vec<(f64, f64)> = points.iter().copied().filter(valid).collect();
    if points.is_empty() || !(target > 0.0) {
        return Estimate::Unavailable;
    }
    match points.iter().rposition(|p| p.1 > target) {
        None => Estimate::AtMost(points[0].0),
        Some(i) if i + 1 == points.len() => {
            let (x, y) = points[i];
            Estimate::Extrapolated(x * y / target)
        }
        Some(i) => {
            let (a, b) = (points[i], points[i + 1]);
            // Swap the roles of x and y: y falls from above to at most the target across this pair.
            Estimate::Interpolated(loglog((a.1, a.0), (b.1, b.0), target))
        }
    }
}

/// `y` at `x` on a curve of `(x, y)` points (any order; sorted by `x` here): interpolated in
/// log-log between the neighbouring points, extrapolated with `y ∝ 1/x` from the largest `x`
/// beyond it, [`Estimate::BelowRange`] below the smallest.
pub fn y_at(points: &[(f64, f64)], x: f64) -> Estimate {
    let mut points: Vec<(f64, f64)> = points.iter().copied().filter(valid).collect();
    if points.is_empty() || !(x > 0.0 && x.is_finite()) {
        return Estimate::Unavailable;
    }
    points.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (first, last) = (points[0], points[points.len() - 1]);
    if x < first.0 {
        return Estimate::BelowRange;
    }
    if x > last.0 {
        return Estimate::Extrapolated(last.1 * last.0 / x);
    }
    for pair in points.windows(2) {
        let (a, b) = (pair[0], pair[1]);
        if x == a.0 {
            return Estimate::Interpolated(a.1);
        }
        if x <= b.0 {
            return Estimate::Interpolated(if x == b.0 { b.1 } else { loglog(a, b, x) });
        }
    }
    Estimate::Interpolated(last.1)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(e: Estimate, want: f64) -> bool {
        match e {
            Estimate::Interpolated(v) | Estimate::AtMost(v) | Estimate::Extrapolated(v) => {
                (v - want).abs() <= 1e-9 * want.abs()
            }
            Estimate::BelowRange | Estimate::Unavailable => false,
        }
    }

    /// `y = 1 / x` at x = 1, 2, 4, 8.
    fn inverse() -> Vec<(f64, f64)> {
        [1.0, 2.0, 4.0, 8.0].iter().map(|&x| (x, 1.0 / x)).collect()
    }

    #[test]
    fn reach_interpolates_in_log_log() {
        // On y = 1/x the log-log line is exact: y = 0.3 at x = 1/0.3.
        let e = x_to_reach(&inverse(), 0.3);
        assert!(matches!(e, Estimate::Interpolated(_)) && close(e, 1.0 / 0.3), "{e:?}");
        // Exactly on a point.
        assert!(close(x_to_reach(&inverse(), 0.25), 4.0));
        // Between (1, 1) and (2, 0.01): slope log(0.01)/log(2); y = 0.1 halfway in log x.
        let e = x_to_reach(&[(1.0, 1.0), (2.0, 0.01)], 0.1);
        assert!(close(e, 2f64.sqrt()), "{e:?}");
    }

    #[test]
    fn reach_outside_the_range() {
        assert_eq!(x_to_reach(&inverse(), 2.0), Estimate::AtMost(1.0));
        let e = x_to_reach(&inverse(), 0.01);
        assert!(matches!(e, Estimate::Extrapolated(_)) && close(e, 100.0), "{e:?}");
        assert_eq!(x_to_reach(&[], 0.1), Estimate::Unavailable);
        assert_eq!(x_to_reach(&inverse(), 0.0), Estimate::Unavailable);
        assert_eq!(x_to_reach(&[(0.0, 1.0), (f64::NAN, 0.5)], 0.1), Estimate::Unavailable);
    }

    #[test]
    fn reach_takes_the_last_crossing_in_measurement_order() {
        // A noisy curve that dips below the target at x = 2, rises, then falls again: it stays
        // below 0.2 only from between x = 4 and 8.
        let pts = [(1.0, 1.0), (2.0, 0.1), (4.0, 0.5), (8.0, 0.05)];
        assert!(close(x_to_reach(&pts, 0.2), loglog((0.5, 4.0), (0.05, 8.0), 0.2)));
        // Still above at the end: extrapolated from the last point even after an early dip.
        let pts = [(1.0, 1.0), (2.0, 0.1), (4.0, 0.5)];
        assert_eq!(x_to_reach(&pts, 0.2), Estimate::Extrapolated(10.0));
    }

    #[test]
    fn value_at_interpolates_and_extrapolates() {
        let e = y_at(&inverse(), 3.0);
        assert!(matches!(e, Estimate::Interpolated(_)) && close(e, 1.0 / 3.0), "{e:?}");
        assert!(close(y_at(&inverse(), 1.0), 1.0));
        assert!(close(y_at(&inverse(), 8.0), 0.125));
        let e = y_at(&inverse(), 16.0);
        assert!(matches!(e, Estimate::Extrapolated(_)) && close(e, 1.0 / 16.0), "{e:?}");
        assert_eq!(y_at(&inverse(), 0.5), Estimate::BelowRange);
        // Unsorted input (timing noise) is sorted by x first.
        let e = y_at(&[(4.0, 0.25), (1.0, 1.0), (2.0, 0.5)], 3.0);
        assert!(close(e, 1.0 / 3.0), "{e:?}");
        assert_eq!(y_at(&[], 1.0), Estimate::Unavailable);
        assert_eq!(y_at(&inverse(), f64::NAN), Estimate::Unavailable);
    }

    #[test]
    fn show_marks_the_kind() {
        let f = |v: f64| format!("{v:.1}");
        assert_eq!(Estimate::Interpolated(1.0).show(f), "1.0");
        assert_eq!(Estimate::AtMost(1.0).show(f), "≤ 1.0");
        assert_eq!(Estimate::Extrapolated(1.0).show(f), "≈ 1.0");
        assert_eq!(Estimate::BelowRange.show(f), "n/a (< 1st rung)");
        assert_eq!(Estimate::Unavailable.show(f), "n/a");
    }
}
