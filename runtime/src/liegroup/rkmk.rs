//! Runge–Kutta–Munthe-Kaas (RKMK) on the Dormand–Prince 5(4) tableau.
//!
//! H. Munthe-Kaas, *Runge–Kutta methods on Lie groups*, BIT 38 (1998) 92–111, and *High
//! order Runge–Kutta methods on manifolds*, Appl. Numer. Math. 29 (1999) 115–127;
//! Iserles, Munthe-Kaas, Nørsett & Zanna, *Lie-group methods*, Acta Numerica 9 (2000),
//! §4.2 (Algorithm 4.2, RKMK with the full `dexp⁻¹`).
//!
//! One step from `y₀ = (g₀, v₀)` writes the solution near `y₀` in local exponential
//! coordinates `Θ = (θ_1, …, θ_m, δx, δv)`, `y = y₀ · exp(Θ)`, i.e.
//! `R_k = R_k₀ exp(θ_k)`, `x = x₀ + δx`, `v = v₀ + δv`. In these coordinates the ODE is
//! an ordinary one on a vector space starting at `Θ = 0`:
//!
//! ```text
//! θ̇_k = J_r(θ_k)⁻¹ ω_k(y),   δẋ = u(y),   δv̇ = f(t, y),    y = y₀ · exp(Θ)
//! ```
//!
//! (`J_r⁻¹` = [`so3::dexp_inv`](crate::geometry::so3::dexp_inv), closed form: no truncation error from the series). The
//! Dormand–Prince stages are taken on this ODE, so the method has the tableau's orders:
//! 5 for the propagated solution, 4 for the embedded one, 4 for the continuous
//! extension. The step ends with `g₁ = g₀ · exp(Θ₁)` and the next step re-centres the
//! coordinates at `g₁`. FSAL carries over: the last stage is `f(t + h, y₁)`, and at the
//! new centre `J_r(0)⁻¹ = I`, so the raw `f` is the next first stage.
//!
//! * Error control: the embedded estimate `h Σ (b_i − b̂_i) K_i` in local coordinates,
//!   in the weighted RMS norm of [`Options`] with the scale `atol + rtol · 1` for the
//!   rotation components (a rotation has magnitude one; `θ` itself starts at 0) and
//!   the usual `atol + rtol · max(|y₀|, |y₁|)` for `x` and `v`. Steps whose stage
//!   rotation vectors exceed `π` in norm are rejected before the estimate
//!   (`J_r⁻¹` is singular at `2π`, and exp is not injective beyond `π`).
//! * Dense output: the Dormand–Prince continuous extension of `Θ(t)` in each step's own
//!   coordinates, then `y₀ · exp(Θ(t))` — it stays on the group. [`LieTrajectory`]
//!   stores per step `Θ₁`, the end derivatives and the fifth coefficient `r₅`, and the
//!   step's length (so that a step cut short by a terminal event keeps its
//!   interpolant); [`LieSdirk`](super::LieSdirk) stores the `r₅` that makes its
//!   Hermite interpolant in the same coordinates pass through the previous point.
//! * Events: [`Rkmk5::solve_with_events`], see [`LieEvent`].
//! * Normalisation policy: the group update `q₀ ⊗ exp(θ)` is a product of unit
//!   quaternions, unit up to round-off; every accepted state is normalised once (one
//!   square root per rotation per step), so the drift never accumulates. Without it the
//!   drift is a random walk of round-off (measured in
//!   `so3::tests::product_drift_without_normalisation_is_round_off`: 1e-14 after 10⁵
//!   updates) — the normalisation is hygiene, not a correction of the method.

use nalgebra::Vector3;

use super::chart::{chart_field, magnitudes, retract};
use super::drive::{LieMethod, LieStepper, attempt, begin, drive};
use super::events::{LieEvent, LieEventHit};
use super::trajectory::{LieProblem, LieRun, LieTrajectory};
use super::{LieState, LieSystem};
use crate::numerics::tableau::{DOPRI5, DOPRI5_DENSE};
use crate::numerics::{error_norm, underflow};
use crate::{ErrorKind, Options, PiController, SolveError};

/// RKMK with the Dormand–Prince 5(4) tableau (see the module documentation), adaptive
/// with a [`PiController`] or, with [`fixed`](Self::fixed), at a fixed step for
/// convergence studies.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Rkmk5 {
    /// Tolerances and step limits of the adaptive mode (`max_steps` also bounds the
    /// fixed mode).
    pub options: Options,
    /// `Some(h)`: no error control, steps of `h` (the last one shortened to hit `tf`).
    pub fixed_step: Option<f64>,
}

