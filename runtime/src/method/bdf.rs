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
//! `I − cJ`, whose LU is reused while `c` (that is `h` and `k`) and `J` are unchanged;
//! `J` comes from [`OdeSystem::jacobian`] or forward differences and is refreshed only
//! when Newton fails or converges too slowly. When `h` changes, the differences are
//! re-interpolated to the new spacing (Shampine & Reichelt, eq. 2.4).
//!
//! **Error and order.** The local error of order `k` is `d / (k + 1)`; the next
//! difference `∇^{k+2} y_{n+1}` and the previous one `∇ᵏ y_{n+1}` give the estimates
//! for orders `k + 1` and `k − 1`. Between changes `h` is kept (and with it the LU);
//! after `k + 1` accepted steps of the same size, the order among `k − 1, k, k + 1`
//! whose estimate allows the largest step is taken and `h` changes by that factor (at
//! most 10×). A rejected step shrinks `h` by the order-`k` estimate (at most 5×), a
//! failed Newton iteration first refreshes `J`, then halves `h`. The error is
//! controlled per step, so the global error is about the number of steps times the
//! tolerance on non-dissipative problems. Orders 1 and 2 are A-stable (1 also
//! L-stable), 3–5 only A(α)-stable (α ≈ 86°, 73°, 52°): with stiff eigenvalues close
//! to the imaginary axis (lightly damped fast oscillations), prefer [`Sdirk4`].
//!
//! **When to use.** Stiff problems with a smooth solution, where it needs one
//! Newton solve per step (about two right-hand-side evaluations) instead of one per
//! stage: it is the default stiff method of CVODE, `ode15s` and diffsol. For a
//! discontinuous right-hand side, many restarts or a very low accuracy, [`Sdirk4`]
//! (one-step, L-stable) is the safer choice.
//!
//! **Dense output.** Every accepted point is stored with the derivative the formula
//! assigns to it, `f_{n+1} = (ψ + d)/c` (equal to `f(t_{n+1}, y_{n+1})` up to the
//! Newton tolerance, without the extra evaluation and without amplifying the Newton
//! error by the stiff part of `J`), and the [`Trajectory`] interpolates by cubic
//! Hermite.
//!
//! [`Sdirk4`]: super::Sdirk4

use nalgebra::{DMatrix, DVector, Dyn, LU};

use super::{Run, check_finite, error_norm, initial_step, jacobian, underflow};
use crate::trajectory::Interpolant;
use crate::{ErrorKind, OdeSystem, Options, Problem, SolveError, Trajectory};

/// Highest order.
pub const MAX_ORDER: usize = 5;
/// Newton iterations per step before the attempt counts as failed.
const MAX_NEWTON_ITERATIONS: usize = 4;
/// Consecutive Newton failures (a failure with a stale Jacobian refreshes it, one with
/// a fresh Jacobian halves `h`) before giving up with [`ErrorKind::NewtonDivergence`].
pub const MAX_NEWTON_FAILURES: usize = 12;
/// Smallest step-size factor after a rejected step.
const MIN_FACTOR: f64 = 0.2;
/// Largest step-size factor after an accepted step.
const MAX_FACTOR: f64 = 10.0;

/// Adaptive variable-order BDF (orders 1–5) for stiff problems.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Bdf {
    pub options: Options,
}

/// The Newton matrix `I − cJ` and what it was built from.
struct NewtonMatrix {
    jac: DMatrix<f64>,
    /// `J` was evaluated at the current accepted point.
    jac_current: bool,
    /// `J` must be (re)evaluated before the next attempt.
    jac_needed: bool,
    lu: Option<LU<f64, Dyn, Dyn>>,
    /// The `c = h / γ_k` of the factorised matrix.
    lu_c: f64,
}

/// Outcome of the corrector of one attempt.
enum NewtonOutcome {
    /// Converged after `iterations`; `y1` and `correction` hold the result.
    Converged { iterations: usize },
    /// Diverged, too slow, or met a non-finite value (kept for reporting).
    Failed { non_finite: Option<ErrorKind> },
}

/// Buffers of [`Bdf::newton`], allocated once per integration.
struct NewtonWork {
    predictor: Vec<f64>,
    fz: Vec<f64>,
    delta: DVector<f64>,
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

    pub fn solve<S: OdeSystem + ?Sized>(
        &self,
        system: &S,
        problem: &Problem,
    ) -> Result<Trajectory, SolveError> {
        let mut run = Run::start(system, problem, Interpolant::Hermite, Some(&self.options))?;
        let outcome = self.integrate(&mut run, problem);
        run.finish(outcome)
    }

