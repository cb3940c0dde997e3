//! NumPy arrays in and out: a state or a batch of states (one per row), checked against
//! the scene's coordinates, and results shaped like the input.

use numpy::{PyArray1, PyArrayMethods, PyReadonlyArrayDyn, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// Any array-like (list, tuple, array of any dtype) as a C-contiguous `float64` array.
pub fn as_f64<'py>(x: &Bound<'py, PyAny>) -> PyResult<PyReadonlyArrayDyn<'py, f64>> {
    if let Ok(a) = x.extract::<PyReadonlyArrayDyn<'py, f64>>()
        && a.is_c_contiguous()
    {
        return Ok(a);
    }
    let np = x.py().import("numpy")?;
    let a = np.call_method1("ascontiguousarray", (x, "float64"))?;
    a.extract::<PyReadonlyArrayDyn<'py, f64>>()
}

/// States of `n` coordinates: one (shape `(n,)`) or a batch (shape `(b, n)`).
pub struct States {
    /// The values, row after row.
    pub data: Vec<f64>,
    /// `None` for a single state, `Some(b)` for a batch of `b`.
    pub batch: Option<usize>,
}

impl States {
    pub fn count(&self) -> usize {
        self.batch.unwrap_or(1)
    }

    pub fn row(&self, i: usize, n: usize) -> &[f64] {
        &self.data[i * n..(i + 1) * n]
    }
}

/// Reads argument `what` of `scene` as states of its `coordinates`.
pub fn states(
    scene: &str,
    what: &str,
    x: &Bound<'_, PyAny>,
    coordinates: &[&str],
) -> PyResult<States> {
    states_of(scene, what, x, coordinates, "coordinates")
}

/// [`states`] of the entries `names`, which an error calls `noun` ("coordinates",
/// "configuration slots").
pub fn states_of(
    scene: &str,
    what: &str,
    x: &Bound<'_, PyAny>,
    coordinates: &[&str],
    noun: &str,
) -> PyResult<States> {
    let a = as_f64(x)?;
    let n = coordinates.len();
    let shape = a.shape().to_vec();
    let batch = match shape.as_slice() {
        [m] if *m == n => None,
        [b, m] if *m == n => Some(*b),
        _ => {
            return Err(PyValueError::new_err(format!(
                "{what} has shape {shape:?}; {scene} has {n} {noun} ({}), so give an \
                 array of shape ({n},) for one state or (batch, {n}) for a batch",
                coordinates.join(", ")
            )));
        }
    };
    Ok(States {
        data: a.as_slice()?.to_vec(),
        batch,
    })
}

/// The optional arguments `names` of one call agree on the batch: all single, or all
/// batches of one size.
pub fn same_batch(scene: &str, args: &[(&str, &States)]) -> PyResult<()> {
    let (first, s0) = args[0];
    for (name, s) in &args[1..] {
        if s.batch != s0.batch {
            let show =
                |b: Option<usize>| b.map_or("one state".to_string(), |b| format!("a batch of {b}"));
            return Err(PyValueError::new_err(format!(
                "{scene}: {first} is {} but {name} is {}; give them the same shape",
                show(s0.batch),
                show(s.batch)
            )));
        }
    }
    Ok(())
}

/// `data` (`count` blocks of `shape`'s product) as an array of shape `shape`, or
/// `(batch, *shape)` for a batch.
pub fn shaped<'py>(
    py: Python<'py>,
    data: Vec<f64>,
    batch: Option<usize>,
    shape: &[usize],
) -> PyResult<Bound<'py, PyAny>> {
    let mut full: Vec<usize> = batch.into_iter().collect();
    full.extend_from_slice(shape);
    Ok(PyArray1::from_vec(py, data).reshape(full)?.into_any())
}

/// A vector as a one-dimensional array.
pub fn vector<'py>(py: Python<'py>, data: &[f64]) -> Bound<'py, PyAny> {
    PyArray1::from_slice(py, data).into_any()
}
