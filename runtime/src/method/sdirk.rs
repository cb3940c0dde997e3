//! Hairer–Wanner SDIRK4 ([`tableau::SDIRK4`](crate::tableau::SDIRK4)): an L-stable,
//! stiffly accurate singly diagonally implicit Runge–Kutta method of order 4 with an
//! embedded order-3 error estimate (Hairer & Wanner, *Solving ODEs II*, §IV.6).
//!
//! Each stage solves `Y_i = y_n + h Σ_{j<i} a_ij F_j + hγ f(t_n + c_i h, Y_i)` by
//! simplified Newton with the one matrix `I − hγJ` for all stages (its LU is reused
//! while `h` and `J` stay the same), `J ≈ ∂f/∂y(t_n, y_n)` from the system or by
//! forward differences. The unknowns are the stage increments `Z_i = Y_i − y_n`
//! (Hairer & Wanner II, §IV.8), whose round-off is that of an `O(h)` quantity rather than
//! of the state. Convergence is monitored as there (rate `θ`, stop when
//! `θ/(1−θ) ‖Δ‖` is below a tolerance scaled down by how much a DIRK amplifies stage
//! errors, see `numerics::newton::dirk_stage_tolerance`). On failure the step is halved and, if
//! the Jacobian was old, refreshed; after [`MAX_NEWTON_FAILURES`] consecutive failures
//! the integration stops with [`ErrorKind::NewtonDivergence`].
//! The dense output is the quintic Hermite through the last three points (local error
//! `O(h⁶)`), cubic Hermite on the step's ends for the first step after a (re)start (which a
//! stored solution rewrites from the next point once it is taken).

use nalgebra::DVector;

use super::stepper::{Begin, Eval, StepResult, StepState, Stepper, check_budget};
use crate::numerics::control::PiController;
use crate::numerics::newton::{
    DIRK_THETA_REUSE_JACOBIAN as THETA_REUSE_JACOBIAN, DirkStage, NewtonMatrix, StageFailure,
    dirk_stage_newton, dirk_stage_tolerance,
};
use crate::numerics::tableau::SDIRK4;
use crate::numerics::{error_norm, underflow};
use crate::{ErrorKind, OdeSystem, Options};

/// Consecutive Newton failures (each halving `h`) before giving up.
pub const MAX_NEWTON_FAILURES: usize = 12;

/// Adaptive SDIRK4 for stiff problems.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Sdirk4 {
    pub options: Options,
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

    /// The stepping state for states of `dim` components.
    pub fn stepper(&self, dim: usize) -> Sdirk4Stepper {
        Sdirk4Stepper {
            s: StepState::new(dim, self.options),
            controller: PiController::new(3),
            newton: NewtonMatrix::new(dim),
            eta: 1.0,
            stage_f: vec![vec![0.0; dim]; SDIRK4.stages()],
            y1: vec![0.0; dim],
            base: vec![0.0; dim],
            z: vec![0.0; dim],
            fz: vec![0.0; dim],
            delta: DVector::zeros(dim),
        }
    }
}

/// The state of an [`Sdirk4`] integration (see [`Stepper`]).
#[derive(Debug)]
pub struct Sdirk4Stepper {
    s: StepState,
    controller: PiController,
    newton: NewtonMatrix,
    /// Last convergence-rate estimate `η`, carried across stages (Hairer's `FACCON`).
    eta: f64,
    stage_f: Vec<Vec<f64>>,
    y1: Vec<f64>,
    base: Vec<f64>,
    z: Vec<f64>,
    fz: Vec<f64>,
    delta: DVector<f64>,
}

impl Stepper for Sdirk4Stepper {
    fn state(&self) -> &StepState {
        &self.s
    }

    fn state_mut(&mut self) -> &mut StepState {
        &mut self.s
    }

    fn begin<S: OdeSystem + ?Sized>(&mut self, ev: &mut Eval<'_, S>, at: Begin) -> StepResult {
        self.s.enter(ev, at, 4, self.s.h)?;
        self.controller = PiController::new(3);
        if at.fresh {
            self.newton = NewtonMatrix::new(at.y.len());
            self.eta = 1.0;
        } else {
            // Unlike BDF's, SDIRK4's error estimate is filtered through (I − hγJ)⁻¹: a J
            // of the equations before the discontinuity would distort the error control
            // itself, not only slow Newton (measured: the stiff two-block chain,
            // k2/k1 = 1e12, ended in an ill-posed mode with the old J kept; it completes
            // with a fresh one).
            self.newton.jac_needed = true;
        }
        Ok(())
    }

