//! [`LieSdirk`]: a diagonally implicit Runge–Kutta–Munthe-Kaas method for stiff
//! problems on `SO(3)^m × ℝⁿ` — Hairer & Wanner's SDIRK4
//! ([`tableau::SDIRK4`](crate::tableau::SDIRK4), the tableau of
//! [`Sdirk4`](crate::Sdirk4)) applied in local exponential coordinates.
//!
//! # The method
//!
//! As in [`Rkmk5`](super::Rkmk5) (see [`rkmk`](super::rkmk)), a step from `y₀` writes
//! the solution as `y = y₀ · exp(Θ)` with `Θ = (θ_1, …, θ_m, δx, δv)` and integrates
//! the ordinary ODE `Θ̇ = F(t, Θ) = (J_r(θ_k)⁻¹ ω_k(y), u(y), f(t, y))` from `Θ = 0`.
//! Here the RK method is SDIRK4 (5 stages, `γ = ¼`): stage `i` solves
//!
//! ```text
//! Θ_i = h Σ_{j<i} a_ij K_j + hγ F(t + c_i h, Θ_i),    K_i = F(t + c_i h, Θ_i),
//! ```
//!
//! i.e. `Θ_i = h Σ_j a_ij dexp⁻¹_{Θ_j}(F(Y_j))` with `Y_j = y₀ · exp(Θ_j)`, the RKMK
//! stage equation (Munthe-Kaas, BIT 38 (1998) 92–111; Iserles, Munthe-Kaas, Nørsett &
//! Zanna, Acta Numerica 9 (2000), §4.2, which holds for implicit tableaus too). The
//! method is stiffly accurate, so `Θ₁ = Θ_5` and `y₁ = y₀ · exp(Θ₁)`. Orders are the
//! tableau's: 4, with an embedded order-3 estimate; L-stable.
//!
//! * **Newton.** Each stage is solved by simplified Newton with the one matrix
//!   `I − hγJ` (size `2(3m + n)`), `J = ∂F/∂Θ` at `Θ = 0`:
//!
//!   ```text
//!   J = [ −½ ω̂ (rotation blocks), 0 | I        ]
//!       [ ∂f/∂φ                      | ∂f/∂v    ]
//!   ```
//!
//!   from [`LieSystem::jacobian`] (`∂f/∂φ` along `y · exp(s e_k)`), or central
//!   differences of `f` along `y · exp(±δ e_k)` and `v ± δ e_k` when the system has
//!   none. The `θ`-dependence of `J_r(θ)⁻¹` inside the step is neglected (simplified
//!   Newton: it changes the convergence rate, not the solution). Convergence control,
//!   the stopping tolerance, the predictor, the stage derivatives
//!   `K_i = (Θ_i − base_i)/(hγ)`, Jacobian reuse and the failure handling (halve `h`,
//!   refresh an old Jacobian, give up with [`ErrorKind::NewtonDivergence`] after
//!   twelve consecutive failures) are those of [`Sdirk4`](crate::Sdirk4); in addition
//!   a Newton failure counts as a rejection for the [`PiController`] (no growth on the
//!   next accepted step), which roughly halves the failed attempts when the error
//!   estimate allows steps over which the body turns too far for the frozen matrix.
//!   In the fixed mode a failure is retried once with a fresh Jacobian.
//! * **Error control.** `h Σ (b_i − b̂_i) K_i` filtered through `(I − hγJ)⁻¹`
//!   (Shampine's device), in the norm of [`Rkmk5`](super::Rkmk5) (scale 1 for rotation
//!   components), with a [`PiController`] for an order-3 estimate. Steps whose stage
//!   rotation vectors leave `|θ| < π` count as Newton failures.
//! * **Dense output.** In each step's local coordinates, the quartic through `Θ(0) = 0`,
//!   `Θ(h) = Θ₁`, the derivatives `Θ̇(0) = (ω₀, u₀, f(t₀, y₀))`,
//!   `Θ̇(h) = (J_r(θ₁)⁻¹ ω₁, u₁, f(t₁, y₁))` and the previous accepted point in the same
//!   chart (cubic Hermite on the first step), mapped by `y₀ · exp(Θ(t))` onto the group:
//!   interpolation error `O(h⁵)`, one order above the step's local error, stored in
//!   [`LieTrajectory`] as the Dormand–Prince extension's form with its quartic term `r₅`.
//!   Measured on S10 at the step midpoints against the exact solution from the step's
//!   start: within 0.04–0.36 of the tolerance from rtol 1e-4 to 1e-8 (the cubic Hermite
//!   alone: 1.3–1.4 times it). `f(t₁, y₁)` is one extra rhs evaluation per step, which
//!   the next step's predictor and Jacobian use.
//! * **Normalisation.** As [`Rkmk5`](super::Rkmk5): every accepted quaternion is
//!   normalised once.
//!
//! # When to use
//!
//! For stiff Lie-group problems: stiff rotational springs or joint stops, strong
//! damping, fast modes that decay and need not be resolved. There an explicit method's
//! step is bounded by stability (`h|λ| ≲ 3`) and [`LieSdirk`] takes steps set by the
//! accuracy of the slow motion (measured in the tests: a body dragged by a stiff,
//! damped torsional spring after a spinning frame, `K = 10⁶`, `c = 10³`, 20 s at
//! `rtol = 10⁻⁶`: 434 steps against Rkmk5's 5836). For non-stiff problems
//! [`Rkmk5`](super::Rkmk5) is cheaper per step, of higher order and has a fourth-order
//! dense output.
//!
//! A limitation inherited from the tableau: when the slow motion is *curved* on the
//! time scale of the steps (a stiff spring towards a path `φ(t)` with `φ̈ ≠ 0`, a
//! Prothero–Robinson problem), SDIRK4's embedded estimate is order-reduced (see the
//! tableau test `sdirk4_error_estimate_is_unique_and_order_reduced_when_stiff`) and
//! the steps stay small, as for the Euclidean [`Sdirk4`](crate::Sdirk4) (measured:
//! 4527 steps against Sdirk4's 4734 on the linearisation and Rkmk5's 2128, 2 s at
//! `rtol = 10⁻⁶`).

