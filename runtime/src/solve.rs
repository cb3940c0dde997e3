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
        Err(msg) => {
            sol.append_columns(system.output_names(), |_, _, _| {});
            return Err(SolveError::new(ErrorKind::InvalidInput(msg), sol));
        }
    };
    let result = run(stepper, system, problem, observer, &mut sol, &mut tracker);
    // The system's outputs (a closed mechanism's constraint forces), from each row kept,
    // whether the run completed or not.
    sol.append_columns(system.output_names(), |t, y, out| system.outputs(t, y, out));
    match result {
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
    // A system with a manifold (it has a conditioning) is followed and projected after
    // each step; the others skip both.
    let manifold = system.conditioning(&y).is_some();
    let at = Begin { y: &y, ..at };
    stepper.begin(&mut Eval::new(system, &mut sol.stats), at)?;
    sol.push_start(t0, stepper.y(), stepper.f());
    while stepper.t() < tf {
        let t_prev = stepper.t();
        stepper.step(&mut Eval::new(system, &mut sol.stats), tf)?;
        let t = stepper.t();
        if manifold {
            stepper.prepare_dense();
            if let Some(ts) = singular_point(system, stepper.dense(), t_prev, t) {
                // The run ends where the manifold became singular (at most a fraction of
                // the step past its end), with the part of the step up to there kept and
                // the error naming the constraint.
                let t_row = ts.min(t);
                let mut cut = stepper.dense().clone();
                cut.truncate(t_row);
                let mut ys = vec![0.0; y.len()];
                cut.eval(t_row, &mut ys);
                let mut f = vec![0.0; y.len()];
                Eval::new(system, &mut sol.stats).rhs(t_row, &ys, &mut f)?;
                sol.push_step(t_row, &ys, &f, Some(&cut), Keep::Last);
                // The error the projection gives there, named at the point's time.
                let mut at_point = ys.clone();
                stepper.dense().eval(ts, &mut at_point);
                for mut state in [at_point, ys] {
                    if let Err(ErrorKind::Loops { error, .. }) = system.project(ts, &mut state) {
                        return Err(ErrorKind::Loops { t: ts, error });
                    }
                }
            }
        }
        if manifold {
            y.copy_from_slice(stepper.y());
            if system.project(t, &mut y)? {
                stepper.nudge(&mut Eval::new(system, &mut sol.stats), &y)?;
            }
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

/// Where in the step from `t0` to `t1` the system's manifold is singular
/// ([`OdeSystem::conditioning`] below [`SINGULAR_PIVOT`](crate::loops::SINGULAR_PIVOT)),
/// if anywhere: the conditioning is sampled at the step's ends and five inner points of
/// its dense output, and around the smallest inner sample its minimum is found by
/// golden-section search, so that a singular configuration the mechanism passes through
/// between two steps is not stepped over, and is reported where the conditioning is
/// least (to the dense output's accuracy). Below the threshold at the step's end (a
/// method whose steps shrink as the constraint forces grow), the point is extrapolated
/// from the last two samples: the conditioning touches zero quadratically.
fn singular_point<S: OdeSystem + ?Sized>(
    system: &S,
    dense: &crate::method::stepper::DenseStep,
    t0: f64,
    t1: f64,
) -> Option<f64> {
    const SAMPLES: usize = 7;
    let threshold = crate::loops::SINGULAR_PIVOT;
    let mut y = vec![0.0; system.dim()];
    let mut rho = |t: f64| {
        dense.eval(t, &mut y);
        system.conditioning(&y).unwrap_or(1.0)
    };
    let ts: Vec<f64> = (0..SAMPLES)
        .map(|k| t0 + (t1 - t0) * k as f64 / (SAMPLES - 1) as f64)
        .collect();
    let values: Vec<f64> = ts.iter().map(|&t| rho(t)).collect();
    let (k, &least) = values
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.total_cmp(b.1))?;
    if k == 0 || (k == SAMPLES - 1 && least >= threshold) {
        return (!(least >= threshold)).then_some(ts[k]);
    }
    if k == SAMPLES - 1 {
        // Below the threshold at the step's end, still falling: the conditioning
        // touches zero quadratically, so its square root falls linearly to the point.
        let (r0, r1) = (values[k - 1].max(0.0).sqrt(), least.max(0.0).sqrt());
        if r0 > r1 {
            return Some(t1 + r1 * (t1 - ts[k - 1]) / (r0 - r1));
        }
        return Some(t1);
    }
    // Golden-section search for the minimum in the bracket around the smallest sample:
    // the singular point is where the conditioning touches zero.
    let ratio = (5f64.sqrt() - 1.0) / 2.0;
    let (mut a, mut b) = (ts[k - 1], ts[k + 1]);
    let mut c = b - ratio * (b - a);
    let mut d = a + ratio * (b - a);
    let (mut fc, mut fd) = (rho(c), rho(d));
    for _ in 0..80 {
        if b - a <= 4.0 * f64::EPSILON * b.abs().max(1.0) {
            break;
        }
        if fc < fd {
            (b, d, fd) = (d, c, fc);
            c = b - ratio * (b - a);
            fc = rho(c);
        } else {
            (a, c, fc) = (c, d, fd);
            d = a + ratio * (b - a);
            fd = rho(d);
        }
    }
    let (t_min, f_min) = if fc < fd { (c, fc) } else { (d, fd) };
    (!(f_min.min(least) >= threshold)).then_some(t_min)
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
