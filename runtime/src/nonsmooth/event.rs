//! Event-driven integration of mechanisms with non-smooth elements on joint
//! coordinates (theory.md §1, §3).
//!
//! Design:
//!
//! * **Modes.** Every element is in one [`Mode`]; inside a mode assignment the
//!   dynamics are a smooth ODE in `(q, v)` ([`mode`](super::mode): slip forces as
//!   functions of the velocity, stuck/contact forces from the Delassus system, the
//!   constrained coordinates frozen exactly: their derivatives are `0.0`, so `q_c` and
//!   `v_c = 0.0` do not move by a single bit).
//! * **Between switches** one [`Stepper`] (DOPRI5 for non-stiff problems, SDIRK4 or BDF
//!   for stiff ones) integrates that ODE step by step; at a switch it is restarted at the
//!   new state, keeping its step size and Jacobian (BDF drops its history).
//! * **Events.** Each element has a switching function, positive while its mode holds
//!   (stick: `f_crit − |f|`; slip: `±v_c`; free stop: gap; contact: `λ`; compressed:
//!   penetration). Inside every accepted step the functions are sampled on the method's
//!   dense output ([`DenseStep`]) at [`SAMPLES`] points; a sign change is located by the
//!   Anderson–Björck root finder ([`rootfind`](crate::numerics::rootfind)) to `TIME_TOL`
//!   relative in time (or `rtol / 100` where that is tighter), the step is cut there
//!   (its dense output restricted to the part before the event) and the integration
//!   restarts exactly at the first time past the root.
//! * **Transitions.** At the event the switching elements are updated (a slipping
//!   velocity that reached zero is set to `0.0`; a rigid stop applies Newton's impact law
//!   `v⁺_c = −e v⁻_c` through the generalised impulse `−M⁻¹ e_c P`; a spring-backed stop
//!   toggles free/compressed, or, resting on a stiff support (`resting`), is re-anchored
//!   at its static compression or lifts off) and the modes of all elements at rest on a switching
//!   surface (dash-pots with `v_c = 0`, rigid stops closed at rest) are *selected*:
//!   every combination of their candidate modes is evaluated and the unique consistent
//!   one is taken ([`mode::select`](super::mode)), otherwise
//!   [`ErrorKind::IllPosedMode`]. The old mode of an element whose switching function
//!   fired is not a candidate.
//! * **Initialisation** selects the initial modes the same way; a state that penetrates
//!   a rigid stop or a given stuck force with `|f| > f_crit` is
//!   [`ErrorKind::InconsistentInitialData`]. Given forces (`forces0`) are checked
//!   against the bounds; where the state determines the force (always, for independent
//!   constraints) the determined value is what the trajectory shows.
//! * **Accumulating events.** If event gaps shrink geometrically ([`ZENO_GEOMETRIC`]
//!   gaps each at most [`ZENO_RATIO`] times the previous, the last below [`ZENO_SPAN`]
//!   of the integration interval: a Zeno point) or
//!   [`ZENO_EVENTS`] events fall in a span shorter than [`ZENO_SPAN`] of the
//!   integration interval (chattering), the span is counted in
//!   [`Stats::zeno_detected`], handed to [`time_stepping`] (θ = 1, [`HANDOVER_STEPS`]
//!   fixed steps over three times the extrapolated remaining Zeno time, or twice the
//!   cluster's duration), counted in [`Stats::zeno_handovers`], and the event-driven
//!   integration resumes from its final state with a fresh consistent initialisation.
//!   A run of rebounds of one rigid stop and nothing else (up to [`MAX_BOUNCES`]) is not
//!   handed over: once a rebound would stay within the position tolerance, the stop
//!   settles into contact and the switch log gives the bounces' accumulation time,
//!   computed in closed form ([`Switch::accumulation`]).
//!
//! Statistics: `steps`, `rejected_steps`, `rhs_evaluations`, … count every step,
//! including the part of a step past an event (it was paid for), plus the
//! time-stepping of handed-over spans; `events` counts switching instants,
//! `mode_changes` element mode changes (also on resuming after a handover).
//!
//! The [`Solution`] has the columns `q_<joint>`, `v_<joint>` and `f_<element>`; at every
//! event two rows share the event time (before and after the switch), so jumps show in
//! plots. Between the rows it is the method's dense output (forces linear), and its
//! [`switches`](Solution::switches) log every mode change, impact and hand-over.
//!
//! **Non-monotone laws** (theory.md §3, 4.9b). The increasing pieces of `v = φ(f)`
//! between its folds are *branches* ([`Graph::branches`]); a slip mode carries its
//! branch, and while slipping the force is the inverse of `φ` on that branch
//! (safeguarded Newton inside the branch's force interval, bracketed by the folds).
//! Just past the branch's end the force continues along the law's piece up to its fold
//! and is held at the fold force beyond, so the right-hand side stays continuous for the
//! stages and the root finder, and smooth across approach 2's cut at the plateau speed.
//! A fold itself is a square-root singularity of the force in the velocity: a step that
//! straddles one is taken again to land short of it and straddle from closer by
//! ([`FOLD_LANDING`], [`FOLD_REFINEMENTS`]; theory.md §3). The switching function is the
//! distance of `|v_c|` to the nearer end of the branch's velocity range, exactly. A
//! branch entered at its end, as when leaving a plateau, departs from it only
//! quadratically in time (and at a fold the first steps can swing back past it by more
//! than the tolerance): its function arms only once the speed is the integrator's
//! accuracy inside the range ([`arming_distance`](mode::arming_distance)), and until
//! then a dip back past the end while the acceleration points into the range is no
//! event.
//!
//! * Approach 1 ([`Selection::NoVelocityJumps`]): at a fold's velocity the force jumps
//!   to the next branch at the same velocity (hysteresis: inner → outer at `v_max`,
//!   outer → inner at `v_min`); `v` is continuous bit for bit.
//! * Approach 2 ([`Selection::MaximalDissipation`]): the branches the envelope
//!   `ψ(f) = inf_{g ≥ f} φ(g)` touches, joined by *plateau* modes
//!   ([`Mode::PlateauPos`]/[`Mode::PlateauNeg`]): `v_c = ±v_min` exactly, the force from
//!   the Delassus system like a stuck element's, switching when it leaves the interval
//!   between the two branch forces at `v_min`. At `|v_c| = v_min` the branch below, the
//!   plateau and the branch above are selected among like the modes at rest.
//!
//! Impacts: Newton's law on every rigid stop closed at the impact instant at once (the
//! impacting one, the others approaching or in contact), as the time-stepper applies it.
//!
//! Not supported: two constrained elements on one coordinate (their Delassus matrix is
//! singular), non-monotone laws whose folds do not alternate maximum, minimum, … ending
//! with a minimum ([`ErrorKind::InvalidInput`]).

use std::collections::VecDeque;

use nalgebra::{DMatrix, DVector, SVector};

use super::NonSmoothProblem;
use super::law::{Branches, Graph};
use super::mode::{self, Choices};
use super::timestepping::time_stepping_observed;
use crate::Method;
use crate::element::{Element, ElementKind, Law, Mode, NonSmooth, Selection, Side, StopKind};
use crate::events::{Crossings, EventHit, Tracker, hermite_qv};
use crate::input::{Capped, Input};
use crate::method::{Begin, DenseStep, Eval, Stepper};
use crate::numerics::factor;
use crate::numerics::rootfind::find_root;
use crate::solve::{Observer, unobserved};
use crate::{ErrorKind, Keep, OdeSystem, Options, Solution, SolveError, Stats, Switch, SwitchKind};
use resting::{Pressed, Support};
/// Samples of the switching functions per accepted step (the last at the step's end).
pub const SAMPLES: usize = 4;
/// Relative width in time of a located event bracket, or `rtol / 100` where that is
/// tighter (an event time needs to be no better than the state's tolerance allows, and
/// at rtol 1e-12 a bracket of 1e-12 · t would be most of the error).
pub const TIME_TOL: f64 = 1e-12;
/// Chattering: this many events …
pub const ZENO_EVENTS: usize = 50;
/// … within this fraction of `tf − t0`.
pub const ZENO_SPAN: f64 = 1e-3;
/// Zeno: this many consecutive event gaps, each …
pub const ZENO_GEOMETRIC: usize = 10;
/// … at most this fraction of the previous one.
pub const ZENO_RATIO: f64 = 0.9;
/// Fixed steps of the time-stepping that takes over a span of accumulating events.
pub const HANDOVER_STEPS: usize = 200;
/// Rebounds of one rigid stop in a row (and nothing else) that the Zeno test leaves to
/// settle by themselves before it hands them over to time-stepping: at restitution `e`
/// a ball needs about `ln(h₀ / tol) / (2 (1 − e))` of them to fall below the position
/// tolerance (≈ 900 at e = 0.99 from 1 m to 1e-8).
pub const MAX_BOUNCES: usize = 20_000;
/// Approaching a fold of a slip law, the step that straddled it is taken again to land
/// at this fraction of the way to the estimated fold ([`Driver::refine_fold`]).
pub const FOLD_LANDING: f64 = 0.9;
/// At most this many retaken steps per fold.
pub const FOLD_REFINEMENTS: usize = 8;
/// Events at one and the same instant before the mode selection counts as cycling.
const SAME_TIME_EVENTS: usize = 20;

/// Event-driven integration (see the module documentation). `input(t, q, v)` gives the
/// applied generalised forces `τ`.
pub fn event_driven<S, F, const N: usize>(
    system: &S,
    input: &F,
    problem: &NonSmoothProblem<N>,
    method: &Method,
) -> Result<Solution, SolveError>
where
    S: NonSmooth<N>,
    F: Fn(f64, &SVector<f64, N>, &SVector<f64, N>) -> SVector<f64, N>,
{
    event_driven_observed(system, input, problem, method, &mut unobserved)
}

pub(super) fn event_driven_observed<S, F, O, const N: usize>(
    system: &S,
    input: &F,
    problem: &NonSmoothProblem<N>,
    method: &Method,
    observer: &mut O,
) -> Result<Solution, SolveError>
where
    S: NonSmooth<N>,
    F: Fn(f64, &SVector<f64, N>, &SVector<f64, N>) -> SVector<f64, N>,
    O: Observer + ?Sized,
{
    let mut stepper = method.stepper(2 * N);
    let mut driver = Driver::new(system, input, problem, &stepper.options())?;
    let outcome = driver.begin(&mut stepper, problem).and_then(|()| {
        while driver.t < problem.tf {
            driver.advance(&mut stepper, problem.tf, observer)?;
        }
        Ok(())
    });
    match outcome {
        Ok(()) => Ok(driver.out),
        Err(kind) => Err(SolveError::new(kind, driver.out)),
    }
}

