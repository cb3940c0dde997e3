//! Runtime of filippov: what generated kernels implement, an independent numeric
//! reference of the same physics, and the integrators that run them.
//!
//! * The ground floor, which imports none of the rest: what a scene's non-smooth
//!   elements are and their modes (`element`: [`NonSmooth`], [`Mode`]; re-exported in
//!   [`nonsmooth`]), the runtime model of a multibody tree (`model`, re-exported as
//!   [`numeric::Model`]) and rotations ([`geometry`]: [`UnitQuat`], SO(3)).
//! * [`system`]: the [`Mechanism`] trait the derive implements; [`kernels`]: the
//!   traits of the kernels a scene asks for by name (Coriolis matrix, energies, …).
//! * [`numeric`]: plain numeric RNEA / CRBA / exact `∂M/∂q` over a runtime
//!   [`numeric::Model`] — the cross-check and the baseline.
//! * [`compact`]: the loops the derive calls for large trees (ABA, CRBA and the
//!   Jacobian by duals over a table of the bodies); [`real`]: the scalars every generic
//!   kernel runs on ([`Real`], [`Dual`], SIMD [`Lanes`]).
//! * Integration, in layers whose arrows point down:
//!   - drivers: [`solve`] (smooth), [`solve_nonsmooth`] (event-driven or
//!     time-stepping, [`nonsmooth`]; its step-level form
//!     [`nonsmooth::Integrator`], which a controller drives with `set_input` and
//!     `advance_to`), the Lie-group methods' own `solve` ([`liegroup`]), ensembles
//!     of runs in SIMD lanes ([`lockstep`]), ensembles of runs on every core, drawn
//!     reproducibly and gathered into a table ([`ensemble`]); user
//!     [`Event`]s, located the same way by every driver ([`events`]);
//!   - methods ([`method`]): [`Rk4`], [`Dopri5`], [`Sdirk4`], [`Bdf`], each a
//!     configuration that makes a [`Stepper`] — the step-level trait every driver runs
//!     on (begin afresh or after a discontinuity, one accepted step, dense output);
//!   - shared numerics ([`numerics`]): error norms, [`PiController`], tableaus
//!     ([`tableau`]), dense output, the Newton matrix, root finding.
//! * The problem ([`OdeSystem`], [`Problem`], the adapters [`MechanicalSystem`] and
//!   [`NumericSystem`]; [`NonSmoothProblem`]) and the result: one [`Solution`] for every
//!   driver — rows at the accepted steps (or at requested times, [`Output`]), the
//!   method's own dense output between them, named columns, [`Stats`], and for
//!   non-smooth runs the log of every [`Switch`]; a [`SolveError`] keeps the solution
//!   up to the failure.
//! * [`liegroup`]: Lie-group integration on SO(3)ᵐ × ℝⁿ ([`LieSystem`]; explicit
//!   [`Rkmk5`], stiff [`LieSdirk`]; events with [`LieEvent`], an [`Event`] of the
//!   group's state), and the trait of
//!   scenes with spherical and free joints ([`LieMechanism`]) with its adapter
//!   [`LieMechanical`]. These keep their own step-level trait (`LieStepper`: start, one
//!   accepted step, under one driver that also locates [`LieEvent`]s) and result
//!   ([`LieTrajectory`], which holds a flat [`Solution`]): their states are not vectors
//!   — configurations move by `g · exp(h v̂)` and the dense output lives in the local
//!   coordinates of each step — so a [`Stepper`] over slices cannot carry them without
//!   losing the group.
//!
//! # Running a simulation and reading it back
//!
//! ```
//! use std::ops::ControlFlow;
//! use filippov_runtime::{FnSystem, Method, Options, Output, Problem, solve, solve_with};
//! // Harmonic oscillator x'' = −x.
//! let osc = FnSystem::new(2, |_t, y: &[f64], dy: &mut [f64]| {
//!     dy[0] = y[1];
//!     dy[1] = -y[0];
//! });
//! let problem = Problem::new(0.0, 10.0, [1.0, 0.0]);
//! let sol = solve(&osc, &problem, &Method::Dopri5(Options::tolerances(1e-9, 1e-12))).unwrap();
//! // Anywhere in [0, 10], at the method's own order (no allocation with `at_into`).
//! let mut y = [0.0; 2];
//! sol.at_into(0.5, &mut y);
//! assert!((y[0] - 0.5f64.cos()).abs() < 1e-8);
//! // Rows, named columns, statistics, CSV.
//! assert_eq!(sol.names(), ["y0", "y1"]);
//! assert!(sol.rows().all(|(t, y)| (y[0] - t.cos()).abs() < 1e-7));
//! println!("{}", sol.stats);
//! // Only some times kept, and an observer that could stop the run (progress bars).
//! let grid = Problem::new(0.0, 10.0, [1.0, 0.0]).with_output(Output::Times(vec![1.0, 2.0, 3.0]));
//! let mut steps = 0;
//! let sol = solve_with(&osc, &grid, &Method::Bdf(Options::tolerances(1e-8, 1e-10)), &mut |_t: f64, _y: &[f64]| {
//!     steps += 1;
//!     ControlFlow::Continue(())
//! }).unwrap();
//! assert_eq!(sol.times(), [1.0, 2.0, 3.0]);
//! assert_eq!(steps, sol.stats.steps);
//! ```
//!
//! A mechanism from the derive runs the same way through [`MechanicalSystem`]; a scene
//! with friction, dash-pots or stops through [`solve_nonsmooth`], which returns the same
//! [`Solution`] with force columns and its [`switches`](Solution::switches).
//!
//! # Thread safety
//!
//! Generated scenes are plain `f64` structs: `Send + Sync + Copy`. [`Solution`],
//! [`Stats`], [`Options`], [`Problem`], [`NonSmoothProblem`] and the steppers are `Send +
//! Sync`; a parameter sweep may run one integration per thread.
pub mod compact;
mod conservative;
pub mod contacts;
mod element;
pub mod ensemble;
mod error;
pub mod events;
pub mod geometry;
mod input;
pub mod kernels;
pub mod liegroup;
pub mod lockstep;
pub mod loops;
mod mechanical;
pub mod method;
mod model;
pub mod nonsmooth;
pub mod numeric;
pub mod numerics;
mod options;
mod problem;
pub mod real;
mod solution;
mod solve;
mod stats;
pub mod system;

