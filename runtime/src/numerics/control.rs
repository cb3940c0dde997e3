//! Step-size control from the error estimate.

/// Proportional–integral step-size controller (K. Gustafsson, ACM TOMS 17 (1991)
/// 533–554, in the form used by Hairer's `DOPRI5` code, cf. Hairer & Wanner, *Solving
/// ODEs II*, §IV.2, "PI step size control"): after an accepted step with scaled error `err ≤ 1` the step is multiplied by
///
/// ```text
/// safety · err^(−α) · err_prev^(β),   clamped to [fac_min, fac_max],
/// ```
///
/// and after a rejected step by `safety · err^(−α)` clamped to `[fac_min, 1]`. Right
/// after a rejection the step may not grow. For an error estimator of order `p`
/// (local error `O(h^(p+1))`), `k = p + 1`, `β = 0.2 / k` and `α = 1/k − 0.75 β`, which
/// for Dormand–Prince (`p = 4`) gives Hairer's `α = 0.17`, `β = 0.04`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PiController {
    pub alpha: f64,
    pub beta: f64,
    pub safety: f64,
    pub fac_min: f64,
    pub fac_max: f64,
    err_prev: f64,
    rejected_last: bool,
}

impl PiController {
    /// Controller for an error estimate of order `p` (see the type's documentation).
    pub fn new(p: u32) -> Self {
        let k = f64::from(p + 1);
        let beta = 0.2 / k;
        PiController {
            alpha: 1.0 / k - 0.75 * beta,
            beta,
            safety: 0.9,
            fac_min: 0.2,
            fac_max: 10.0,
            err_prev: 1e-4,
            rejected_last: false,
        }
    }

    /// Factor for the next step after a step with `err ≤ 1` was accepted.
    pub fn accept(&mut self, err: f64) -> f64 {
        let err = err.max(1e-10);
        let mut fac = self.safety * err.powf(-self.alpha) * self.err_prev.powf(self.beta);
        fac = fac.clamp(self.fac_min, self.fac_max);
        if self.rejected_last {
            fac = fac.min(1.0);
        }
        self.err_prev = err;
        self.rejected_last = false;
        fac
    }

    /// Factor for the retry after a step with `err > 1` was rejected (always `< 1`).
    pub fn reject(&mut self, err: f64) -> f64 {
        self.rejected_last = true;
        let fac = if err.is_finite() {
            self.safety * err.powf(-self.alpha)
        } else {
            self.fac_min
        };
        fac.clamp(self.fac_min, self.safety)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dopri_coefficients_and_limits() {
        let mut c = PiController::new(4);
        assert!((c.alpha - 0.17).abs() < 1e-15 && (c.beta - 0.04).abs() < 1e-15);
        // Tiny error: growth capped at fac_max.
        assert_eq!(c.accept(0.0), 10.0);
        // Error exactly at tolerance with the same previous error: shrink by about safety.
        let mut c = PiController::new(4);
        c.accept(1.0);
        let f = c.accept(1.0);
        assert!((f - 0.9).abs() < 1e-12);
        // Huge error: shrink capped at fac_min, also for NaN/∞.
        assert_eq!(c.reject(1e12), 0.2);
        assert_eq!(c.reject(f64::INFINITY), 0.2);
        assert!(c.reject(1.5) < 0.9);
    }

    #[test]
    fn no_growth_right_after_rejection_and_integral_action() {
        let mut c = PiController::new(4);
        c.reject(2.0);
        assert!(c.accept(1e-6) <= 1.0);
        assert!(c.accept(1e-6) > 1.0);
        // A previous large error damps the growth (the integral part).
        let mut a = PiController::new(4);
        let mut b = PiController::new(4);
        a.accept(0.9);
        b.accept(0.01);
        assert!(a.accept(0.1) > b.accept(0.1));
    }
}
