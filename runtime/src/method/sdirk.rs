//! Hairer–Wanner SDIRK4 ([`tableau::SDIRK4`](super::tableau::SDIRK4)): an L-stable,
//! stiffly accurate singly diagonally implicit Runge–Kutta method of order 4 with an
//! embedded order-3 error estimate (Hairer & Wanner, *Solving ODEs II*, §IV.6).
//!
//! Each stage solves `Y_i = y_n + h Σ_{j<i} a_ij F_j + hγ f(t_n + c_i h, Y_i)` by
//! simplified Newton with the one matrix `I − hγJ` for all stages (its LU is reused
//! while `h` and `J` stay the same), `J ≈ ∂f/∂y(t_n, y_n)` from the system or by
//! forward differences. Convergence is monitored as in Hairer & Wanner II, §IV.8
//! (rate `θ`, stop when `θ/(1−θ) ‖Δ‖` is below a tolerance scaled down by how much a
//! DIRK amplifies stage errors, see [`KAPPA`]). On failure the step is halved and, if
//! the Jacobian was old, refreshed; after [`MAX_NEWTON_FAILURES`] consecutive failures
//! the integration stops with [`ErrorKind::NewtonDivergence`].

use nalgebra::{DMatrix, DVector, Dyn, LU};

use super::tableau::SDIRK4;
use super::{Run, error_norm, initial_step, jacobian, underflow};
use crate::control::PiController;
use crate::trajectory::Interpolant;
use crate::{ErrorKind, OdeSystem, Options, Problem, SolveError, Trajectory};

/// Newton iterations per stage before the step counts as failed.
const MAX_NEWTON_ITERATIONS: usize = 10;
/// Consecutive Newton failures (each halving `h`) before giving up.
pub const MAX_NEWTON_FAILURES: usize = 12;
/// Newton stops when the estimated remaining error of a stage is below `κ / (10 A)`
/// times the tolerance, where `A = Σ_j |a_sj| / γ ≈ 68` ([`newton_amplification`]).
///
/// `κ ∈ [0.01, 0.1]` (Hairer & Wanner II, §IV.8) suits a collocation method such as
/// RADAU5, whose stages are solved together so that their Newton error enters `y₁`
/// once. In a
/// DIRK the stage derivatives are recovered as `k_j = (Y_j − base_j)/(hγ)`, so a stage
/// error `δ_j` reaches `y₁ = Y_s` (and the error estimate) multiplied by up to
/// `|a_sj|/γ` (up to 31 here), and it does so with the same sign step after step. The
/// extra factor 10 keeps it below the local error of the order-4 solution, which is
/// well under the order-3 estimate that the tolerance controls. With plain `κ` the
/// global error stopped following the tolerance (see
/// `sdirk4_global_error_is_proportional_to_the_tolerance`).
const KAPPA: f64 = 0.05;
/// After an accepted step, the Jacobian is kept if Newton converged at least this fast.
const THETA_REUSE_JACOBIAN: f64 = 0.1;

/// Adaptive SDIRK4 for stiff problems.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Sdirk4 {
    pub options: Options,
}

/// The Newton matrix `I − hγJ` and what it was built from.
struct NewtonMatrix {
    jac: DMatrix<f64>,
    /// `J` was evaluated at the current accepted point.
    jac_current: bool,
    /// `J` must be (re)evaluated before the next attempt.
    jac_needed: bool,
    lu: Option<LU<f64, Dyn, Dyn>>,
    lu_h: f64,
    /// Last convergence-rate estimate `η`, carried across stages (Hairer's `FACCON`).
    eta: f64,
}

/// Outcome of the stage solves of one attempt.
enum StageOutcome {
    /// All stages converged; the slowest observed contraction rate.
    Converged { theta_max: f64 },
    /// Newton diverged, was too slow, or hit a non-finite value (kept for reporting).
    Failed { non_finite: Option<ErrorKind> },
}

