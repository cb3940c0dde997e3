//! The step-level trait every method implements, and what drivers build on.
//!
//! A [`Stepper`] owns the method's state between steps (current point, step size,
//! controller, Newton matrix, history) and nothing of the problem: each call is handed
//! the system through an [`Eval`], so a driver may change the equations between steps
//! (the event-driven integrator does, at every mode switch) and keep the stepper.
//!
//! The life of a stepper:
//!
//! 1. [`begin`](Stepper::begin) afresh at `(t₀, y₀)`: checks the configuration, evaluates
//!    `f(t₀, y₀)` and chooses the first step (Hairer, Nørsett & Wanner I, §II.4).
//! 2. [`step`](Stepper::step) towards `t_end`: attempts steps — each accepted or
//!    rejected by the method's error estimate and step-size controller, or failed by
//!    Newton — until one is accepted, never passing `t_end` (a step that would nearly
//!    reach it is stretched to end exactly there). Afterwards [`t`](Stepper::t),
//!    [`y`](Stepper::y), [`f`](Stepper::f) are the new point and
//!    [`dense`](Stepper::dense) the method's continuous extension over the step.
//! 3. [`begin`](Stepper::begin) again at a discontinuity `(t, y⁺)`: everything that
//!    assumed a smooth past (the FSAL derivative, BDF's history, the controller's memory)
//!    is dropped; BDF keeps its Jacobian (a stale Jacobian still serves a simplified
//!    Newton iteration and is refreshed at its first failure; SDIRK4 re-evaluates it,
//!    because its error estimate is filtered through it), and the step size is kept unless
//!    the starting-step estimate at the new point is smaller (`restart_step`): the
//!    equations changed, and a step that suited the old ones may straddle a kink of the
//!    new ones (measured: keeping it made SDIRK4 and BDF fail Newton on S4's plateau
//!    exits).
//!
//! Attempts are counted in the [`Stats`](crate::Stats) of the `Eval` (`steps +
//! rejected_steps`); reaching the method's `max_steps` there ends with
//! [`ErrorKind::MaxSteps`].

pub use crate::numerics::dense::DenseStep;
pub use crate::numerics::eval::Eval;
use crate::{ErrorKind, OdeSystem, Options};

/// What every stepper keeps: the current point and its derivative, the next step to
/// try, the last step's dense output, and the options.
#[derive(Clone, Debug)]
pub struct StepState {
    pub t: f64,
    /// Next step to try.
    pub h: f64,
    pub y: Vec<f64>,
    /// `f(t, y)` (for BDF, the derivative its formula assigns to the point).
    pub f: Vec<f64>,
    /// The continuous extension over the last accepted step.
    pub dense: DenseStep,
    pub options: Options,
    /// The time of the accepted point before the current one, while the solution has
    /// been smooth since then (no start or restart in between): with it a one-step method
    /// writes the quintic two-step Hermite extension
    /// (`DenseStep::set_hermite5`) instead of its own lower-degree one.
    pub prev: Option<f64>,
    /// `y` at the previous point (meaningful while `prev` is `Some`).
    pub prev_y: Vec<f64>,
    /// `f` at the previous point (meaningful while `prev` is `Some`).
    pub prev_f: Vec<f64>,
    /// `Some(n)`: the first `n` components are positions, read back with
    /// `DenseStep::set_positions_quintic` (the system's [`OdeSystem::second_order`] when
    /// its [`dense_positions`](OdeSystem::dense_positions) is on; set at the start).
    pub dense_positions: Option<usize>,
}

impl StepState {
    pub(crate) fn new(dim: usize, options: Options) -> Self {
        StepState {
            t: 0.0,
            h: 0.0,
            y: vec![0.0; dim],
            f: vec![0.0; dim],
            dense: DenseStep::new(dim),
            options,
            prev: None,
            prev_y: vec![0.0; dim],
            prev_f: vec![0.0; dim],
            dense_positions: None,
        }
    }

