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
//! (`J_r⁻¹` = [`so3::dexp_inv`], closed form: no truncation error from the series). The
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

use super::events::{EventTracker, LieEvent, LieEventHit};
use super::so3::{self, UnitQuat};
use super::{LieState, LieSystem};
use crate::numerics::tableau::{DOPRI5, DOPRI5_DENSE, dopri5_dense};
use crate::numerics::{error_norm, starting_step, underflow};
use crate::{ErrorKind, Keep, Options, Output, PiController, Solution, SolveError, Stats};
use nalgebra::Vector3;

/// An initial-value problem for a [`LieSystem`]: integrate from `(t0, y0)` to `tf ≥ t0`.
#[derive(Clone, Debug, PartialEq)]
pub struct LieProblem {
    pub t0: f64,
    pub tf: f64,
    pub y0: LieState,
}

impl LieProblem {
    pub fn new(t0: f64, tf: f64, y0: LieState) -> Self {
        LieProblem { t0, tf, y0 }
    }

    fn validate<S: LieSystem + ?Sized>(&self, system: &S) -> Result<(), String> {
        if !self.t0.is_finite() || !self.tf.is_finite() || self.tf < self.t0 {
            return Err(format!(
                "need finite t0 ≤ tf (t0 = {}, tf = {})",
                self.t0, self.tf
            ));
        }
        let y = &self.y0;
        let (m, n) = (system.n_rot(), system.n_euclid());
        if y.rotations.len() != m || y.euclid.len() != n || y.velocity.len() != 3 * m + n {
            return Err(format!(
                "y0 has {} rotations, {} Euclidean coordinates and {} velocities; the system \
                 needs {m}, {n} and 3·{m} + {n} = {}",
                y.rotations.len(),
                y.euclid.len(),
                y.velocity.len(),
                3 * m + n
            ));
        }
        let finite = |x: &[f64]| x.iter().all(|v| v.is_finite());
        let quats_finite = y.rotations.iter().all(|q| finite(&q.coords()));
        if !finite(&y.euclid) || !finite(&y.velocity) || !quats_finite {
            return Err("y0 has a NaN or infinite component".into());
        }
        Ok(())
    }
}

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

/// The next attempt from `t` towards `tf` with the step `h` wanted (`fixed_step` if
/// set, else `h` within `h_max`), counted against `max_steps`: the step to take, cut to
/// end at `tf` (without leaving a sliver), and whether it is the last.
pub(super) fn attempt(
    attempts: &mut usize,
    h: f64,
    fixed_step: Option<f64>,
    options: &Options,
    t: f64,
    tf: f64,
) -> Result<(f64, bool), ErrorKind> {
    if *attempts >= options.max_steps {
        return Err(ErrorKind::MaxSteps { t });
    }
    *attempts += 1;
    let (h, last) = match fixed_step {
        // Shorten the last step, and avoid a sliver from round-off.
        Some(h) => (h, t + h * (1.0 + 1e-9) >= tf),
        None => {
            let h = h.min(options.h_max);
            (h, t + 1.01 * h >= tf)
        }
    };
    Ok((if last { tf - t } else { h }, last))
}

/// [`LieStepper::start`] for a method of `order`: `y = y0`, `f = f(t0, y0)`, the first
/// point stored; returns `t0` and the first step to try (`fixed_step`, or the starting
/// step when the interval is not empty).
pub(super) fn begin<S: LieSystem + ?Sized>(
    run: &mut LieRun<'_, S>,
    problem: &LieProblem,
    y: &mut LieState,
    f: &mut [f64],
    fixed_step: Option<f64>,
    order: u32,
    options: &Options,
) -> Result<(f64, f64), ErrorKind> {
    let t = problem.t0;
    y.clone_from(&problem.y0);
    run.rhs(t, y, f)?;
    run.traj.push(y, t, f);
    let h = match fixed_step {
        Some(h) => h,
        None if problem.tf > t => initial_step(run, problem, f, order, options)?,
        None => 0.0,
    };
    Ok((t, h))
}

/// The step-level core of a Lie-group method, under the one driver [`drive`] (the
/// counterpart of [`Stepper`](crate::method::Stepper) for states on the group).
///
/// Two traits, not one: a Lie-group state is a point of `SO(3)ᵐ × ℝⁿ × ℝᵏ` (unit
/// quaternions), and a step's continuous extension is a polynomial in that step's own
/// exponential chart, mapped back to the group. [`Stepper`](crate::method::Stepper)'s
/// flat state vector and per-component polynomial
/// [`DenseStep`](crate::method::DenseStep) would leave the group between steps.
pub(super) trait LieStepper {
    /// Current time.
    fn t(&self) -> f64;

