//! Variable-order, variable-step BDF (backward differentiation formulas) of orders 1–5
//! for stiff problems, in the quasi-constant-step form of MATLAB's `ode15s` with the
//! NDF parameter `κ = 0` (plain BDF; Shampine & Reichelt, "The MATLAB ODE suite",
//! SIAM J. Sci. Comput. 18, 1997, §2; the same structure as SciPy's `BDF`).
//!
//! **What it keeps.** The backward differences of the solution at the current step
//! size `h`, `D_j = ∇ʲ y_n` for `j = 0 … k + 2` (`D_0 = y_n`, `D_1 ≈ h y'_n`). The
//! predictor is `y⁽⁰⁾ = Σ_{j≤k} D_j`, and the order-`k` BDF
//! `Σ_{j=1}^{k} (1/j) ∇ʲ y_{n+1} = h f(t_{n+1}, y_{n+1})` becomes, for the correction
//! `d = y_{n+1} − y⁽⁰⁾`,
//! `d = c f(t_{n+1}, y⁽⁰⁾ + d) − ψ`, with `c = h / γ_k`, `γ_k = Σ_{j=1}^{k} 1/j` and
//! `ψ = Σ_{j=1}^{k} γ_j D_j / γ_k`. It is solved by simplified Newton with the matrix
//! `I − cJ`, whose LU is reused while `J` is unchanged and `c` within 30 % of the
//! factorised one (refactorised at the exact `c` if Newton then fails);
//! `J` comes from [`OdeSystem::jacobian`] or forward differences and is refreshed only
//! when Newton fails or converges too slowly. When `h` changes, the differences are
//! re-interpolated to the new spacing (Shampine & Reichelt, eq. 2.4).
//!
//! **Error and order.** The local error of order `k` is `d / (k + 1)`; the next
//! difference `∇^{k+2} y_{n+1}` and the previous one `∇ᵏ y_{n+1}` give the estimates
//! for orders `k + 1` and `k − 1`. Between changes `h` is kept (and with it the LU);
//! after `k + 1` accepted steps of the same size, the order among `k − 1, k, k + 1`
//! whose estimate allows the largest step is taken. At a new order `h` changes by that
//! estimate's factor (at most 2×); at the same order only if it may double (it then
//! doubles) or must shrink below 0.9 of itself, so that long runs of equal steps keep
//! the differences, the LU and the Newton rate (diffsol's rule). A rejected step
//! shrinks `h` by the order-`k` estimate (at most 5×), a failed Newton iteration first
//! refactorises at the exact `c`, then refreshes `J`, then halves `h`. The error is
//! controlled per step, so the global error is about the number of steps times the
//! tolerance on non-dissipative problems. Orders 1 and 2 are A-stable (1 also
//! L-stable), 3–5 only A(α)-stable (α ≈ 86°, 73°, 52°): with stiff eigenvalues close
//! to the imaginary axis (lightly damped fast oscillations), prefer [`Sdirk4`].
//!
//! **When to use.** Stiff problems with a smooth solution, where it needs one
//! Newton solve per step (1.2–1.3 right-hand-side evaluations on the double pendulum
//! and the Panda at rtol 1e-8) instead of one per
//! stage: it is the default stiff method of CVODE, `ode15s` and diffsol. For a
//! discontinuous right-hand side, many restarts or a very low accuracy, [`Sdirk4`]
//! (one-step, L-stable) is the safer choice.
//!
//! **Dense output.** The interpolating polynomial of the step's order `k` through
//! `y_{n+1}, y_n, …, y_{n+1−k}`, which the backward differences represent:
//! `y(t_{n+1} + s h) = Σ_{j≤k} D_j Π_{m<j} (s + m)/(m + 1)` for `s ∈ [−1, 0]` (local
//! error `O(h^{k+1})`, as the step's). Every accepted point carries the derivative the
//! formula assigns to it, `f_{n+1} = (ψ + d)/c` (equal to `f(t_{n+1}, y_{n+1})` up to
//! the Newton tolerance, without the extra evaluation and without amplifying the Newton
//! error by the stiff part of `J`).
//!
//! **Restart** at a discontinuity drops the history (back to order 1 from the new
//! point) and keeps `h` and `J`.
//!
//! [`Sdirk4`]: super::Sdirk4

