//! The entry points of a non-smooth run: parameters checked, then the chosen driver
//! (event-driven, [`super::event`], or time-stepping, [`super::timestepping`]).

use nalgebra::SVector;

use super::event::event_driven_observed;
use super::timestepping::time_stepping_observed;
use super::{NonSmoothMethod, NonSmoothProblem};
use crate::element::NonSmooth;
use crate::solve::{Observer, unobserved};
use crate::{ErrorKind, Solution, SolveError};

/// Integrates `problem` with the chosen non-smooth method.
pub fn solve_nonsmooth<S, F, const N: usize>(
    system: &S,
    input: &F,
    problem: &NonSmoothProblem<N>,
    method: &NonSmoothMethod,
) -> Result<Solution, SolveError>
where
    S: NonSmooth<N>,
    F: Fn(f64, &SVector<f64, N>, &SVector<f64, N>) -> SVector<f64, N>,
{
    solve_nonsmooth_with(system, input, problem, method, &mut unobserved)
}

/// [`solve_nonsmooth`] with an [`Observer`] called after every accepted step (of the
/// state `[q; v]`); breaking ends the run with [`ErrorKind::Cancelled`].
pub fn solve_nonsmooth_with<S, F, O, const N: usize>(
    system: &S,
    input: &F,
    problem: &NonSmoothProblem<N>,
    method: &NonSmoothMethod,
    observer: &mut O,
) -> Result<Solution, SolveError>
where
    S: NonSmooth<N>,
    F: Fn(f64, &SVector<f64, N>, &SVector<f64, N>) -> SVector<f64, N>,
    O: Observer + ?Sized,
{
    // Parameters first: a non-positive mass or a negative critical force is reported by
    // name before anything is integrated.
    if let Err(e) = system.validate() {
        return Err(SolveError::new(
            ErrorKind::InvalidInput(e.to_string()),
            Solution::new(
                crate::element::column_names::<S, N>(system),
                2 * N,
                problem.output.clone(),
            )
            .with_dense_positions(Some(N)),
        ));
    }
    match *method {
        NonSmoothMethod::EventDriven { method, options } => {
            event_driven_observed(system, input, problem, method, &options, observer)
        }
        NonSmoothMethod::TimeStepping { h, theta } => {
            time_stepping_observed(system, input, problem, h, theta, observer)
        }
    }
}