pub use conservative::{Conservative, ENERGY_SCALE_LIMIT};
pub use element::{Mode, NonSmooth};
pub use error::{ErrorKind, SolveError};
pub use events::{Event, EventDirection, EventHit, Reset};
pub use input::{Input, Unforced};
pub use liegroup::{
    FnLieSystem, LieEvent, LieEventHit, LieInputFn, LieMechanical, LieMechanism, LieProblem,
    LieSdirk, LieState, LieSystem, LieTrajectory, Rkmk5, UnitQuat,
};
pub use mechanical::{InputFn, MechanicalSystem, NumericInputFn, NumericSystem};
pub use method::{Bdf, Dopri5, Method, Rk4, Sdirk4, Stepper};
pub use nonsmooth::{
    NonSmoothMethod, NonSmoothProblem, contact_event_driven, contact_time_stepping,
    solve_nonsmooth, solve_nonsmooth_with,
};
pub use numerics::control::PiController;
pub use numerics::tableau;
pub use options::Options;
pub use problem::{FnSystem, OdeSystem, Problem};
pub use real::{Dual, Lanes, Real};
pub(crate) use solution::Keep;
pub use solution::{Output, Solution, Switch, SwitchKind};
pub use solve::{Observer, integrate, solve, solve_with, solve_with_events};
pub use stats::Stats;
pub use system::{ForwardJacobian, Mechanism, ParameterError, Parameters};