use nalgebra::DVector;

use super::stepper::{Begin, DenseStep, Eval, StepResult, StepState, Stepper, check_budget};
use crate::numerics::newton::NewtonMatrix;
use crate::numerics::{check_finite, error_norm, error_weights, underflow, weighted_norm};
use crate::{ErrorKind, OdeSystem, Options};

/// Highest order.
pub const MAX_ORDER: usize = 5;
/// Newton iterations per step before the attempt counts as failed.
const MAX_NEWTON_ITERATIONS: usize = 4;
/// Newton stops when its estimated remaining error is below this fraction of the
/// tolerance (in the weighted norm of the error test); diffsol's default, CVODE uses 0.1.
/// Against 0.05 (measured with `peers/diffsol`, rtol 1e-4 … 1e-9, with the step-size
/// hysteresis below): the Panda fall needs 1.18 instead of 1.40 evaluations per step at
/// rtol 1e-8 and the double pendulum 1.28 instead of 1.53, with grid errors of the same
/// size (both scenes are chaotic: a run's error varies by 10× between neighbouring
/// tolerances either way). On Robertson's problem the global error at rtol 1e-5 … 1e-8
/// stays between 0.9 and 14 times rtol (0.05: 2–8 times).
const NEWTON_TOL: f64 = 0.2;
/// Consecutive Newton failures (a failure with a stale Jacobian refreshes it, one with
/// a fresh Jacobian halves `h`) before giving up with [`ErrorKind::NewtonDivergence`].
pub const MAX_NEWTON_FAILURES: usize = 12;
/// Smallest step-size factor after a rejected step.
const MIN_FACTOR: f64 = 0.2;
/// After an order selection at the same order, `h` changes only if it may grow by this
/// factor (and then grows by exactly this factor) or must shrink below [`SHRINK_AT`]:
/// in between, the differences, the factorised Newton matrix and the Newton rate stay
/// valid, and a step usually converges after one evaluation (diffsol's defaults; CVODE
/// grows at 1.5). With growth at 1.5 (up to 10×), the double pendulum and the Panda took
/// 7–12 % fewer steps at equal rtol but missed by more, for no gain in time to a given
/// grid error (`peers/diffsol`, rtol 1e-4 … 1e-9).
const GROWTH: f64 = 2.0;
/// See [`GROWTH`].
const SHRINK_AT: f64 = 0.9;
/// Relative change of `c = h/γ_k` within which the factorised `I − cJ` is kept (the
/// simplified Newton iteration converges with it, a little slower; diffsol and CVODE
/// refactorise at 0.3 too). A Newton failure with a kept factorisation refactorises at
/// the exact `c` before anything else.
const LU_KEEP: f64 = 0.3;

/// Adaptive variable-order BDF (orders 1–5) for stiff problems.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Bdf {
    pub options: Options,
}

/// Outcome of the corrector of one attempt.
enum NewtonOutcome {
    /// Converged after `iterations`; `y1` and `correction` hold the result.
    Converged { iterations: usize },
    /// Diverged, too slow, or met a non-finite value (kept for reporting).
    Failed { non_finite: Option<ErrorKind> },
}

/// `γ_k = Σ_{j=1}^{k} 1/j` for `k = 0 … MAX_ORDER + 1`.
fn gamma() -> [f64; MAX_ORDER + 2] {
    let mut g = [0.0; MAX_ORDER + 2];
    for k in 1..g.len() {
        g[k] = g[k - 1] + 1.0 / k as f64;
    }
    g
}

/// Error constant of order `k` in terms of the correction: `1 / (k + 1)`.
fn error_constant(k: usize) -> f64 {
    1.0 / (k + 1) as f64
}

impl Bdf {
    pub fn new(options: Options) -> Self {
        Bdf { options }
    }

