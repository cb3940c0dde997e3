//! Event location for the Lie-group integrators ([`Rkmk5`](super::Rkmk5),
//! [`LieSdirk`](super::LieSdirk)): `solve_with_events`.
//!
//! An event is a scalar function `g(t, y)` of the time and the [`LieState`]. After each
//! accepted step from `t₀` to `t₁` the integrator evaluates `g(t₁, y₁)`; when the sign
//! changed from the last accepted point (strictly: `g(t₀) > 0 ≥ g(t₁)` is a falling
//! crossing, `g(t₀) < 0 ≤ g(t₁)` a rising one) in the event's [`EventDirection`], the
//! crossing is located on the step's dense output ([`LieTrajectory::at`], on the group)
//! by the Anderson–Björck bracketing method of
//! [`numerics::rootfind`](crate::numerics::rootfind) to
//! `|Δt| ≤ 1e-12 · max(1, |t₁|)`. The reported time is the end of the final bracket
//! on the crossed side (where the sign has changed, or `g = 0`).
//!
//! * A value of exactly zero at the start does not count; the function must leave zero
//!   and come back.
//! * Two crossings of one function inside one step cancel and are not seen (as in every
//!   step-end sign test); limit the step with [`Options::h_max`](crate::Options::h_max)
//!   if events may be closer together than the steps.
//! * A **terminal** event ends the integration at the first terminal crossing: the
//!   trajectory's last point becomes the event state (the last interval keeps the
//!   step's interpolant, so [`LieTrajectory::at`] stays exact up to there), and events
//!   after it in the same step are dropped.
//!
//! Located events are counted in [`Stats::events`](crate::Stats::events).

use super::trajectory::{LieProblem, LieRun, LieTrajectory};
use super::{LieState, LieSystem};
use crate::ErrorKind;
use crate::numerics::rootfind::find_root;

/// Which sign changes of an event function count.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum EventDirection {
    /// Both directions.
    #[default]
    Either,
    /// From negative to non-negative.
    Rising,
    /// From positive to non-positive.
    Falling,
}

/// An event function `g(t, y)` for `solve_with_events` (see the
/// [module documentation](self)).
#[derive(Clone, Copy)]
pub struct LieEvent<'a> {
    pub function: &'a dyn Fn(f64, &LieState) -> f64,
    /// End the integration at the first crossing.
    pub terminal: bool,
    pub direction: EventDirection,
}

impl<'a> LieEvent<'a> {
    /// A non-terminal event in both directions.
    pub fn new(function: &'a dyn Fn(f64, &LieState) -> f64) -> Self {
        LieEvent {
            function,
            terminal: false,
            direction: EventDirection::Either,
        }
    }

    /// The same event, terminal.
    pub fn terminal(self) -> Self {
        LieEvent {
            terminal: true,
            ..self
        }
    }

    /// The same event, counting only crossings in `direction`.
    pub fn direction(self, direction: EventDirection) -> Self {
        LieEvent { direction, ..self }
    }
}

impl std::fmt::Debug for LieEvent<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LieEvent")
            .field("terminal", &self.terminal)
            .field("direction", &self.direction)
            .finish_non_exhaustive()
    }
}

/// A located event.
#[derive(Clone, Debug, PartialEq)]
pub struct LieEventHit {
    /// Index of the event in the slice passed to `solve_with_events`.
    pub event: usize,
    /// The time of the crossing.
    pub t: f64,
    /// The state there (from the dense output).
    pub state: LieState,
}

/// The event functions' values at the last accepted point and the events found.
pub(super) struct EventTracker<'e, 'a> {
    events: &'e [LieEvent<'a>],
    values: Vec<f64>,
    hits: Vec<LieEventHit>,
}

impl<'e, 'a> EventTracker<'e, 'a> {
    /// Evaluates the functions at the initial point; a NaN there is invalid input.
    pub(super) fn new(events: &'e [LieEvent<'a>], problem: &LieProblem) -> Result<Self, String> {
        let values: Vec<f64> = events
            .iter()
            .map(|e| (e.function)(problem.t0, &problem.y0))
            .collect();
        if let Some(k) = values.iter().position(|g| g.is_nan()) {
            return Err(format!("event {k} is NaN at the initial point"));
        }
        Ok(EventTracker {
            events,
            values,
            hits: Vec::new(),
        })
    }

    pub(super) fn into_hits(self) -> Vec<LieEventHit> {
        self.hits
    }

    /// Checks the step ending at the trajectory's last point (there are at least two
    /// points); `Ok(true)` when a terminal event cut the trajectory there.
    pub(super) fn after_step<S: LieSystem + ?Sized>(
        &mut self,
        run: &mut LieRun<'_, S>,
    ) -> Result<bool, ErrorKind> {
        let traj = &run.traj;
        let n = traj.len();
        let (t0, t1) = (traj.times()[n - 2], traj.times()[n - 1]);
        let y1 = traj.state(n - 1);
        let xtol = 1e-12 * t1.abs().max(1.0);
        let mut found: Vec<(usize, f64)> = Vec::new();
        for (k, event) in self.events.iter().enumerate() {
            let (a, b) = (self.values[k], (event.function)(t1, &y1));
            self.values[k] = b;
            let falling = a > 0.0 && b <= 0.0;
            let rising = a < 0.0 && b >= 0.0;
            let counts = match event.direction {
                EventDirection::Either => falling || rising,
                EventDirection::Rising => rising,
                EventDirection::Falling => falling,
            };
            if !counts {
                continue;
            }
            // find_root wants g(lo) > 0 ≥ g(hi).
            let sign = if falling { 1.0 } else { -1.0 };
            let g = |t: f64| sign * (event.function)(t, &dense(traj, t));
            let bracket = find_root(g, t0, t1, sign * a, sign * b, xtol);
            found.push((k, bracket.hi));
        }
        if found.is_empty() {
            return Ok(false);
        }
        found.sort_by(|x, y| x.1.total_cmp(&y.1));
        let stop = found
            .iter()
            .find(|&&(k, _)| self.events[k].terminal)
            .map(|&(_, t)| t);
        for &(k, t) in &found {
            if stop.is_some_and(|ts| t > ts) {
                break;
            }
            self.hits.push(LieEventHit {
                event: k,
                t,
                state: dense(traj, t),
            });
        }
        run.traj.flat.stats.events = self.hits.len();
        let Some(ts) = stop else {
            return Ok(false);
        };
        let state = dense(&run.traj, ts);
        let mut f = vec![0.0; state.velocity.len()];
        run.rhs(ts, &state, &mut f)?;
        run.traj.truncate_last(ts, &state, &f);
        Ok(true)
    }
}

/// The dense output at `t` inside the trajectory's span.
fn dense(traj: &LieTrajectory, t: f64) -> LieState {
    traj.at(t)
        .expect("event times lie inside the last step, which the trajectory covers")
}

#[cfg(test)]
mod tests;