impl LieMethod for Rkmk5 {
    type Stepper = Rkmk5Stepper;

    fn check(&self) -> Result<(), String> {
        self.validate()
    }

    fn stepper(&self, y0: &LieState) -> Rkmk5Stepper {
        let st = Stages::new(y0);
        let d = st.theta.len();
        Rkmk5Stepper {
            method: *self,
            st,
            t: 0.0,
            y: y0.clone(),
            h: 0.0,
            controller: PiController::new(4),
            err_vec: vec![0.0; d],
            r5: vec![0.0; d],
            mag0: vec![0.0; d],
            mag1: vec![0.0; d],
            attempts: 0,
        }
    }
}

impl Rkmk5 {
    /// Adaptive steps.
    pub fn new(options: Options) -> Self {
        Rkmk5 {
            options,
            fixed_step: None,
        }
    }

    /// Fixed steps of `h`.
    pub fn fixed(h: f64) -> Self {
        Rkmk5 {
            options: Options::default(),
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

    /// [`solve`](Self::solve) with event location: after every accepted step the event
    /// functions are evaluated at its end, and each sign change (in the event's
    /// [`direction`](LieEvent::direction)) is located on the dense output
    /// ([`LieTrajectory::at`]) to `|Δt| ≤ 1e-12 · max(1, |t|)`. The first terminal
    /// event ends the integration there: its state becomes the trajectory's last point.
    /// Returns the trajectory and the located events in time order. On failure the
    /// [`SolveError`] carries the accepted steps, not the events found before.
    pub fn solve_with_events<S: LieSystem + ?Sized>(
        &self,
        system: &S,
        problem: &LieProblem,
        events: &[LieEvent<'_>],
    ) -> Result<(LieTrajectory, Vec<LieEventHit>), SolveError> {
        drive(self, system, problem, events)
    }

    fn validate(&self) -> Result<(), String> {
        match self.fixed_step {
            Some(h) if !(h.is_finite() && h > 0.0) => {
                Err(format!("fixed step h = {h} must be positive and finite"))
            }
            _ => self.options.validate(),
        }
    }
}

/// The stepping state of an [`Rkmk5`] integration (see [`LieStepper`]).
pub(super) struct Rkmk5Stepper {
    method: Rkmk5,
    st: Stages,
    t: f64,
    y: LieState,
    /// The next step to try.
    h: f64,
    controller: PiController,
    err_vec: Vec<f64>,
    r5: Vec<f64>,
    mag0: Vec<f64>,
    mag1: Vec<f64>,
    /// Attempts so far (bounded by `max_steps`).
    attempts: usize,
}

impl LieStepper for Rkmk5Stepper {
    fn t(&self) -> f64 {
        self.t
    }

    fn start<S: LieSystem + ?Sized>(
        &mut self,
        run: &mut LieRun<'_, S>,
        problem: &LieProblem,
    ) -> Result<(), ErrorKind> {
        let (method, f) = (&self.method, &mut self.st.f0);
        (self.t, self.h) = begin(
            run,
            problem,
            &mut self.y,
            f,
            method.fixed_step,
            5,
            &method.options,
        )?;
        Ok(())
    }

    fn step<S: LieSystem + ?Sized>(
        &mut self,
        run: &mut LieRun<'_, S>,
        tf: f64,
    ) -> Result<(), ErrorKind> {
        let opts = &self.method.options;
        let e = DOPRI5.error_weights();
        let (t, st) = (self.t, &mut self.st);
        loop {
            let (h, last) = attempt(
                &mut self.attempts,
                self.h,
                self.method.fixed_step,
                opts,
                t,
                tf,
            )?;
            self.h = h;
            if underflow(t, h, opts) {
                return Err(ErrorKind::StepSizeUnderflow { t, h });
            }
            if !stages(run, t, h, &self.y, st)? {
                if self.method.fixed_step.is_some() {
                    return Err(ErrorKind::InvalidInput(format!(
                        "fixed step h = {h} turns a body by more than π in one step at t = {t}"
                    )));
                }
                run.traj.flat.stats.rejected_steps += 1;
                self.h *= self.controller.reject(f64::INFINITY);
                continue;
            }
            let err = if self.method.fixed_step.is_some() {
                0.0
            } else {
                for (i, ei) in self.err_vec.iter_mut().enumerate() {
                    *ei = h * (0..7).map(|j| e[j] * st.k[j][i]).sum::<f64>();
                }
                magnitudes(&self.y, &mut self.mag0);
                magnitudes(&st.next, &mut self.mag1);
                error_norm(&self.err_vec, &self.mag0, &self.mag1, opts)
            };
            if err <= 1.0 {
                for (i, r) in self.r5.iter_mut().enumerate() {
                    *r = h * (0..7).map(|j| DOPRI5_DENSE[j] * st.k[j][i]).sum::<f64>();
                }
                self.t = if last { tf } else { t + h };
                // The normalisation policy of the module documentation.
                for q in &mut st.next.rotations {
                    *q = q.normalised();
                }
                std::mem::swap(&mut self.y, &mut st.next);
                std::mem::swap(&mut st.f0, &mut st.f1);
                run.traj.push(&self.y, self.t, &st.f0);
                run.traj
                    .push_chart(h, &st.theta1, &st.k[0], &st.k[6], &self.r5);
                run.traj.flat.stats.steps += 1;
                if !last {
                    self.h *= self.controller.accept(err);
                }
                return Ok(());
            }
            run.traj.flat.stats.rejected_steps += 1;
            self.h *= self.controller.reject(err);
        }
    }
}

/// Work vectors of one step. `k[s]` are the stage derivatives in local coordinates.
struct Stages {
    k: [Vec<f64>; 7],
    theta: Vec<f64>,
    theta1: Vec<f64>,
    /// Raw `f` at the step's start (FSAL: at the end of the previous step).
    f0: Vec<f64>,
    f: Vec<f64>,
    f1: Vec<f64>,
    point: LieState,
    next: LieState,
}

impl Stages {
    fn new(y0: &LieState) -> Self {
        let d = 3 * y0.rotations.len() + y0.euclid.len() + y0.velocity.len();
        let nv = y0.velocity.len();
        Stages {
            k: std::array::from_fn(|_| vec![0.0; d]),
            theta: vec![0.0; d],
            theta1: vec![0.0; d],
            f0: vec![0.0; nv],
            f: vec![0.0; nv],
            f1: vec![0.0; nv],
            point: y0.clone(),
            next: y0.clone(),
        }
    }
}

/// The six new stages of a step of size `h` from `y` (with `st.f0 = f(t, y)`); leaves
/// `Θ₁` in `st.theta1`, `y · exp(Θ₁)` in `st.next`, `f(t + h, ·)` there in `st.f1`.
/// `Ok(false)` when a stage rotation vector leaves the ball `|θ| < π`.
fn stages<S: LieSystem + ?Sized>(
    run: &mut LieRun<'_, S>,
    t: f64,
    h: f64,
    y: &LieState,
    st: &mut Stages,
) -> Result<bool, ErrorKind> {
    st.theta.fill(0.0);
    chart_field(&st.theta, y, &st.f0, &mut st.k[0]);
    let m = y.rotations.len();
    for s in 1..7 {
        for (i, x) in st.theta.iter_mut().enumerate() {
            *x = h * (0..s).map(|j| DOPRI5.a(s, j) * st.k[j][i]).sum::<f64>();
        }
        if let Some(c) = st.theta.iter().position(|x| !x.is_finite()) {
            let component = if c < 3 * m { 4 * (c / 3) } else { c + m };
            return Err(ErrorKind::NonFinite {
                t: t + h,
                component,
            });
        }
        let too_far = (0..m).any(|k| {
            Vector3::from_column_slice(&st.theta[3 * k..3 * k + 3]).norm() >= std::f64::consts::PI
        });
        if too_far {
            return Ok(false);
        }
        retract(y, &st.theta, &mut st.point);
        run.rhs(t + DOPRI5.c[s] * h, &st.point, &mut st.f)?;
        let (_, rest) = st.k.split_at_mut(s);
        chart_field(&st.theta, &st.point, &st.f, &mut rest[0]);
        if s == 6 {
            // Row 7 of A is b: this stage is the new state.
            st.theta1.copy_from_slice(&st.theta);
            st.next.clone_from(&st.point);
            st.f1.copy_from_slice(&st.f);
        }
    }
    Ok(true)
}