    /// The stepping state for states of `dim` components.
    pub fn stepper(&self, dim: usize) -> BdfStepper {
        BdfStepper {
            s: StepState::new(dim, self.options),
            gamma: gamma(),
            newton: NewtonMatrix::new(dim),
            h_next: 0.0,
            order: 1,
            equal_steps: 0,
            eta: 1.0,
            diff: vec![vec![0.0; dim]; MAX_ORDER + 3],
            y1: vec![0.0; dim],
            y_prev: vec![0.0; dim],
            psi: vec![0.0; dim],
            predictor: vec![0.0; dim],
            fz: vec![0.0; dim],
            delta: DVector::zeros(dim),
            correction: vec![0.0; dim],
            scratch: vec![0.0; dim],
            weights: vec![0.0; dim],
            dense_pending: None,
        }
    }
}

/// The state of a [`Bdf`] integration (see [`Stepper`]).
#[derive(Debug)]
pub struct BdfStepper {
    /// `s.h` is the spacing of the differences in `diff`.
    s: StepState,
    gamma: [f64; MAX_ORDER + 2],
    newton: NewtonMatrix,
    /// The spacing wanted for the next step.
    h_next: f64,
    order: usize,
    equal_steps: usize,
    /// Convergence-rate estimate `η = θ/(1 − θ)` of the last Newton solve, carried to the
    /// next one (so that a step may converge after one iteration).
    eta: f64,
    /// `D_j = ∇ʲ y_n` at spacing `h`, `j = 0 … MAX_ORDER + 2`.
    diff: Vec<Vec<f64>>,
    y1: Vec<f64>,
    y_prev: Vec<f64>,
    psi: Vec<f64>,
    predictor: Vec<f64>,
    fz: Vec<f64>,
    delta: DVector<f64>,
    correction: Vec<f64>,
    scratch: Vec<f64>,
    /// The error test's weights at the predictor, for the norms of one Newton solve.
    weights: Vec<f64>,
    /// The last accepted step's start and order, while its extension is not yet built
    /// into `s.dense` ([`Stepper::prepare_dense`]).
    dense_pending: Option<(f64, usize)>,
}

impl BdfStepper {
    /// Order 1 from the current point, differences at spacing `h`.
    fn reset_history(&mut self) {
        self.diff[0].copy_from_slice(&self.s.y);
        for (d, fi) in self.diff[1].iter_mut().zip(&self.s.f) {
            *d = self.s.h * fi;
        }
        self.order = 1;
        self.equal_steps = 0;
        self.h_next = self.s.h;
        self.dense_pending = None;
    }

    /// The interpolating polynomial of the accepted step from `t0` (see the module
    /// documentation) into `dense`, in powers of `θ = s + 1`.
    fn set_dense(&mut self, t0: f64, k: usize) {
        let n = self.s.y.len();
        let c = self.s.dense.reset(t0, self.s.h, k);
        // basis_j(θ) = Π_{m<j} (θ − 1 + m)/(m + 1), built up one factor at a time.
        let mut basis = [0.0; MAX_ORDER + 1];
        basis[0] = 1.0;
        for j in 0..=k {
            if j > 0 {
                let a = (j - 1) as f64 - 1.0;
                let scale = 1.0 / j as f64;
                for p in (0..=j).rev() {
                    let shifted = if p > 0 { basis[p - 1] } else { 0.0 };
                    basis[p] = (shifted + a * basis[p]) * scale;
                }
            }
            for (p, &b) in basis.iter().enumerate().take(j + 1) {
                if b != 0.0 {
                    for (cp, d) in c[p * n..(p + 1) * n].iter_mut().zip(&self.diff[j]) {
                        *cp += b * d;
                    }
                }
            }
        }
    }
}

impl Stepper for BdfStepper {
    fn state(&self) -> &StepState {
        &self.s
    }

    fn state_mut(&mut self) -> &mut StepState {
        &mut self.s
    }

