//! The smooth driver: [`solve`] integrates an [`OdeSystem`] from `t0` to `tf` with any
//! [`Stepper`], written once for every method. An [`Observer`] sees every accepted step
//! (progress bars, cancellation).

use std::ops::ControlFlow;

use crate::events::{Event, EventHit, Tracker};
use crate::method::{Begin, Eval, Stepper, with_stepper};
use crate::{ErrorKind, Keep, Method, OdeSystem, Problem, Solution, SolveError};

/// Sees every accepted step of an integration: `(t, y)` after the step. Returning
/// `ControlFlow::Break(())` stops the integration with [`ErrorKind::Cancelled`] (the
/// solution so far is kept in the error). Closures `FnMut(f64, &[f64]) ->
/// ControlFlow<()>` are observers.
pub trait Observer {
    fn observe(&mut self, t: f64, y: &[f64]) -> ControlFlow<()>;
}

impl<F: FnMut(f64, &[f64]) -> ControlFlow<()>> Observer for F {
    fn observe(&mut self, t: f64, y: &[f64]) -> ControlFlow<()> {
        self(t, y)
    }
}

/// The observer that never stops anything.
pub(crate) fn unobserved(_: f64, _: &[f64]) -> ControlFlow<()> {
    ControlFlow::Continue(())
}

/// Integrates `problem` for `system` with `method`.
///
/// ```
/// use filippov_runtime::{FnSystem, Method, Options, Problem, solve};
/// let decay = FnSystem::new(1, |_t, y: &[f64], dy: &mut [f64]| dy[0] = -y[0]);
/// let sol = solve(&decay, &Problem::new(0.0, 1.0, [1.0]), &Method::Dopri5(Options::tolerances(1e-8, 1e-10))).unwrap();
/// assert!((sol.last().unwrap().1[0] - (-1.0f64).exp()).abs() < 1e-7);
/// ```
pub fn solve<S: OdeSystem + ?Sized>(
    system: &S,
    problem: &Problem,
    method: &Method,
) -> Result<Solution, SolveError> {
    solve_with(system, problem, method, &mut unobserved)
}

/// [`solve`] with an [`Observer`] called after every accepted step.
///
/// ```
/// use std::ops::ControlFlow;
/// use filippov_runtime::{ErrorKind, FnSystem, Method, Options, Problem, solve_with};
/// let decay = FnSystem::new(1, |_t, y: &[f64], dy: &mut [f64]| dy[0] = -y[0]);
/// // Stop as soon as y < 0.5.
/// let mut stop = |_t: f64, y: &[f64]| if y[0] < 0.5 { ControlFlow::Break(()) } else { ControlFlow::Continue(()) };
/// let err = solve_with(&decay, &Problem::new(0.0, 10.0, [1.0]), &Method::Dopri5(Options::default()), &mut stop).unwrap_err();
/// assert!(matches!(err.kind, ErrorKind::Cancelled { .. }));
/// assert!(err.solution.last().unwrap().1[0] < 0.5);
/// ```
pub fn solve_with<S: OdeSystem + ?Sized, O: Observer + ?Sized>(
    system: &S,
    problem: &Problem,
    method: &Method,
    observer: &mut O,
) -> Result<Solution, SolveError> {
    with_stepper!(method, system.dim(), |stepper| integrate(
        &mut stepper,
        system,
        problem,
        observer
    ))
}