    /// Writes the dense output of the step from the current point to `t + h`, where the
    /// new point is `y1` with `f1 = f(t + h, y1)`: the quintic two-step Hermite
    /// extension if the previous point is known, else `own` (the method's own extension,
    /// given the state).
    pub(crate) fn set_dense(
        &mut self,
        h: f64,
        y1: &[f64],
        f1: &[f64],
        own: impl FnOnce(&mut DenseStep, &[f64], &[f64]),
    ) {
        // The positions of a second-order state get their own quintic below: the
        // two-step Hermite is not computed for them.
        let first = self.dense_positions.unwrap_or(0);
        match self.prev {
            Some(tm) => self.dense.set_hermite5(
                first,
                tm,
                &self.prev_y,
                &self.prev_f,
                self.t,
                h,
                &self.y,
                &self.f,
                y1,
                f1,
            ),
            None => own(&mut self.dense, &self.y, &self.f),
        }
        if let Some(n) = self.dense_positions {
            self.dense
                .set_positions_quintic(n, &self.y, &self.f, y1, f1);
        }
    }

    /// Moves to the accepted point `(t1, y1)` with `f1 = f(t1, y1)`; the current point
    /// becomes the previous one.
    pub(crate) fn advance(&mut self, t1: f64, y1: &[f64], f1: &[f64]) {
        self.prev = Some(self.t);
        std::mem::swap(&mut self.prev_y, &mut self.y);
        std::mem::swap(&mut self.prev_f, &mut self.f);
        self.t = t1;
        self.y.copy_from_slice(y1);
        self.f.copy_from_slice(f1);
    }

    /// Forgets the past: the next step starts a smooth stretch.
    pub(crate) fn forget(&mut self) {
        self.prev = None;
    }

    /// [`Stepper::begin`] for a method of `order`: afresh, [`start`](Self::start);
    /// after a discontinuity, [`resume`](Self::resume) with the step `h_kept`.
    pub(crate) fn enter<S: OdeSystem + ?Sized>(
        &mut self,
        ev: &mut Eval<'_, S>,
        at: Begin,
        order: u32,
        h_kept: f64,
    ) -> StepResult {
        if at.fresh {
            self.start(ev, at.t, at.y, at.span, order)
        } else {
            self.resume(ev, at.t, at.y, at.span, order, h_kept)
        }
    }

    /// A fresh start for a method of `order`: checks the options, evaluates `f` and
    /// chooses the first step (when `span > 0`).
    fn start<S: OdeSystem + ?Sized>(
        &mut self,
        ev: &mut Eval<'_, S>,
        t: f64,
        y: &[f64],
        span: f64,
        order: u32,
    ) -> Result<(), ErrorKind> {
        self.options.validate().map_err(ErrorKind::InvalidInput)?;
        self.forget();
        self.dense_positions = crate::problem::dense_positions(ev.system);
        self.t = t;
        self.y.copy_from_slice(y);
        ev.rhs(t, y, &mut self.f)?;
        if span > 0.0 {
            self.h = crate::numerics::initial_step(
                t,
                y,
                &self.f,
                span,
                order,
                &self.options,
                |t, y, dy| ev.rhs(t, y, dy),
            )?;
        }
        Ok(())
    }

    /// A restart for a method of `order`: evaluates `f` at the new point and takes the
    /// step `h_kept` unless the starting-step estimate there is smaller.
    fn resume<S: OdeSystem + ?Sized>(
        &mut self,
        ev: &mut Eval<'_, S>,
        t: f64,
        y: &[f64],
        span: f64,
        order: u32,
        h_kept: f64,
    ) -> Result<(), ErrorKind> {
        self.forget();
        self.t = t;
        self.y.copy_from_slice(y);
        ev.rhs(t, y, &mut self.f)?;
        self.h = restart_step(ev, t, y, &self.f, span, order, &self.options, h_kept)?;
        Ok(())
    }
}

/// Where a stepper begins an arc: at `(t, y)` with `span` left to integrate (it bounds the
/// first step; `0` takes no step), afresh or after a discontinuity.
#[derive(Clone, Copy, Debug)]
pub struct Begin<'a> {
    pub t: f64,
    pub y: &'a [f64],
    pub span: f64,
    /// `true`: the start of a run ([`Stepper::begin`]'s first life stage); `false`: a
    /// restart after a discontinuity (its third).
    pub fresh: bool,
}

