//! Multiple importance sampling weights (Veach 1997, chapter 9) that stay finite for
//! infinite, zero, negative and NaN densities.
//!
//! Densities are sanitized first: NaN and negative values count as 0. An infinite density
//! (a delta lobe: [`crate::BsdfSample::mis_pdf`] is `+inf` for one) wins against any finite
//! one; two infinite densities share equally.
//! Ratios are formed before squaring, so no finite input can overflow.

#[inline(always)]
fn sanitize(pdf: f32) -> f32 {
    // f32::max maps NaN to 0.
    pdf.max(0.0)
}

/// Shared skeleton: weight of `f` against `g` given `h(ratio) = weight of the smaller one`.
#[inline(always)]
fn heuristic(f: f32, g: f32, small_over_large: impl Fn(f32) -> f32) -> f32 {
    if f == f32::INFINITY {
        return if g == f32::INFINITY { 0.5 } else { 1.0 };
    }
    if g == f32::INFINITY || f <= 0.0 {
        return 0.0;
    }
    if f >= g { 1.0 - small_over_large(g / f) } else { small_over_large(f / g) }
}

/// Balance heuristic, Veach eq. 9.10: `w = nf pf / (nf pf + ng pg)`.
#[inline]
pub fn balance_heuristic(nf: f32, f_pdf: f32, ng: f32, g_pdf: f32) -> f32 {
    // A product 0 * inf (an unused technique with a delta density) is NaN: sanitize again.
    let f = sanitize(sanitize(nf) * sanitize(f_pdf));
    let g = sanitize(sanitize(ng) * sanitize(g_pdf));
    // For r = small/large: w_small = r / (1 + r).
    heuristic(f, g, |r| r / (1.0 + r))
}

/// Power heuristic with beta = 2, Veach eq. 9.13: `w = (nf pf)^2 / ((nf pf)^2 + (ng pg)^2)`.
#[inline]
pub fn power_heuristic(nf: f32, f_pdf: f32, ng: f32, g_pdf: f32) -> f32 {
    let f = sanitize(sanitize(nf) * sanitize(f_pdf));
    let g = sanitize(sanitize(ng) * sanitize(g_pdf));
    // For r = small/large: w_small = r^2 / (1 + r^2).
    heuristic(f, g, |r| {
        let r2 = r * r;
        r2 / (1.0 + r2)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reference(f: f64, g: f64, beta: i32) -> f64 {
        f.powi(beta) / (f.powi(beta) + g.powi(beta))
    }

    #[test]
    fn weights_match_the_textbook_formulas() {
        for (f, g) in [(1.0f32, 1.0f32), (0.3, 2.0), (5.0, 0.01), (1e-20, 3e-20), (1e30, 2e30), (7.0, 0.0)] {
            let b = balance_heuristic(1.0, f, 1.0, g) as f64;
            let p = power_heuristic(1.0, f, 1.0, g) as f64;
            assert!((b - reference(f as f64, g as f64, 1)).abs() < 1e-6, "{f} {g}");
            assert!((p - reference(f as f64, g as f64, 2)).abs() < 1e-6, "{f} {g}");
            // The weights of the two techniques sum to one.
            assert!((p + power_heuristic(1.0, g, 1.0, f) as f64 - 1.0).abs() < 1e-6);
        }
        assert!((power_heuristic(2.0, 1.0, 1.0, 1.0) - 0.8).abs() < 1e-7);
    }

    #[test]
    fn special_densities_give_finite_weights_in_range() {
        for (n, p) in [(0.0f32, f32::INFINITY), (f32::NAN, f32::INFINITY), (0.0, f32::NAN)] {
            assert_eq!(balance_heuristic(n, p, 1.0, 1.0), 0.0);
            assert_eq!(power_heuristic(n, p, 1.0, 1.0), 0.0);
            assert_eq!(power_heuristic(1.0, 1.0, n, p), 1.0);
        }
        let specials = [0.0, -1.0, f32::NAN, f32::INFINITY, f32::NEG_INFINITY, f32::MAX, f32::MIN_POSITIVE, 1e-45, 1.0];
        for &f in &specials {
            for &g in &specials {
                for h in [balance_heuristic, power_heuristic] {
                    let w = h(1.0, f, 1.0, g);
                    assert!((0.0..=1.0).contains(&w), "{f} {g} -> {w}");
                }
            }
        }
        assert_eq!(power_heuristic(1.0, f32::INFINITY, 1.0, 1e30), 1.0);
        assert_eq!(power_heuristic(1.0, 1e30, 1.0, f32::INFINITY), 0.0);
        assert_eq!(power_heuristic(1.0, 0.0, 1.0, 0.0), 0.0);
        assert_eq!(power_heuristic(1.0, f32::MAX, 1.0, f32::MAX), 0.5);
    }
}