use nalgebra::{DMatrix, DVector, Vector3};

use super::chart::{chart_field, magnitudes, retract};
use super::drive::{LieMethod, LieStepper, attempt, begin, drive};
use super::events::{LieEvent, LieEventHit};
use super::trajectory::{LieProblem, LieRun, LieTrajectory};
use super::{LieState, LieSystem};
use crate::geometry::so3::{self, UnitQuat};
use crate::numerics::newton::{
    DIRK_THETA_REUSE_JACOBIAN as THETA_REUSE_JACOBIAN, DirkStage, NewtonMatrix, StageFailure,
    dirk_stage_newton, dirk_stage_tolerance,
};
use crate::numerics::tableau::{SDIRK4, dopri5_dense};
use crate::numerics::{error_norm, underflow};
use crate::{ErrorKind, Options, PiController, SolveError};

/// Consecutive Newton failures (each halving `h`) before giving up (as `Sdirk4`).
const MAX_NEWTON_FAILURES: usize = 12;

/// Diagonally implicit RKMK on the SDIRK4 tableau, for stiff problems (see the
/// [module documentation](self)). Adaptive with a [`PiController`] or, with
/// [`fixed`](Self::fixed), at a fixed step for convergence studies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LieSdirk {
    /// Tolerances and step limits. In the fixed mode only the tolerances (as the
    /// Newton tolerance) and `max_steps` are used.
    pub options: Options,
    /// `Some(h)`: no error control, steps of `h` (the last one shortened to hit `tf`).
    pub fixed_step: Option<f64>,
}

impl Default for LieSdirk {
    fn default() -> Self {
        LieSdirk::new(Options::default())
    }
}

/// The Newton matrix `I − hγJ` (shared with `Sdirk4`) and the last convergence-rate
/// estimate, carried across stages.
struct Newton {
    m: NewtonMatrix,
    eta: f64,
}

/// Outcome of the stage solves of one attempt.
enum StageOutcome {
    /// All stages converged; the slowest observed contraction rate.
    Converged { theta_max: f64 },
    /// Newton diverged, was too slow, or met a non-finite value (kept for reporting).
    Failed { non_finite: Option<ErrorKind> },
    /// A stage rotation vector left the ball `|θ| < π`.
    TooFar,
}