/// What a stepper's calls end with.
pub type StepResult = Result<(), ErrorKind>;

/// One method's stepping state (see the module documentation).
pub trait Stepper {
    /// The state every stepper keeps.
    fn state(&self) -> &StepState;

    /// The same, to change.
    fn state_mut(&mut self) -> &mut StepState;

    /// Moves the current point to `y` at the same time, by about the local error (a
    /// projection onto an invariant manifold, [`OdeSystem::project`]): the step size is
    /// kept, and `f` evaluated at the new point (one right-hand side). A multistep method
    /// shifts its past with the point instead.
    fn nudge<S: OdeSystem + ?Sized>(&mut self, ev: &mut Eval<'_, S>, y: &[f64]) -> StepResult {
        let s = self.state_mut();
        s.y.copy_from_slice(y);
        let mut f = std::mem::take(&mut s.f);
        let done = ev.rhs(s.t, y, &mut f);
        self.state_mut().f = f;
        done
    }

    /// Begins at `at` (see the module documentation): afresh, checking the options
    /// (invalid ones are [`ErrorKind::InvalidInput`] before anything is evaluated) and
    /// choosing the first step; or after a discontinuity, dropping what assumed a smooth
    /// past.
    fn begin<S: OdeSystem + ?Sized>(&mut self, ev: &mut Eval<'_, S>, at: Begin) -> StepResult;

    /// Advances by one accepted step, ending at or before `t_end`.
    fn step<S: OdeSystem + ?Sized>(&mut self, ev: &mut Eval<'_, S>, t_end: f64) -> StepResult;

    /// The options the method runs with (for a fixed-step method, the defaults with its
    /// step as `h0`).
    fn options(&self) -> Options {
        self.state().options
    }
    /// Current time.
    fn t(&self) -> f64 {
        self.state().t
    }
    /// Current state.
    fn y(&self) -> &[f64] {
        &self.state().y
    }
    /// `f(t, y)` at the current point (for BDF, the derivative its formula assigns).
    fn f(&self) -> &[f64] {
        &self.state().f
    }
    /// Builds the continuous extension of the last accepted step, for a method that
    /// builds it on demand (BDF: from its differences, which stay valid until the next
    /// step). A driver calls it after [`step`](Self::step) before reading
    /// [`dense`](Self::dense); steps whose extension nobody reads skip its cost.
    fn prepare_dense(&mut self) {}
    /// The continuous extension over the last accepted step (after
    /// [`prepare_dense`](Self::prepare_dense)).
    fn dense(&self) -> &DenseStep {
        &self.state().dense
    }
}

/// The step after a restart at `(t, y)` with `f = f(t, y)`: the step size kept from
/// before, or the starting-step estimate for a method of `order` if that is smaller
/// (one right-hand-side evaluation).
#[allow(clippy::too_many_arguments)]
pub(crate) fn restart_step<S: OdeSystem + ?Sized>(
    ev: &mut Eval<'_, S>,
    t: f64,
    y: &[f64],
    f: &[f64],
    span: f64,
    order: u32,
    options: &Options,
    h_kept: f64,
) -> Result<f64, ErrorKind> {
    if span <= 0.0 {
        return Ok(h_kept);
    }
    let fresh =
        crate::numerics::initial_step(t, y, f, span, order, options, |t, y, dy| ev.rhs(t, y, dy))?;
    Ok(if h_kept > 0.0 {
        h_kept.min(fresh)
    } else {
        fresh
    })
}

/// Checks that the step budget is not used up (see the module documentation).
pub(crate) fn check_budget(
    stats: &crate::Stats,
    options: &Options,
    t: f64,
) -> Result<(), ErrorKind> {
    if stats.steps + stats.rejected_steps >= options.max_steps {
        Err(ErrorKind::MaxSteps { t })
    } else {
        Ok(())
    }
}