    /// The past shifted with the point: `∇⁰ y_n` moves, the differences stay (the
    /// projection moves the recent past about as much as the point).
    fn nudge<S: OdeSystem + ?Sized>(&mut self, _ev: &mut Eval<'_, S>, y: &[f64]) -> StepResult {
        for ((d, &new), old) in self.diff[0].iter_mut().zip(y).zip(&self.s.y) {
            *d += new - old;
        }
        self.s.y.copy_from_slice(y);
        self.dense_pending = None;
        Ok(())
    }

    fn prepare_dense(&mut self) {
        if let Some((t0, order)) = self.dense_pending.take() {
            self.set_dense(t0, order);
        }
    }

    fn dense(&self) -> &DenseStep {
        debug_assert!(self.dense_pending.is_none(), "prepare_dense before dense");
        &self.s.dense
    }

    fn begin<S: OdeSystem + ?Sized>(&mut self, ev: &mut Eval<'_, S>, at: Begin) -> StepResult {
        self.s.enter(ev, at, 1, self.h_next)?;
        if at.fresh {
            self.newton = NewtonMatrix::new(at.y.len());
        } else {
            self.newton.mark_stale();
        }
        self.reset_history();
        Ok(())
    }

    fn step<S: OdeSystem + ?Sized>(&mut self, ev: &mut Eval<'_, S>, t_end: f64) -> StepResult {
        let n = self.s.y.len();
        // The differences change below: the last step's extension, if nobody asked
        // for it, is not built.
        self.dense_pending = None;
        let mut failures = 0;
        // A non-finite rhs value met ahead of the current time (see `Sdirk4`): a
        // Newton failure, but what is reported if the step then underflows.
        let mut non_finite_ahead: Option<ErrorKind> = None;
        // After a Newton failure with a factorisation kept from a nearby `c`, the next
        // attempts factorise at the exact `c` (nothing is kept).
        let mut lu_keep = LU_KEEP;
        loop {
            let t = self.s.t;
            check_budget(ev.stats, &self.s.options, t)?;
            let mut h_new = self.h_next.min(self.s.options.h_max);
            let last = t + 1.01 * h_new >= t_end;
            if last {
                h_new = t_end - t;
            }
            if underflow(t, h_new, &self.s.options) {
                return Err(
                    non_finite_ahead.unwrap_or(ErrorKind::StepSizeUnderflow { t, h: h_new })
                );
            }
            if h_new != self.s.h {
                rescale(&mut self.diff, self.order, h_new / self.s.h);
                self.s.h = h_new;
                self.equal_steps = 0;
            }
            let (h, order) = (self.s.h, self.order);
            self.h_next = h;
            self.newton
                .update_jacobian(ev, t, &self.s.y, &mut self.scratch, true)?;
            let c = h / self.gamma[order];
            let lu_exact = self
                .newton
                .factor_near(c, lu_keep, &mut ev.stats.lu_factorisations);
            // Predictor and the constant part ψ of the corrector.
            // Summed in the same order as term by term per component, by rows of `diff`.
            self.y1.copy_from_slice(&self.diff[0]);
            self.psi.fill(0.0);
            for j in 1..=order {
                let g = self.gamma[j];
                for ((y, p), d) in self.y1.iter_mut().zip(&mut self.psi).zip(&self.diff[j]) {
                    *y += d;
                    *p += g * d;
                }
            }
            let g = self.gamma[order];
            for p in &mut self.psi {
                *p /= g;
            }
            let t1 = if last { t_end } else { t + h };
            let iterations = match self.newton(ev, t1, c) {
                NewtonOutcome::Failed { non_finite } => {
                    ev.stats.rejected_steps += 1;
                    failures += 1;
                    if non_finite.is_some() {
                        non_finite_ahead = non_finite;
                    }
                    if failures >= MAX_NEWTON_FAILURES {
                        return Err(non_finite_ahead.unwrap_or(ErrorKind::NewtonDivergence { t }));
                    }
                    // A factorisation at another `c` is redone first, then a stale
                    // Jacobian refreshed; with a fresh one, halve h.
                    if !lu_exact {
                        lu_keep = 0.0;
                    } else if self.newton.jac_current {
                        self.h_next = 0.5 * h;
                    } else {
                        self.newton.jac_needed = true;
                    }
                    continue;
                }
                NewtonOutcome::Converged { iterations } => iterations,
            };
            failures = 0;
            let safety = 0.9 * (2 * MAX_NEWTON_ITERATIONS + 1) as f64
                / (2 * MAX_NEWTON_ITERATIONS + iterations) as f64;
            for (e, d) in self.scratch.iter_mut().zip(&self.correction) {
                *e = error_constant(order) * d;
            }
            let err = error_norm(&self.scratch, &self.s.y, &self.y1, &self.s.options);
            if err > 1.0 {
                ev.stats.rejected_steps += 1;
                let factor = (safety * err.powf(-1.0 / (order + 1) as f64)).max(MIN_FACTOR);
                self.h_next = h * factor;
                continue;
            }
            // Accepted: update the differences (∇^{k+2}, ∇^{k+1}, then the lower ones).
            for i in 0..n {
                self.diff[order + 2][i] = self.correction[i] - self.diff[order + 1][i];
                self.diff[order + 1][i] = self.correction[i];
            }
            for j in (0..=order).rev() {
                let (lo, hi) = self.diff.split_at_mut(j + 1);
                for (a, b) in lo[j].iter_mut().zip(&hi[0]) {
                    *a += b;
                }
            }
            self.dense_pending = Some((t, order));
            self.s.t = t1;
            self.y_prev.copy_from_slice(&self.s.y);
            self.s.y.copy_from_slice(&self.y1);
            for i in 0..n {
                self.s.f[i] = (self.psi[i] + self.correction[i]) / c;
            }
            ev.stats.steps += 1;
            self.newton.jac_current = false;
            self.equal_steps += 1;
            if self.equal_steps >= order + 1 {
                self.select_order(err, safety);
            }
            return Ok(());
        }
    }
}

