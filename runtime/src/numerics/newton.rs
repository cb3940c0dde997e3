//! The simplified-Newton matrix `I − s J` shared by the implicit methods (SDIRK4 with
//! `s = hγ`, BDF with `s = h/γ_k`), and Jacobians by forward differences where the system
//! has none.
//!
//! Policy (Hairer & Wanner, *Solving ODEs II*, §IV.8): `J` is evaluated at an accepted
//! point and kept while Newton converges fast; it is marked stale after every accepted
//! step and refreshed only when an iteration fails with a stale one (or converged
//! slowly). The LU of `I − s J` is kept while `s` and `J` are unchanged.

use nalgebra::DMatrix;

use super::eval::Eval;
use super::lu::DenseLu;
use super::tableau::SDIRK4;
use crate::{ErrorKind, OdeSystem};

/// The stage Newton iteration of the stiffly accurate DIRK methods (`Sdirk4` and, on the
/// group, `LieSdirk`): iterations per stage before the step counts as failed.
pub(crate) const DIRK_MAX_NEWTON_ITERATIONS: usize = 10;
/// After an accepted DIRK step, the Jacobian is kept if Newton converged at least this
/// fast.
pub(crate) const DIRK_THETA_REUSE_JACOBIAN: f64 = 0.1;

/// A DIRK stage's Newton iteration stops when its estimated remaining error is below
/// this fraction of the tolerance (in the error test's weighted norm).
///
/// `κ ∈ [0.01, 0.1]` (Hairer & Wanner II, §IV.8, here 0.05) suits a collocation method
/// such as RADAU5, whose stages are solved together so that their Newton error enters
/// `y₁` once. In a DIRK the stage derivatives are recovered as
/// `k_j = (Z_j − base_j)/(hγ)`, so a stage error `δ_j` reaches `y₁ = Z_s` (and the error
/// estimate) multiplied by up to `|a_sj|/γ`, in all up to `A = Σ_j |a_sj|/γ ≈ 68`
/// ([`dirk_amplification`]), and with the same sign step after step: the global error
/// grows with the number of steps times `A δ`. Measured on S10 (the free body, three
/// flip periods, against a different method): with `κ / (10 A)` `LieSdirk`'s error
/// stopped following the tolerance below rtol 1e-8 (8.6e-7 at 1e-8, 1.3e-9 at 1e-12),
/// while at a fixed step with a tight Newton tolerance it converges at order 4 to the
/// reference's accuracy; with `κ / (1000 A)` it follows the tolerance (1.5e-7 at 1e-8,
/// 3.5e-11 at 1e-12) for 10–25 % more evaluations, and a tenth of that changes nothing.
pub(crate) fn dirk_stage_tolerance() -> f64 {
    0.05 / (1000.0 * dirk_amplification())
}

/// `Σ_j |a_sj| / γ` of SDIRK4: the largest factor by which Newton errors in the stages
/// can reach the result `y₁ = Z_s` through the stage derivatives
/// `k_j = (Z_j − base_j)/(hγ)`.
pub(crate) fn dirk_amplification() -> f64 {
    let s = SDIRK4.stages();
    (0..s).map(|j| SDIRK4.a(s - 1, j).abs()).sum::<f64>() / SDIRK4.a(0, 0)
}

/// `J`, what it was built from, and the factorised `I − s J`.
#[derive(Debug)]
pub(crate) struct NewtonMatrix {
    pub jac: DMatrix<f64>,
    /// `J` was evaluated at the current accepted point.
    pub jac_current: bool,
    /// `J` must be (re)evaluated before the next attempt.
    pub jac_needed: bool,
    lu: DenseLu,
    /// `lu` holds `I − s J` for the current `J` and `s = scale`.
    factored: bool,
    /// The `s` of the factorised matrix.
    scale: f64,
}

impl NewtonMatrix {
    pub fn new(n: usize) -> Self {
        NewtonMatrix {
            jac: DMatrix::zeros(n, n),
            jac_current: false,
            jac_needed: true,
            lu: DenseLu::new(n),
            factored: false,
            scale: f64::NAN,
        }
    }

