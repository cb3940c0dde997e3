//! A run's result in Python: the rows as NumPy arrays with named columns, dense output
//! at any time, the switch log and the user events as records, the statistics.

use filippov_runtime::{LieState, LieTrajectory, Mode, Solution, SwitchKind};
use pyo3::exceptions::{PyKeyError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::arrays::{as_f64, shaped, vector};

/// The result of a run (`scene.solve`, `scene.solve_nonsmooth`, `Integrator.solution`).
///
/// `t` and `y` are the rows (`y[i]` the state at `t[i]`); `names` the columns (`q_<joint>`,
/// `v_<joint>`, then a non-smooth run's element forces `f_<element>`), and
/// `solution["q_elbow"]` one column. `at(t)` evaluates the method's dense output
/// anywhere in the run. `switches` is the log of every switch as records (a list of
/// dicts, `pandas.DataFrame(solution.switches)` makes a table of it).
///
/// A run of a scene with spherical or free joints has the columns `q_<slot>` (a
/// quaternion as `q_<joint>.qw` … `q_<joint>.qz`) and `v_<coordinate>`, and `at(t)`
/// reads the integrator's dense output on the group (unit quaternions).
#[pyclass(name = "Solution", module = "filippov", frozen)]
pub struct PySolution {
    pub inner: Solution,
    /// For a run on a Lie group: its trajectory, whose dense output `at` reads.
    pub group: Option<OnGroup>,
}

/// The dense output of a run on a Lie group: the trajectory, and how one of its states
/// is written as a row of the solution.
pub struct OnGroup {
    pub trajectory: LieTrajectory,
    pub row: fn(&LieState, &mut [f64]),
}

impl From<Solution> for PySolution {
    fn from(inner: Solution) -> Self {
        PySolution { inner, group: None }
    }
}

fn mode(m: Option<Mode>) -> Option<String> {
    m.map(|m| format!("{m:?}"))
}

fn kind(k: SwitchKind) -> String {
    format!("{k:?}")
}

#[pymethods]
impl PySolution {
    /// The times of the rows.
    #[getter]
    fn t<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        vector(py, self.inner.times())
    }

    /// The rows, shape `(len(t), len(names))`.
    #[getter]
    fn y<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let s = &self.inner;
        let data: Vec<f64> = (0..s.len())
            .flat_map(|i| s.state(i).iter().copied())
            .collect();
        shaped(py, data, Some(s.len()), &[s.dim()])
    }

    /// The columns' names.
    #[getter]
    fn names(&self) -> Vec<String> {
        self.inner.names().to_vec()
    }

    fn __len__(&self) -> usize {
        self.inner.len()
    }

    /// One column by name (`"t"` gives the times).
    fn __getitem__<'py>(&self, py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyAny>> {
        if name == "t" {
            return Ok(self.t(py));
        }
        match self.inner.column(name) {
            Some(c) => Ok(vector(py, &c)),
            None => Err(PyKeyError::new_err(format!(
                "no column `{name}`; the columns are t, {}",
                self.inner.names().join(", ")
            ))),
        }
    }

    /// The state at time `t` (a number: shape `(len(names),)`), or at each of the times
    /// in an array (shape `(len(times), len(names))`), on the method's dense output.
    fn at<'py>(&self, py: Python<'py>, t: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        let s = &self.inner;
        let (times, batch): (Vec<f64>, Option<usize>) = match t.extract::<f64>() {
            Ok(x) => (vec![x], None),
            Err(_) => {
                let a = as_f64(t)?;
                let v = a.as_slice()?.to_vec();
                let n = v.len();
                (v, Some(n))
            }
        };
        let mut out = vec![0.0; times.len() * s.dim()];
        let (Some(&first), Some(&last)) = (s.times().first(), s.times().last()) else {
            return Err(PyValueError::new_err("the solution has no rows"));
        };
        // A state on the group to read the trajectory into, one for all the times.
        let mut on_group = self
            .group
            .as_ref()
            .and_then(|g| Some((g, g.trajectory.last()?.1)));
        for (k, &tk) in times.iter().enumerate() {
            let row = &mut out[k * s.dim()..(k + 1) * s.dim()];
            let inside = match &mut on_group {
                Some((g, y)) => {
                    g.trajectory.at_into(tk, y) && {
                        (g.row)(y, row);
                        true
                    }
                }
                None => s.at_into(tk, row),
            };
            if !inside {
                return Err(PyValueError::new_err(format!(
                    "t = {tk} is outside the run [{first}, {last}]"
                )));
            }
        }
        shaped(py, out, batch, &[s.dim()])
    }

    /// The switch log: one dict per entry, in time order, with `t`, `kind` (`Mode`,
    /// `Impact`, `Settled`, `HandOverToTimeStepping`, `HandBack`, `Reset`), `element`,
    /// `index`, `from`, `to` (modes such as `Stick`, `SlipPos(0)`, `Contact`), `jump`
    /// (force jump or impulse), `accumulation`, and the states `before` and `after`.
    #[getter]
    fn switches<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let list = PyList::empty(py);
        for s in &self.inner.switches {
            let d = PyDict::new(py);
            d.set_item("t", s.t)?;
            d.set_item("kind", kind(s.kind))?;
            d.set_item("element", s.element.clone())?;
            d.set_item("index", s.index)?;
            d.set_item("from", mode(s.from))?;
            d.set_item("to", mode(s.to))?;
            d.set_item("jump", s.jump)?;
            d.set_item("accumulation", s.accumulation)?;
            d.set_item("before", vector(py, &s.before))?;
            d.set_item("after", vector(py, &s.after))?;
            list.append(d)?;
        }
        Ok(list)
    }

    /// The user events located in the run: dicts with `event`, `t` and `state`.
    #[getter]
    fn events<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let list = PyList::empty(py);
        for e in &self.inner.events {
            let d = PyDict::new(py);
            d.set_item("event", e.event)?;
            d.set_item("t", e.t)?;
            d.set_item("state", vector(py, &e.state))?;
            list.append(d)?;
        }
        Ok(list)
    }

    /// The run's cost: steps, rejected steps, right-hand sides, Jacobians, events, …
    #[getter]
    fn stats<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let s = &self.inner.stats;
        let d = PyDict::new(py);
        d.set_item("steps", s.steps)?;
        d.set_item("rejected_steps", s.rejected_steps)?;
        d.set_item("rhs_evaluations", s.rhs_evaluations)?;
        d.set_item("jacobian_evaluations", s.jacobian_evaluations)?;
        d.set_item("finite_difference_jacobians", s.finite_difference_jacobians)?;
        d.set_item("lu_factorisations", s.lu_factorisations)?;
        d.set_item("newton_iterations", s.newton_iterations)?;
        d.set_item("events", s.events)?;
        d.set_item("mode_changes", s.mode_changes)?;
        d.set_item("zeno_detected", s.zeno_detected)?;
        d.set_item("zeno_handovers", s.zeno_handovers)?;
        d.set_item("resting_energy_dropped", s.resting_energy_dropped)?;
        d.set_item("contact_sweeps", s.contact_sweeps)?;
        Ok(d)
    }

    /// `{"t": times, name: column, …}`.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        d.set_item("t", self.t(py))?;
        for (j, name) in self.inner.names().iter().enumerate() {
            d.set_item(name, vector(py, &self.inner.component(j)))?;
        }
        Ok(d)
    }

    /// The rows as a `pandas.DataFrame` (columns `t` and `names`); needs pandas.
    fn to_pandas<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let pandas = py.import("pandas").map_err(|_| {
            pyo3::exceptions::PyImportError::new_err(
                "to_pandas needs pandas (`pip install pandas`); to_dict() gives the same columns as NumPy arrays",
            )
        })?;
        pandas.call_method1("DataFrame", (self.to_dict(py)?,))
    }

    fn __repr__(&self) -> String {
        let s = &self.inner;
        let span = match (s.times().first(), s.times().last()) {
            (Some(a), Some(b)) => format!("t ∈ [{a}, {b}]"),
            _ => "empty".into(),
        };
        format!(
            "Solution({} rows, {span}, columns {}, {} switches, {} steps)",
            s.len(),
            s.names().join(", "),
            s.switches.len(),
            s.stats.steps
        )
    }
}
