//! Scenes with contacts (`#[contact]`): the capability `contacts` of
//! [`module!`](crate::module). Their runs are the contact integrators:
//! `contact_event_driven` (contacts alone; spatial ones where their slips stop along a
//! fixed direction) or `contact_time_stepping` (Moreau–Jean, planar and spatial, beside
//! joint friction and stops).

use filippov_runtime::contacts::Contacts;
use filippov_runtime::system::Parameters;
use filippov_runtime::{
    Mechanism, Method, NonSmoothMethod, contact_event_driven, contact_time_stepping,
};
use nalgebra::SVector;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::from_solve_error;
use crate::scene::nonsmooth_problem;
use crate::solution::PySolution;

/// Which contact integrator.
enum How {
    /// Moreau–Jean with this step.
    Stepping(f64),
    /// Event-driven with this method between events.
    Events(Method),
}

/// A run of a scene with contacts, the GIL released while it integrates: event-driven
/// (default) or `method="time_stepping"` with a step `h`; `solve_nonsmooth`'s other
/// options. The solution has the contact forces as columns (`λ_<contact>.n`, then the
/// tangential `λ_<contact>.<axis>`).
pub fn solve_contacts<S, const N: usize, const K: usize, const T: usize>(
    py: Python<'_>,
    name: &str,
    scene: &S,
    t_end: f64,
    q0: &Bound<'_, PyAny>,
    v0: Option<&Bound<'_, PyAny>>,
    opts: Option<&Bound<'_, PyDict>>,
) -> PyResult<PySolution>
where
    S: Mechanism<N> + Contacts<N, K, T> + Parameters + Sync,
{
    let (problem, method, tau) =
        nonsmooth_problem::<S, N>("solve_contacts", name, t_end, q0, v0, opts)?;
    let how = match method {
        NonSmoothMethod::TimeStepping { h, theta } => {
            if theta != 1.0 {
                return Err(PyValueError::new_err(format!(
                    "solve_contacts(): contacts are time-stepped by Moreau–Jean's scheme, \
                     implicit in the velocity (θ = 1); drop theta = {theta}"
                )));
            }
            How::Stepping(h)
        }
        NonSmoothMethod::EventDriven(m) => How::Events(m),
        other => {
            return Err(PyValueError::new_err(format!(
                "solve_contacts(): {other:?} is not a contact integrator; the methods are \
                 event_driven and time_stepping"
            )));
        }
    };
    let run = py.detach(|| {
        let input = move |_t: f64, _q: &SVector<f64, N>, _v: &SVector<f64, N>| tau;
        match &how {
            How::Stepping(h) => contact_time_stepping(scene, &input, &problem, *h),
            How::Events(m) => contact_event_driven(scene, &input, &problem, m),
        }
    });
    run.map(PySolution::from)
        .map_err(|e| from_solve_error(py, e))
}

/// The contacts' names, as declared.
pub fn contacts<S, const N: usize, const K: usize, const T: usize>() -> Vec<&'static str>
where
    S: Contacts<N, K, T>,
{
    S::CONTACTS.to_vec()
}