    /// Evaluates `J` at `(t, y)` if it is needed (see [`jacobian`] for `f` and `fresh`).
    pub fn update_jacobian<S: OdeSystem + ?Sized>(
        &mut self,
        ev: &mut Eval<'_, S>,
        t: f64,
        y: &[f64],
        f: &mut [f64],
        fresh: bool,
    ) -> Result<(), ErrorKind> {
        if self.jac_needed {
            jacobian(ev, t, y, f, fresh, &mut self.jac)?;
            self.jacobian_updated();
        }
        Ok(())
    }

    /// `jac` was just evaluated at the current accepted point (by the caller, for
    /// methods with their own Jacobian, e.g. in a Lie-group chart).
    pub fn jacobian_updated(&mut self) {
        self.jac_current = true;
        self.jac_needed = false;
        self.factored = false;
    }

    /// Factorises `I − s J` unless it is already factorised for this `s` and `J`
    /// (counted in `lu`).
    pub fn factor(&mut self, s: f64, lu_count: &mut usize) {
        if !self.factored || self.scale != s {
            self.lu.factor_shifted(&self.jac, s);
            self.factored = true;
            self.scale = s;
            *lu_count += 1;
        }
    }

    /// Like [`factor`](Self::factor), but keeps a factorisation of the current `J` whose
    /// `s` is within the relative distance `keep` of the wanted one (the simplified
    /// Newton iteration converges with it, a little slower; CVODE and diffsol do the
    /// same for BDF). Returns whether the factorised `s` is exactly `s`.
    pub fn factor_near(&mut self, s: f64, keep: f64, lu_count: &mut usize) -> bool {
        if self.factored && (s / self.scale - 1.0).abs() <= keep {
            return self.scale == s;
        }
        self.factor(s, lu_count);
        true
    }

    /// The factorised matrix (after [`factor`](Self::factor)).
    pub fn lu(&self) -> &DenseLu {
        debug_assert!(self.factored, "factorised before use");
        &self.lu
    }

    /// After a failure with a stale `J`: refresh it before the next attempt.
    pub fn refresh_if_stale(&mut self) {
        if !self.jac_current {
            self.jac_needed = true;
        }
    }

    /// At a discontinuity (new equations from here on): `J` may still serve the
    /// simplified Newton iteration, but is refreshed at the first failure.
    pub fn mark_stale(&mut self) {
        self.jac_current = false;
    }
}

/// `∂f/∂y(t, y)` into `jac`: from the system, or by forward differences with increments
/// `√(ε max(10⁻⁵, |y_j|))` (Hairer & Wanner II, §IV.8) around `f`. With `fresh`, `f` is
/// first overwritten by `f(t, y)` (only when differences are needed): for methods whose
/// stored derivative is not `f(t, y)` itself (BDF's is the formula's), differencing
/// against it would mix the Newton error into `J`.
pub(crate) fn jacobian<S: OdeSystem + ?Sized>(
    ev: &mut Eval<'_, S>,
    t: f64,
    y: &[f64],
    f: &mut [f64],
    fresh: bool,
    jac: &mut DMatrix<f64>,
) -> Result<(), ErrorKind> {
    ev.stats.jacobian_evaluations += 1;
    if !ev.system.jacobian(t, y, jac) {
        ev.stats.finite_difference_jacobians += 1;
        if fresh {
            ev.rhs(t, y, f)?;
        }
        let mut yp = y.to_vec();
        let mut fp = vec![0.0; y.len()];
        for j in 0..y.len() {
            let delta = (f64::EPSILON * y[j].abs().max(1e-5)).sqrt();
            yp[j] = y[j] + delta;
            ev.rhs(t, &yp, &mut fp)?;
            for i in 0..y.len() {
                jac[(i, j)] = (fp[i] - f[i]) / delta;
            }
            yp[j] = y[j];
        }
    }
    match jac.iter().position(|x| !x.is_finite()) {
        Some(p) => Err(ErrorKind::NonFinite {
            t,
            component: p % y.len(),
        }),
        None => Ok(()),
    }
}
