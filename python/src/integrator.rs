//! The step-level non-smooth integrator in Python, for controller loops: set the
//! input, advance to the next sample, read the state.

use std::mem::ManuallyDrop;
use std::sync::Mutex;

use filippov_runtime::nonsmooth::{Integrator, NoInput, NonSmooth};
use filippov_runtime::{ErrorKind, NonSmoothMethod, NonSmoothProblem, Solution};
use nalgebra::SVector;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays::{states, vector};
use crate::errors::{from_solve_error, solve_error};
use crate::solution::PySolution;

/// What the Python class needs of a run, whatever its scene.
trait Stepping: Send {
    fn t(&self) -> f64;
    fn tf(&self) -> f64;
    fn q(&self) -> Vec<f64>;
    fn v(&self) -> Vec<f64>;
    fn input(&self) -> Vec<f64>;
    fn modes(&self) -> Vec<Option<String>>;
    fn set_input(&mut self, u: &[f64]) -> Result<(), ErrorKind>;
    fn step(&mut self) -> Result<(f64, usize, usize), ErrorKind>;
    fn advance_to(&mut self, t: f64) -> Result<(), ErrorKind>;
    fn solution(&self) -> &Solution;
    fn ended(&self) -> Option<f64>;
}

/// A run that owns its scene. The integrator borrows the scene for as long as it
/// lives, so the scene sits on the heap behind a raw pointer that the run outlives
/// never: `drop` ends the run first, then frees the scene.
struct Owned<S: NonSmooth<N> + 'static, const N: usize> {
    run: ManuallyDrop<Integrator<'static, S, NoInput<N>, N>>,
    scene: *mut S,
}

// SAFETY: the raw pointer is the only handle on the scene besides the integrator's
// shared borrow; both move together, and the scene is `Send + Sync`.
unsafe impl<S: NonSmooth<N> + Send + Sync + 'static, const N: usize> Send for Owned<S, N> where
    Integrator<'static, S, NoInput<N>, N>: Send
{
}

impl<S: NonSmooth<N> + 'static, const N: usize> Drop for Owned<S, N> {
    fn drop(&mut self) {
        // SAFETY: the run, which borrows the scene, is dropped before the scene, and
        // neither is used again.
        unsafe {
            ManuallyDrop::drop(&mut self.run);
            drop(Box::from_raw(self.scene));
        }
    }
}

impl<S: NonSmooth<N> + Send + Sync + 'static, const N: usize> Stepping for Owned<S, N>
where
    Integrator<'static, S, NoInput<N>, N>: Send,
{
    fn t(&self) -> f64 {
        self.run.t()
    }
    fn tf(&self) -> f64 {
        self.run.tf()
    }
    fn q(&self) -> Vec<f64> {
        self.run.q().as_slice().to_vec()
    }
    fn v(&self) -> Vec<f64> {
        self.run.v().as_slice().to_vec()
    }
    fn input(&self) -> Vec<f64> {
        self.run.input().as_slice().to_vec()
    }
    fn modes(&self) -> Vec<Option<String>> {
        self.run
            .modes()
            .into_iter()
            .map(|m| m.map(|m| format!("{m:?}")))
            .collect()
    }
    fn set_input(&mut self, u: &[f64]) -> Result<(), ErrorKind> {
        self.run.set_input(SVector::from_column_slice(u))
    }
    fn step(&mut self) -> Result<(f64, usize, usize), ErrorKind> {
        self.run.step().map(|s| (s.t, s.switches, s.events))
    }
    fn advance_to(&mut self, t: f64) -> Result<(), ErrorKind> {
        self.run.advance_to(t)
    }
    fn solution(&self) -> &Solution {
        self.run.solution()
    }
    fn ended(&self) -> Option<f64> {
        self.run.ended()
    }
}

/// A non-smooth run in progress, driven from Python (`scene.integrator(t_end, q0, v0,
/// **options)`): `set_input(u)` holds the applied generalised forces `u` until the next
/// call; `advance_to(t)` integrates to `t`; `step()` takes one step; `q`, `v`, `t`,
/// `modes` read the state; `solution()` is the run so far, switch log included. After an
/// error every call raises it again, and `solution()` still holds the run up to it.
#[pyclass(name = "Integrator", module = "filippov", frozen)]
pub struct PyIntegrator {
    run: Mutex<Box<dyn Stepping>>,
    scene: String,
    joints: Vec<&'static str>,
}