    /// Begins at `problem.y0`: evaluates `f` there, stores the first point, and (when
    /// the interval is not empty) chooses the first step.
    fn start<S: LieSystem + ?Sized>(
        &mut self,
        run: &mut LieRun<'_, S>,
        problem: &LieProblem,
    ) -> Result<(), ErrorKind>;

    /// Attempts steps until one is accepted, ending at or before `tf`, and stores it
    /// with its continuous extension in `run.traj`.
    fn step<S: LieSystem + ?Sized>(
        &mut self,
        run: &mut LieRun<'_, S>,
        tf: f64,
    ) -> Result<(), ErrorKind>;
}

/// What the shared driver needs of a Lie-group method.
pub(super) trait LieMethod {
    type Stepper: LieStepper;

    /// The method's own configuration.
    fn check(&self) -> Result<(), String>;

    /// A stepper for states shaped like `y0`.
    fn stepper(&self, y0: &LieState) -> Self::Stepper;
}

/// Validation, the run, the event tracker and the error wrapping shared by the methods.
pub(super) fn drive<M: LieMethod, S: LieSystem + ?Sized>(
    method: &M,
    system: &S,
    problem: &LieProblem,
    events: &[LieEvent<'_>],
) -> Result<(LieTrajectory, Vec<LieEventHit>), SolveError> {
    let traj = LieTrajectory::new(system.n_rot(), system.n_euclid());
    let checked = method
        .check()
        .and_then(|()| system.validate())
        .and_then(|()| problem.validate(system));
    let mut tracker = match checked.and_then(|()| EventTracker::new(events, problem)) {
        Ok(tracker) => tracker,
        Err(msg) => {
            return Err(SolveError::new(ErrorKind::InvalidInput(msg), traj.flat));
        }
    };
    let mut run = LieRun { system, traj };
    let mut stepper = method.stepper(&problem.y0);
    let mut integrate = || -> Result<(), ErrorKind> {
        stepper.start(&mut run, problem)?;
        while stepper.t() < problem.tf {
            stepper.step(&mut run, problem.tf)?;
            if !events.is_empty() && tracker.after_step(&mut run)? {
                break;
            }
        }
        Ok(())
    };
    match integrate() {
        Ok(()) => Ok((run.traj, tracker.into_hits())),
        Err(kind) => Err(SolveError::new(kind, run.traj.flat)),
    }
}

/// One integration in progress.
pub(super) struct LieRun<'a, S: ?Sized> {
    pub(super) system: &'a S,
    pub(super) traj: LieTrajectory,
}

