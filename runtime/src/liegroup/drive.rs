//! The one driver of the Lie-group methods ([`Rkmk5`](super::Rkmk5),
//! [`LieSdirk`](super::LieSdirk)): their step-level trait, validation, the run loop with
//! the event tracker, and the pieces of a step every method shares (the next attempt,
//! the start, the starting step).

use super::chart::{chart_field, magnitudes, retract};
use super::events::{AfterStep, EventTracker, LieEvent, LieEventHit};
use super::trajectory::{LieProblem, LieRun, LieTrajectory};
use super::{LieState, LieSystem};
use crate::numerics::starting_step;
use crate::{ErrorKind, Options, SolveError};

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
            if events.is_empty() {
                continue;
            }
            match tracker.after_step(&mut run)? {
                AfterStep::Go => {}
                AfterStep::End => break,
                AfterStep::Reset { t, state, end } => {
                    // The state after the reset, a second point at `t`, then the run
                    // begins again there.
                    let again = LieProblem::new(t, problem.tf, state);
                    stepper.start(&mut run, &again)?;
                    run.traj.push_jump_interval();
                    if end {
                        break;
                    }
                }
            }
        }
        Ok(())
    };
    let sampled = integrate().and_then(|()| {
        let system = run.system;
        let mut evaluations = 0;
        let rows = run.traj.sample(&problem.output, |t, y, f| {
            evaluations += 1;
            system.rhs(t, y, f);
            match f.iter().position(|x| !x.is_finite()) {
                Some(component) => Err(ErrorKind::NonFinite { t, component }),
                None => Ok(()),
            }
        })?;
        run.traj.flat.stats.rhs_evaluations += evaluations;
        Ok(rows)
    });
    match sampled {
        Ok(rows) => {
            run.traj.stats = run.traj.flat.stats;
            run.traj.show(rows.map(|mut r| {
                r.stats = run.traj.stats;
                r
            }));
            Ok((run.traj, tracker.into_hits()))
        }
        Err(kind) => Err(SolveError::new(kind, run.traj.flat)),
    }
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
