//! The step-level integrator of a non-smooth run: started once, then driven by its
//! caller — a step at a time, up to a time, with an input that the caller sets between
//! calls (a digital controller's zero-order hold). [`solve_nonsmooth`](super::solve_nonsmooth)
//! is this loop run to the end.
//!
//! A controller's loop, for a scene made with `#[derive(Mechanism)]` (the whole program
//! is `examples/controller.rs`; the crate `filippov`'s front page runs a shorter one):
//!
//! ```ignore
//! let mut run = Integrator::held(&scene, &problem, &NonSmoothMethod::default())?;
//! for k in 0..samples {
//!     let u = kp * (target - run.q()[0]) - kd * run.v()[0]; // read the sensors
//!     run.set_input(CartPendulum::input_forces(&SVector::from([u])))?; // hold u
//!     run.advance_to((k + 1) as f64 * 1e-3)?; // to the next sample
//! }
//! let solution = run.into_solution(); // rows, switch log, statistics
//! ```

use nalgebra::SVector;

use super::event::Driver;
use super::timestepping::TimeSteps;
use super::{NonSmoothMethod, NonSmoothProblem};
use crate::element::{Mode, NonSmooth};
use crate::events::{Event, Tracker};
use crate::input::{Held, Input};
use crate::method::{AnyStepper, Stepper};
use crate::solve::{Observer, unobserved};
use crate::{ErrorKind, Solution, SolveError};

/// The input of [`Integrator::held`]: no function, only the held value.
pub type NoInput<const N: usize> = fn(f64, &SVector<f64, N>, &SVector<f64, N>) -> SVector<f64, N>;

fn no_input<const N: usize>(_: f64, _: &SVector<f64, N>, _: &SVector<f64, N>) -> SVector<f64, N> {
    SVector::zeros()
}

/// What one [`Integrator::step`] did.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct Stepped {
    /// The time reached.
    pub t: f64,
    /// Entries added to the switch log ([`Solution::switches`]): switches, impacts,
    /// resets, hand-overs.
    pub switches: usize,
    /// User events located ([`Solution::events`]).
    pub events: usize,
}

/// A non-smooth run in progress (see the module documentation).
///
/// The applied forces are `τ = input(t, q, v) + u`, where `input` is the function given
/// to [`new`](Self::new) and `u` the value last given to
/// [`set_input`](Self::set_input) (zero at first), held until the next call. A new `u`
/// is a discontinuity of the forces: the event-driven method selects the elements'
/// modes again there (a stuck element whose force now passes its limit breaks away) and
/// restarts its smooth method; time-stepping takes it from its next step on.
///
/// Every call keeps what was computed before it: after an error the integrator refuses
/// further steps with the same error, and [`solution`](Self::solution) still holds the
/// run up to it.
pub struct Integrator<'a, S, F, const N: usize>
where
    S: NonSmooth<N>,
    F: Input<N>,
{
    system: &'a S,
    run: Run<'a, S, F, N>,
    tf: f64,
    /// The problem's `tstops` and the index of the next one.
    tstops: Vec<f64>,
    next_stop: usize,
    failed: Option<ErrorKind>,
}

enum Run<'a, S, F, const N: usize> {
    EventDriven {
        driver: Box<Driver<'a, S, Held<F, N>, N>>,
        stepper: AnyStepper,
    },
    TimeStepping {
        steps: TimeSteps<'a, N>,
        input: Held<F, N>,
    },
}

impl<'a, S, const N: usize> Integrator<'a, S, NoInput<N>, N>
where
    S: NonSmooth<N>,
{
    /// An integrator whose forces are only the held value of
    /// [`set_input`](Self::set_input).
    pub fn held(
        system: &'a S,
        problem: &NonSmoothProblem<N>,
        method: &NonSmoothMethod,
    ) -> Result<Self, SolveError> {
        Self::new(system, no_input::<N> as NoInput<N>, problem, method)
    }
}