impl Sdirk4 {
    pub fn new(options: Options) -> Self {
        Sdirk4 { options }
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
        let s = SDIRK4.stages();
        let gamma = SDIRK4.a(0, 0);
        let mut t = problem.t0;
        let mut y = problem.y0.clone();
        let mut f = vec![0.0; n];
        run.rhs(t, &y, &mut f)?;
        run.traj.push(t, &y, &f);
        if problem.tf == problem.t0 {
            return Ok(());
        }
        let mut h = initial_step(run, problem, &f, 4, opts)?;
        let mut controller = PiController::new(3);
        let mut newton = NewtonMatrix {
            jac: DMatrix::zeros(n, n),
            jac_current: false,
            jac_needed: true,
            lu: None,
            lu_h: f64::NAN,
            eta: 1.0,
        };
        let mut stage_f: Vec<Vec<f64>> = vec![vec![0.0; n]; s];
        let mut y1 = vec![0.0; n];
        let e = SDIRK4.error_weights();
        let mut failures = 0;
        let mut attempts = 0;
        // A non-finite rhs value met ahead of the current time. Inside Newton it is
        // treated as a failure (the iterate may just have strayed), but if the step
        // size then underflows in front of it, it is what gets reported.
        let mut non_finite_ahead: Option<ErrorKind> = None;
        loop {
            if attempts >= opts.max_steps {
                return Err(ErrorKind::MaxSteps { t });
            }
            attempts += 1;
            h = h.min(opts.h_max);
            let last = t + 1.01 * h >= problem.tf;
            if last {
                h = problem.tf - t;
            }
            if underflow(t, h, opts) {
                return Err(non_finite_ahead.unwrap_or(ErrorKind::StepSizeUnderflow { t, h }));
            }
            if newton.jac_needed {
                jacobian(run, t, &y, &mut f, false, &mut newton.jac)?;
                newton.jac_current = true;
                newton.jac_needed = false;
                newton.lu = None;
            }
            if newton.lu.is_none() || newton.lu_h != h {
                let m = DMatrix::identity(n, n) - &newton.jac * (h * gamma);
                newton.lu = Some(m.lu());
                newton.lu_h = h;
                run.stats().lu_factorisations += 1;
            }
            match self.stages(run, &mut newton, t, h, &y, &f, &mut stage_f, &mut y1) {
                StageOutcome::Failed { non_finite } => {
                    run.stats().rejected_steps += 1;
                    failures += 1;
                    if non_finite.is_some() {
                        non_finite_ahead = non_finite;
                    }
                    if failures >= MAX_NEWTON_FAILURES {
                        return Err(non_finite_ahead.unwrap_or(ErrorKind::NewtonDivergence { t }));
                    }
                    if !newton.jac_current {
                        newton.jac_needed = true;
                    }
                    h *= 0.5;
                    continue;
                }
                StageOutcome::Converged { theta_max } => {
                    failures = 0;
                    // Error estimate h Σ (b_i − b̂_i) F_i, filtered through (I − hγJ)⁻¹
                    // so that stiff components do not inflate it (Shampine's device, as
                    // in RADAU5: Hairer & Wanner II, §IV.8).
                    let mut err = DVector::from_fn(n, |i, _| {
                        h * (0..s).map(|j| e[j] * stage_f[j][i]).sum::<f64>()
                    });
                    let lu = newton.lu.as_ref().expect("factorised above");
                    if !lu.solve_mut(&mut err) {
                        err.fill(f64::INFINITY);
                    }
                    let err = error_norm(err.as_slice(), &y, &y1, opts);
                    if err <= 1.0 {
                        t = if last { problem.tf } else { t + h };
                        y.copy_from_slice(&y1);
                        run.rhs(t, &y, &mut f)?;
                        run.traj.push(t, &y, &f);
                        run.stats().steps += 1;
                        if matches!(non_finite_ahead, Some(ErrorKind::NonFinite { t: bad, .. }) if bad <= t)
                        {
                            non_finite_ahead = None;
                        }
                        if last {
                            return Ok(());
                        }
                        newton.jac_current = false;
                        newton.jac_needed = theta_max > THETA_REUSE_JACOBIAN;
                        let fac = controller.accept(err);
                        // Keep h (and the LU) when it would grow only a little.
                        if !(1.0..=1.2).contains(&fac) {
                            h *= fac;
                        }
                    } else {
                        run.stats().rejected_steps += 1;
                        h *= controller.reject(err);
                        if !newton.jac_current {
                            newton.jac_needed = true;
                        }
                    }
                }
            }
        }
    }