/// Work vectors of one integration: `n = 3m + n_euclid` velocities, `2n` local
/// coordinates.
struct Work {
    n: usize,
    m: usize,
    /// Stage derivatives `K_i` in local coordinates.
    k: Vec<Vec<f64>>,
    /// `Θ̇` at the step's start and end.
    k_start: Vec<f64>,
    k_end: Vec<f64>,
    base: Vec<f64>,
    z: Vec<f64>,
    fz: Vec<f64>,
    f_stage: Vec<f64>,
    delta: DVector<f64>,
    theta1: Vec<f64>,
    zeros: Vec<f64>,
    point: LieState,
    next: LieState,
    mag0: Vec<f64>,
    mag1: Vec<f64>,
    /// Row-major `∂f/∂φ`, `∂f/∂v`.
    dq: Vec<f64>,
    dv: Vec<f64>,
    /// The accepted point before the current one, its time, and its coordinates in the
    /// current point's chart: the dense output's fifth condition.
    prev: Option<f64>,
    prev_y: LieState,
    prev_theta: Vec<f64>,
    /// The quartic term of the dense output (`r₅` of [`dopri5_dense`]).
    r5: Vec<f64>,
}

impl Work {
    fn new(y0: &LieState) -> Self {
        let n = y0.velocity.len();
        let d = 2 * n;
        Work {
            n,
            m: y0.rotations.len(),
            k: vec![vec![0.0; d]; SDIRK4.stages()],
            k_start: vec![0.0; d],
            k_end: vec![0.0; d],
            base: vec![0.0; d],
            z: vec![0.0; d],
            fz: vec![0.0; d],
            f_stage: vec![0.0; n],
            delta: DVector::zeros(d),
            theta1: vec![0.0; d],
            zeros: vec![0.0; d],
            point: y0.clone(),
            next: y0.clone(),
            mag0: vec![0.0; d],
            mag1: vec![0.0; d],
            dq: vec![0.0; n * n],
            dv: vec![0.0; n * n],
            prev: None,
            prev_y: y0.clone(),
            prev_theta: vec![0.0; d],
            r5: vec![0.0; d],
        }
    }
}

/// The stepping state of a [`LieSdirk`] integration (see [`LieStepper`]).
pub(super) struct LieSdirkStepper {
    method: LieSdirk,
    w: Work,
    t: f64,
    y: LieState,
    /// `f(t, y)`.
    f: Vec<f64>,
    /// The next step to try.
    h: f64,
    controller: PiController,
    newton: Newton,
    /// Consecutive Newton failures.
    failures: usize,
    /// Attempts so far (bounded by `max_steps`).
    attempts: usize,
    /// A non-finite rhs value met ahead of the current time (as in `Sdirk4`).
    non_finite_ahead: Option<ErrorKind>,
}

impl LieStepper for LieSdirkStepper {
    fn t(&self) -> f64 {
        self.t
    }

    fn start<S: LieSystem + ?Sized>(
        &mut self,
        run: &mut LieRun<'_, S>,
        problem: &LieProblem,
    ) -> Result<(), ErrorKind> {
        let method = &self.method;
        (self.t, self.h) = begin(
            run,
            problem,
            &mut self.y,
            &mut self.f,
            method.fixed_step,
            4,
            &method.options,
        )?;
        Ok(())
    }