/// [`solve`] locating user [`Event`]s (see [`crate::events`]): each crossing is in the
/// solution's [`events`](Solution::events), and a terminal one ends the run there.
///
/// ```
/// use filippov_runtime::{Event, FnSystem, Method, Options, Problem, solve_with_events};
/// // A ball thrown up at 10 m/s: when does it fall back through y = 0?
/// let ball = FnSystem::new(2, |_t, y: &[f64], dy: &mut [f64]| {
///     dy[0] = y[1];
///     dy[1] = -9.81;
/// });
/// let ground = |_t: f64, y: &[f64]| y[0];
/// let events = [Event::new(&ground).terminal()];
/// let problem = Problem::new(0.0, 10.0, [0.0, 10.0]);
/// let method = Method::Dopri5(Options::tolerances(1e-10, 1e-12));
/// let sol = solve_with_events(&ball, &problem, &method, &events).unwrap();
/// let landing = 2.0 * 10.0 / 9.81;
/// assert!((sol.events[0].t - landing).abs() < 1e-9);
/// assert_eq!(sol.last().unwrap().0, sol.events[0].t);
/// ```
pub fn solve_with_events<S: OdeSystem + ?Sized>(
    system: &S,
    problem: &Problem,
    method: &Method,
    events: &[Event<'_>],
) -> Result<Solution, SolveError> {
    with_stepper!(method, system.dim(), |stepper| integrate_with(
        &mut stepper,
        system,
        problem,
        &mut unobserved,
        events
    ))
}

/// The driver itself, for any [`Stepper`] (see the module documentation).
pub fn integrate<St, S, O>(
    stepper: &mut St,
    system: &S,
    problem: &Problem,
    observer: &mut O,
) -> Result<Solution, SolveError>
where
    St: Stepper,
    S: OdeSystem + ?Sized,
    O: Observer + ?Sized,
{
    integrate_with(stepper, system, problem, observer, &[])
}

fn integrate_with<St, S, O>(
    stepper: &mut St,
    system: &S,
    problem: &Problem,
    observer: &mut O,
    events: &[Event<'_>],
) -> Result<Solution, SolveError>
where
    St: Stepper,
    S: OdeSystem + ?Sized,
    O: Observer + ?Sized,
{
    let mut sol = Solution::new(system.names(), system.dim(), problem.output.clone())
        .with_dense_positions(crate::problem::dense_positions(system));
    let checked = if sol.dim() != system.dim() {
        Err(format!(
            "the system names {} components but has dimension {}",
            sol.dim(),
            system.dim()
        ))
    } else {
        system
            .validate()
            .and_then(|()| problem.validate(system.dim()))
    };
    let tracker = checked.and_then(|()| Tracker::new(events, problem.t0, &problem.y0));
    let mut tracker = match tracker {
        Ok(tracker) => tracker,
        Err(msg) => return Err(SolveError::new(ErrorKind::InvalidInput(msg), sol)),
    };
    match run(stepper, system, problem, observer, &mut sol, &mut tracker) {
        Ok(()) => Ok(sol),
        Err(kind) => Err(SolveError::new(kind, sol)),
    }
}

fn run<St, S, O>(
    stepper: &mut St,
    system: &S,
    problem: &Problem,
    observer: &mut O,
    sol: &mut Solution,
    tracker: &mut Tracker<'_, '_, [f64]>,
) -> Result<(), ErrorKind>
where
    St: Stepper,
    S: OdeSystem + ?Sized,
    O: Observer + ?Sized,
{
    let (t0, tf) = (problem.t0, problem.tf);
    let at = Begin {
        t: t0,
        y: &problem.y0,
        span: tf - t0,
        fresh: true,
    };
    // A closed mechanism starts on its constraints (its given state, if off them, is
    // projected: `loops::assemble` completes a partial one) and is put back on them
    // after every step.
    let mut y = problem.y0.clone();
    system.project(t0, &mut y)?;
    let at = Begin { y: &y, ..at };
    stepper.begin(&mut Eval::new(system, &mut sol.stats), at)?;
    sol.push_start(t0, stepper.y(), stepper.f());
    while stepper.t() < tf {
        let t_prev = stepper.t();
        stepper.step(&mut Eval::new(system, &mut sol.stats), tf)?;
        let t = stepper.t();
        y.copy_from_slice(stepper.y());
        if system.project(t, &mut y)? {
            stepper.nudge(&mut Eval::new(system, &mut sol.stats), &y)?;
        }
        if !tracker.is_empty() {
            match locate_events(stepper, system, problem, sol, tracker, t_prev)? {
                Located::Nothing => {}
                Located::End => return Ok(()),
                Located::Reset => continue,
            }
        }
        let keep = if t >= tf { Keep::Last } else { Keep::AsAsked };
        let needs_dense = sol.needs_dense(t);
        if needs_dense {
            stepper.prepare_dense();
        }
        let dense = needs_dense.then(|| stepper.dense());
        sol.push_step(t, stepper.y(), stepper.f(), dense, keep);
        if observer.observe(t, stepper.y()).is_break() {
            return Err(ErrorKind::Cancelled { t });
        }
    }
    Ok(())
}

/// What the user events of a step did to the run.
enum Located {
    /// Nothing but records: the step stands.
    Nothing,
    /// A terminal event ended the run.
    End,
    /// A reset changed the state; the stepper begins again from there.
    Reset,
}

/// The user events of the step from `t_prev` to the stepper's point, recorded in `sol`.
/// At a terminal crossing the step's dense output is cut there and its row written; at a
/// reset the row before it and the row after it are written at its time, and the stepper
/// begins again from the new state.
fn locate_events<St, S>(
    stepper: &mut St,
    system: &S,
    problem: &Problem,
    sol: &mut Solution,
    tracker: &mut Tracker<'_, '_, [f64]>,
    t_prev: f64,
) -> Result<Located, ErrorKind>
where
    St: Stepper,
    S: OdeSystem + ?Sized,
{
    stepper.prepare_dense();
    let dense = stepper.dense();
    let at = |t: f64| {
        let mut y = vec![0.0; stepper.y().len()];
        dense.eval(t, &mut y);
        y
    };
    let crossings = tracker.step(t_prev, stepper.t(), stepper.y(), at);
    for &(event, t) in &crossings.found {
        sol.events.push(EventHit {
            event,
            t,
            state: at(t),
        });
        sol.stats.events += 1;
    }
    let Some(te) = crossings.reset.map(|r| r.1).or(crossings.terminal) else {
        return Ok(Located::Nothing);
    };
    let mut cut = dense.clone();
    cut.truncate(te);
    let mut y = at(te);
    let mut f = vec![0.0; y.len()];
    Eval::new(system, &mut sol.stats).rhs(te, &y, &mut f)?;
    let Some((k, _)) = crossings.reset else {
        sol.push_step(te, &y, &f, Some(&cut), Keep::Last);
        return Ok(Located::End);
    };
    sol.push_step(te, &y, &f, Some(&cut), Keep::Event);
    tracker
        .apply_reset(k, te, &mut y)
        .map_err(ErrorKind::InvalidInput)?;
    if let Some(component) = y.iter().position(|x| !x.is_finite()) {
        return Err(ErrorKind::NonFinite { t: te, component });
    }
    Eval::new(system, &mut sol.stats).rhs(te, &y, &mut f)?;
    sol.push_jump(te, &y, &f);
    if crossings.terminal.is_some() {
        return Ok(Located::End);
    }
    let at = Begin {
        t: te,
        y: &y,
        span: problem.tf - te,
        fresh: false,
    };
    stepper.begin(&mut Eval::new(system, &mut sol.stats), at)?;
    Ok(Located::Reset)
}