impl BdfStepper {
    /// Order selection from the error estimates of orders k − 1, k, k + 1 after an
    /// accepted step with error `err`.
    fn select_order(&mut self, err: f64, safety: f64) {
        let order = self.order;
        let (y_prev, y, opts) = (&self.y_prev, &self.s.y, &self.s.options);
        let scratch = &mut self.scratch;
        let mut estimate = |k: usize, d: &[f64]| {
            for (e, x) in scratch.iter_mut().zip(d) {
                *e = error_constant(k) * x;
            }
            error_norm(scratch, y_prev, y, opts)
        };
        let err_down = if order > 1 {
            estimate(order - 1, &self.diff[order])
        } else {
            f64::INFINITY
        };
        let err_up = if order < MAX_ORDER {
            estimate(order + 1, &self.diff[order + 2])
        } else {
            f64::INFINITY
        };
        let factors = [
            err_down.powf(-1.0 / order as f64),
            err.powf(-1.0 / (order + 1) as f64),
            err_up.powf(-1.0 / (order + 2) as f64),
        ];
        let best = (0..3)
            .max_by(|&a, &b| factors[a].total_cmp(&factors[b]))
            .expect("three candidates");
        self.order = order + best - 1;
        let factor = (safety * factors[best]).min(GROWTH);
        if best != 1 || factor >= GROWTH || factor <= SHRINK_AT {
            self.h_next = self.s.h * factor;
        }
    }