    fn step<S: LieSystem + ?Sized>(
        &mut self,
        run: &mut LieRun<'_, S>,
        tf: f64,
    ) -> Result<(), ErrorKind> {
        let opts = self.method.options;
        let fixed_step = self.method.fixed_step;
        let d = 2 * self.w.n;
        let gamma = SDIRK4.a(0, 0);
        let e = SDIRK4.error_weights();
        let t = self.t;
        loop {
            let (h, last) = attempt(&mut self.attempts, self.h, fixed_step, &opts, t, tf)?;
            self.h = h;
            if underflow(t, h, &opts) {
                return Err(self
                    .non_finite_ahead
                    .clone()
                    .unwrap_or(ErrorKind::StepSizeUnderflow { t, h }));
            }
            let (w, newton) = (&mut self.w, &mut self.newton);
            if newton.m.jac_needed {
                newton_jacobian(run, t, &self.y, w, &mut newton.m.jac)?;
                newton.m.jacobian_updated();
            }
            newton
                .m
                .factor(h * gamma, &mut run.traj.flat.stats.lu_factorisations);
            chart_field(&w.zeros, &self.y, &self.f, &mut w.k_start);
            let outcome = self.method.stages(run, newton, t, h, &self.y, w);
            let theta_max = match outcome {
                StageOutcome::Converged { theta_max } => theta_max,
                StageOutcome::TooFar if fixed_step.is_some() => {
                    return Err(ErrorKind::InvalidInput(format!(
                        "fixed step h = {h} turns a body by more than π in one step at t = {t}"
                    )));
                }
                StageOutcome::Failed { .. } | StageOutcome::TooFar => {
                    run.traj.flat.stats.rejected_steps += 1;
                    self.failures += 1;
                    if let StageOutcome::Failed {
                        non_finite: Some(kind),
                    } = outcome
                    {
                        self.non_finite_ahead = Some(kind);
                    }
                    let give_up = match fixed_step {
                        // Fixed steps: one retry with a fresh Jacobian.
                        Some(_) => newton.m.jac_current,
                        None => self.failures >= MAX_NEWTON_FAILURES,
                    };
                    if give_up {
                        return Err(self
                            .non_finite_ahead
                            .clone()
                            .unwrap_or(ErrorKind::NewtonDivergence { t }));
                    }
                    if !newton.m.jac_current {
                        newton.m.jac_needed = true;
                    }
                    if fixed_step.is_none() {
                        self.h *= 0.5;
                        self.controller.reject(f64::INFINITY);
                    }
                    continue;
                }
            };
            self.failures = 0;
            let err = if fixed_step.is_some() {
                0.0
            } else {
                // h Σ (b_i − b̂_i) K_i through (I − hγJ)⁻¹ (Shampine's filter).
                let mut est = DVector::from_fn(d, |i, _| {
                    h * (0..e.len()).map(|j| e[j] * w.k[j][i]).sum::<f64>()
                });
                if !newton.m.solve(est.as_mut_slice()) {
                    est.fill(f64::INFINITY);
                }
                magnitudes(&self.y, &mut w.mag0);
                magnitudes(&w.next, &mut w.mag1);
                error_norm(est.as_slice(), &w.mag0, &w.mag1, &opts)
            };
            if err <= 1.0 {
                self.t = if last { tf } else { t + h };
                let t1 = self.t;
                // The normalisation policy of `Rkmk5`.
                for q in &mut w.next.rotations {
                    *q = q.normalised();
                }
                std::mem::swap(&mut self.y, &mut w.next);
                run.rhs(t1, &self.y, &mut self.f)?;
                chart_field(&w.theta1, &self.y, &self.f, &mut w.k_end);
                run.traj.push(&self.y, t1, &self.f);
                // `w.next` is now the step's start: the chart of its dense output.
                let t_start = t1 - h;
                quartic_term(w, t_start, h);
                run.traj
                    .push_chart(h, &w.theta1, &w.k_start, &w.k_end, &w.r5);
                w.prev = Some(t_start);
                // `w.next` is scratch from here on (the next step's stages overwrite it):
                // swap instead of copying the state each step.
                std::mem::swap(&mut w.prev_y, &mut w.next);
                run.traj.flat.stats.steps += 1;
                if matches!(self.non_finite_ahead, Some(ErrorKind::NonFinite { t: bad, .. }) if bad <= t1)
                {
                    self.non_finite_ahead = None;
                }
                if !last {
                    newton.m.jac_current = false;
                    newton.m.jac_needed = theta_max > THETA_REUSE_JACOBIAN;
                    if fixed_step.is_none() {
                        let fac = self.controller.accept(err);
                        // Keep h (and the LU) when it would grow only a little.
                        if !(1.0..=1.2).contains(&fac) {
                            self.h *= fac;
                        }
                    }
                }
                return Ok(());
            }
            run.traj.flat.stats.rejected_steps += 1;
            self.h *= self.controller.reject(err);
            if !newton.m.jac_current {
                newton.m.jac_needed = true;
            }
        }
    }
}

impl LieMethod for LieSdirk {
    type Stepper = LieSdirkStepper;

