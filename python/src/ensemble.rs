//! Ensembles from Python: `scene.ensemble(...)` draws runs reproducibly, `run(start,
//! stop)` integrates any range of them (on every core, the GIL released) into a table of
//! NumPy columns. Any range gives the rows a plain loop gives, so `filippov.ensembles`
//! can cut an ensemble into chunks for a Dask cluster and get the same table.

use std::ops::Range;

use filippov_runtime::ensemble::{Draw, Ensemble, Table};
use filippov_runtime::nonsmooth::NonSmooth;
use filippov_runtime::system::Parameters;
use numpy::PyArray1;
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};

/// What the Python class needs of an ensemble, whatever its scene.
trait Runs: Send + Sync {
    fn len(&self) -> usize;
    fn input_names(&self) -> Vec<String>;
    fn output_names(&self) -> Vec<String>;
    fn table(&self, runs: Range<usize>, threads: Option<usize>, progress: bool) -> Table;
}

impl<S, const N: usize> Runs for Ensemble<S, N>
where
    S: NonSmooth<N> + Parameters + Sync + 'static,
{
    fn len(&self) -> usize {
        Ensemble::len(self)
    }
    fn input_names(&self) -> Vec<String> {
        Self::names()
    }
    fn output_names(&self) -> Vec<String> {
        filippov_runtime::ensemble::final_state_names(&S::JOINTS)
    }
    fn table(&self, runs: Range<usize>, threads: Option<usize>, progress: bool) -> Table {
        Ensemble::table(self, runs, threads, progress)
    }
}

/// A draw from Python: a number (fixed), `("uniform", low, high)`, or a list or array
/// of values (a grid).
fn draw(what: &str, x: &Bound<'_, PyAny>) -> PyResult<Draw> {
    if let Ok(v) = x.extract::<f64>() {
        return Ok(Draw::Fixed(v));
    }
    if let Ok(t) = x.cast::<PyTuple>() {
        let kind: Option<String> = t.get_item(0).ok().and_then(|k| k.extract().ok());
        if kind.as_deref() == Some("uniform") && t.len() == 3 {
            return Ok(Draw::Uniform {
                low: t.get_item(1)?.extract()?,
                high: t.get_item(2)?.extract()?,
            });
        }
        return Err(PyValueError::new_err(format!(
            "{what}: a draw is a number, (\"uniform\", low, high), or a list of grid values"
        )));
    }
    let values = crate::arrays::as_f64(x)
        .and_then(|a| Ok(a.as_slice()?.to_vec()))
        .map_err(|_| {
            PyTypeError::new_err(format!(
                "{what}: a draw is a number, (\"uniform\", low, high), or a list of grid values"
            ))
        })?;
    Ok(Draw::Grid(values))
}

/// One draw per coordinate: a list whose entries are draws, or nothing (all zero).
fn coordinate_draws(
    what: &str,
    x: Option<&Bound<'_, PyAny>>,
    joints: &[&str],
) -> PyResult<Vec<Draw>> {
    let Some(x) = x else {
        return Ok(vec![Draw::Fixed(0.0); joints.len()]);
    };
    let items: Vec<Bound<'_, PyAny>> = x.try_iter()?.collect::<PyResult<_>>()?;
    if items.len() != joints.len() {
        return Err(PyValueError::new_err(format!(
            "{what} has {} entries for the {} coordinates ({}); give one draw per coordinate",
            items.len(),
            joints.len(),
            joints.join(", ")
        )));
    }
    items
        .iter()
        .zip(joints)
        .map(|(item, j)| draw(&format!("{what}[{j}]"), item))
        .collect()
}

/// An ensemble of `scene`'s class: `parameters` overrides the scene's own values by
/// name with draws.
#[allow(clippy::too_many_arguments)]
pub fn new<S, const N: usize>(
    name: &str,
    scene: &S,
    scene_obj: &Bound<'_, PyAny>,
    t_end: f64,
    parameters: Option<&Bound<'_, PyDict>>,
    q0: Option<&Bound<'_, PyAny>>,
    v0: Option<&Bound<'_, PyAny>>,
    samples: usize,
    seed: u64,
    options: Option<&Bound<'_, PyDict>>,
) -> PyResult<PyEnsemble>
where
    S: NonSmooth<N> + Parameters + Sync + 'static,
{
    let py = scene_obj.py();
    let mut draws: Vec<Draw> = scene.values().into_iter().map(Draw::Fixed).collect();
    if let Some(d) = parameters {
        for (k, v) in d.iter() {
            let k: String = k.extract()?;
            let Some(i) = S::NAMES.iter().position(|p| *p == k) else {
                return Err(PyTypeError::new_err(format!(
                    "{name}.ensemble(): no parameter `{k}`; the parameters are {}",
                    S::NAMES.join(", ")
                )));
            };
            draws[i] = draw(&k, &v)?;
        }
    }
    let joints: Vec<&str> = S::JOINTS.to_vec();
    let q = coordinate_draws("q0", q0, &joints)?;
    let v = coordinate_draws("v0", v0, &joints)?;
    let (method, common) = crate::options::nonsmooth("ensemble", N, options)?;
    if common.t0 != 0.0 || common.tau.is_some() || common.output != filippov_runtime::Output::Steps
    {
        return Err(PyValueError::new_err(
            "ensemble(): runs start at t0 = 0 with no applied forces and keep every step; \
             t0, tau, times and every are not options here",
        ));
    }
    let ens = Ensemble::<S, N>::new(draws, q, v, samples, seed, t_end)
        .map_err(|e| PyValueError::new_err(format!("{name}.ensemble(): {e}")))?
        .with_method(method);
    // What rebuilds it elsewhere (pickle): the scene and these arguments.
    let spec = PyDict::new(py);
    spec.set_item("t_end", t_end)?;
    spec.set_item("parameters", parameters)?;
    spec.set_item("q0", q0)?;
    spec.set_item("v0", v0)?;
    spec.set_item("samples", samples)?;
    spec.set_item("seed", seed)?;
    if let Some(o) = options {
        spec.update(o.as_mapping())?;
    }
    Ok(PyEnsemble {
        runs: Box::new(ens),
        scene: scene_obj.clone().unbind(),
        spec: spec.unbind(),
    })
}

