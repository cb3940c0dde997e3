//! The entry points of a non-smooth run: the step-level [`Integrator`] run to the end
//! (event-driven, [`super::event`], or time-stepping, [`super::timestepping`]).

use nalgebra::SVector;

use super::integrator::Integrator;
use super::{NonSmoothMethod, NonSmoothProblem};
use crate::element::NonSmooth;
use crate::solve::{Observer, unobserved};
use crate::{Solution, SolveError};

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
/// state `[q; v]`); breaking ends the run with [`ErrorKind::Cancelled`](crate::ErrorKind::Cancelled).
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
    let mut run = Integrator::start(system, input, problem, method)?;
    while run.t() < problem.tf && run.ended().is_none() {
        if let Err(kind) = run.step_observed(problem.tf, observer) {
            return Err(SolveError::new(kind, run.into_solution()));
        }
    }
    Ok(run.into_solution())
}