impl<S: LieSystem + ?Sized> LieRun<'_, S> {
    /// `dv = f(t, y)`, counted and checked; a non-finite component is reported at its
    /// index in the flat layout of [`LieTrajectory::flat`].
    pub(super) fn rhs(&mut self, t: f64, y: &LieState, dv: &mut [f64]) -> Result<(), ErrorKind> {
        self.traj.flat.stats.rhs_evaluations += 1;
        self.system.rhs(t, y, dv);
        match dv.iter().position(|x| !x.is_finite()) {
            Some(j) => Err(ErrorKind::NonFinite {
                t,
                component: 4 * y.rotations.len() + y.euclid.len() + j,
            }),
            None => Ok(()),
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

/// `y₀ · exp(Θ)` into `out` (same shapes as `base`).
pub(super) fn retract(base: &LieState, theta: &[f64], out: &mut LieState) {
    let m = base.rotations.len();
    for (k, (q, q0)) in out.rotations.iter_mut().zip(&base.rotations).enumerate() {
        *q = *q0 * UnitQuat::exp(&Vector3::from_column_slice(&theta[3 * k..3 * k + 3]));
    }
    let rest = &theta[3 * m..];
    let n = base.euclid.len();
    for (x, (x0, d)) in out.euclid.iter_mut().zip(base.euclid.iter().zip(rest)) {
        *x = x0 + d;
    }
    for (v, (v0, d)) in out
        .velocity
        .iter_mut()
        .zip(base.velocity.iter().zip(&rest[n..]))
    {
        *v = v0 + d;
    }
}

/// `Θ̇ = (J_r(θ_k)⁻¹ ω_k, u, f)` at `Θ` with `y = y₀ · exp(Θ)` and `f = f(t, y)`.
pub(super) fn chart_field(theta: &[f64], y: &LieState, f: &[f64], out: &mut [f64]) {
    let m = y.rotations.len();
    for k in 0..m {
        let th = Vector3::from_column_slice(&theta[3 * k..3 * k + 3]);
        let w = so3::dexp_inv_apply(&th, &y.omega(k));
        out[3 * k..3 * k + 3].copy_from_slice(w.as_slice());
    }
    let n = y.euclid.len();
    out[3 * m..3 * m + n].copy_from_slice(y.euclid_velocity());
    out[3 * m + n..].copy_from_slice(f);
}

/// Reference magnitudes for the error weights: 1 per rotation component, `|x|`, `|v|`.
pub(super) fn magnitudes(y: &LieState, out: &mut [f64]) {
    let m3 = 3 * y.rotations.len();
    out[..m3].fill(1.0);
    let n = y.euclid.len();
    out[m3..m3 + n].copy_from_slice(&y.euclid);
    out[m3 + n..].copy_from_slice(&y.velocity);
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

/// The starting step ([`starting_step`], shared with the flat methods) in the local
/// coordinates of the first step, for a method of order `order`; one extra rhs
/// evaluation. `f0 = f(t₀, y₀)`. The trial step is at most 1 (a trial rotation stays
/// well inside the chart).
fn initial_step<S: LieSystem + ?Sized>(
    run: &mut LieRun<'_, S>,
    problem: &LieProblem,
    f0: &[f64],
    order: u32,
    options: &Options,
) -> Result<f64, ErrorKind> {
    let y0 = &problem.y0;
    let d = 3 * y0.rotations.len() + y0.euclid.len() + y0.velocity.len();
    let (mut mag, zero) = (vec![0.0; d], vec![0.0; d]);
    let (mut k0, mut theta) = (vec![0.0; d], vec![0.0; d]);
    magnitudes(y0, &mut mag);
    chart_field(&zero, y0, f0, &mut k0);
    let mut point = y0.clone();
    let mut f = vec![0.0; f0.len()];
    let span = problem.tf - problem.t0;
    starting_step(&mag, &k0, span, 1.0, order, options, |h0, k1| {
        for (x, k) in theta.iter_mut().zip(&k0) {
            *x = h0 * k;
        }
        retract(y0, &theta, &mut point);
        run.rhs(problem.t0 + h0, &point, &mut f)?;
        chart_field(&theta, &point, &f, k1);
        Ok(())
    })
}

/// The accepted states of a Lie-group integration with their dense output.
///
/// Stored twice over: as a flat [`Solution`] (per point the quaternions `w, x, y, z`
/// of every rotation, then `x`, then `v`; derivatives `q̇ = ½ q ⊗ (0, ω)`, `ẋ = u`,
/// `v̇ = f`; its own interpolation is cubic Hermite and leaves the group), and per step
/// the local-coordinate data of the continuous extension (Dormand–Prince for
/// [`Rkmk5`], quartic through the previous point for [`LieSdirk`](super::LieSdirk)),
/// used by
/// [`at`](Self::at).
#[derive(Clone, Debug, PartialEq)]
pub struct LieTrajectory {
    n_rot: usize,
    n_euclid: usize,
    pub(super) flat: Solution,
    /// Per interval: `Θ₁, K₁, K₇, r₅`, each of the local dimension (`K₁`, `K₇` the
    /// derivatives of `Θ` at the ends; `r₅` the quartic term, `0` for the cubic Hermite).
    chart: Vec<f64>,
    /// Per interval: the step's length `h` (the chart's time scale; longer than the
    /// interval when a terminal event cut the step short).
    steps: Vec<f64>,
}

impl LieTrajectory {
    pub(super) fn new(n_rot: usize, n_euclid: usize) -> Self {
        let mut names = Vec::new();
        for k in 0..n_rot {
            names.extend(["w", "x", "y", "z"].map(|c| format!("q{k}_{c}")));
        }
        names.extend((0..n_euclid).map(|i| format!("x{i}")));
        names.extend((0..3 * n_rot + n_euclid).map(|j| format!("v{j}")));
        LieTrajectory {
            n_rot,
            n_euclid,
            flat: Solution::new(names, 0, Output::Steps),
            chart: Vec::new(),
            steps: Vec::new(),
        }
    }

    fn local_dim(&self) -> usize {
        6 * self.n_rot + 2 * self.n_euclid
    }

    pub(super) fn push(&mut self, y: &LieState, t: f64, f: &[f64]) {
        let (mut flat, mut dflat) = (Vec::new(), Vec::new());
        for (k, q) in y.rotations.iter().enumerate() {
            let [w, x, yy, z] = q.coords();
            let u = Vector3::new(x, yy, z);
            let om = y.omega(k);
            let du = (om * w + u.cross(&om)) * 0.5;
            flat.extend_from_slice(&q.coords());
            dflat.extend_from_slice(&[-0.5 * u.dot(&om), du.x, du.y, du.z]);
        }
        flat.extend_from_slice(&y.euclid);
        flat.extend_from_slice(&y.velocity);
        dflat.extend_from_slice(y.euclid_velocity());
        dflat.extend_from_slice(f);
        self.flat.push_step(t, &flat, &dflat, None, Keep::AsAsked);
    }

    /// The continuous extension of the interval ending at the last pushed point: a step
    /// of length `h` reaching `Θ₁`, with `Θ'` = `k1` at its start and `k7` at its end.
    pub(super) fn push_chart(
        &mut self,
        h: f64,
        theta1: &[f64],
        k1: &[f64],
        k7: &[f64],
        r5: &[f64],
    ) {
        for part in [theta1, k1, k7, r5] {
            self.chart.extend_from_slice(part);
        }
        self.steps.push(h);
    }

    /// Replaces the last point by `(t, y)` with `f = f(t, y)`, `t` inside the last
    /// interval (a terminal event); the interval keeps its step's interpolant.
    pub(super) fn truncate_last(&mut self, t: f64, y: &LieState, f: &[f64]) {
        let n = self.len();
        let mut flat = Solution::new(self.flat.names().to_vec(), 0, Output::Steps);
        for i in 0..n - 1 {
            flat.push_step(
                self.flat.times()[i],
                self.flat.state(i),
                self.flat.derivative(i),
                None,
                Keep::AsAsked,
            );
        }
        flat.stats = self.flat.stats;
        self.flat = flat;
        self.push(y, t, f);
    }

    /// Number of stored points.
    pub fn len(&self) -> usize {
        self.flat.len()
    }

    pub fn is_empty(&self) -> bool {
        self.flat.is_empty()
    }

    /// Times of the stored points, increasing.
    pub fn times(&self) -> &[f64] {
        self.flat.times()
    }

    /// State at stored point `i`.
    pub fn state(&self, i: usize) -> LieState {
        let y = self.flat.state(i);
        let m4 = 4 * self.n_rot;
        let rotations = y[..m4]
            .chunks(4)
            .map(|c| UnitQuat::from_coords_unchecked(c[0], c[1], c[2], c[3]))
            .collect();
        let euclid = y[m4..m4 + self.n_euclid].to_vec();
        let velocity = y[m4 + self.n_euclid..].to_vec();
        LieState::new(rotations, euclid, velocity)
    }

    /// The last stored time and state.
    pub fn last(&self) -> Option<(f64, LieState)> {
        let n = self.len();
        (n > 0).then(|| (self.times()[n - 1], self.state(n - 1)))
    }

    /// The state at `t` from the continuous extension in the local coordinates of the
    /// step containing `t` (on the group; fourth order for [`Rkmk5`], third for
    /// [`LieSdirk`](super::LieSdirk)), or `None` outside `[t_first, t_last]`.
    pub fn at(&self, t: f64) -> Option<LieState> {
        let times = self.times();
        let (&first, &last) = (times.first()?, times.last()?);
        if !(first..=last).contains(&t) {
            return None;
        }
        let i = times.partition_point(|&ti| ti <= t).saturating_sub(1);
        if i + 1 >= self.len() {
            return Some(self.state(i));
        }
        let h = self.steps[i];
        let s = (t - times[i]) / h;
        let d = self.local_dim();
        let data = &self.chart[4 * d * i..4 * d * (i + 1)];
        let (th1, rest) = data.split_at(d);
        let (k1, rest) = rest.split_at(d);
        let (k7, r5) = rest.split_at(d);
        let theta: Vec<f64> = (0..d)
            .map(|c| dopri5_dense(s, h, 0.0, th1[c], k1[c], k7[c], r5[c]))
            .collect();
        let base = self.state(i);
        let mut y = base.clone();
        retract(&base, &theta, &mut y);
        for q in &mut y.rotations {
            *q = q.normalised();
        }
        Some(y)
    }

    /// The flat trajectory (layout in the type's documentation), e.g. for CSV output.
    pub fn flat(&self) -> &Solution {
        &self.flat
    }

    /// Cost of the integration.
    pub fn stats(&self) -> &Stats {
        &self.flat.stats
    }
}