    fn step<S: OdeSystem + ?Sized>(&mut self, ev: &mut Eval<'_, S>, t_end: f64) -> StepResult {
        let n = self.s.y.len();
        let s = SDIRK4.stages();
        let gamma = SDIRK4.a(0, 0);
        let e = SDIRK4.error_weights();
        let mut failures = 0;
        // A non-finite rhs value met ahead of the current time. Inside Newton it is
        // treated as a failure (the iterate may just have strayed), but if the step
        // size then underflows in front of it, it is what gets reported.
        let mut non_finite_ahead: Option<ErrorKind> = None;
        loop {
            let t = self.s.t;
            check_budget(ev.stats, &self.s.options, t)?;
            let mut h = self.s.h.min(self.s.options.h_max);
            let last = t + 1.01 * h >= t_end;
            if last {
                h = t_end - t;
            }
            if underflow(t, h, &self.s.options) {
                return Err(non_finite_ahead.unwrap_or(ErrorKind::StepSizeUnderflow { t, h }));
            }
            self.newton
                .update_jacobian(ev, t, &self.s.y, &mut self.s.f, false)?;
            self.newton
                .factor(h * gamma, &mut ev.stats.lu_factorisations);
            match self.stages(ev, t, h) {
                StageOutcome::Failed { non_finite } => {
                    ev.stats.rejected_steps += 1;
                    failures += 1;
                    if non_finite.is_some() {
                        non_finite_ahead = non_finite;
                    }
                    if failures >= MAX_NEWTON_FAILURES {
                        return Err(non_finite_ahead.unwrap_or(ErrorKind::NewtonDivergence { t }));
                    }
                    self.newton.refresh_if_stale();
                    self.s.h = 0.5 * h;
                }
                StageOutcome::Converged { theta_max } => {
                    failures = 0;
                    // Error estimate h Σ (b_i − b̂_i) F_i, filtered through (I − hγJ)⁻¹
                    // so that stiff components do not inflate it (Shampine's device, as
                    // in RADAU5: Hairer & Wanner II, §IV.8).
                    let stage_f = &self.stage_f;
                    let mut err = DVector::from_fn(n, |i, _| {
                        h * (0..s).map(|j| e[j] * stage_f[j][i]).sum::<f64>()
                    });
                    if !self.newton.solve(err.as_mut_slice()) {
                        err.fill(f64::INFINITY);
                    }
                    let err = error_norm(err.as_slice(), &self.s.y, &self.y1, &self.s.options);
                    if err <= 1.0 {
                        let t1 = if last { t_end } else { t + h };
                        // f at the new point into `fz` first: the dense output needs
                        // both ends.
                        ev.rhs(t1, &self.y1, &mut self.fz)?;
                        let (y1, f1) = (&self.y1, &self.fz);
                        self.s.set_dense(h, y1, f1, |dense, y0, f0| {
                            dense.set_hermite(t, h, y0, f0, y1, f1)
                        });
                        self.s.advance(t1, y1, f1);
                        ev.stats.steps += 1;
                        self.newton.jac_current = false;
                        self.newton.jac_needed = theta_max > THETA_REUSE_JACOBIAN;
                        let fac = self.controller.accept(err);
                        // Keep h (and the LU) when it would grow only a little.
                        self.s.h = if (1.0..=1.2).contains(&fac) {
                            h
                        } else {
                            h * fac
                        };
                        return Ok(());
                    }
                    ev.stats.rejected_steps += 1;
                    self.s.h = h * self.controller.reject(err);
                    self.newton.refresh_if_stale();
                }
            }
        }
    }
}

impl Sdirk4Stepper {
    /// Solves the stages of one step from `(t, y)`; on success `stage_f[i] = F_i` and
    /// `y1 = y + Z_s`.
    fn stages<S: OdeSystem + ?Sized>(
        &mut self,
        ev: &mut Eval<'_, S>,
        t: f64,
        h: f64,
    ) -> StageOutcome {
        let n = self.s.y.len();
        let gamma = SDIRK4.a(0, 0);
        let hg = h * gamma;
        let y = &self.s.y;
        let mut theta_max: f64 = 0.0;
        let lu = &self.newton;
        // …and stop once a correction is down to ten round-offs of the state: stiff
        // components evaluated at `y + z` carry the round-off of `y`, so no iteration
        // gets below it (measured: S4 at rtol 1e-12 failed Newton without this stop).
        let stagnant = 10.0 * f64::EPSILON * error_norm(y, y, y, &self.s.options);
        for i in 0..SDIRK4.stages() {
            // Increments: `base` and `z` are `Y − y`, `y1` holds the point `y + z`.
            for k in 0..n {
                self.base[k] = h
                    * (0..i)
                        .map(|j| SDIRK4.a(i, j) * self.stage_f[j][k])
                        .sum::<f64>();
                // Predictor: the previous stage's derivative (f(t, y) for the first).
                let guess = if i == 0 {
                    self.s.f[k]
                } else {
                    self.stage_f[i - 1][k]
                };
                self.z[k] = self.base[k] + hg * guess;
            }
            // Never ask for less than ten round-offs of the increment (as RADAU5's
            // `10 uround / rtol`, but also valid when `rtol = 0`)…
            let roundoff = 10.0 * f64::EPSILON * error_norm(&self.z, y, y, &self.s.options);
            let stage = DirkStage {
                hg,
                base: &self.base,
                tol: dirk_stage_tolerance().max(roundoff),
                stagnant,
                scale: y,
                options: &self.s.options,
            };
            let (y1, c) = (&mut self.y1, t + SDIRK4.c[i] * h);
            let solved = dirk_stage_newton(
                &stage,
                &mut self.z,
                &mut self.fz,
                self.delta.as_mut_slice(),
                &mut self.eta,
                &mut theta_max,
                |delta| lu.solve(delta),
                |z, fz| {
                    for k in 0..n {
                        y1[k] = y[k] + z[k];
                    }
                    ev.rhs(c, y1, fz).map_err(StageFailure::Evaluation)?;
                    ev.stats.newton_iterations += 1;
                    Ok(())
                },
            );
            match solved {
                Ok(()) => {}
                Err(StageFailure::Evaluation(kind)) => {
                    return StageOutcome::Failed {
                        non_finite: Some(kind),
                    };
                }
                Err(_) => return StageOutcome::Failed { non_finite: None },
            }
            // F_i from the converged stage value (not f(Y_i)): avoids amplifying the
            // Newton error by the stiff part (Hairer & Wanner II, §IV.8).
            for k in 0..n {
                self.stage_f[i][k] = (self.z[k] - self.base[k]) / hg;
            }
        }
        // Stiffly accurate: the last stage is the new state.
        for k in 0..n {
            self.y1[k] = y[k] + self.z[k];
        }
        StageOutcome::Converged { theta_max }
    }
}
