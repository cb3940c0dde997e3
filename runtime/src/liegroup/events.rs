//! User events on Lie-group runs ([`Rkmk5`](super::Rkmk5),
//! [`LieSdirk`](super::LieSdirk)): the shared [`crate::events`] with the
//! [`LieState`] as the state, located on the group's dense output
//! ([`LieTrajectory::at`]). A terminal event cuts the trajectory's last interval at the
//! event (its interpolant kept, so `at` stays exact up to there).

use super::LieState;
use super::LieSystem;
use super::trajectory::{LieProblem, LieRun, LieTrajectory};
use crate::ErrorKind;
pub use crate::events::EventDirection;
use crate::events::{Event, EventHit, Tracker};

/// An event function `g(t, y)` of a Lie-group run.
pub type LieEvent<'a> = Event<'a, LieState>;

/// A located event of a Lie-group run.
pub type LieEventHit = EventHit<LieState>;

/// The shared tracker and the events found, for one Lie-group run.
pub(super) struct EventTracker<'e, 'a> {
    tracker: Tracker<'e, 'a, LieState>,
    hits: Vec<LieEventHit>,
}

impl<'e, 'a> EventTracker<'e, 'a> {
    /// Evaluates the functions at the initial point; a NaN there is invalid input.
    pub(super) fn new(events: &'e [LieEvent<'a>], problem: &LieProblem) -> Result<Self, String> {
        Ok(EventTracker {
            tracker: Tracker::new(events, problem.t0, &problem.y0)?,
            hits: Vec::new(),
        })
    }

    pub(super) fn into_hits(self) -> Vec<LieEventHit> {
        self.hits
    }

    /// Checks the step ending at the trajectory's last point (there are at least two
    /// points). At a terminal event or a reset the trajectory is cut at the crossing;
    /// a reset then gives the new state to begin again from.
    pub(super) fn after_step<S: LieSystem + ?Sized>(
        &mut self,
        run: &mut LieRun<'_, S>,
    ) -> Result<AfterStep, ErrorKind> {
        let traj = &run.traj;
        let n = traj.len();
        let (t0, t1) = (traj.times()[n - 2], traj.times()[n - 1]);
        let y1 = traj.state(n - 1);
        let crossings = self.tracker.step(t0, t1, &y1, |t| dense(traj, t));
        for &(event, t) in &crossings.found {
            self.hits.push(LieEventHit {
                event,
                t,
                state: dense(traj, t),
            });
        }
        run.traj.flat.stats.events = self.hits.len();
        let Some(ts) = crossings.reset.map(|r| r.1).or(crossings.terminal) else {
            return Ok(AfterStep::Go);
        };
        let mut state = dense(&run.traj, ts);
        let mut f = vec![0.0; state.velocity.len()];
        run.rhs(ts, &state, &mut f)?;
        run.traj.truncate_last(ts, &state, &f);
        let Some((k, _)) = crossings.reset else {
            return Ok(AfterStep::End);
        };
        self.tracker
            .apply_reset(k, ts, &mut state)
            .map_err(ErrorKind::InvalidInput)?;
        for q in &mut state.rotations {
            *q = q.normalised();
        }
        Ok(AfterStep::Reset {
            t: ts,
            state,
            end: crossings.terminal.is_some(),
        })
    }
}

/// What the events of a step ask of the run.
pub(super) enum AfterStep {
    /// Nothing but records.
    Go,
    /// A terminal event ended the run.
    End,
    /// A reset at `t` changed the state to `state`; the run ends there when the event
    /// is also terminal (`end`).
    Reset { t: f64, state: LieState, end: bool },
}

/// The dense output at `t` inside the trajectory's span.
fn dense(traj: &LieTrajectory, t: f64) -> LieState {
    traj.at(t)
        .expect("event times lie inside the last step, which the trajectory covers")
}

#[cfg(test)]
mod tests;
