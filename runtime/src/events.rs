//! User events, one mechanism for every driver: a scalar function `g(t, y)` of the time
//! and the state whose sign changes are located and recorded, and, for a terminal event,
//! end the run. Smooth runs ([`solve_with_events`](crate::solve_with_events)),
//! non-smooth runs ([`Integrator::with_events`](crate::nonsmooth::Integrator::with_events),
//! event-driven and time-stepping) and Lie-group runs (`solve_with_events` of
//! [`Rkmk5`](crate::Rkmk5) and [`LieSdirk`](crate::LieSdirk), whose state `y` is a
//! [`LieState`](crate::LieState)) all use [`Event`] and [`EventHit`].
//!
//! After each accepted step from `t₀` to `t₁` the driver evaluates `g(t₁, y₁)`; when the
//! sign changed from the last accepted point (strictly: `g(t₀) > 0 ≥ g(t₁)` is a falling
//! crossing, `g(t₀) < 0 ≤ g(t₁)` a rising one) in the event's [`EventDirection`], the
//! crossing is located on the step's continuous extension by the Anderson–Björck
//! bracketing method of [`numerics::rootfind`](crate::numerics::rootfind) to
//! `|Δt| ≤ 1e-12 · max(1, |t₁|)`. The reported time is the end of the final bracket on
//! the crossed side (where the sign has changed, or `g = 0`).
//!
//! * A value of exactly zero at the start does not count; the function must leave zero
//!   and come back.
//! * Two crossings of one function inside one step cancel and are not seen (as in every
//!   step-end sign test); limit the step with [`Options::h_max`](crate::Options::h_max)
//!   if events may be closer together than the steps.
//! * A state that jumps (an impact, a mode switch that changes velocities) is a crossing
//!   at the jump's time when `g` changes sign across it.
//! * A **terminal** event ends the run at the first terminal crossing: the last row is
//!   the state there, and crossings after it in the same step are dropped.
//! * An event with a **reset** changes the state at each crossing (a user-written impact,
//!   a kick, a re-initialisation): the step is cut there, the row before the reset and
//!   the row after it are both kept at the crossing's time, and the run goes on from the
//!   new state as from any discontinuity (the method restarts; a non-smooth run selects
//!   its modes again, and an impact that the new state makes is applied; time-stepping
//!   ends its step at the crossing, on the cubic below, and steps on from the new state).
//!   Crossings after it in the same step are dropped; the functions are evaluated afresh
//!   at the new state, so the reset itself is not a crossing. A reset that leaves a rigid
//!   stop penetrated is [`InconsistentInitialData`](crate::ErrorKind::InconsistentInitialData).
//!   A Lie-group run keeps the two points at the crossing's time and begins again from
//!   the new state (its quaternions re-normalised).
//! * Time-stepping has no continuous extension of its own: between two steps the
//!   positions are the cubic through both ends' positions and velocities, the velocities
//!   the line between them (exact where the motion is, under a constant force with
//!   θ = ½ for instance).
//!
//! Located events are counted in [`Stats::events`](crate::Stats::events) of smooth and
//! Lie-group runs (non-smooth runs count their switches there) and listed in the order of
//! their times.

use std::borrow::Borrow;

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

/// An event function `g(t, y)` (see the [module documentation](self)); `Y` is the state
/// type of the run: `[f64]` (`[q; v]` for mechanisms) or a Lie-group state.
///
/// The function and the reset are `Sync` (closures are, unless they capture a `Cell` or
/// an `Rc`), so that a run with events can move to another thread.
pub struct Event<'a, Y: ?Sized = [f64]> {
    pub function: &'a (dyn Fn(f64, &Y) -> f64 + Sync),
    /// End the run at the first crossing.
    pub terminal: bool,
    pub direction: EventDirection,
    /// Change the state at each crossing, `reset(t, y)` in place, and go on from the new
    /// state (see the [module documentation](self)).
    pub reset: Option<&'a Reset<Y>>,
}