    fn check(&self) -> Result<(), String> {
        match self.fixed_step {
            Some(h) if !(h.is_finite() && h > 0.0) => {
                Err(format!("fixed step h = {h} must be positive and finite"))
            }
            _ => self.options.validate(),
        }
    }

    fn stepper(&self, y0: &LieState) -> LieSdirkStepper {
        let w = Work::new(y0);
        let (n, d) = (w.n, 2 * w.n);
        LieSdirkStepper {
            method: *self,
            w,
            t: 0.0,
            y: y0.clone(),
            f: vec![0.0; n],
            h: 0.0,
            controller: PiController::new(3),
            newton: Newton {
                m: NewtonMatrix::new(d),
                eta: 1.0,
            },
            failures: 0,
            attempts: 0,
            non_finite_ahead: None,
        }
    }
}

impl LieSdirk {
    /// Adaptive steps.
    pub fn new(options: Options) -> Self {
        LieSdirk {
            options,
            fixed_step: None,
        }
    }

    /// Fixed steps of `h`, with the stage equations solved to `rtol = 1e-10`,
    /// `atol = 1e-12` (so that the Newton error stays below the truncation error in
    /// convergence studies).
    pub fn fixed(h: f64) -> Self {
        LieSdirk {
            options: Options::tolerances(1e-10, 1e-12),
            fixed_step: Some(h),
        }
    }

    /// Integrates `problem` for `system`. On failure the [`SolveError`] carries the
    /// accepted steps as the flat trajectory ([`LieTrajectory::flat`]).
    pub fn solve<S: LieSystem + ?Sized>(
        &self,
        system: &S,
        problem: &LieProblem,
    ) -> Result<LieTrajectory, SolveError> {
        drive(self, system, problem, &[]).map(|(traj, _)| traj)
    }