    fn integrate<S: OdeSystem + ?Sized>(
        &self,
        run: &mut Run<'_, S>,
        problem: &Problem,
    ) -> Result<(), ErrorKind> {
        let opts = &self.options;
        let n = problem.y0.len();
        let gamma = gamma();
        let mut t = problem.t0;
        let mut y = problem.y0.clone();
        let mut f = vec![0.0; n];
        run.rhs(t, &y, &mut f)?;
        run.traj.push(t, &y, &f);
        if problem.tf == problem.t0 {
            return Ok(());
        }
        // `h` is the spacing of the differences in `diff`; `h_next` the wanted one.
        let mut h = initial_step(run, problem, &f, 1, opts)?;
        let mut h_next = h;
        let mut diff = vec![vec![0.0; n]; MAX_ORDER + 3];
        diff[0].copy_from_slice(&y);
        for (d, fi) in diff[1].iter_mut().zip(&f) {
            *d = h * fi;
        }
        let mut order = 1;
        let mut equal_steps = 0;
        let mut newton = NewtonMatrix {
            jac: DMatrix::zeros(n, n),
            jac_current: false,
            jac_needed: true,
            lu: None,
            lu_c: f64::NAN,
        };
        let mut y1 = vec![0.0; n];
        let mut y_prev = vec![0.0; n];
        let mut psi = vec![0.0; n];
        let mut work = NewtonWork {
            predictor: vec![0.0; n],
            fz: vec![0.0; n],
            delta: DVector::zeros(n),
        };
        let mut correction = vec![0.0; n];
        let mut scratch = vec![0.0; n];
        let mut failures = 0;
        let mut attempts = 0;
        // A non-finite rhs value met ahead of the current time (see `Sdirk4`): a
        // Newton failure, but what is reported if the step then underflows.
        let mut non_finite_ahead: Option<ErrorKind> = None;
        loop {
            if attempts >= opts.max_steps {
                return Err(ErrorKind::MaxSteps { t });
            }
            attempts += 1;
            let mut h_new = h_next.min(opts.h_max);
            let last = t + 1.01 * h_new >= problem.tf;
            if last {
                h_new = problem.tf - t;
            }
            if underflow(t, h_new, opts) {
                return Err(
                    non_finite_ahead.unwrap_or(ErrorKind::StepSizeUnderflow { t, h: h_new })
                );
            }
            if h_new != h {
                rescale(&mut diff, order, h_new / h);
                h = h_new;
                equal_steps = 0;
            }
            h_next = h;
            if newton.jac_needed {
                jacobian(run, t, &y, &mut scratch, true, &mut newton.jac)?;
                newton.jac_current = true;
                newton.jac_needed = false;
                newton.lu = None;
            }
            let c = h / gamma[order];
            if newton.lu.is_none() || newton.lu_c != c {
                let m = DMatrix::identity(n, n) - &newton.jac * c;
                newton.lu = Some(m.lu());
                newton.lu_c = c;
                run.stats().lu_factorisations += 1;
            }
            // Predictor and the constant part ψ of the corrector.
            for i in 0..n {
                y1[i] = (0..=order).map(|j| diff[j][i]).sum();
                psi[i] = (1..=order).map(|j| gamma[j] * diff[j][i]).sum::<f64>() / gamma[order];
            }
            let t1 = if last { problem.tf } else { t + h };
            let outcome = self.newton(
                run,
                &newton,
                &mut work,
                t1,
                c,
                &psi,
                &mut y1,
                &mut correction,
            );
            let iterations = match outcome {
                NewtonOutcome::Failed { non_finite } => {
                    run.stats().rejected_steps += 1;
                    failures += 1;
                    if non_finite.is_some() {
                        non_finite_ahead = non_finite;
                    }
                    if failures >= MAX_NEWTON_FAILURES {
                        return Err(non_finite_ahead.unwrap_or(ErrorKind::NewtonDivergence { t }));
                    }
                    // A stale Jacobian is refreshed first; with a fresh one, halve h.
                    if newton.jac_current {
                        h_next = 0.5 * h;
                    } else {
                        newton.jac_needed = true;
                    }
                    continue;
                }
                NewtonOutcome::Converged { iterations } => iterations,
            };
            failures = 0;
            let safety = 0.9 * (2 * MAX_NEWTON_ITERATIONS + 1) as f64
                / (2 * MAX_NEWTON_ITERATIONS + iterations) as f64;
            for (e, d) in scratch.iter_mut().zip(&correction) {
                *e = error_constant(order) * d;
            }
            let err = error_norm(&scratch, &y, &y1, opts);
            if err > 1.0 {
                run.stats().rejected_steps += 1;
                let factor = (safety * err.powf(-1.0 / (order + 1) as f64)).max(MIN_FACTOR);
                h_next = h * factor;
                continue;
            }
            // Accepted: update the differences (∇^{k+2}, ∇^{k+1}, then the lower ones).
            for i in 0..n {
                diff[order + 2][i] = correction[i] - diff[order + 1][i];
                diff[order + 1][i] = correction[i];
            }
            for j in (0..=order).rev() {
                let (lo, hi) = diff.split_at_mut(j + 1);
                for (a, b) in lo[j].iter_mut().zip(&hi[0]) {
                    *a += b;
                }
            }
            t = t1;
            y_prev.copy_from_slice(&y);
            y.copy_from_slice(&y1);
            for i in 0..n {
                f[i] = (psi[i] + correction[i]) / c;
            }
            run.traj.push(t, &y, &f);
            run.stats().steps += 1;
            if matches!(non_finite_ahead, Some(ErrorKind::NonFinite { t: bad, .. }) if bad <= t) {
                non_finite_ahead = None;
            }
            if last {
                return Ok(());
            }
            newton.jac_current = false;
            equal_steps += 1;
            if equal_steps < order + 1 {
                continue;
            }
            // Order selection from the error estimates of orders k − 1, k, k + 1.
            let mut estimate = |k: usize, d: &[f64]| {
                for (e, x) in scratch.iter_mut().zip(d) {
                    *e = error_constant(k) * x;
                }
                error_norm(&scratch, &y_prev, &y, opts)
            };
            let err_down = if order > 1 {
                estimate(order - 1, &diff[order])
            } else {
                f64::INFINITY
            };
            let err_up = if order < MAX_ORDER {
                estimate(order + 1, &diff[order + 2])
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
            order = order + best - 1;
            h_next = h * (safety * factors[best]).min(MAX_FACTOR);
        }
    }

    /// Simplified Newton for the correction `d`: on entry `y1` is the predictor, on
    /// success `y1 = y⁽⁰⁾ + d` and `correction = d`.
    #[allow(clippy::too_many_arguments)]
    fn newton<S: OdeSystem + ?Sized>(
        &self,
        run: &mut Run<'_, S>,
        newton: &NewtonMatrix,
        work: &mut NewtonWork,
        t1: f64,
        c: f64,
        psi: &[f64],
        y1: &mut [f64],
        correction: &mut [f64],
    ) -> NewtonOutcome {
        let n = y1.len();
        let lu = newton.lu.as_ref().expect("factorised before Newton");
        let NewtonWork {
            predictor,
            fz,
            delta,
        } = work;
        predictor.copy_from_slice(y1);
        // Stop when the estimated remaining error is a small fraction of the tolerance
        // (Shampine & Reichelt's choice), never below ten round-offs of `y`.
        let roundoff =
            10.0 * f64::EPSILON * error_norm(predictor, predictor, predictor, &self.options);
        let tol = self.options.rtol.sqrt().min(0.03).max(roundoff);
        correction.fill(0.0);
        let mut norm_prev = f64::NAN;
        for iteration in 0..MAX_NEWTON_ITERATIONS {
            if let Err(kind) = run.rhs(t1, y1, fz) {
                return NewtonOutcome::Failed {
                    non_finite: Some(kind),
                };
            }
            run.stats().newton_iterations += 1;
            for i in 0..n {
                delta[i] = c * fz[i] - psi[i] - correction[i];
            }
            if !lu.solve_mut(delta) {
                return NewtonOutcome::Failed { non_finite: None };
            }
            let norm = error_norm(delta.as_slice(), predictor, predictor, &self.options);
            let rate = norm / norm_prev;
            if iteration > 0 {
                // Diverging, or predicted not to converge in the iterations left.
                let left = (MAX_NEWTON_ITERATIONS - iteration) as i32;
                if rate.is_nan() || rate >= 1.0 || rate.powi(left) / (1.0 - rate) * norm > tol {
                    return NewtonOutcome::Failed { non_finite: None };
                }
            }
            for i in 0..n {
                y1[i] += delta[i];
                correction[i] += delta[i];
            }
            if check_finite(t1, y1).is_err() {
                return NewtonOutcome::Failed { non_finite: None };
            }
            if norm == 0.0 || (iteration > 0 && rate / (1.0 - rate) * norm < tol) {
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
/// factor 1 (Shampine & Reichelt 1997, eq. 2.4).
fn rescale(diff: &mut [Vec<f64>], order: usize, factor: f64) {
    let r = change_matrix(order, factor);
    let u = change_matrix(order, 1.0);
    let ru = &r * &u;
    let n = diff[0].len();
    let mut new = vec![vec![0.0; n]; order + 1];
    for (a, row) in new.iter_mut().enumerate() {
        for (b, old) in diff.iter().take(order + 1).enumerate() {
            let w = ru[(b, a)];
            if w != 0.0 {
                for (x, o) in row.iter_mut().zip(old) {
                    *x += w * o;
                }
            }
        }
    }
    for (d, row) in diff.iter_mut().zip(new) {
        *d = row;
    }
}

/// `R` of [`rescale`]: row 0 is ones, `R_i0 = 0` for `i ≥ 1`.
fn change_matrix(order: usize, factor: f64) -> DMatrix<f64> {
    let mut r = DMatrix::zeros(order + 1, order + 1);
    for j in 0..=order {
        let mut p = 1.0;
        r[(0, j)] = p;
        for i in 1..=order {
            p *= (i as f64 - 1.0 - factor * j as f64) / i as f64;
            r[(i, j)] = p;
        }
    }
    r
}

#[cfg(test)]
mod tests;