/// A reset: changes the state `y` at the crossing's time `t`, in place.
pub type Reset<Y> = dyn Fn(f64, &mut Y) + Sync;

impl<Y: ?Sized> Clone for Event<'_, Y> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<Y: ?Sized> Copy for Event<'_, Y> {}

impl<'a, Y: ?Sized> Event<'a, Y> {
    /// A non-terminal event in both directions.
    pub fn new(function: &'a (dyn Fn(f64, &Y) -> f64 + Sync)) -> Self {
        Event {
            function,
            terminal: false,
            direction: EventDirection::Either,
            reset: None,
        }
    }

    /// The same event, changing the state at each crossing with `reset(t, y)` (in place)
    /// and going on from there.
    pub fn reset(self, reset: &'a Reset<Y>) -> Self {
        Event {
            reset: Some(reset),
            ..self
        }
    }

    /// The same event, terminal.
    pub fn terminal(self) -> Self {
        Event {
            terminal: true,
            ..self
        }
    }

    /// The same event, counting only crossings in `direction`.
    pub fn direction(self, direction: EventDirection) -> Self {
        Event { direction, ..self }
    }
}

impl<Y: ?Sized> std::fmt::Debug for Event<'_, Y> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Event")
            .field("terminal", &self.terminal)
            .field("direction", &self.direction)
            .field("reset", &self.reset.is_some())
            .finish_non_exhaustive()
    }
}

/// A located event.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct EventHit<S = Vec<f64>> {
    /// Index of the event in the slice the run was given.
    pub event: usize,
    /// The time of the crossing.
    pub t: f64,
    /// The state there.
    pub state: S,
}

/// The event functions' values at the last accepted point.
pub(crate) struct Tracker<'e, 'a, Y: ?Sized> {
    events: &'e [Event<'a, Y>],
    values: Vec<f64>,
}

/// The crossings of one step: `(event, time)` in the order of their times, cut after
/// the first one that acts (terminal, or with a reset), and that one.
pub(crate) struct Crossings {
    pub found: Vec<(usize, f64)>,
    /// The first terminal crossing's time, if it is the first that acts.
    pub terminal: Option<f64>,
    /// The first crossing with a reset, `(event, time)`, if it is the first that acts
    /// (an event both terminal and with a reset gives both).
    pub reset: Option<(usize, f64)>,
}

impl<'e, 'a, Y: ?Sized> Tracker<'e, 'a, Y> {
    /// No events.
    pub(crate) fn none() -> Self {
        Tracker {
            events: &[],
            values: Vec::new(),
        }
    }