    /// Solves the stages of one step; on success `stage_f[i] = F_i` and `y1 = Y_s`.
    #[allow(clippy::too_many_arguments)]
    fn stages<S: OdeSystem + ?Sized>(
        &self,
        run: &mut Run<'_, S>,
        newton: &mut NewtonMatrix,
        t: f64,
        h: f64,
        y: &[f64],
        f: &[f64],
        stage_f: &mut [Vec<f64>],
        y1: &mut [f64],
    ) -> StageOutcome {
        let n = y.len();
        let gamma = SDIRK4.a(0, 0);
        let hg = h * gamma;
        let lu = newton.lu.as_ref().expect("factorised before the stages");
        let mut base = vec![0.0; n];
        let mut z = vec![0.0; n];
        let mut fz = vec![0.0; n];
        let mut delta = DVector::zeros(n);
        let mut theta_max: f64 = 0.0;
        // Never ask for less than ten round-offs of `y` (as RADAU5's `10 uround / rtol`,
        // but also valid when `rtol = 0`).
        let roundoff = 10.0 * f64::EPSILON * error_norm(y, y, y, &self.options);
        let newton_tol = (KAPPA / (10.0 * newton_amplification())).max(roundoff);
        for i in 0..SDIRK4.stages() {
            for k in 0..n {
                base[k] = y[k] + h * (0..i).map(|j| SDIRK4.a(i, j) * stage_f[j][k]).sum::<f64>();
                // Predictor: the previous stage's derivative (f(t, y) for the first).
                let guess = if i == 0 { f[k] } else { stage_f[i - 1][k] };
                z[k] = base[k] + hg * guess;
            }
            let mut eta = newton.eta.max(f64::EPSILON).powf(0.8);
            let mut norm_prev = f64::NAN;
            let mut converged = false;
            for iteration in 0..MAX_NEWTON_ITERATIONS {
                if let Err(kind) = run.rhs(t + SDIRK4.c[i] * h, &z, &mut fz) {
                    return StageOutcome::Failed {
                        non_finite: Some(kind),
                    };
                }
                run.stats().newton_iterations += 1;
                for k in 0..n {
                    delta[k] = -(z[k] - base[k] - hg * fz[k]);
                }
                if !lu.solve_mut(&mut delta) {
                    return StageOutcome::Failed { non_finite: None };
                }
                let norm = error_norm(delta.as_slice(), y, y, &self.options);
                if iteration > 0 {
                    let theta = norm / norm_prev;
                    theta_max = theta_max.max(theta);
                    if theta.is_nan() || theta >= 0.99 {
                        return StageOutcome::Failed { non_finite: None };
                    }
                    eta = theta / (1.0 - theta);
                }
                for k in 0..n {
                    z[k] += delta[k];
                }
                norm_prev = norm;
                if eta * norm <= newton_tol || norm == 0.0 {
                    converged = true;
                    break;
                }
            }
            if !converged {
                return StageOutcome::Failed { non_finite: None };
            }
            newton.eta = eta;
            // F_i from the converged stage value (not f(Y_i)): avoids amplifying the
            // Newton error by the stiff part (Hairer & Wanner II, §IV.8).
            for k in 0..n {
                stage_f[i][k] = (z[k] - base[k]) / hg;
            }
        }
        y1.copy_from_slice(&z);
        StageOutcome::Converged { theta_max }
    }
}

/// `Σ_j |a_sj| / γ`: the largest factor by which Newton errors in the stages can reach
/// the result `y₁ = Y_s` through the stage derivatives `k_j = (Y_j − base_j)/(hγ)`.
fn newton_amplification() -> f64 {
    let s = SDIRK4.stages();
    (0..s).map(|j| SDIRK4.a(s - 1, j).abs()).sum::<f64>() / SDIRK4.a(0, 0)
}