impl<'a, S, F, const N: usize> Integrator<'a, S, F, N>
where
    S: NonSmooth<N>,
    F: Input<N>,
{
    /// Starts `problem` with `method`: parameters, options and initial state checked,
    /// the consistent modes at `t0` selected (an impact at `t0` applied and logged) and
    /// the first row written. `tf` of the problem is the end of the run; `input(t, q, v)`
    /// gives applied generalised forces (a closure; see [`held`](Self::held) for none).
    pub fn new(
        system: &'a S,
        input: F,
        problem: &NonSmoothProblem<N>,
        method: &NonSmoothMethod,
    ) -> Result<Self, SolveError>
    where
        F: Fn(f64, &SVector<f64, N>, &SVector<f64, N>) -> SVector<f64, N>,
    {
        Self::start(system, input, problem, method)
    }

    /// [`new`](Self::new) for any [`Input`].
    pub(super) fn start(
        system: &'a S,
        input: F,
        problem: &NonSmoothProblem<N>,
        method: &NonSmoothMethod,
    ) -> Result<Self, SolveError> {
        // Parameters first: a non-positive mass or a negative critical force is reported
        // by name before anything is integrated.
        if let Err(e) = crate::element::refuse_contacts::<S, N>()
            .and_then(|()| system.validate().map_err(|e| e.to_string()))
        {
            return Err(SolveError::new(
                ErrorKind::InvalidInput(e),
                Solution::new(
                    crate::element::column_names::<S, N>(system),
                    2 * N,
                    problem.output.clone(),
                )
                .with_dense_positions(Some(N)),
            ));
        }
        let stops_ok = problem.tstops.windows(2).all(|w| w[0] < w[1])
            && problem
                .tstops
                .iter()
                .all(|&t| t.is_finite() && t > problem.t0 && t < problem.tf);
        if !stops_ok {
            return Err(SolveError::new(
                ErrorKind::InvalidInput(format!(
                    "tstops must increase strictly and lie inside (t0, tf) = ({}, {}); got {:?}",
                    problem.t0, problem.tf, problem.tstops
                )),
                Solution::new(
                    crate::element::column_names::<S, N>(system),
                    2 * N,
                    problem.output.clone(),
                ),
            ));
        }
        let input = Held {
            function: input,
            held: SVector::zeros(),
        };
        let run = match *method {
            NonSmoothMethod::EventDriven(method) => {
                let mut stepper = method.stepper(2 * N);
                let options = stepper.options();
                let mut driver = Box::new(Driver::new(system, input, problem, &options)?);
                if let Err(kind) = driver.begin(&mut stepper, problem) {
                    return Err(SolveError::new(kind, driver.out));
                }
                Run::EventDriven { driver, stepper }
            }
            NonSmoothMethod::TimeStepping { h, theta } => Run::TimeStepping {
                steps: TimeSteps::new(system, &input, problem, h, theta)?,
                input,
            },
        };
        Ok(Integrator {
            system,
            run,
            tf: problem.tf,
            tstops: problem.tstops.clone(),
            next_stop: 0,
            failed: None,
        })
    }

    /// The same run locating user [`Event`]s of `(t, [q; v])` from here on (see
    /// [`crate::events`]): each crossing is added to the solution's
    /// [`events`](Solution::events), a terminal one ends the run there
    /// ([`ended`](Self::ended)), and one with a reset changes the state there and the run
    /// goes on from the new state. A function that is NaN at the current point is
    /// [`ErrorKind::InvalidInput`].
    pub fn with_events(mut self, events: &'a [Event<'a>]) -> Result<Self, SolveError> {
        let y: Vec<f64> = self.q().iter().chain(self.v().iter()).copied().collect();
        let tracker = match Tracker::new(events, self.t(), &y[..]) {
            Ok(tracker) => tracker,
            Err(msg) => {
                return Err(SolveError::new(
                    ErrorKind::InvalidInput(msg),
                    self.into_solution(),
                ));
            }
        };
        match &mut self.run {
            Run::EventDriven { driver, .. } => driver.tracker = tracker,
            Run::TimeStepping { steps, .. } => steps.tracker = tracker,
        }
        Ok(self)
    }

    /// The time a terminal user event ended the run at, if one did: the run goes no
    /// further.
    pub fn ended(&self) -> Option<f64> {
        match &self.run {
            Run::EventDriven { driver, .. } => driver.ended,
            Run::TimeStepping { steps, .. } => steps.ended,
        }
    }

    /// The time reached.
    pub fn t(&self) -> f64 {
        match &self.run {
            Run::EventDriven { driver, .. } => driver.t,
            Run::TimeStepping { steps, .. } => steps.t,
        }
    }

    /// The end of the run (the problem's `tf`).
    pub fn tf(&self) -> f64 {
        self.tf
    }

    /// The positions at [`t`](Self::t).
    pub fn q(&self) -> SVector<f64, N> {
        match &self.run {
            Run::EventDriven { driver, .. } => driver.q,
            Run::TimeStepping { steps, .. } => SVector::from_column_slice(&steps.state()[..N]),
        }
    }

    /// The velocities at [`t`](Self::t).
    pub fn v(&self) -> SVector<f64, N> {
        match &self.run {
            Run::EventDriven { driver, .. } => driver.v,
            Run::TimeStepping { steps, .. } => SVector::from_column_slice(&steps.state()[N..2 * N]),
        }
    }

    /// The elements' modes at [`t`](Self::t), in the scene's order: the event-driven
    /// method's current modes; time-stepping's from its last step (`None` before the
    /// first).
    pub fn modes(&self) -> Vec<Option<Mode>> {
        match &self.run {
            Run::EventDriven { driver, .. } => driver.modes.iter().copied().map(Some).collect(),
            Run::TimeStepping { steps, .. } => steps.modes.clone(),
        }
    }

    /// The value held by [`set_input`](Self::set_input).
    pub fn input(&self) -> SVector<f64, N> {
        match &self.run {
            Run::EventDriven { driver, .. } => driver.input.held,
            Run::TimeStepping { input, .. } => input.held,
        }
    }

    /// The run so far: rows, switch log and statistics.
    pub fn solution(&self) -> &Solution {
        match &self.run {
            Run::EventDriven { driver, .. } => &driver.out,
            Run::TimeStepping { steps, .. } => &steps.traj,
        }
    }

    /// The run so far, taken.
    pub fn into_solution(self) -> Solution {
        match self.run {
            Run::EventDriven { driver, .. } => driver.out,
            Run::TimeStepping { steps, .. } => steps.traj,
        }
    }

    /// Holds `u` (generalised forces added to the input function's) from now on. A
    /// value that differs from the held one is a discontinuity of the forces (see the
    /// type's documentation); errors: a non-finite `u` ([`ErrorKind::InvalidInput`],
    /// naming the coordinate), or no consistent mode under the new forces
    /// ([`ErrorKind::IllPosedMode`]).
    pub fn set_input(&mut self, u: SVector<f64, N>) -> Result<(), ErrorKind> {
        self.check()?;
        if let Some(c) = u.iter().position(|x| !x.is_finite()) {
            let names = crate::element::column_names::<S, N>(self.system);
            let name = names[c].strip_prefix("q_").unwrap_or(&names[c]).to_string();
            return Err(ErrorKind::InvalidInput(format!(
                "the input on coordinate `{name}` is {} (it must be finite)",
                u[c]
            )));
        }
        if u == self.input() {
            return Ok(());
        }
        let result = match &mut self.run {
            Run::EventDriven { driver, stepper } => {
                driver.input.held = u;
                driver.input_changed(stepper)
            }
            Run::TimeStepping { input, .. } => {
                input.held = u;
                Ok(())
            }
        };
        self.keep(result)
    }

    /// One step towards `tf`: an accepted step of the smooth method, or a step cut at
    /// an event with the switch there (event-driven), or one step of size `h`
    /// (time-stepping). Nothing is done at `tf`. Says what the step did: the time
    /// reached, and how many switch-log entries and user events it added.
    pub fn step(&mut self) -> Result<Stepped, ErrorKind> {
        let sol = self.solution();
        let (switches, events) = (sol.switches.len(), sol.events.len());
        self.step_observed(self.tf, &mut unobserved)?;
        let sol = self.solution();
        Ok(Stepped {
            t: self.t(),
            switches: sol.switches.len() - switches,
            events: sol.events.len() - events,
        })
    }

    /// Integrates up to exactly `t` (`t ≤ tf`; the last step ends there). A row is
    /// written at `t`, and the state there is [`q`](Self::q), [`v`](Self::v).
    ///
    /// A terminal user event ends the run on the way: `advance_to` returns `Ok` at the
    /// event's time ([`t`](Self::t), [`ended`](Self::ended)), and asking for a later
    /// time afterwards is [`ErrorKind::InvalidInput`].
    pub fn advance_to(&mut self, t: f64) -> Result<(), ErrorKind> {
        self.check()?;
        if let Some(te) = self.ended()
            && t > te
        {
            return Err(ErrorKind::InvalidInput(format!(
                "advance_to({t}): the run ended at t = {te}, at a terminal event"
            )));
        }
        if !(t.is_finite() && t >= self.t() && t <= self.tf) {
            return Err(ErrorKind::InvalidInput(format!(
                "advance_to({t}): the time must lie between the time reached, {}, and the \
                 end of the run, tf = {}",
                self.t(),
                self.tf
            )));
        }
        while self.t() < t && self.ended().is_none() {
            self.step_observed(t, &mut unobserved)?;
        }
        Ok(())
    }

    /// One step towards `t_stop`, the observer called after it.
    pub(super) fn step_observed<O: Observer + ?Sized>(
        &mut self,
        t_stop: f64,
        observer: &mut O,
    ) -> Result<(), ErrorKind> {
        self.check()?;
        if self.t() >= t_stop || self.ended().is_some() {
            return Ok(());
        }
        let stop = self
            .tstops
            .get(self.next_stop)
            .copied()
            .filter(|&s| s <= t_stop);
        let t_stop = stop.unwrap_or(t_stop);
        // Up to a tstop the input is read just before it (the interval's own input).
        let until = stop.map_or(f64::INFINITY, f64::next_down);
        let result = match &mut self.run {
            Run::EventDriven { driver, stepper } => {
                driver.until = until;
                driver.advance(stepper, t_stop, observer).and_then(|()| {
                    if Some(driver.t) == stop {
                        driver.input_changed(stepper)
                    } else {
                        Ok(())
                    }
                })
            }
            Run::TimeStepping { steps, input } => {
                steps.until = until;
                steps.step(self.system, input, t_stop).and_then(|()| {
                    if observer.observe(steps.t, steps.state()).is_break() {
                        Err(ErrorKind::Cancelled { t: steps.t })
                    } else {
                        Ok(())
                    }
                })
            }
        };
        if stop.is_some_and(|s| self.t() >= s) {
            self.next_stop += 1;
        }
        self.keep(result)
    }

    /// The error an earlier call ended with.
    fn check(&self) -> Result<(), ErrorKind> {
        match &self.failed {
            Some(kind) => Err(kind.clone()),
            None => Ok(()),
        }
    }

    /// Remembers an error: the run cannot go on from a state half through a step.
    fn keep(&mut self, result: Result<(), ErrorKind>) -> Result<(), ErrorKind> {
        if let Err(kind) = &result {
            self.failed = Some(kind.clone());
        }
        result
    }
}