    /// Evaluates the functions at the initial point; a NaN there is invalid input.
    pub(crate) fn new(events: &'e [Event<'a, Y>], t0: f64, y0: &Y) -> Result<Self, String> {
        let values: Vec<f64> = events.iter().map(|e| (e.function)(t0, y0)).collect();
        if let Some(k) = values.iter().position(|g| g.is_nan()) {
            return Err(format!("event {k} is NaN at the initial point"));
        }
        Ok(Tracker { events, values })
    }

    /// Whether there are any events to track.
    pub(crate) fn is_empty(&self) -> bool {
        self.events.is_empty()
    }

    /// The crossings of the step from the last point to `(t1, y1)`, located on
    /// `state_at`, the step's continuous extension over `[t0, t1]`.
    pub(crate) fn step<O>(
        &mut self,
        t0: f64,
        t1: f64,
        y1: &Y,
        state_at: impl Fn(f64) -> O,
    ) -> Crossings
    where
        O: Borrow<Y>,
    {
        let xtol = 1e-12 * t1.abs().max(1.0);
        let mut found: Vec<(usize, f64)> = Vec::new();
        for (k, event) in self.events.iter().enumerate() {
            let (a, b) = (self.values[k], (event.function)(t1, y1));
            self.values[k] = b;
            let Some(sign) = counts(event.direction, a, b) else {
                continue;
            };
            // find_root wants g(lo) > 0 ≥ g(hi).
            let g = |t: f64| sign * (event.function)(t, state_at(t).borrow());
            let bracket = find_root(g, t0, t1, sign * a, sign * b, xtol);
            found.push((k, bracket.hi));
        }
        self.finish(found)
    }

    /// A jump of the state at `t` to `y` (an impact or a switch): a sign change across it
    /// is a crossing at `t`.
    pub(crate) fn jump(&mut self, t: f64, y: &Y) -> Crossings {
        let mut found = Vec::new();
        for (k, event) in self.events.iter().enumerate() {
            let (a, b) = (self.values[k], (event.function)(t, y));
            self.values[k] = b;
            if counts(event.direction, a, b).is_some() {
                found.push((k, t));
            }
        }
        self.finish(found)
    }

    fn finish(&self, mut found: Vec<(usize, f64)>) -> Crossings {
        found.sort_by(|x, y| x.1.total_cmp(&y.1));
        let acts = |k: usize| self.events[k].terminal || self.events[k].reset.is_some();
        let Some(first) = found.iter().position(|&(k, _)| acts(k)) else {
            return Crossings {
                found,
                terminal: None,
                reset: None,
            };
        };
        found.truncate(first + 1);
        let (k, t) = found[first];
        Crossings {
            found,
            terminal: self.events[k].terminal.then_some(t),
            reset: self.events[k].reset.is_some().then_some((k, t)),
        }
    }

    /// Applies event `k`'s reset to `y` at `t`, and takes the new state as the last
    /// point: the functions are evaluated there afresh (a sign change across the reset
    /// itself is not a crossing). A NaN there is an error naming the event.
    pub(crate) fn apply_reset(&mut self, k: usize, t: f64, y: &mut Y) -> Result<(), String> {
        if let Some(reset) = self.events[k].reset {
            reset(t, y);
        }
        for (j, event) in self.events.iter().enumerate() {
            self.values[j] = (event.function)(t, y);
            if self.values[j].is_nan() {
                return Err(format!(
                    "event {j} is NaN after the reset of event {k} at t = {t}"
                ));
            }
        }
        Ok(())
    }
}

/// `Some(sign)` when `a → b` is a crossing in `direction`: `1` falling, `−1` rising.
fn counts(direction: EventDirection, a: f64, b: f64) -> Option<f64> {
    let falling = a > 0.0 && b <= 0.0;
    let rising = a < 0.0 && b >= 0.0;
    let counted = match direction {
        EventDirection::Either => falling || rising,
        EventDirection::Rising => rising,
        EventDirection::Falling => falling,
    };
    counted.then_some(if falling { 1.0 } else { -1.0 })
}

/// The continuous extension of a time-stepping step from `(t0, q0, v0)` to
/// `(t1, q1, v1)` at `t`, written into `y = [q; v]`: positions on the cubic through both
/// ends' positions and velocities, velocities on the line between them.
pub(crate) fn hermite_qv((t0, y0): (f64, &[f64]), (t1, y1): (f64, &[f64]), t: f64, y: &mut [f64]) {
    let n = y0.len() / 2;
    let h = t1 - t0;
    let s = if h > 0.0 { (t - t0) / h } else { 1.0 };
    let (h00, h10, h01, h11) = (
        (1.0 + 2.0 * s) * (1.0 - s) * (1.0 - s),
        s * (1.0 - s) * (1.0 - s),
        s * s * (3.0 - 2.0 * s),
        s * s * (s - 1.0),
    );
    for i in 0..n {
        y[i] = h00 * y0[i] + h * h10 * y0[n + i] + h01 * y1[i] + h * h11 * y1[n + i];
        y[n + i] = (1.0 - s) * y0[n + i] + s * y1[n + i];
    }
}