impl PyIntegrator {
    pub(crate) fn start<S, const N: usize>(
        py: Python<'_>,
        name: &str,
        scene: S,
        problem: &NonSmoothProblem<N>,
        method: &NonSmoothMethod,
        tau: SVector<f64, N>,
    ) -> PyResult<Self>
    where
        S: NonSmooth<N> + Send + Sync + 'static,
    {
        let ptr = Box::into_raw(Box::new(scene));
        // SAFETY: `ptr` stays valid until `Owned::drop`, which ends the run first.
        let scene_ref: &'static S = unsafe { &*ptr };
        let run = match Integrator::held(scene_ref, problem, method) {
            Ok(run) => run,
            Err(e) => {
                // SAFETY: nothing borrows the scene any more.
                drop(unsafe { Box::from_raw(ptr) });
                return Err(from_solve_error(py, e));
            }
        };
        let mut owned = Owned {
            run: ManuallyDrop::new(run),
            scene: ptr,
        };
        if tau.iter().any(|&x| x != 0.0)
            && let Err(kind) = owned.set_input(tau.as_slice())
        {
            let message = kind.to_string();
            return Err(solve_error(py, &kind, message, owned.solution().clone()));
        }
        Ok(PyIntegrator {
            run: Mutex::new(Box::new(owned)),
            scene: name.to_string(),
            joints: S::JOINTS.to_vec(),
        })
    }

    fn with<R>(
        &self,
        py: Python<'_>,
        f: impl FnOnce(&mut dyn Stepping) -> Result<R, ErrorKind> + Send,
    ) -> PyResult<R>
    where
        R: Send,
    {
        let mut run = self.run.lock().unwrap_or_else(|p| p.into_inner());
        let run: &mut dyn Stepping = run.as_mut();
        let out = py.detach(|| f(run));
        out.map_err(|kind| {
            let message = format!("{}: {kind}", self.scene);
            solve_error(py, &kind, message, run.solution().clone())
        })
    }

    fn read<R>(&self, f: impl FnOnce(&dyn Stepping) -> R) -> R {
        let run = self.run.lock().unwrap_or_else(|p| p.into_inner());
        f(run.as_ref())
    }
}

#[pymethods]
impl PyIntegrator {
    /// The time reached.
    #[getter]
    fn t(&self) -> f64 {
        self.read(|r| r.t())
    }

    /// The end of the run.
    #[getter]
    fn tf(&self) -> f64 {
        self.read(|r| r.tf())
    }

    /// The positions now.
    #[getter]
    fn q<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        vector(py, &self.read(|r| r.q()))
    }

    /// The velocities now.
    #[getter]
    fn v<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        vector(py, &self.read(|r| r.v()))
    }

    /// The held input `u`.
    #[getter]
    fn input<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        vector(py, &self.read(|r| r.input()))
    }

    /// Each element's mode (`Stick`, `SlipPos(0)`, `Contact`, …; None for a time-stepping
    /// run, which has no modes between steps).
    #[getter]
    fn modes(&self) -> Vec<Option<String>> {
        self.read(|r| r.modes())
    }

    /// The time a terminal event ended the run at, if one did (None otherwise).
    #[getter]
    fn ended(&self) -> Option<f64> {
        self.read(|r| r.ended())
    }

    /// Whether the run can go no further: it reached `tf`, or a terminal event ended it.
    #[getter]
    fn done(&self) -> bool {
        self.read(|r| r.t() >= r.tf() || r.ended().is_some())
    }

    /// Holds the applied generalised forces `u` (one per coordinate) from now on.
    fn set_input(&self, py: Python<'_>, u: &Bound<'_, PyAny>) -> PyResult<()> {
        let u = states(&self.scene, "u", u, &self.joints)?;
        if u.batch.is_some() {
            return Err(PyValueError::new_err(format!(
                "{}: u is one value per coordinate, shape ({},)",
                self.scene,
                self.joints.len()
            )));
        }
        self.with(py, move |r| r.set_input(&u.data))
    }

    /// One step; returns `{"t", "switches", "events"}` (entries added to the logs).
    fn step<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let (t, switches, events) = self.with(py, |r| r.step())?;
        let d = PyDict::new(py);
        d.set_item("t", t)?;
        d.set_item("switches", switches)?;
        d.set_item("events", events)?;
        Ok(d)
    }

    /// Integrates to time `t` (the GIL released meanwhile).
    fn advance_to(&self, py: Python<'_>, t: f64) -> PyResult<()> {
        self.with(py, move |r| r.advance_to(t))
    }

    /// The run so far: rows, switch log, statistics (a copy).
    fn solution(&self) -> PySolution {
        PySolution::from(self.read(|r| r.solution().clone()))
    }

    fn __repr__(&self) -> String {
        self.read(|r| format!("Integrator({}, t = {}, tf = {})", self.scene, r.t(), r.tf()))
    }
}