/// The ODE of the driver's current modes (a macro rather than a method, so that it
/// borrows only the fields it reads and the statistics stay free to be counted in).
macro_rules! mode_system {
    ($d:expr) => {
        ModeSystem {
            system: $d.system,
            input: &$d.input,
            until: $d.until,
            elements: &$d.elements,
            branches: &$d.branches,
            modes: &$d.modes,
        }
    };
}

/// Where a row of the output comes from.
#[derive(Clone, Copy)]
enum Row<'d> {
    /// The first row of the integration.
    Start,
    /// The end of an accepted step (or of a step cut at an event), with the method's
    /// dense output over it.
    Step {
        dense: Option<&'d DenseStep>,
        keep: Keep,
    },
    /// A second row at the same time (after a switch).
    Jump,
}

/// The switching functions' state along one smooth arc (see [`Driver::scan`]).
struct Arming {
    armed: Vec<bool>,
    /// The value above which each function arms ([`Driver::arm_level`]).
    level: Vec<f64>,
    /// The last sample where each function was seen positive, with its value.
    last_positive: Vec<(f64, f64)>,
}

impl Arming {
    /// Before the first arc.
    fn empty() -> Self {
        Arming {
            armed: Vec::new(),
            level: Vec::new(),
            last_positive: Vec::new(),
        }
    }
}

/// The smooth ODE `(q̇, v̇) = (v, a)` of one mode assignment.
struct ModeSystem<'a, S, I, const N: usize> {
    system: &'a S,
    input: &'a I,
    /// The input is read at `min(t, until)` (see [`Driver::until`]).
    until: f64,
    elements: &'a [Element],
    branches: &'a [Branches],
    modes: &'a [Mode],
}

impl<S, I, const N: usize> OdeSystem for ModeSystem<'_, S, I, N>
where
    S: NonSmooth<N>,
    I: Input<N>,
{
    fn dim(&self) -> usize {
        2 * N
    }

    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        let q = SVector::<f64, N>::from_column_slice(&y[..N]);
        let v = SVector::<f64, N>::from_column_slice(&y[N..]);
        let tau = self.input.forces(t.min(self.until), &q, &v);
        match mode::evaluate(
            self.system,
            self.elements,
            self.branches,
            self.modes,
            &q,
            &v,
            &tau,
        ) {
            Some(ev) => {
                dy[..N].copy_from_slice(v.as_slice());
                dy[N..].copy_from_slice(ev.a.as_slice());
            }
            // Dependent constraints: reported by the smooth method as non-finite.
            None => dy.fill(f64::NAN),
        }
    }

    /// `y = [q; v]`, `q̇ = v` in every mode.
    fn second_order(&self) -> Option<usize> {
        Some(N)
    }

    /// Positions read back with the quintic in `q, q̇, q̈` (see the trait).
    fn dense_positions(&self) -> bool {
        true
    }
}

/// One event-driven integration in progress.
pub(super) struct Driver<'a, S, I, const N: usize> {
    system: &'a S,
    pub(super) input: I,
    elements: Vec<Element>,
    /// Slip branches and plateaus of non-monotone laws (empty for the others).
    branches: Vec<Branches>,
    /// Forces that tell approach-1 elements which branch they are on when the modes are
    /// initialised again after a hand-over.
    hints: Vec<Option<f64>>,
    pub(super) modes: Vec<Mode>,
    pub(super) t: f64,
    pub(super) q: SVector<f64, N>,
    pub(super) v: SVector<f64, N>,
    pub(super) out: Solution,
    /// Times of the recent events, for the Zeno test.
    event_times: VecDeque<f64>,
    /// The rigid stop of the latest run of events that were each one rebound of it and
    /// nothing else, and the run's length (`None` after any other event): a ball bouncing
    /// towards rest. The Zeno test
    /// leaves such a run to [`rebound_invisible`](Self::rebound_invisible), which
    /// settles it at its computed accumulation time, for up to [`MAX_BOUNCES`] events.
    bounces: Option<(usize, usize)>,
    options: Options,
    span: f64,
    /// The end of the run.
    tf: f64,
    /// The switching functions' state along the current arc.
    arming: Arming,
    /// Approaching a fold (see [`refine_fold`](Self::refine_fold)): the time the steps
    /// land on short of it, and the last estimate of when it is reached.
    landing: Option<f64>,
    approach: Option<FoldApproach>,
    /// Scratch for dense-output evaluations.
    buf: Vec<f64>,
    /// The element forces of the last row written.
    last_forces: Vec<f64>,
    /// While a step ends at a time where the input may jump (a `tstop`), the float just
    /// before it: the input is read at `min(t, until)`, so that the step sees the input
    /// of its own interval up to its end (∞ otherwise).
    pub(super) until: f64,
    /// The user events (none unless the integrator was given some).
    pub(super) tracker: Tracker<'a, 'a, [f64]>,
    /// The time a terminal user event ended the run at.
    pub(super) ended: Option<f64>,
}

/// The last estimate of when `element` reaches a fold, and how many times its step has
/// been taken again ([`Driver::refine_fold`]).
#[derive(Clone, Copy)]
struct FoldApproach {
    element: usize,
    t: f64,
    refinements: usize,
}

/// A located event: its time (the first time past the root) and the elements whose
/// switching functions fired.
struct Located {
    t: f64,
    triggered: Vec<usize>,
}

