//! Runtime of filippov: what generated kernels implement, an independent numeric
//! reference of the same physics, and the integrators that run them.
//!
//! * [`system`]: the [`Mechanism`] trait the derive implements.
//! * [`numeric`]: plain numeric RNEA / CRBA / exact `∂M/∂q` over a runtime
//!   [`numeric::Model`] — the cross-check and the baseline.
//! * Integration, separated diffsol-style into the problem ([`OdeSystem`], [`Problem`],
//!   the adapters [`MechanicalSystem`] and [`NumericSystem`]), the methods ([`Rk4`],
//!   [`Dopri5`], [`Sdirk4`], [`Bdf`], tableaus in [`tableau`]), their configuration
//!   ([`Options`], [`PiController`]) and the result ([`Trajectory`], [`Stats`],
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
mod control;
mod error;
pub mod liegroup;
mod mechanical;
mod method;
pub mod nonsmooth;
pub mod numeric;
mod options;
mod problem;
mod stats;
pub mod system;
mod trajectory;

pub use control::PiController;
pub use error::{ErrorKind, SolveError};
pub use liegroup::{
    EventDirection, FnLieSystem, LieEvent, LieEventHit, LieInputFn, LieMechanical, LieMechanism,
    LieProblem, LieSdirk, LieState, LieSystem, LieTrajectory, Rkmk5, UnitQuat,
};
pub use mechanical::{InputFn, MechanicalSystem, NumericInputFn, NumericSystem};
pub use method::tableau;
pub use method::{Bdf, Dopri5, Method, Rk4, Sdirk4, solve};
pub use nonsmooth::{NonSmooth, NonSmoothMethod, NonSmoothProblem, SmoothMethod, solve_nonsmooth};
pub use options::Options;
pub use problem::{FnSystem, OdeSystem, Problem};
pub use stats::Stats;
pub use system::{ForwardJacobian, Mechanism, ParameterError};
pub use trajectory::{Interpolant, Trajectory};
