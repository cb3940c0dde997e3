//! Bracketing root finder for switching functions: the Anderson–Björck variant of the
//! Illinois (modified regula falsi) method (N. Anderson & Å. Björck, "A new high order
//! method of regula falsi type for computing a root of an equation", BIT 13 (1973)
//! 253–264; the Illinois rule is M. Dowell & P. Jarratt, BIT 11 (1971) 168–174), with a
//! bisection safeguard.
//!
//! A switching function is positive while its mode holds and the event is where it
//! becomes `≤ 0`, so the result is a *bracket* `[lo, hi]` with `g(lo) > 0 ≥ g(hi)`:
//! the integrator steps exactly to `hi`, the first time known to be past the switch,
//! and the mode change is decided there (never on the wrong side).

/// The final bracket: `g(lo) > 0`, `g(hi) ≤ 0`, `hi − lo ≤ xtol` (or no float between).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bracket {
    pub lo: f64,
    pub hi: f64,
    pub g_lo: f64,
    pub g_hi: f64,
    /// Evaluations of `g` spent.
    pub evaluations: usize,
}

/// Largest number of evaluations; with the bisection safeguard the bracket halves at
/// least every third step, so 300 is far more than any `f64` interval needs.
const MAX_EVALUATIONS: usize = 300;

/// Narrows `[a, b]` with `g(a) = ga > 0 ≥ gb = g(b)` to width `xtol`.
///
/// Each step takes the secant (regula falsi) point of the current bracket. When the
/// same end is kept twice in a row, its stored value is scaled by the Anderson–Björck
/// factor `m = 1 − g(x)/g(new end)` (or ½ if `m ≤ 0`, the Illinois rule), which
/// restores superlinear convergence (order ≈ 1.7). If three steps have not halved the
/// bracket, the next point is the midpoint instead.
pub fn find_root<G: FnMut(f64) -> f64>(
    mut g: G,
    a: f64,
    b: f64,
    ga: f64,
    gb: f64,
    xtol: f64,
) -> Bracket {
    debug_assert!(ga > 0.0 && gb <= 0.0 && a < b);
    let (mut lo, mut hi, mut glo, mut ghi) = (a, b, ga, gb);
    // Values used in the secant formula; may be scaled (Anderson–Björck).
    let (mut slo, mut shi) = (ga, gb);
    // Which end was replaced last: +1 lo, −1 hi, 0 none yet.
    let mut last_side = 0;
    let mut evaluations = 0;
    let mut width_before = hi - lo;
    let mut since_halving = 0;
    while hi - lo > xtol && evaluations < MAX_EVALUATIONS {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break; // adjacent floats
        }
        let x = if since_halving >= 3 {
            mid
        } else {
            let x = hi - shi * (hi - lo) / (shi - slo);
            if x > lo && x < hi { x } else { mid }
        };
        let gx = g(x);
        evaluations += 1;
        if gx > 0.0 {
            if last_side == 1 {
                // lo replaced twice in a row: scale the stale value at hi.
                let m = 1.0 - gx / slo;
                shi *= if m > 0.0 { m } else { 0.5 };
            }
            lo = x;
            glo = gx;
            slo = gx;
            last_side = 1;
        } else {
            if last_side == -1 {
                let m = 1.0 - gx / shi;
                slo *= if m > 0.0 { m } else { 0.5 };
            }
            hi = x;
            ghi = gx;
            shi = gx;
            last_side = -1;
        }
        since_halving += 1;
        if hi - lo <= 0.5 * width_before {
            width_before = hi - lo;
            since_halving = 0;
        }
    }
    Bracket {
        lo,
        hi,
        g_lo: glo,
        g_hi: ghi,
        evaluations,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(g: impl Fn(f64) -> f64 + Copy, a: f64, b: f64, root: f64, max_evals: usize) {
        let xtol = 1e-12 * root.abs().max(1.0);
        let r = find_root(g, a, b, g(a), g(b), xtol);
        assert!(r.hi - r.lo <= xtol, "{r:?}");
        assert!(r.g_lo > 0.0 && r.g_hi <= 0.0, "{r:?}");
        assert!(
            r.lo <= root + xtol && r.hi >= root - xtol,
            "{r:?} vs {root}"
        );
        assert!(r.evaluations <= max_evals, "{} evaluations", r.evaluations);
    }

    #[test]
    fn smooth_roots_converge_superlinearly() {
        // cos on [0, 3]: root π/2.
        check(|x: f64| x.cos(), 0.0, 3.0, std::f64::consts::FRAC_PI_2, 15);
        // Strongly convex: plain regula falsi would keep one end for ever.
        check(|x: f64| 1.0 - x.powi(10), 0.0, 1.3, 1.0, 40);
        // exp decreasing through a tiny value.
        check(|x: f64| (-x).exp() - 1e-3, 0.0, 20.0, 1000f64.ln(), 40);
        // A root far from the origin (relative tolerance in time).
        let t0 = 5.0 * std::f64::consts::PI;
        check(move |x: f64| (t0 - x).sin(), t0 - 1.0, t0 + 0.5, t0, 25);
    }

    #[test]
    fn flat_and_discontinuous_functions_still_bracket() {
        // Triple root: slow for secants, the bisection safeguard keeps it linear.
        check(|x: f64| -(x - 0.3).powi(3), 0.0, 1.0, 0.3, 150);
        // A jump (sign change without a zero): the bracket still closes on it.
        check(
            |x: f64| if x < 0.7 { 1.0 } else { -2.0 },
            0.0,
            1.0,
            0.7,
            150,
        );
        // Exact zero at the right end is a valid "≤ 0" end.
        let r = find_root(|x: f64| 1.0 - x, 0.0, 1.0, 1.0, 0.0, 1e-12);
        assert!(r.hi - r.lo <= 1e-12 && (r.hi - 1.0).abs() <= 1e-12);
    }
}