impl<'a, S, I, const N: usize> Driver<'a, S, I, N>
where
    S: NonSmooth<N>,
    I: Input<N>,
{
    /// A driver for `problem` with checked options, time span, initial state and
    /// elements (the first row is written by [`begin`](Self::begin)).
    pub(super) fn new(
        system: &'a S,
        input: I,
        problem: &NonSmoothProblem<N>,
        options: &Options,
    ) -> Result<Self, SolveError> {
        let out = Solution::new(
            crate::element::column_names::<S, N>(system),
            2 * N,
            problem.output.clone(),
        )
        .with_dense_positions(Some(N));
        let elements: Vec<Element> = (0..S::ELEMENTS).map(|e| system.element(e)).collect();
        let mut driver = Driver {
            system,
            input,
            branches: vec![Branches::default(); elements.len()],
            hints: vec![None; elements.len()],
            elements,
            modes: Vec::new(),
            t: problem.t0,
            q: problem.q0,
            v: problem.v0,
            out,
            event_times: VecDeque::new(),
            bounces: None,
            options: *options,
            span: problem.tf - problem.t0,
            tf: problem.tf,
            arming: Arming::empty(),
            landing: None,
            approach: None,
            buf: vec![0.0; 2 * N],
            last_forces: Vec::new(),
            until: f64::INFINITY,
            tracker: Tracker::none(),
            ended: None,
        };
        if let Err(msg) = driver
            .validate(problem)
            .and_then(|()| driver.build_branches())
        {
            driver.out.stats = Stats::default();
            return Err(SolveError::new(ErrorKind::InvalidInput(msg), driver.out));
        }
        Ok(driver)
    }

    /// The applied forces at `(t, q, v)`, read at `min(t, until)`.
    fn tau(&self, t: f64, q: &SVector<f64, N>, v: &SVector<f64, N>) -> SVector<f64, N> {
        self.input.forces(t.min(self.until), q, v)
    }

    fn validate(&self, problem: &NonSmoothProblem<N>) -> Result<(), String> {
        self.options.validate()?;
        crate::element::refuse_contacts::<S, N>()?;
        super::bearing::refuse(self.system)?;
        problem.check_span_and_start(&S::JOINTS)?;
        if !problem.forces0.is_empty() && problem.forces0.len() != self.elements.len() {
            return Err(format!(
                "forces0 has {} entries for {} elements",
                problem.forces0.len(),
                self.elements.len()
            ));
        }
        if let Some(f) = problem.forces0.iter().flatten().find(|f| !f.is_finite()) {
            return Err(format!("initial force {f} is not finite"));
        }
        for el in &self.elements {
            mode::validate_element(el, N)?;
        }
        Ok(())
    }

    /// The branches of the non-monotone laws (their folds located once); every user
    /// law checked finite on its domain ([`Graph::new`]).
    fn build_branches(&mut self) -> Result<(), String> {
        for (e, el) in self.elements.iter().enumerate() {
            match el.kind {
                ElementKind::DashPot {
                    law: Law::BinghamNonMonotone { .. },
                    ..
                } => {
                    self.branches[e] = Graph::new(self.system, e)
                        .and_then(|g| g.branches(self.system))
                        .map_err(|err| err.to_string())?;
                }
                ElementKind::DashPot {
                    law: Law::BinghamMonotone,
                    ..
                } => {
                    Graph::new(self.system, e).map_err(|err| err.to_string())?;
                }
                _ => {}
            }
        }
        Ok(())
    }

    /// The first row and consistent modes at `t0`; the stepper started there.
    pub(super) fn begin<St: Stepper>(
        &mut self,
        stepper: &mut St,
        problem: &NonSmoothProblem<N>,
    ) -> Result<(), ErrorKind> {
        self.initialise(problem, false)?;
        self.rest_supports()?;
        self.start_arc(stepper, true)
    }

    /// One accepted step towards `t_stop` (≤ `tf`), or one step cut at an event and the
    /// switch there; a hand-over to time-stepping ends by `t_stop`.
    pub(super) fn advance<St: Stepper, O: Observer + ?Sized>(
        &mut self,
        stepper: &mut St,
        t_stop: f64,
        observer: &mut O,
    ) -> Result<(), ErrorKind> {
        let mut buf = std::mem::take(&mut self.buf);
        buf.resize(2 * N, 0.0);
        let stepped = self.advance_with(stepper, t_stop, observer, &mut buf);
        self.buf = buf;
        stepped
    }

    fn advance_with<St: Stepper, O: Observer + ?Sized>(
        &mut self,
        stepper: &mut St,
        t_stop: f64,
        observer: &mut O,
        buf: &mut [f64],
    ) -> Result<(), ErrorKind> {
        let tf = self.tf;
        {
            let sys = mode_system!(self);
            // Approaching a fold (see `refine_fold`), the steps land short of it.
            let t_end = self.landing.map_or(t_stop, |t| t.min(t_stop));
            let stepped = stepper.step(&mut Eval::new(&sys, &mut self.out.stats), t_end);
            stepped.map_err(|kind| self.explain(kind))?;
        }
        // Events are located on the step's extension: always needed here.
        stepper.prepare_dense();
        let (t1, y1) = (stepper.t(), stepper.y());
        let mut arming = std::mem::replace(&mut self.arming, Arming::empty());
        let located = self.scan(stepper.dense(), t1, y1, &mut arming, buf);
        self.arming = arming;
        match located {
            None => {
                if let Some(act) = self.user_events(stepper.dense(), t1, y1) {
                    let mut cut = stepper.dense().clone();
                    cut.truncate(act.t);
                    return self.act(act, &cut, buf, stepper);
                }
                let (t1, y1) = (stepper.t(), stepper.y());
                let mut q = SVector::from_column_slice(&y1[..N]);
                let mut v = SVector::from_column_slice(&y1[N..]);
                if self.project(t1, &mut q, &mut v)? {
                    let y: Vec<f64> = q.iter().chain(v.iter()).copied().collect();
                    let sys = mode_system!(self);
                    stepper.nudge(&mut Eval::new(&sys, &mut self.out.stats), &y)?;
                }
                let keep = if t1 >= tf { Keep::Last } else { Keep::AsAsked };
                self.push_row(
                    t1,
                    &q,
                    &v,
                    Row::Step {
                        dense: Some(stepper.dense()),
                        keep,
                    },
                )?;
                self.t = t1;
                self.q = q;
                self.v = v;
                if self.landing.is_some_and(|t| t1 >= t) {
                    self.landing = None;
                }
                if t1 < tf && self.rest_supports()? {
                    self.restart(stepper)?;
                }
            }
            Some(event) => {
                let mut approach = self.approach;
                let refine = self.refine_fold(&event, stepper.dense(), &mut approach, buf);
                self.approach = approach;
                if refine {
                    // The step straddled a fold too far from its start: taken again
                    // from its start, landing short of the estimate, so that the next
                    // step straddles the fold from closer by.
                    self.landing = Some(self.t + FOLD_LANDING * (event.t - self.t));
                } else {
                    (self.landing, self.approach) = (None, None);
                    let mut dense = stepper.dense().clone();
                    dense.truncate(event.t);
                    dense.eval(event.t, buf);
                    if let Some(act) = self.user_events(&dense, event.t, buf) {
                        dense.truncate(act.t);
                        return self.act(act, &dense, buf, stepper);
                    }
                    self.transition(event.t, buf, &event.triggered, &dense)?;
                    if let Some(act) = self.user_jump() {
                        if let Some(k) = act.reset {
                            self.apply_reset(k)?;
                        }
                        if act.terminal {
                            self.ended = Some(self.t);
                            return Ok(());
                        }
                    }
                    if let Some(end) = self.check_accumulation(t_stop)? {
                        self.hand_over(end, observer)?;
                        if self.ended.is_some() {
                            return Ok(());
                        }
                    }
                }
                self.restart(stepper)?;
            }
        }
        if observer.observe(self.t, &self.state()).is_break() {
            return Err(ErrorKind::Cancelled { t: self.t });
        }
        Ok(())
    }

    /// The applied forces changed at the current time (a controller's new sample):
    /// the modes are selected again at the current state, as at a switch (a stuck
    /// element whose holding force now passes its limit breaks away, a stop in contact
    /// whose force would pull opens), their changes logged with a second row at this
    /// time, and the stepper restarts.
    pub(super) fn input_changed<St: Stepper>(&mut self, stepper: &mut St) -> Result<(), ErrorKind> {
        let forces_before = self.last_forces.clone();
        self.until = f64::INFINITY;
        let (t, mut q, mut v) = (self.t, self.q, self.v);
        let old = self.modes.clone();
        let none = vec![None; self.elements.len()];
        self.select_modes(t, &mut q, &mut v, &none, false)?;
        if old != self.modes {
            self.jump_to(q, v, &old, &forces_before)?;
        }
        self.restart(stepper)
    }

    /// The modes changed at the current time from `old` (the row before written, its
    /// element forces `forces_before`): the state `(q, v)` taken, its second row written,
    /// the event counted and each element whose mode changed logged.
    fn jump_to(
        &mut self,
        q: SVector<f64, N>,
        v: SVector<f64, N>,
        old: &[Mode],
        forces_before: &[f64],
    ) -> Result<(), ErrorKind> {
        let t = self.t;
        let before = self.state();
        (self.q, self.v) = (q, v);
        let forces_after = self.push_row(t, &q, &v, Row::Jump)?;
        let after = self.state();
        self.out.stats.events += 1;
        for e in 0..self.elements.len() {
            if old[e] != self.modes[e] {
                self.out.stats.mode_changes += 1;
                let jump = forces_after[e] - forces_before[e];
                self.log(t, SwitchKind::Mode, e, old[e], jump, (&before, &after));
            }
        }
        Ok(())
    }

    /// The user events of the arc from the current point to `(t1, y1)` on `dense`,
    /// recorded; the first that acts (terminal, or with a reset).
    fn user_events(&mut self, dense: &DenseStep, t1: f64, y1: &[f64]) -> Option<Act> {
        if self.tracker.is_empty() {
            return None;
        }
        let at = |t: f64| {
            let mut y = vec![0.0; 2 * N];
            dense.eval(t, &mut y);
            y
        };
        let crossings = self.tracker.step(self.t, t1, y1, at);
        for &(event, t) in &crossings.found {
            self.out.events.push(EventHit {
                event,
                t,
                state: at(t),
            });
        }
        Act::of(&crossings)
    }

    /// The user events crossed by the jump of the state at the switch just applied,
    /// recorded; the first that acts.
    fn user_jump(&mut self) -> Option<Act> {
        if self.tracker.is_empty() {
            return None;
        }
        let state = self.state();
        let crossings = self.tracker.jump(self.t, &state);
        for &(event, t) in &crossings.found {
            self.out.events.push(EventHit {
                event,
                t,
                state: state.clone(),
            });
        }
        Act::of(&crossings)
    }

    /// The user events between two rows of time-stepping (see [`hermite_qv`]),
    /// recorded; the first that acts.
    fn user_events_between(&mut self, a: (f64, &[f64]), b: (f64, &[f64])) -> Option<Act> {
        if self.tracker.is_empty() {
            return None;
        }
        let at = |t: f64| {
            let mut y = vec![0.0; 2 * N];
            hermite_qv(a, b, t, &mut y);
            y
        };
        let crossings = self.tracker.step(a.0, b.0, b.1, at);
        for &(event, t) in &crossings.found {
            self.out.events.push(EventHit {
                event,
                t,
                state: at(t),
            });
        }
        Act::of(&crossings)
    }

    /// Acts on a user event at `act.t` inside the arc whose extension `dense` is cut
    /// there: a terminal event without a reset ends the run; a reset writes the row
    /// before it, changes the state, selects the modes again, and (unless the event is
    /// also terminal) restarts the stepper.
    fn act<St: Stepper>(
        &mut self,
        act: Act,
        dense: &DenseStep,
        buf: &mut [f64],
        stepper: &mut St,
    ) -> Result<(), ErrorKind> {
        let Some(k) = act.reset else {
            return self.end_at(act.t, dense, buf);
        };
        dense.eval(act.t, buf);
        let q = SVector::from_column_slice(&buf[..N]);
        let v = SVector::from_column_slice(&buf[N..2 * N]);
        let row = Row::Step {
            dense: Some(dense),
            keep: Keep::Event,
        };
        self.push_row(act.t, &q, &v, row)?;
        (self.t, self.q, self.v) = (act.t, q, v);
        self.apply_reset(k)?;
        if act.terminal {
            self.ended = Some(act.t);
            return Ok(());
        }
        self.restart(stepper)
    }

    /// Applies user event `k`'s reset to the current state (its row written), then
    /// selects the modes at the new state as at a start (an impact the new state makes
    /// is applied and logged), writes the row after it, and logs the reset and each
    /// other element whose mode changed.
    fn apply_reset(&mut self, k: usize) -> Result<(), ErrorKind> {
        let t = self.t;
        let before = self.state();
        let mut y = before.clone();
        self.tracker
            .apply_reset(k, t, &mut y)
            .map_err(ErrorKind::InvalidInput)?;
        if let Some(component) = y.iter().position(|x| !x.is_finite()) {
            return Err(ErrorKind::NonFinite { t, component });
        }
        let (old, forces_before) = (self.modes.clone(), self.last_forces.clone());
        self.out.switches.push(Switch::of_run(
            t,
            SwitchKind::Reset,
            before.clone(),
            y.clone(),
        ));
        let logged = self.out.switches.len();
        let q = SVector::<f64, N>::from_column_slice(&y[..N]);
        let v = SVector::<f64, N>::from_column_slice(&y[N..2 * N]);
        self.initialise(&NonSmoothProblem::new(t, t, q, v), true)?;
        self.out.stats.events += 1;
        let after = self.state();
        for e in 0..self.elements.len() {
            let entry = self.out.switches[logged..]
                .iter()
                .any(|s| s.index == Some(e));
            if old[e] != self.modes[e] && !entry {
                self.out.stats.mode_changes += 1;
                let jump = self.last_forces[e] - forces_before[e];
                self.log(t, SwitchKind::Mode, e, old[e], jump, (&y, &after));
            }
        }
        Ok(())
    }

    /// Ends the run at a terminal user event at `te`, on the arc's extension `dense`
    /// (cut at `te`).
    fn end_at(&mut self, te: f64, dense: &DenseStep, buf: &mut [f64]) -> Result<(), ErrorKind> {
        dense.eval(te, buf);
        let q = SVector::from_column_slice(&buf[..N]);
        let v = SVector::from_column_slice(&buf[N..2 * N]);
        self.push_row(
            te,
            &q,
            &v,
            Row::Step {
                dense: Some(dense),
                keep: Keep::Last,
            },
        )?;
        (self.t, self.q, self.v) = (te, q, v);
        self.ended = Some(te);
        Ok(())
    }

    /// The stepper started again at the current point (after a switch, or an input
    /// that changed), and the switching functions armed anew.
    pub(super) fn restart<St: Stepper>(&mut self, stepper: &mut St) -> Result<(), ErrorKind> {
        self.start_arc(stepper, false)
    }

    /// A smooth arc from the current point: the stepper started (`fresh`) or restarted
    /// there, the switching functions armed.
    fn start_arc<St: Stepper>(&mut self, stepper: &mut St, fresh: bool) -> Result<(), ErrorKind> {
        let y = self.state();
        {
            let sys = mode_system!(self);
            let ev = &mut Eval::new(&sys, &mut self.out.stats);
            let at = Begin {
                t: self.t,
                y: &y,
                span: self.tf - self.t,
                fresh,
            };
            stepper.begin(ev, at)?;
        }
        self.arming = self.arm(self.t, &y);
        Ok(())
    }

    /// Whether the event just located is an element reaching a fold of its slip law
    /// ([`mode::fold_end`]) inside a step that should be taken again first.
    ///
    /// Where the slip force has its square-root singularity the solution has a
    /// `(t* − t)^{3/2}` term; past the fold the force is continued (clamped), so a step
    /// from `t_a` straddling `t*` fits one polynomial to two different pieces. Its stages
    /// lie mostly past the fold, where the method's error estimate cannot see the
    /// branch's singular term, of size `(t* − t_a)^{3/2}`: the event is located early or
    /// late by far more than the tolerance (147·rtol on S4 approach 1 with DOPRI5), and
    /// every later state inherits that shift. The cure is to straddle from close by: the
    /// step is taken again from `t_a` to land at [`FOLD_LANDING`] of the way to the
    /// estimate, and the fold is located anew from there. This repeats (at most
    /// [`FOLD_REFINEMENTS`] times) until two estimates agree to the velocity tolerance
    /// `atol + rtol·|v_fold|` divided by the rate the speed approaches the fold at, or the
    /// straddling step is itself that short. Each repetition shrinks the distance tenfold
    /// and the singular term some thirtyfold.
    fn refine_fold(
        &self,
        event: &Located,
        dense: &DenseStep,
        approach: &mut Option<FoldApproach>,
        buf: &mut [f64],
    ) -> bool {
        let ta = self.t;
        let d = event.t - ta;
        dense.eval(event.t, buf);
        let fold = event.triggered.iter().find_map(|&e| {
            let (dir, k) = self.modes[e].slip()?;
            let c = self.elements[e].coordinate;
            let w = dir * buf[N + c];
            if !mode::fold_end(&self.branches[e], k, w) {
                return None;
            }
            let end = mode::branch_end(&self.branches[e], k, w);
            Some((e, end, (end - dir * self.v[c]).abs() / d))
        });
        let Some((element, end, rate)) = fold else {
            *approach = None;
            return false;
        };
        let dt_tol = (self.options.atol + self.options.rtol * end.abs()) / rate;
        let refinements = match *approach {
            Some(a) if a.element == element => {
                if (event.t - a.t).abs() <= dt_tol {
                    *approach = None;
                    return false;
                }
                a.refinements
            }
            _ => 0,
        };
        if refinements >= FOLD_REFINEMENTS || !(d > dt_tol) {
            *approach = None;
            return false;
        }
        *approach = Some(FoldApproach {
            element,
            t: event.t,
            refinements: refinements + 1,
        });
        true
    }

    /// A step budget used up while one element switched over and over is reported as
    /// that element switching ([`ErrorKind::KeepsSwitching`]), naming its recent modes.
    fn explain(&self, kind: ErrorKind) -> ErrorKind {
        let ErrorKind::MaxSteps { t } = kind else {
            return kind;
        };
        self.switching_element(t).unwrap_or(kind)
    }

    /// The element behind most of the last switches, if one dominates them.
    fn switching_element(&self, t: f64) -> Option<ErrorKind> {
        const RECENT: usize = 50;
        let recent: Vec<&Switch> = self
            .out
            .switches
            .iter()
            .rev()
            .take(RECENT)
            .filter(|s| s.element.is_some())
            .collect();
        let mut best: Option<(&str, usize)> = None;
        for s in &recent {
            let name = s.element.as_deref().unwrap_or_default();
            let n = recent
                .iter()
                .filter(|r| r.element.as_deref() == Some(name))
                .count();
            if best.is_none_or(|(_, m)| n > m) {
                best = Some((name, n));
            }
        }
        let (element, n) = best?;
        // Ten or more switches of one element within a thousandth of the interval: a
        // long run that merely used up its budget is not reported as switching.
        let times: Vec<f64> = recent
            .iter()
            .filter(|s| s.element.as_deref() == Some(element))
            .map(|s| s.t)
            .collect();
        let spread = times.first()? - times.get(9).or(times.last())?;
        if n < 10 || spread > ZENO_SPAN * self.span {
            return None;
        }
        let mut cycle: Vec<String> = recent
            .iter()
            .filter(|s| s.element.as_deref() == Some(element))
            .take(6)
            .map(|s| match (s.from, s.to) {
                (Some(a), Some(b)) if s.kind == SwitchKind::Mode => format!("{a:?} → {b:?}"),
                _ => format!("{:?}", s.kind),
            })
            .collect();
        cycle.reverse();
        Some(ErrorKind::KeepsSwitching {
            t,
            element: element.to_string(),
            cycle: format!("last switches: {}", cycle.join(", ")),
        })
    }

    /// The current `[q; v]`.
    /// The integrator's accuracy at a component of size `x`: `atol + rtol |x|`.
    /// A closed mechanism's state put back on its loops' constraints (see
    /// [`crate::loops`]), the coordinates of stuck elements and of stops in contact
    /// held where they are (their velocities stay exactly zero). Returns whether it
    /// moved.
    fn project(
        &self,
        t: f64,
        q: &mut SVector<f64, N>,
        v: &mut SVector<f64, N>,
    ) -> Result<bool, ErrorKind> {
        if S::LOOP_CONSTRAINTS.is_empty() {
            return Ok(false);
        }
        let mut held = [false; N];
        for (el, m) in self.elements.iter().zip(&self.modes) {
            if matches!(m, Mode::Stick | Mode::Contact) {
                held[el.coordinate] = true;
            }
        }
        self.system
            .project_onto_loops(q, v, &held)
            .map_err(|error| ErrorKind::Loops { t, error })
    }

    fn tol(&self, x: f64) -> f64 {
        self.options.atol + self.options.rtol * x.abs()
    }

    fn state(&self) -> Vec<f64> {
        self.q.iter().chain(self.v.iter()).copied().collect()
    }

    /// Appends `(q, v, f)` at `t` in the current modes; returns the element forces.
    fn push_row(
        &mut self,
        t: f64,
        q: &SVector<f64, N>,
        v: &SVector<f64, N>,
        row: Row<'_>,
    ) -> Result<Vec<f64>, ErrorKind> {
        let tau = self.tau(t, q, v);
        let ev = mode::evaluate(
            self.system,
            &self.elements,
            &self.branches,
            &self.modes,
            q,
            v,
            &tau,
        )
        .ok_or_else(|| ErrorKind::IllPosedMode {
            t,
            detail: "constraints of the current modes are dependent".into(),
        })?;
        let mut y: Vec<f64> = q.iter().chain(v.iter()).copied().collect();
        y.extend_from_slice(&ev.f);
        if let Row::Step {
            keep: Keep::Event, ..
        } = row
        {
            // The row just before a break-away: the located state has the stuck force at
            // ±f_crit up to the root finder's bracket (|f| may pass the bound by that
            // round-off); the row shows the bound, as a slipping element's row shows
            // v_c = 0 exactly.
            for (e, el) in self.elements.iter().enumerate() {
                if let (ElementKind::DashPot { f_crit, .. }, Mode::Stick) = (el.kind, self.modes[e])
                {
                    y[2 * N + e] = ev.f[e].clamp(-f_crit, f_crit);
                }
            }
        }
        crate::element::push_loop_forces(
            self.system,
            self.elements.iter().map(|el| el.coordinate),
            (q, v, &tau),
            &ev.f,
            &mut y,
        );
        let mut dy: Vec<f64> = v.iter().chain(ev.a.iter()).copied().collect();
        dy.resize(y.len(), 0.0);
        match row {
            Row::Start => self.out.push_start(t, &y, &dy),
            Row::Step { dense, keep } => self.out.push_step(t, &y, &dy, dense, keep),
            Row::Jump => self.out.push_jump(t, &y, &dy),
        }
        self.last_forces.clone_from(&ev.f);
        Ok(ev.f)
    }

    /// The switching functions at the start of a smooth arc: a function is armed when
    /// above its [`arm_level`](Self::arm_level) there.
    fn arm(&self, t: f64, y: &[f64]) -> Arming {
        let g0 = self.switching_all(t, y);
        let level: Vec<f64> = (0..g0.len()).map(|e| self.arm_level(e)).collect();
        Arming {
            armed: g0.iter().zip(&level).map(|(g, l)| g > l).collect(),
            level,
            last_positive: g0
                .iter()
                .map(|g| (t, if *g > 0.0 { *g } else { f64::MIN_POSITIVE }))
                .collect(),
        }
    }

    /// The value element `e`'s switching function must exceed to arm: `0`, except on a
    /// branch of a non-monotone law, where it is the
    /// [`arming_distance`](mode::arming_distance) of the branch's ends: a branch entered
    /// at its end (where its function starts at `0`) stays unarmed while it departs
    /// from it, and a dip back past that end is judged by [`dip`](Self::dip).
    fn arm_level(&self, e: usize) -> f64 {
        match self.modes[e]
            .slip()
            .and_then(|(_, k)| self.branches[e].slip.get(k))
        {
            Some(b) => {
                let tol = (self.options.atol, self.options.rtol);
                mode::arming_distance(b.v_lo, tol).max(mode::arming_distance(b.v_hi, tol))
            }
            None => 0.0,
        }
    }

    /// Whether element `e`, slipping on a branch it entered at an end `≠ 0` (its
    /// function not yet armed) and past that end at `(t, y)`, is only dipping there: its
    /// acceleration still points into the branch's range. Leaving a plateau onto the
    /// outer branch starts at the branch's fold, where the force has its square-root
    /// singularity (the system is locally stiff there), and the first steps can swing
    /// back past the end by more than the tolerance, several times; the exact solution
    /// departs quadratically and never returns unless the load turns, which turns the
    /// acceleration too. (An armed function, reached from inside the range, always
    /// fires: far past the end, in a long step, the acceleration need not point out.)
    fn dip(&self, e: usize, t: f64, y: &[f64]) -> bool {
        let Some((d, k)) = self.modes[e].slip() else {
            return false;
        };
        let c = self.elements[e].coordinate;
        let w = d * y[N + c];
        let Some(b) = self.branches[e].slip.get(k) else {
            return false;
        };
        let below = w < b.v_lo && b.v_lo > 0.0;
        let above = w > b.v_hi;
        if !(below || above) {
            return false;
        }
        match self.evaluate_at(t, y).2 {
            Some(ev) => {
                let into = d * ev.a[c];
                (below && into > 0.0) || (above && into < 0.0)
            }
            None => false,
        }
    }

    /// `y = [q; v]` split, and the dynamics of the current modes at `(t, q, v)` (`None`
    /// where their constraints are dependent).
    fn evaluate_at(
        &self,
        t: f64,
        y: &[f64],
    ) -> (
        SVector<f64, N>,
        SVector<f64, N>,
        Option<mode::Evaluation<N>>,
    ) {
        let q = SVector::<f64, N>::from_column_slice(&y[..N]);
        let v = SVector::<f64, N>::from_column_slice(&y[N..2 * N]);
        let tau = self.tau(t, &q, &v);
        let ev = mode::evaluate(
            self.system,
            &self.elements,
            &self.branches,
            &self.modes,
            &q,
            &v,
            &tau,
        );
        (q, v, ev)
    }

    /// Switching function values of all elements at state `y` (`q, v`) and time `t`.
    fn switching_all(&self, t: f64, y: &[f64]) -> Vec<f64> {
        let (q, v, ev) = self.evaluate_at(t, y);
        match ev {
            Some(ev) => self
                .elements
                .iter()
                .enumerate()
                .map(|(e, el)| {
                    let c = el.coordinate;
                    // A stop in contact with a stuck dash-pot beside it holds until the
                    // load pulls away by more than the dash-pot's critical force.
                    let f = match (el.kind, mode::stuck_partner(&self.elements, &self.modes, e)) {
                        (ElementKind::Stop { side, .. }, Some(p)) => match self.elements[p].kind {
                            ElementKind::DashPot { f_crit, .. } => {
                                ev.f[e] + ev.f[p] + mode::side_sign(side) * f_crit
                            }
                            ElementKind::Stop { .. } => ev.f[e],
                        },
                        _ => ev.f[e],
                    };
                    // A spring-backed stop resting on its support: lift-off, or its held
                    // position off the static compression by the tolerance.
                    if let (Some(support), Mode::Contact) = (Support::of(el), self.modes[e]) {
                        let drift = support.drift_margin(q[c], support.s * ev.f[e], self.tol(q[c]));
                        return (support.s * f).min(drift);
                    }
                    mode::switching(el, &self.branches[e], self.modes[e], q[c], v[c], f)
                })
                .collect(),
            None => vec![f64::NAN; self.elements.len()],
        }
    }

    /// The first event in the accepted step ending at `(t1, y1)` with dense output
    /// `dense`, if any.
    ///
    /// A switching function is *armed* once it has been seen positive in its mode; an
    /// armed function fires when it reaches `≤ 0`, an unarmed one (entered on its
    /// boundary, where it is `0`) when it goes below zero, with the bracket starting at
    /// the step's start.
    fn scan(
        &self,
        dense: &DenseStep,
        t1: f64,
        y1: &[f64],
        arming: &mut Arming,
        buf: &mut [f64],
    ) -> Option<Located> {
        let m = self.elements.len();
        if m == 0 {
            return None;
        }
        let ta = dense.t0();
        let Arming {
            armed,
            level,
            last_positive,
        } = arming;
        for e in 0..m {
            if !armed[e] {
                last_positive[e] = (ta, f64::MIN_POSITIVE);
            }
        }
        for s in 1..=SAMPLES {
            let ts = if s == SAMPLES {
                buf.copy_from_slice(y1);
                t1
            } else {
                let ts = ta + (t1 - ta) * s as f64 / SAMPLES as f64;
                dense.eval(ts, buf);
                ts
            };
            let g = self.switching_all(ts, buf);
            let fired: Vec<usize> = (0..m)
                .filter(|&e| (armed[e] && g[e] <= 0.0) || (g[e] < 0.0 && !self.dip(e, ts, buf)))
                .collect();
            if fired.is_empty() {
                for e in 0..m {
                    if g[e] > 0.0 {
                        armed[e] |= g[e] > level[e];
                        last_positive[e] = (ts, g[e]);
                    }
                }
                continue;
            }
            let xtol = TIME_TOL.min(1e-2 * self.options.rtol) * ts.abs().max(1.0);
            let brackets: Vec<(usize, f64, f64)> = fired
                .iter()
                .map(|&e| {
                    let (a, ga) = last_positive[e];
                    let r = find_root(
                        |t| {
                            dense.eval(t, buf);
                            self.switching_all(t, buf)[e]
                        },
                        a,
                        ts,
                        ga,
                        g[e],
                        xtol,
                    );
                    (e, r.lo, r.hi)
                })
                .collect();
            let t_event = brackets.iter().map(|b| b.2).fold(f64::INFINITY, f64::min);
            let triggered = brackets
                .iter()
                .filter(|b| b.1 < t_event || b.2 == t_event)
                .map(|b| b.0)
                .collect();
            return Some(Located {
                t: t_event,
                triggered,
            });
        }
        None
    }

    /// Applies the transitions of the `triggered` elements at `t` (state `y` before
    /// the switch), selects the new modes, and records both rows.
    fn transition(
        &mut self,
        t: f64,
        y: &[f64],
        triggered: &[usize],
        dense: &DenseStep,
    ) -> Result<(), ErrorKind> {
        let mut q = SVector::<f64, N>::from_column_slice(&y[..N]);
        let mut v = SVector::<f64, N>::from_column_slice(&y[N..2 * N]);
        // A rigid stop reached: the located time is past the root by up to the root
        // finder's bracket, so the velocities lean towards the stop by a·Δt; a rebound
        // would keep that lean, and a series of rebounds at restitution e sums it
        // 1/(1 − e) times over. The velocities are taken at the root, Δt = (q_c −
        // position)/v_c earlier on the step's dense output (the largest Δt when several
        // stops are reached at once), before any element sets its velocity below.
        let rigid_free = |e: usize| match (self.elements[e].kind, self.modes[e]) {
            (
                ElementKind::Stop {
                    kind: StopKind::Rigid { .. },
                    position,
                    ..
                },
                Mode::Free,
            ) => Some((self.elements[e].coordinate, position)),
            _ => None,
        };
        let dt = triggered
            .iter()
            .filter_map(|&e| rigid_free(e))
            .map(|(c, position)| (q[c] - position) / v[c])
            .filter(|dt| dt.is_finite() && *dt > 0.0)
            .fold(0.0, f64::max);
        if dt > 0.0 && t - dt >= dense.t0() {
            let mut at_root = vec![0.0; y.len()];
            dense.eval(t - dt, &mut at_root);
            v.copy_from_slice(&at_root[N..2 * N]);
        }
        // A slipping element's event is its velocity reaching zero (or, on a branch of a
        // non-monotone law, a fold's velocity or approach 2's plateau speed): the located
        // state has it up to the root finder's round-off, which must not show (as a
        // negative f·v, or a velocity jump) in the pre-switch row, and the plateau speed
        // must hold exactly. Likewise a rigid stop reached touches it up to the bracket:
        // the row shows the contact position exactly.
        // On a closed mechanism's loops (the coordinates of stuck elements and stops in
        // contact held), before the switching coordinates are set exactly below: a
        // coordinate set there moves off the loops by the root finder's round-off only.
        self.project(t, &mut q, &mut v)?;
        for &e in triggered {
            let el = self.elements[e];
            if let (ElementKind::DashPot { .. }, Some((d, k))) = (el.kind, self.modes[e].slip()) {
                let c = el.coordinate;
                v[c] = d * mode::branch_end(&self.branches[e], k, d * v[c]);
            }
            if let Some((c, position)) = rigid_free(e) {
                q[c] = position;
            }
        }
        let forces_before = self.push_row(
            t,
            &q,
            &v,
            Row::Step {
                dense: Some(dense),
                keep: Keep::Event,
            },
        )?;
        let before: Vec<f64> = q.iter().chain(v.iter()).copied().collect();
        let old = self.modes.clone();
        let mut impacts: Vec<(usize, f64)> = Vec::new();
        // Stops whose rebound would be too small to see: they settle into contact.
        let mut settled: Vec<(usize, f64)> = Vec::new();
        let mut excluded: Vec<Option<Mode>> = vec![None; self.elements.len()];
        let mut jumped = false;
        for &e in triggered {
            let el = self.elements[e];
            let c = el.coordinate;
            match (el.kind, self.modes[e]) {
                (ElementKind::DashPot { law, .. }, Mode::SlipPos(k) | Mode::SlipNeg(k)) => {
                    let (d, w) = (v[c].signum(), v[c].abs());
                    let approach1 = law
                        == Law::BinghamNonMonotone {
                            selection: Selection::NoVelocityJumps,
                        };
                    if w != 0.0 && approach1 {
                        // A fold: the force jumps to the next branch, v continuous.
                        let up = w == self.branches[e].slip[k].v_hi;
                        self.modes[e] =
                            Mode::slipping(d, mode::fold_jump(&self.branches[e], k, up));
                    } else {
                        // Rest (selected at v_c = 0) or approach 2's plateau speed
                        // (selected among the two branches and the plateau there).
                        excluded[e] = Some(self.modes[e]);
                    }
                }
                (
                    ElementKind::Stop {
                        kind: StopKind::Rigid { restitution },
                        position,
                        side,
                    },
                    Mode::Free,
                ) => {
                    q[c] = position;
                    // Approaching: gap rate −s v_c < 0.
                    if mode::side_sign(side) * v[c] > 0.0 {
                        let e_eff = match self.rebound_invisible(t, &q, &v, c, side, restitution) {
                            Some(remaining) => {
                                settled.push((e, t + remaining));
                                0.0
                            }
                            None => restitution,
                        };
                        impacts.extend(self.impact(e, &mut q, &mut v, e_eff));
                        jumped = true;
                    }
                }
                (
                    ElementKind::Stop {
                        kind: StopKind::SpringBacked { .. },
                        ..
                    },
                    Mode::Contact,
                ) => {
                    // Resting (see `resting`): re-anchored at the static compression, or
                    // lifted off at the stop's position when the load no longer presses.
                    let Some(support) = Support::of(&el) else {
                        continue;
                    };
                    let lambda = support.s * forces_before[e];
                    let held = self.stored_energy(&q, &v);
                    if lambda > support.drift_margin(q[c], lambda, self.tol(q[c])) {
                        q[c] = support.reanchor(q[c], lambda, self.tol(q[c]));
                    } else {
                        q[c] = support.position;
                        self.modes[e] = Mode::Free;
                    }
                    self.out.stats.resting_energy_dropped += held - self.stored_energy(&q, &v);
                }
                (
                    ElementKind::Stop {
                        kind: StopKind::SpringBacked { .. },
                        ..
                    },
                    m,
                ) => {
                    self.modes[e] = if m == Mode::Compressed {
                        Mode::Free
                    } else {
                        Mode::Compressed
                    };
                }
                (_, m) => excluded[e] = Some(m),
            }
        }
        self.select_modes(t, &mut q, &mut v, &excluded, jumped)?;
        let changes = old.iter().zip(&self.modes).filter(|(a, b)| a != b).count();
        self.out.stats.events += 1;
        self.out.stats.mode_changes += changes;
        self.t = t;
        self.q = q;
        self.v = v;
        let forces_after = self.push_row(t, &q, &v, Row::Jump)?;
        // A run of single rebounds of one stop (see `bounces`).
        let rebound = match impacts.as_slice() {
            [(e, _)] if changes == 0 && settled.is_empty() => Some(*e),
            _ => None,
        };
        if let Some((stop, n)) = self.bounces
            && settled.iter().any(|(e, _)| *e == stop)
        {
            // The rebounds of the run that just settled have their Zeno point computed:
            // their times leave the Zeno tests (events at one instant stay counted).
            let keep = self.event_times.len().saturating_sub(n);
            self.event_times.truncate(keep);
        }
        self.bounces = match (rebound, self.bounces) {
            (Some(e), Some((last, n))) if e == last => Some((e, n + 1)),
            (Some(e), _) => Some((e, 1)),
            (None, _) => None,
        };
        let after: Vec<f64> = q.iter().chain(v.iter()).copied().collect();
        self.log_impacts(t, &impacts, &settled, &old, (&before, &after));
        // Mode changes of the elements that took no impulse (an impacted stop's entry
        // already carries its modes across the instant).
        for e in 0..self.elements.len() {
            if old[e] != self.modes[e] && !impacts.iter().any(|(s, _)| *s == e) {
                self.log(
                    t,
                    SwitchKind::Mode,
                    e,
                    old[e],
                    forces_after[e] - forces_before[e],
                    (&before, &after),
                );
            }
        }
        Ok(())
    }

    /// Adds a switch of element `e` (from mode `from` to its current mode) to the log,
    /// with the states `[q; v]` just before and after it.
    fn log(
        &mut self,
        t: f64,
        kind: SwitchKind,
        e: usize,
        from: Mode,
        jump: f64,
        (before, after): (&[f64], &[f64]),
    ) {
        self.out.switches.push(Switch {
            t,
            kind,
            element: Some(self.elements[e].name.to_string()),
            index: Some(e),
            from: Some(from),
            to: Some(self.modes[e]),
            jump,
            accumulation: None,
            before: before.to_vec(),
            after: after.to_vec(),
        });
    }

    /// The mechanical energy at `(q, v)`: kinetic, potential and the spring energy of
    /// every spring-backed stop pressed into its support (what resting changes, for
    /// [`Stats::resting_energy_dropped`]).
    fn stored_energy(&self, q: &SVector<f64, N>, v: &SVector<f64, N>) -> f64 {
        let springs: f64 = self
            .elements
            .iter()
            .filter_map(|el| {
                let s = Support::of(el)?;
                let pen = s.penetration(q[el.coordinate]).max(0.0);
                Some(0.5 * s.k * pen * pen)
            })
            .sum();
        self.system.kinetic_energy(q, v) + self.system.potential_energy(q) + springs
    }

    /// Spring-backed stops pressed onto their support that now rest on it (see
    /// [`resting`]): each one's vibration is removed by an impulse along its coordinate
    /// (`v⁺ = v − W e_c v_c / W_cc`, so `v_c = 0`), its coordinate set to the static
    /// compression and its mode to `Contact`; a second row is written at the current
    /// time and the changes are logged. Returns whether any stop came to rest.
    fn rest_supports(&mut self) -> Result<bool, ErrorKind> {
        // Pressed in, or free at rest on the support's position (let go there).
        let pressed: Vec<usize> = (0..self.elements.len())
            .filter(|&e| {
                let el = &self.elements[e];
                let c = el.coordinate;
                Support::of(el).is_some()
                    && match self.modes[e] {
                        Mode::Compressed => true,
                        Mode::Free => {
                            mode::gap(el, self.q[c]) <= self.tol(self.q[c])
                                && self.v[c].abs() <= self.tol(0.0)
                        }
                        _ => false,
                    }
            })
            .collect();
        if pressed.is_empty() {
            return Ok(false);
        }
        let (t, mut q, mut v) = (self.t, self.q, self.v);
        let old = self.modes.clone();
        let hold_force = |modes: &[Mode], q: &SVector<f64, N>, v: &SVector<f64, N>, e: usize| {
            let tau = self.tau(t, q, v);
            mode::evaluate(
                self.system,
                &self.elements,
                &self.branches,
                modes,
                q,
                v,
                &tau,
            )
            .map(|ev| ev.f[e])
        };
        let mut modes = self.modes.clone();
        for e in pressed {
            let Some(support) = Support::of(&self.elements[e]) else {
                continue;
            };
            let c = self.elements[e].coordinate;
            let mut trial = modes.clone();
            trial[e] = Mode::Contact;
            let Some(f) = hold_force(&trial, &q, &v, e) else {
                continue;
            };
            let w = self.system.inverse_mass_matrix(&q);
            let at = Pressed {
                qc: q[c],
                vc: v[c],
                lambda: support.s * f,
                wcc: w[(c, c)],
            };
            let tol = (self.tol(q[c]), self.tol(v[c]));
            if !support.rests(at, tol, self.options.rtol, self.tf - t) {
                continue;
            }
            v -= w.column(c) * (v[c] / w[(c, c)]);
            v[c] = 0.0;
            let lambda = hold_force(&trial, &q, &v, e).map_or(at.lambda, |f| support.s * f);
            q[c] = support.anchor(lambda);
            modes = trial;
        }
        if modes == old {
            return Ok(false);
        }
        self.out.stats.resting_energy_dropped +=
            self.stored_energy(&self.q, &self.v) - self.stored_energy(&q, &v);
        let forces_before = self.last_forces.clone();
        self.modes = modes;
        self.jump_to(q, v, &old, &forces_before)?;
        Ok(true)
    }

    /// Logs the impacts of one instant: `Settled` for a stop in contact after it,
    /// `Impact` otherwise (the rule of [`SwitchKind::Settled`]); `settled` gives the
    /// accumulation time of rebounds taken as their Zeno limit.
    fn log_impacts(
        &mut self,
        t: f64,
        impacts: &[(usize, f64)],
        settled: &[(usize, f64)],
        old: &[Mode],
        states: (&[f64], &[f64]),
    ) {
        for &(e, impulse) in impacts {
            let kind = if self.modes[e] == Mode::Contact {
                SwitchKind::Settled
            } else {
                SwitchKind::Impact
            };
            self.log(t, kind, e, old[e], impulse, states);
            if let (Some(&(_, accumulation)), Some(entry)) = (
                settled.iter().find(|(s, _)| *s == e),
                self.out.switches.last_mut(),
            ) {
                entry.accumulation = accumulation.is_finite().then_some(accumulation);
            }
        }
    }

    /// Whether the rebound of a rigid stop on coordinate `c` (state `q`, `v` at the
    /// impact, `v_c` approaching) would stay below the position tolerance, and if so
    /// the time its rebounds take to accumulate: with the acceleration `a` pressing the
    /// coordinate onto the stop, a rebound at speed `w = e |v_c|` rises `w² / 2a`; when
    /// that is within `atol + rtol (1 + |q_c|)` the bounces that follow are invisible and
    /// accumulate in a time `2w / (a (1 − e))` (their flight times `2w eᵏ / a` summed;
    /// infinite at `e = 1`), so the impact is taken as plastic and the stop settles into
    /// contact now — the Zeno limit, computed instead of stepped through (thousands of
    /// re-impacts at ~1e-10 m/s otherwise, each a restart), its time in the switch log.
    fn rebound_invisible(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        v: &SVector<f64, N>,
        c: usize,
        side: Side,
        restitution: f64,
    ) -> Option<f64> {
        let tau = self.tau(t, q, v);
        let Some(ev) = mode::evaluate(
            self.system,
            &self.elements,
            &self.branches,
            &self.modes,
            q,
            v,
            &tau,
        ) else {
            return None;
        };
        let pressing = mode::side_sign(side) * ev.a[c];
        let w = restitution * v[c].abs();
        let tolerance = self.options.atol + self.options.rtol * (1.0 + q[c].abs());
        (pressing > 0.0 && w * w <= 2.0 * pressing * tolerance).then(|| {
            if restitution < 1.0 {
                2.0 * w / (pressing * (1.0 - restitution))
            } else {
                f64::INFINITY
            }
        })
    }

    /// Newton's impact law for the stop `element` (coordinate `c`, restitution `e`
    /// after [`rebound_invisible`](Self::rebound_invisible)) and every other rigid stop
    /// closed at this instant (its gap within the position tolerance), applied to all of
    /// them at once as the time-stepper does: each approaching stop `k` gets
    /// `v⁺_k = −e_k v⁻_k`, each in contact `v⁺_k = 0`, through impulses `P_k` that only
    /// push, with `v⁺ = v⁻ − M⁻¹ Σ e_k P_k`. A stop whose impulse would pull takes none
    /// (it separates); one left out that would then move into its stop is put back — a
    /// small linear complementarity problem, solved by exchanging one stop at a time.
    /// Applied one after the other instead, two stops hit together bounce off each other
    /// in an endless geometric series at one instant. So an arm resting on one limit is
    /// not pushed into another either. Bounded element forces carry no impulse. Closed
    /// stops taking part are put exactly on their surfaces. Returns `(element,
    /// impulse)` for every stop that took one.
    fn impact(
        &self,
        element: usize,
        q: &mut SVector<f64, N>,
        v: &mut SVector<f64, N>,
        restitution: f64,
    ) -> Vec<(usize, f64)> {
        let c = self.elements[element].coordinate;
        let before = *v;
        // (element, coordinate, side sign, target velocity after) of every stop that
        // may take part; the first is the impacting one.
        let mut cands: Vec<(usize, usize, f64, f64)> = vec![(
            element,
            c,
            match self.elements[element].kind {
                ElementKind::Stop { side, .. } => mode::side_sign(side),
                ElementKind::DashPot { .. } => 1.0,
            },
            -restitution * before[c],
        )];
        let mut starts = vec![true];
        for (k, (el, m)) in self.elements.iter().zip(&self.modes).enumerate() {
            let ElementKind::Stop {
                kind: StopKind::Rigid { restitution: ek },
                side,
                position,
            } = el.kind
            else {
                continue;
            };
            let ck = el.coordinate;
            if k == element || ck == c || cands.iter().any(|x| x.1 == ck) {
                continue;
            }
            let s = mode::side_sign(side);
            let tol = self.options.atol + self.options.rtol * (1.0 + position.abs());
            // Only stops closed now take part: the mode alone can be stale (a hand-back
            // from time-stepping re-initialises modes after the impacts it applies).
            if mode::gap(el, q[ck]) > tol {
                continue;
            }
            // Approaching: Newton's law; in contact, or separating (it joins only if the
            // others' impulses would push it in): held, `v⁺ = 0`.
            let contact = *m == Mode::Contact;
            let approaching = !contact && s * before[ck] > 0.0;
            cands.push((k, ck, s, if approaching { -ek * before[ck] } else { 0.0 }));
            starts.push(approaching || contact);
        }
        let w = self.system.inverse_mass_matrix(q);
        let mut active = starts;
        let mut result: Option<(Vec<f64>, SVector<f64, N>)> = None;
        for _ in 0..2 * cands.len() + 2 {
            let idx: Vec<usize> = (0..cands.len()).filter(|&i| active[i]).collect();
            let k = idx.len();
            let wss = DMatrix::from_fn(k, k, |i, j| w[(cands[idx[i]].1, cands[idx[j]].1)]);
            let rhs = DVector::from_fn(k, |i, _| {
                let (_, ck, _, target) = cands[idx[i]];
                before[ck] - target
            });
            let Some(p) = factor::lu_solve(wss, &rhs) else {
                break;
            };
            // A stop's impulse removes velocity into it: it has the sign `side_sign`.
            let pulling = (1..k)
                .filter(|&i| cands[idx[i]].2 * p[i] < 0.0)
                .min_by(|&a, &b| (cands[idx[a]].2 * p[a]).total_cmp(&(cands[idx[b]].2 * p[b])));
            if let Some(i) = pulling {
                active[idx[i]] = false;
                continue;
            }
            let mut after = before;
            for (i, &j) in idx.iter().enumerate() {
                after -= w.column(cands[j].1) * p[i];
            }
            for &j in &idx {
                after[cands[j].1] = cands[j].3;
            }
            let mut impulses = vec![0.0; cands.len()];
            for (i, &j) in idx.iter().enumerate() {
                impulses[j] = p[i];
            }
            result = Some((impulses, after));
            // A stop left out that now moves into its surface joins.
            match (0..cands.len()).find(|&j| !active[j] && cands[j].2 * after[cands[j].1] > 0.0) {
                Some(j) => active[j] = true,
                None => break,
            }
        }
        match result {
            Some((impulses, after)) => {
                *v = after;
                let mut out = Vec::new();
                for (j, &(k, ck, _, _)) in cands.iter().enumerate() {
                    if active[j] {
                        if let ElementKind::Stop { position, .. } = self.elements[k].kind {
                            q[ck] = position;
                        }
                        if j == 0 || impulses[j] != 0.0 {
                            out.push((k, impulses[j]));
                        }
                    }
                }
                out
            }
            None => {
                let p = (1.0 + restitution) * before[c] / w[(c, c)];
                *v = before - w.column(c) * p;
                v[c] = -restitution * before[c];
                vec![(element, p)]
            }
        }
    }

    /// Re-selects the modes of every element at rest on a switching surface
    /// (dash-pots with `v_c = 0`, rigid stops closed with `v_c = 0`), excluding the
    /// modes just left; after a velocity jump, dash-pots that now move slip that way.
    fn select_modes(
        &mut self,
        t: f64,
        q: &mut SVector<f64, N>,
        v: &mut SVector<f64, N>,
        excluded: &[Option<Mode>],
        jumped: bool,
    ) -> Result<(), ErrorKind> {
        let mut choices: Choices = Vec::new();
        for (e, el) in self.elements.iter().enumerate() {
            let c = el.coordinate;
            let branches = &self.branches[e];
            // Approach 2 at exactly a plateau speed: the branch below, the plateau and
            // the branch above are the candidates. A branch whose end fired stays one:
            // entered at its end (leaving the plateau), a branch departs from it only
            // quadratically, and at a fold, where the force has its square-root
            // singularity, the first steps can dip back past the end by more than the
            // tolerance. Such a dip is no switch: the branch's acceleration still points
            // into its range, which its margin sees, while a branch reached from inside
            // has it pointing out.
            if let (ElementKind::DashPot { .. }, Some(i)) =
                (el.kind, mode::plateau_at(branches, v[c].abs()))
            {
                let d = v[c].signum();
                let cands = [
                    Mode::slipping(d, i),
                    Mode::on_plateau(d, i),
                    Mode::slipping(d, i + 1),
                ]
                .into_iter()
                .filter(|m| m.slip().is_some() || Some(*m) != excluded[e])
                .collect();
                choices.push((e, cands));
                continue;
            }
            let at_rest_on_surface = match el.kind {
                ElementKind::DashPot { .. } => v[c] == 0.0,
                ElementKind::Stop {
                    kind: StopKind::Rigid { .. },
                    ..
                } => mode::gap(el, q[c]) <= 0.0 && v[c] == 0.0,
                ElementKind::Stop { .. } => false,
            };
            if at_rest_on_surface {
                let cands = mode::candidates(el)
                    .iter()
                    .copied()
                    .filter(|m| Some(*m) != excluded[e])
                    .collect();
                choices.push((e, cands));
            } else if jumped || self.modes[e].is_constraint() {
                // Moving off a surface: the direction (and for non-monotone laws the
                // speed, and the branch the element was on) decides.
                let hint = self.hints[e].or_else(|| {
                    self.modes[e]
                        .slip()
                        .and_then(|(_, k)| branches.slip.get(k))
                        .map(|b| 0.5 * (b.f_lo + b.f_hi.min(2.0 * b.f_lo + 1.0)))
                });
                let k = mode::branch_of(branches, v[c].abs(), hint);
                self.modes[e] = match el.kind {
                    ElementKind::DashPot { .. } if v[c] > 0.0 => Mode::SlipPos(k),
                    ElementKind::DashPot { .. } => Mode::SlipNeg(k),
                    ElementKind::Stop {
                        kind: StopKind::Rigid { .. },
                        ..
                    } => Mode::Free,
                    // A spring-backed stop resting on its support set moving by an
                    // impact elsewhere (a support takes no impulse) vibrates again.
                    ElementKind::Stop { .. } if self.modes[e] == Mode::Contact && v[c] != 0.0 => {
                        Mode::Compressed
                    }
                    _ => self.modes[e],
                };
            }
        }
        let tau = self.tau(t, q, v);
        self.modes = mode::select(
            self.system,
            &self.elements,
            &self.branches,
            &self.modes,
            &choices,
            q,
            v,
            &tau,
            (self.options.atol, self.options.rtol),
        )
        .map_err(|detail| ErrorKind::IllPosedMode { t, detail })?;
        check_unique_forces(&self.elements, &self.modes, v, &S::JOINTS)
            .map_err(|detail| ErrorKind::IllPosedMode { t, detail })?;
        for (e, el) in self.elements.iter().enumerate() {
            if let (
                Mode::Contact,
                ElementKind::Stop {
                    position,
                    kind: StopKind::Rigid { .. },
                    ..
                },
            ) = (self.modes[e], el.kind)
            {
                q[el.coordinate] = position;
            }
        }
        Ok(())
    }

    /// Consistent initial modes (see the module documentation) and the first row (a
    /// second row at the same time when `resuming` after a hand-over).
    fn initialise(
        &mut self,
        problem: &NonSmoothProblem<N>,
        resuming: bool,
    ) -> Result<(), ErrorKind> {
        let (mut q, mut v) = (problem.q0, problem.v0);
        // A closed mechanism starts on its loops (`loops::assemble` completes a partial
        // start).
        if !resuming {
            self.system
                .project_onto_loops(&mut q, &mut v, &[])
                .map_err(|error| ErrorKind::Loops {
                    t: problem.t0,
                    error,
                })?;
        }
        for (e, el) in self.elements.iter().enumerate() {
            let Some(f) = problem.forces0.get(e).copied().flatten() else {
                continue;
            };
            match el.kind {
                ElementKind::DashPot { f_crit, .. } if f.abs() > f_crit * (1.0 + 1e-12) => {
                    return Err(ErrorKind::InconsistentInitialData(format!(
                        "element `{}`: the given force {f} exceeds f_crit = {f_crit}",
                        el.name
                    )));
                }
                ElementKind::Stop { side, .. } if mode::side_sign(side) * f < 0.0 => {
                    return Err(ErrorKind::InconsistentInitialData(format!(
                        "stop `{}`: the given force {f} pulls (a stop can only push)",
                        el.name
                    )));
                }
                _ => {}
            }
        }
        let mut modes = Vec::with_capacity(self.elements.len());
        // Impacts at t0: the state `[q; v]` before each, and its impulses.
        type StartImpact = (Vec<f64>, Vec<(usize, f64)>);
        let mut start_impacts: Vec<StartImpact> = Vec::new();
        for (e, el) in self.elements.iter().enumerate() {
            let c = el.coordinate;
            let g = mode::gap(el, q[c]);
            let m = match el.kind {
                ElementKind::DashPot { .. } => Mode::Stick,
                ElementKind::Stop {
                    kind: StopKind::Rigid { restitution },
                    position,
                    side,
                } => {
                    mode::check_not_penetrating(el, q[c], &S::JOINTS)
                        .map_err(ErrorKind::InconsistentInitialData)?;
                    if g <= 0.0 {
                        q[c] = position;
                        if mode::side_sign(side) * v[c] > 0.0 {
                            // Starting on the stop and moving into it: an impact at t0,
                            // logged below with the state before it.
                            let pre: Vec<f64> = q.iter().chain(v.iter()).copied().collect();
                            let impulses = self.impact(e, &mut q, &mut v, restitution);
                            start_impacts.push((pre, impulses));
                        }
                    }
                    Mode::Free
                }
                ElementKind::Stop { side, .. } => {
                    if g < 0.0 || (g == 0.0 && mode::side_sign(side) * v[c] > 0.0) {
                        Mode::Compressed
                    } else {
                        Mode::Free
                    }
                }
            };
            modes.push(m);
        }
        self.modes = modes;
        let none = vec![None; self.elements.len()];
        // Dash-pots that move slip their way; the ones at rest are selected.
        self.select_modes(problem.t0, &mut q, &mut v, &none, true)
            .map_err(|kind| match kind {
                ErrorKind::IllPosedMode { detail, .. } => ErrorKind::InconsistentInitialData(
                    format!("no unique consistent initial mode: {detail}"),
                ),
                other => other,
            })?;
        self.t = problem.t0;
        self.q = q;
        self.v = v;
        let Some((pre, _)) = start_impacts.first() else {
            let row = if resuming { Row::Jump } else { Row::Start };
            return self.push_row(problem.t0, &q, &v, row).map(|_| ());
        };
        // An impact at t0: the row before it (the impacted stops still free; the other
        // elements' forces in their modes after it) unless a run is resumed (its last
        // row is that state), then the row after it.
        let mut old = self.modes.clone();
        for &(e, _) in start_impacts.iter().flat_map(|(_, impulses)| impulses) {
            old[e] = Mode::Free;
        }
        if !resuming {
            let (q_pre, v_pre) = (
                SVector::<f64, N>::from_column_slice(&pre[..N]),
                SVector::<f64, N>::from_column_slice(&pre[N..2 * N]),
            );
            let after_modes = std::mem::replace(&mut self.modes, old.clone());
            self.push_row(problem.t0, &q_pre, &v_pre, Row::Start)?;
            self.modes = after_modes;
        }
        self.push_row(problem.t0, &q, &v, Row::Jump)?;
        let after: Vec<f64> = q.iter().chain(v.iter()).copied().collect();
        for (pre, impulses) in start_impacts {
            self.log_impacts(problem.t0, &impulses, &[], &old, (&pre, &after));
        }
        self.out.stats.events += 1;
        Ok(())
    }

    /// Zeno / chattering test after an event (see the module documentation): the end
    /// of the span to hand over to time-stepping, if events accumulate.
    ///
    /// Geometric gaps `g, r g, r² g, …` accumulate at `t + g r/(1 − r)`; the span
    /// handed over is three times that remainder. A dense cluster of events is handed
    /// over for twice the time it took.
    fn check_accumulation(&mut self, tf: f64) -> Result<Option<f64>, ErrorKind> {
        let t = self.t;
        self.event_times.push_back(t);
        if self.event_times.len() > ZENO_EVENTS {
            self.event_times.pop_front();
        }
        let times: Vec<f64> = self.event_times.iter().copied().collect();
        let k = times.len();
        if times.iter().rev().take_while(|&&s| s == t).count() >= SAME_TIME_EVENTS {
            return Err(self
                .switching_element(t)
                .unwrap_or(ErrorKind::IllPosedMode {
                    t,
                    detail: format!("{SAME_TIME_EVENTS} mode switches at one instant (cycling)"),
                }));
        }
        // Rebounds of one stop and nothing else settle by themselves, at their computed
        // accumulation time (`rebound_invisible`): not handed over while the run covers
        // the window a test looks at.
        let bouncing = |window: usize| {
            self.bounces
                .is_some_and(|(_, n)| (window..=MAX_BOUNCES).contains(&n))
        };
        let mut end = None;
        if k > ZENO_GEOMETRIC + 1 && !bouncing(ZENO_GEOMETRIC + 2) {
            let gaps: Vec<f64> = times[k - ZENO_GEOMETRIC - 2..]
                .windows(2)
                .map(|w| w[1] - w[0])
                .collect();
            // Only where the events have become dense at the run's scale: a geometric
            // sequence whose last gap is still above ZENO_SPAN of the interval (a slowly
            // decaying bounce, its accumulation point maybe past tf) is resolved event
            // by event, which takes at most ln(g / (ZENO_SPAN · span)) / ln(1/ZENO_RATIO)
            // (≈ 66) more events before the test applies; handing it over would trade
            // exact switch times for time-stepping's first-order error at large steps.
            let dense = gaps.last().is_some_and(|&g| g < ZENO_SPAN * self.span);
            if dense
                && gaps
                    .windows(2)
                    .all(|g| g[0] > 0.0 && g[1] <= ZENO_RATIO * g[0])
            {
                let (g1, g2) = (gaps[gaps.len() - 2], gaps[gaps.len() - 1]);
                let r = g2 / g1;
                end = Some(t + 3.0 * g2 * r / (1.0 - r));
            }
        }
        if end.is_none()
            && k >= ZENO_EVENTS
            && !bouncing(ZENO_EVENTS)
            && t - times[k - ZENO_EVENTS] < ZENO_SPAN * self.span
        {
            end = Some(t + 2.0 * (t - times[k - ZENO_EVENTS]));
        }
        Ok(end.map(|e: f64| e.min(tf)))
    }

    /// Integrates `[t, end]` with time-stepping (θ = 1, [`HANDOVER_STEPS`] steps),
    /// appends its rows, and re-initialises the modes at its final state. A rigid stop
    /// that the velocity-level time-stepping left slightly penetrated is projected onto
    /// its surface first.
    fn hand_over<O: Observer + ?Sized>(
        &mut self,
        end: f64,
        observer: &mut O,
    ) -> Result<(), ErrorKind> {
        self.out.stats.zeno_detected += 1;
        self.event_times.clear();
        self.bounces = None;
        if end <= self.t {
            return Ok(());
        }
        let state: Vec<f64> = self.q.iter().chain(self.v.iter()).copied().collect();
        self.out.switches.push(Switch::of_run(
            self.t,
            SwitchKind::HandOverToTimeStepping,
            state.clone(),
            state,
        ));
        let problem = NonSmoothProblem::new(self.t, end, self.q, self.v);
        let h = (end - self.t) / HANDOVER_STEPS as f64;
        let input = Capped {
            input: &self.input,
            until: self.until,
        };
        let traj = time_stepping_observed(self.system, &input, &problem, h, 1.0, observer)
            .map_err(|e| e.kind)?;
        self.out.stats.zeno_handovers += 1;
        self.out.stats.steps += traj.stats.steps;
        self.out.stats.rhs_evaluations += traj.stats.rhs_evaluations;
        self.out.stats.newton_iterations += traj.stats.newton_iterations;
        for i in 1..traj.len() {
            let (ta, tb) = (traj.times()[i - 1], traj.times()[i]);
            let (ya, yb) = (&traj.state(i - 1)[..2 * N], &traj.state(i)[..2 * N]);
            if let Some(act) = self.user_events_between((ta, ya), (tb, yb)) {
                let te = act.t;
                let mut row = vec![0.0; 2 * N];
                hermite_qv((ta, ya), (tb, yb), te, &mut row);
                row.extend_from_slice(&traj.state(i)[2 * N..]);
                let keep = if act.reset.is_some() {
                    Keep::Event
                } else {
                    Keep::Last
                };
                self.out.push_step(te, &row, traj.derivative(i), None, keep);
                let ended = traj.switches.iter().filter(|s| s.t <= te).cloned();
                self.out.switches.extend(ended);
                self.t = te;
                self.q = SVector::from_column_slice(&row[..N]);
                self.v = SVector::from_column_slice(&row[N..2 * N]);
                self.last_forces = row[2 * N..2 * N + S::ELEMENTS].to_vec();
                // A reset ends the hand-over: event-driven integration goes on from the
                // new state.
                if let Some(k) = act.reset {
                    self.apply_reset(k)?;
                }
                if act.terminal {
                    self.ended = Some(te);
                }
                return Ok(());
            }
            self.out
                .push_step(tb, traj.state(i), traj.derivative(i), None, Keep::AsAsked);
        }
        // Its transitions join the log between the hand-over and the hand-back.
        self.out.switches.extend(traj.switches.iter().cloned());
        let (t, y) = traj.last().expect("time-stepping keeps the first row");
        let mut q = SVector::<f64, N>::from_column_slice(&y[..N]);
        let v = SVector::<f64, N>::from_column_slice(&y[N..2 * N]);
        for el in &self.elements {
            if let ElementKind::Stop {
                kind: StopKind::Rigid { .. },
                position,
                ..
            } = el.kind
                && mode::gap(el, q[el.coordinate]) < 0.0
            {
                q[el.coordinate] = position;
            }
        }
        let resume = NonSmoothProblem::new(t, t, q, v);
        let before = self.modes.clone();
        self.hints = (0..self.elements.len())
            .map(|e| Some(y[2 * N + e]))
            .collect();
        let resumed = self.initialise(&resume, true);
        self.hints = vec![None; self.elements.len()];
        resumed?;
        self.out.stats.mode_changes += before
            .iter()
            .zip(&self.modes)
            .filter(|(a, b)| a != b)
            .count();
        let state: Vec<f64> = self.q.iter().chain(self.v.iter()).copied().collect();
        self.out.switches.push(Switch::of_run(
            t,
            SwitchKind::HandBack,
            y[..2 * N].to_vec(),
            state,
        ));
        Ok(())
    }
}