    /// Simplified Newton for the correction `d`: on entry `y1` is the predictor, on
    /// success `y1 = y⁽⁰⁾ + d` and `correction = d`.
    fn newton<S: OdeSystem + ?Sized>(
        &mut self,
        ev: &mut Eval<'_, S>,
        t1: f64,
        c: f64,
    ) -> NewtonOutcome {
        let n = self.y1.len();
        let lu = &self.newton;
        let (predictor, fz, delta) = (&mut self.predictor, &mut self.fz, &mut self.delta);
        let weights = &mut self.weights;
        let (y1, correction, psi) = (&mut self.y1, &mut self.correction, &self.psi);
        predictor.copy_from_slice(y1);
        // Stop when the estimated remaining error `η ‖Δ‖` is below `NEWTON_TOL` of the
        // tolerance, never below ten round-offs of `y`. In the first iteration `η` is the
        // last solve's, relaxed towards 1 (`η^0.8`), so that a step whose predictor is
        // already good converges after one evaluation (CVODE, diffsol and Hairer's codes do
        // the same).
        error_weights(predictor, &self.s.options, weights);
        let roundoff = 10.0 * f64::EPSILON * weighted_norm(predictor, weights);
        let tol = NEWTON_TOL.max(roundoff);
        correction.fill(0.0);
        let mut norm_prev = f64::NAN;
        let mut eta = self.eta.max(1e4 * f64::EPSILON).powf(0.8);
        for iteration in 0..MAX_NEWTON_ITERATIONS {
            if let Err(kind) = ev.rhs(t1, y1, fz) {
                return NewtonOutcome::Failed {
                    non_finite: Some(kind),
                };
            }
            ev.stats.newton_iterations += 1;
            for i in 0..n {
                delta[i] = c * fz[i] - psi[i] - correction[i];
            }
            if !lu.solve(delta.as_mut_slice()) {
                return NewtonOutcome::Failed { non_finite: None };
            }
            let norm = weighted_norm(delta.as_slice(), weights);
            if iteration > 0 {
                let rate = norm / norm_prev;
                // Diverging, or predicted not to converge in the iterations left.
                let left = (MAX_NEWTON_ITERATIONS - iteration) as i32;
                if rate.is_nan() || rate >= 1.0 || rate.powi(left) / (1.0 - rate) * norm > tol {
                    return NewtonOutcome::Failed { non_finite: None };
                }
                eta = rate / (1.0 - rate);
            }
            for i in 0..n {
                y1[i] += delta[i];
                correction[i] += delta[i];
            }
            if check_finite(t1, y1).is_err() {
                return NewtonOutcome::Failed { non_finite: None };
            }
            if norm == 0.0 || eta * norm < tol {
                self.eta = eta;
                return NewtonOutcome::Converged {
                    iterations: iteration + 1,
                };
            }
            norm_prev = norm;
        }
        NewtonOutcome::Failed { non_finite: None }
    }
}

/// Re-interpolates the differences `D_0 … D_k` from spacing `h` to `factor · h`:
/// `D ← (R U)ᵀ D` with `R_ij = Π_{m=1}^{i} (m − 1 − factor·j)/m` and `U` the same at
/// factor 1 (Shampine & Reichelt 1997, eq. 2.4). Component by component, without
/// allocating.
fn rescale(diff: &mut [Vec<f64>], order: usize, factor: f64) {
    let (r, u) = (change_matrix(order, factor), change_matrix(order, 1.0));
    let mut ru = [[0.0; MAX_ORDER + 1]; MAX_ORDER + 1];
    for i in 0..=order {
        for j in 0..=order {
            ru[i][j] = (0..=order).map(|m| r[i][m] * u[m][j]).sum();
        }
    }
    let mut old = [0.0; MAX_ORDER + 1];
    for c in 0..diff[0].len() {
        for (b, o) in old.iter_mut().enumerate().take(order + 1) {
            *o = diff[b][c];
        }
        for (a, d) in diff.iter_mut().enumerate().take(order + 1) {
            d[c] = (0..=order).map(|b| ru[b][a] * old[b]).sum();
        }
    }
}

/// `R` of [`rescale`]: row 0 is ones, `R_i0 = 0` for `i ≥ 1`.
fn change_matrix(order: usize, factor: f64) -> [[f64; MAX_ORDER + 1]; MAX_ORDER + 1] {
    let mut r = [[0.0; MAX_ORDER + 1]; MAX_ORDER + 1];
    for j in 0..=order {
        let mut p = 1.0;
        r[0][j] = p;
        for i in 1..=order {
            p *= (i as f64 - 1.0 - factor * j as f64) / i as f64;
            r[i][j] = p;
        }
    }
    r
}

#[cfg(test)]
mod tests;