/// What pickle gets: the function that rebuilds, and its arguments (scene, spec).
type Reduced<'py> = (Bound<'py, PyAny>, (Py<PyAny>, Py<PyDict>));

/// Runs of one scene drawn reproducibly (`scene.ensemble(t_end, parameters={…}, q0=[…],
/// v0=[…], samples=…, seed=…, **options)`): `len(ensemble)` runs, `run(start, stop)`
/// integrates a range of them. Pickles by its scene and arguments.
#[pyclass(name = "Ensemble", module = "filippov", frozen)]
pub struct PyEnsemble {
    runs: Box<dyn Runs>,
    scene: Py<PyAny>,
    spec: Py<PyDict>,
}

#[pymethods]
impl PyEnsemble {
    fn __len__(&self) -> usize {
        self.runs.len()
    }

    /// The inputs' names: the parameters, then `q0_<joint>`, then `v0_<joint>`.
    #[getter]
    fn input_names(&self) -> Vec<String> {
        self.runs.input_names()
    }

    /// The outputs' names: the final `q_<joint>`, `v_<joint>`, the switch-log entries
    /// and the steps.
    #[getter]
    fn output_names(&self) -> Vec<String> {
        self.runs.output_names()
    }

    /// Runs `start` to `stop` (default: all) as a dict of NumPy columns: `run`, the
    /// inputs, the outputs (NaN for a failed run), `error_kind` and `error` (empty
    /// strings for a run that finished). `threads`: None for every core, 1 for a loop on
    /// this thread. The GIL is released while the runs integrate.
    #[pyo3(signature = (start=0, stop=None, threads=None, progress=false))]
    fn run<'py>(
        &self,
        py: Python<'py>,
        start: usize,
        stop: Option<usize>,
        threads: Option<usize>,
        progress: bool,
    ) -> PyResult<Bound<'py, PyDict>> {
        let stop = stop.unwrap_or(self.runs.len()).min(self.runs.len());
        if start > stop {
            return Err(PyValueError::new_err(format!(
                "start = {start} is past stop = {stop}"
            )));
        }
        if threads == Some(0) {
            return Err(PyValueError::new_err(
                "threads must be at least 1 (None: every core)",
            ));
        }
        let runs = &self.runs;
        let table = py.detach(|| runs.table(start..stop, threads, progress));
        columns(py, &table)
    }

    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Reduced<'py>> {
        let module = self.scene.bind(py).get_type().getattr("__module__")?;
        let rebuild = py
            .import(module.extract::<String>()?.as_str())?
            .getattr("_rebuild_ensemble")?;
        Ok((rebuild, (self.scene.clone_ref(py), self.spec.clone_ref(py))))
    }

    fn __repr__(&self) -> String {
        format!(
            "Ensemble({} runs; inputs {}; outputs {})",
            self.runs.len(),
            self.runs.input_names().join(", "),
            self.runs.output_names().join(", ")
        )
    }
}

/// The table as a dict of columns.
fn columns<'py>(py: Python<'py>, t: &Table) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let rows = t.runs.len();
    let runs: Vec<i64> = t.runs.iter().map(|&r| r as i64).collect();
    d.set_item("run", PyArray1::from_vec(py, runs))?;
    let wi = t.input_names.len();
    for (j, name) in t.input_names.iter().enumerate() {
        let col: Vec<f64> = (0..rows).map(|k| t.inputs[k * wi + j]).collect();
        d.set_item(name, PyArray1::from_vec(py, col))?;
    }
    let wo = t.output_names.len();
    for (j, name) in t.output_names.iter().enumerate() {
        let col: Vec<f64> = (0..rows).map(|k| t.outputs[k * wo + j]).collect();
        d.set_item(name, PyArray1::from_vec(py, col))?;
    }
    let np = py.import("numpy")?;
    let kinds: Vec<&str> = t
        .errors
        .iter()
        .map(|e| e.as_ref().map_or("", |e| e.kind.as_str()))
        .collect();
    let messages: Vec<&str> = t
        .errors
        .iter()
        .map(|e| e.as_ref().map_or("", |e| e.message.as_str()))
        .collect();
    // Unicode columns (not object arrays), so that `numpy.savez` keeps them without pickle.
    d.set_item(
        "error_kind",
        np.call_method1("array", (PyList::new(py, kinds)?, "U"))?,
    )?;
    d.set_item(
        "error",
        np.call_method1("array", (PyList::new(py, messages)?, "U"))?,
    )?;
    Ok(d)
}

/// `scene.ensemble(**spec)`: what pickle calls to rebuild an ensemble.
#[pyfunction]
pub fn _rebuild_ensemble<'py>(
    scene: &Bound<'py, PyAny>,
    spec: &Bound<'py, PyDict>,
) -> PyResult<Bound<'py, PyAny>> {
    let t_end = spec
        .get_item("t_end")?
        .ok_or_else(|| PyValueError::new_err("no t_end"))?;
    let kwargs = spec.copy()?;
    kwargs.del_item("t_end")?;
    scene.call_method("ensemble", (t_end,), Some(&kwargs))
}