/// What a user event asks of the run at its crossing.
#[derive(Clone, Copy, Debug)]
struct Act {
    t: f64,
    /// The event whose reset changes the state there.
    reset: Option<usize>,
    /// The run ends there (after the reset, if any).
    terminal: bool,
}

impl Act {
    /// The first crossing that acts, if any.
    fn of(crossings: &Crossings) -> Option<Act> {
        match (crossings.reset, crossings.terminal) {
            (Some((k, t)), terminal) => Some(Act {
                t,
                reset: Some(k),
                terminal: terminal.is_some(),
            }),
            (None, Some(t)) => Some(Act {
                t,
                reset: None,
                terminal: true,
            }),
            (None, None) => None,
        }
    }
}

pub(super) mod resting;
#[cfg(test)]
mod tests;

/// Two elements on one coordinate, one holding it (stuck, in contact, on a plateau) and
/// the other at rest on its slip boundary (v = 0): the coordinate does not move and any
/// split of the holding force between them fits, so the element forces are not unique.
/// This is reported as an ill-posed mode rather than integrated with an arbitrary split.
fn check_unique_forces<const N: usize>(
    elements: &[Element],
    modes: &[Mode],
    v: &SVector<f64, N>,
    joints: &[&str],
) -> Result<(), String> {
    let holds = |m: Mode| {
        matches!(
            m,
            Mode::Stick | Mode::Contact | Mode::PlateauPos(_) | Mode::PlateauNeg(_)
        )
    };
    for (a, ea) in elements.iter().enumerate() {
        for (b, eb) in elements.iter().enumerate().skip(a + 1) {
            if ea.coordinate != eb.coordinate {
                continue;
            }
            let at_rest_slip = |m: Mode| {
                matches!(m, Mode::SlipPos(_) | Mode::SlipNeg(_)) && v[ea.coordinate] == 0.0
            };
            let (ma, mb) = (modes[a], modes[b]);
            // A rigid stop in contact takes what presses on it; a dash-pot beside it
            // takes the rest (stuck), or its slip force: unique either way.
            let is_stop = |e: &Element, m: Mode| {
                matches!(
                    (e.kind, m),
                    (
                        ElementKind::Stop {
                            kind: StopKind::Rigid { .. },
                            ..
                        },
                        Mode::Contact
                    )
                )
            };
            let is_dashpot = |e: &Element| matches!(e.kind, ElementKind::DashPot { .. });
            if (is_stop(ea, ma) && is_dashpot(eb)) || (is_stop(eb, mb) && is_dashpot(ea)) {
                continue;
            }
            if (holds(ma) && (holds(mb) || at_rest_slip(mb))) || (holds(mb) && at_rest_slip(ma)) {
                return Err(format!(
                    "elements `{}` and `{}` both hold {} at rest: their forces are not unique (only their sum is determined)",
                    ea.name,
                    eb.name,
                    crate::element::joint_name(joints, ea.coordinate)
                ));
            }
        }
    }
    Ok(())
}