    /// [`solve`](Self::solve) with event location on the dense output, as
    /// [`Rkmk5::solve_with_events`](super::Rkmk5::solve_with_events) (see
    /// [`LieEvent`]).
    pub fn solve_with_events<S: LieSystem + ?Sized>(
        &self,
        system: &S,
        problem: &LieProblem,
        events: &[LieEvent<'_>],
    ) -> Result<(LieTrajectory, Vec<LieEventHit>), SolveError> {
        drive(self, system, problem, events)
    }

    /// Solves the stages of one step from `y` (with `w.k_start = Θ̇(0)`); on success
    /// `w.k[i] = K_i`, `w.theta1 = Θ₁` and `w.next = y · exp(Θ₁)`.
    fn stages<S: LieSystem + ?Sized>(
        &self,
        run: &mut LieRun<'_, S>,
        newton: &mut Newton,
        t: f64,
        h: f64,
        y: &LieState,
        w: &mut Work,
    ) -> StageOutcome {
        let d = 2 * w.n;
        let hg = h * SDIRK4.a(0, 0);
        let lu = &newton.m;
        magnitudes(y, &mut w.mag0);
        let newton_tol = dirk_stage_tolerance();
        // Stop once a correction is down to ten round-offs of the state (see `Sdirk4`).
        let stagnant = 10.0 * f64::EPSILON * error_norm(&w.mag0, &w.mag0, &w.mag0, &self.options);
        let mut theta_max: f64 = 0.0;
        for i in 0..SDIRK4.stages() {
            for c in 0..d {
                w.base[c] = h * (0..i).map(|j| SDIRK4.a(i, j) * w.k[j][c]).sum::<f64>();
                // Predictor: the previous stage's derivative (Θ̇(0) for the first).
                let guess = if i == 0 { w.k_start[c] } else { w.k[i - 1][c] };
                w.z[c] = w.base[c] + hg * guess;
            }
            // Never ask for less than ten round-offs of the stage's chart coordinates. They
            // are increments, O(h) (not the state, whose round-off `Sdirk4` uses): a floor
            // taken from the state stopped Newton at an error that, amplified up to
            // `dirk_amplification()` ≈ 68 times into the step and repeated with the same
            // sign every step, floored S10's global error near 1e-8 for rtol ≤ 1e-11
            // (measured; 1.3e-9 at rtol 1e-12 with this floor).
            let roundoff = 10.0 * f64::EPSILON * error_norm(&w.z, &w.mag0, &w.mag0, &self.options);
            let stage = DirkStage {
                hg,
                base: &w.base,
                tol: newton_tol.max(roundoff),
                stagnant,
                scale: &w.mag0,
                options: &self.options,
            };
            let (m, c) = (w.m, t + SDIRK4.c[i] * h);
            let (point, f_stage) = (&mut w.point, &mut w.f_stage);
            let solved = dirk_stage_newton(
                &stage,
                &mut w.z,
                &mut w.fz,
                w.delta.as_mut_slice(),
                &mut newton.eta,
                &mut theta_max,
                |delta| lu.solve(delta),
                |z, fz| {
                    if z.iter().any(|x| !x.is_finite()) {
                        return Err(StageFailure::Diverged);
                    }
                    if beyond_pi(z, m) {
                        return Err(StageFailure::TooFar);
                    }
                    retract(y, z, point);
                    run.rhs(c, point, f_stage)
                        .map_err(StageFailure::Evaluation)?;
                    run.traj.flat.stats.newton_iterations += 1;
                    chart_field(z, point, f_stage, fz);
                    Ok(())
                },
            );
            match solved {
                Ok(()) => {}
                Err(StageFailure::TooFar) => return StageOutcome::TooFar,
                Err(StageFailure::Evaluation(kind)) => {
                    return StageOutcome::Failed {
                        non_finite: Some(kind),
                    };
                }
                Err(StageFailure::Diverged) => return StageOutcome::Failed { non_finite: None },
            }
            // K_i from the converged stage value (not F(Θ_i)), as in `Sdirk4`.
            for c in 0..d {
                w.k[i][c] = (w.z[c] - w.base[c]) / hg;
            }
        }
        if beyond_pi(&w.z, w.m) {
            return StageOutcome::TooFar;
        }
        // Stiffly accurate: the last stage is the new state.
        w.theta1.copy_from_slice(&w.z);
        retract(y, &w.theta1, &mut w.next);
        StageOutcome::Converged { theta_max }
    }
}

/// The dense output's quartic term `r₅` ([`dopri5_dense`]), so that it also passes
/// through the previous accepted point: the cubic Hermite on the step's ends and
/// derivatives (local interpolation error `O(h⁴)`, the order of the method's own global
/// error, so that reading the solution between steps lost accuracy: 1.2e-9 on S10's
/// grid against 1.5e-11 at the steps, rtol 1e-12) plus `θ²(1 − θ)² r₅`, which keeps those
/// four conditions and takes the fifth at `θ = −ρ`, `ρ = h_prev / h`: error `O(h⁵)`. In
/// the chart of the step's start `y_n = w.next`, the previous point is
/// `(log(q_n⁻¹ q_{n−1}), x_{n−1} − x_n, v_{n−1} − v_n)`. Zero on the first step (no
/// previous point).
fn quartic_term(w: &mut Work, t_start: f64, h: f64) {
    let Some(t_prev) = w.prev else {
        w.r5.fill(0.0);
        return;
    };
    let (base, prev) = (&w.next, &w.prev_y);
    let m = base.rotations.len();
    for k in 0..m {
        let th = (base.rotations[k].inverse() * prev.rotations[k]).log();
        w.prev_theta[3 * k..3 * k + 3].copy_from_slice(th.as_slice());
    }
    let n = base.euclid.len();
    for i in 0..n {
        w.prev_theta[3 * m + i] = prev.euclid[i] - base.euclid[i];
    }
    for j in 0..base.velocity.len() {
        w.prev_theta[3 * m + n + j] = prev.velocity[j] - base.velocity[j];
    }
    let rho = (t_start - t_prev) / h;
    let weight = (rho * (1.0 + rho)).powi(2);
    for c in 0..w.r5.len() {
        let cubic = dopri5_dense(-rho, h, 0.0, w.theta1[c], w.k_start[c], w.k_end[c], 0.0);
        w.r5[c] = (w.prev_theta[c] - cubic) / weight;
    }
}

/// Whether a rotation vector of `theta` (the first `3m` components) has norm `≥ π`.
fn beyond_pi(theta: &[f64], m: usize) -> bool {
    (0..m).any(|k| {
        Vector3::from_column_slice(&theta[3 * k..3 * k + 3]).norm() >= std::f64::consts::PI
    })
}

/// `J = ∂F/∂Θ` at `Θ = 0` (see the module documentation) into `jac` (`2n × 2n`).
fn newton_jacobian<S: LieSystem + ?Sized>(
    run: &mut LieRun<'_, S>,
    t: f64,
    y: &LieState,
    w: &mut Work,
    jac: &mut DMatrix<f64>,
) -> Result<(), ErrorKind> {
    let (n, m) = (w.n, w.m);
    run.traj.flat.stats.jacobian_evaluations += 1;
    if !run.system.jacobian(t, y, &mut w.dq, &mut w.dv) {
        run.traj.flat.stats.finite_difference_jacobians += 1;
        difference_jacobian(run, t, y, &mut w.dq, &mut w.dv)?;
    }
    if let Some(p) = w.dq.iter().chain(&w.dv).position(|x| !x.is_finite()) {
        // Reported at the row's velocity component in the flat layout.
        return Err(ErrorKind::NonFinite {
            t,
            component: 4 * m + y.euclid.len() + (p % (n * n)) / n,
        });
    }
    jac.fill(0.0);
    for k in 0..m {
        let b = so3::hat(&y.omega(k)) * -0.5;
        for r in 0..3 {
            for c in 0..3 {
                jac[(3 * k + r, 3 * k + c)] = b[(r, c)];
            }
        }
    }
    for r in 0..n {
        jac[(r, n + r)] = 1.0;
    }
    for i in 0..n {
        for j in 0..n {
            jac[(n + i, j)] = w.dq[i * n + j];
            jac[(n + i, n + j)] = w.dv[i * n + j];
        }
    }
    Ok(())
}

/// Central differences of `f` along `y · exp(±δ e_j)` (rotations: `R exp(±δ ê)`;
/// Euclidean coordinates: `x ± δ`) and `v ± δ e_j`, with `δ = ε^⅓ · max(1, |y_j|)`;
/// `4n` rhs evaluations.
fn difference_jacobian<S: LieSystem + ?Sized>(
    run: &mut LieRun<'_, S>,
    t: f64,
    y: &LieState,
    dq: &mut [f64],
    dv: &mut [f64],
) -> Result<(), ErrorKind> {
    let n = y.velocity.len();
    let m = y.rotations.len();
    let (mut fp, mut fm) = (vec![0.0; n], vec![0.0; n]);
    let mut yp = y.clone();
    let scale = f64::EPSILON.cbrt();
    let column = |out: &mut [f64], j: usize, fp: &[f64], fm: &[f64], width: f64| {
        for i in 0..n {
            out[i * n + j] = (fp[i] - fm[i]) / width;
        }
    };
    for j in 0..n {
        let width = if j < 3 * m {
            let (r, c) = (j / 3, j % 3);
            let mut e = Vector3::zeros();
            e[c] = scale;
            yp.rotations[r] = y.rotations[r] * UnitQuat::exp(&e);
            run.rhs(t, &yp, &mut fp)?;
            yp.rotations[r] = y.rotations[r] * UnitQuat::exp(&-e);
            run.rhs(t, &yp, &mut fm)?;
            yp.rotations[r] = y.rotations[r];
            2.0 * scale
        } else {
            let k = j - 3 * m;
            let x = y.euclid[k];
            let delta = scale * x.abs().max(1.0);
            let (xp, xm) = (x + delta, x - delta);
            yp.euclid[k] = xp;
            run.rhs(t, &yp, &mut fp)?;
            yp.euclid[k] = xm;
            run.rhs(t, &yp, &mut fm)?;
            yp.euclid[k] = x;
            xp - xm
        };
        column(dq, j, &fp, &fm, width);
    }
    for j in 0..n {
        let v = y.velocity[j];
        let delta = scale * v.abs().max(1.0);
        let (vp, vm) = (v + delta, v - delta);
        yp.velocity[j] = vp;
        run.rhs(t, &yp, &mut fp)?;
        yp.velocity[j] = vm;
        run.rhs(t, &yp, &mut fm)?;
        yp.velocity[j] = v;
        column(dv, j, &fp, &fm, vp - vm);
    }
    Ok(())
}

#[cfg(test)]
mod tests;
