//! The exceptions a scene raises, each carrying the fields of the typed error it
//! stands for.

use filippov_runtime::{ErrorKind, Solution};
use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::solution::PySolution;

create_exception!(
    filippov,
    FilippovError,
    PyException,
    "The base of every error filippov raises."
);
create_exception!(
    filippov,
    SolveError,
    FilippovError,
    "An integration stopped early. `kind` names the reason (`MaxSteps`, `NonFinite`, \
     `KeepsSwitching`, …), `t` the time (or None), `detail` a dict of the reason's other \
     fields (`column`, `element`, …), and `solution` holds everything computed before."
);
create_exception!(
    filippov,
    ParameterError,
    FilippovError,
    "A scene's parameters make no physical sense; `problems` lists `(parameter, why)`."
);

/// `ParameterError` with its problems.
pub fn parameter_error(py: Python<'_>, scene: &str, e: &filippov_runtime::ParameterError) -> PyErr {
    let err = ParameterError::new_err(format!("{scene}: {e}"));
    let problems: Vec<(String, String)> = e.problems.clone();
    let _ = err.value(py).setattr("problems", problems);
    err
}

/// `SolveError` for `kind`, with the run up to it.
pub fn solve_error(py: Python<'_>, kind: &ErrorKind, message: String, solution: Solution) -> PyErr {
    let detail = PyDict::new(py);
    match kind {
        ErrorKind::StepSizeUnderflow { h, .. } => {
            let _ = detail.set_item("h", *h);
        }
        ErrorKind::NonFinite { component, .. } => {
            let _ = detail.set_item("component", *component);
            if let Some(name) = solution.names().get(*component) {
                let _ = detail.set_item("column", name);
            }
        }
        ErrorKind::InvalidInput(msg) | ErrorKind::InconsistentInitialData(msg) => {
            let _ = detail.set_item("message", msg);
        }
        ErrorKind::IllPosedMode { detail: d, .. } => {
            let _ = detail.set_item("candidates", d);
        }
        ErrorKind::StepNotSolved { detail: d, .. } => {
            let _ = detail.set_item("message", d);
        }
        ErrorKind::KeepsSwitching { element, cycle, .. } => {
            let _ = detail.set_item("element", element);
            let _ = detail.set_item("cycle", cycle);
        }
        ErrorKind::Loops { error, .. } => {
            let _ = detail.set_item("message", error.to_string());
        }
        _ => {}
    }
    let (name, t) = (kind.name(), kind.t());
    let err = SolveError::new_err(message);
    let value = err.value(py);
    let _ = value.setattr("kind", name);
    let _ = value.setattr("t", t);
    let _ = value.setattr("detail", detail);
    let _ = value.setattr("solution", PySolution::from(solution));
    err
}

/// The exception of a failed run, its message the typed error's (with column names).
pub fn from_solve_error(py: Python<'_>, e: filippov_runtime::SolveError) -> PyErr {
    let message = e.to_string();
    solve_error(py, &e.kind, message, *e.solution)
}
