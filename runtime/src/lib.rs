//! Runtime of filippov: what generated kernels implement, an independent numeric
//! reference of the same physics, and the integrators that run them.
//!
//! * [`system`]: the [`Mechanism`] trait the derive implements.
//! * [`numeric`]: plain numeric RNEA / CRBA / exact `∂M/∂q` over a runtime
//!   [`numeric::Model`] — the cross-check and the baseline.
//! * Integration, separated diffsol-style into the problem ([`OdeSystem`], [`Problem`],
//!   the adapters [`MechanicalSystem`] and [`NumericSystem`]), the methods ([`Rk4`],
//!   [`Dopri5`], [`Sdirk4`], [`Bdf`], tableaus in [`tableau`]), their configuration
//!   ([`Options`], [`PiController`]) and the result ([`Solution`], [`Stats`],
//!   [`SolveError`]).
//! * [`liegroup`]: Lie-group integration on SO(3)ᵐ × ℝⁿ ([`LieSystem`]; explicit
//!   [`Rkmk5`], stiff [`LieSdirk`]; event location with [`LieEvent`]), and the trait of
//!   scenes with spherical and free joints ([`LieMechanism`]) with its adapter
//!   [`LieMechanical`].
//!
//! ```
//! use filippov_runtime::{FnSystem, Method, Options, Problem, solve};
//! // Harmonic oscillator x'' = −x.
//! let osc = FnSystem::new(2, |_t, y: &[f64], dy: &mut [f64]| {
//!     dy[0] = y[1];
//!     dy[1] = -y[0];
//! });
//! let problem = Problem::new(0.0, 1.0, [1.0, 0.0]);
//! let traj = solve(&osc, &problem, &Method::Dopri5(Options::tolerances(1e-9, 1e-12))).unwrap();
//! let x = traj.at(0.5).unwrap()[0];
//! assert!((x - 0.5f64.cos()).abs() < 1e-6);
//! ```
mod error;
pub mod liegroup;
mod mechanical;
pub mod method;
pub mod nonsmooth;
pub mod numeric;
pub mod numerics;
mod options;
mod problem;
mod solution;
mod solve;
mod stats;
pub mod system;

pub use error::{ErrorKind, SolveError};
pub use liegroup::{
    EventDirection, FnLieSystem, LieEvent, LieEventHit, LieInputFn, LieMechanical, LieMechanism,
    LieProblem, LieSdirk, LieState, LieSystem, LieTrajectory, Rkmk5, UnitQuat,
};
pub use mechanical::{InputFn, MechanicalSystem, NumericInputFn, NumericSystem};
pub use method::{Bdf, Dopri5, Method, Rk4, Sdirk4, Stepper};
pub use nonsmooth::{
    NonSmooth, NonSmoothMethod, NonSmoothProblem, SmoothMethod, solve_nonsmooth,
    solve_nonsmooth_with,
};
pub use numerics::control::PiController;
pub use numerics::tableau;
pub use options::Options;
pub use problem::{FnSystem, OdeSystem, Problem};
pub use solution::{Output, Solution, Switch, SwitchKind};
pub use solve::{Observer, integrate, solve, solve_with};
pub use stats::Stats;
pub use system::{ForwardJacobian, Mechanism, ParameterError};
