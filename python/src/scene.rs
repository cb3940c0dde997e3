//! What every scene class does, generic over the scene: the class that
//! [`module!`](crate::module) writes for a scene calls these.

use filippov_runtime::kernels::{InverseDynamics, Kinematics};
use filippov_runtime::nonsmooth::NonSmooth;
use filippov_runtime::system::Parameters;
use filippov_runtime::{
    MechanicalSystem, Mechanism, NonSmoothProblem, Problem, solve as solve_smooth,
    solve_nonsmooth as solve_ns,
};
use nalgebra::SVector;
use pyo3::exceptions::{PyKeyError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

use crate::arrays::{States, same_batch, shaped, states};
use crate::errors::{from_solve_error, parameter_error};
use crate::integrator::PyIntegrator;
use crate::options;
use crate::solution::PySolution;

/// The scene built from keyword arguments, one per parameter, and checked.
pub fn new<S, const N: usize>(name: &str, kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<S>
where
    S: Parameters + Mechanism<N>,
{
    let mut values = vec![f64::NAN; S::NAMES.len()];
    let mut given = vec![false; S::NAMES.len()];
    if let Some(d) = kwargs {
        for (k, v) in d.iter() {
            let k: String = k.extract()?;
            let Some(i) = S::NAMES.iter().position(|p| *p == k) else {
                let expect = if S::NAMES.is_empty() {
                    "it takes no parameters".to_string()
                } else {
                    format!("its parameters are {}", S::NAMES.join(", "))
                };
                return Err(PyTypeError::new_err(format!(
                    "{name}() got an unexpected parameter `{k}`; {expect}"
                )));
            };
            values[i] = v.extract::<f64>().map_err(|_| {
                PyTypeError::new_err(format!("{name}(): parameter `{k}` must be a number"))
            })?;
            given[i] = true;
        }
    }
    let missing: Vec<&str> = S::NAMES
        .iter()
        .zip(&given)
        .filter(|(_, g)| !**g)
        .map(|(n, _)| *n)
        .collect();
    if !missing.is_empty() {
        return Err(PyTypeError::new_err(format!(
            "{name}() is missing parameter{} {}; give every parameter by name ({})",
            if missing.len() > 1 { "s" } else { "" },
            missing.join(", "),
            S::NAMES.join(", ")
        )));
    }
    let scene = S::from_values(&values).expect("one value per parameter");
    scene
        .validate()
        .map_err(|e| Python::attach(|py| parameter_error(py, name, &e)))?;
    Ok(scene)
}

/// `{parameter: value}`.
pub fn parameters<'py, S: Parameters>(py: Python<'py>, scene: &S) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for (k, v) in S::NAMES.iter().zip(scene.values()) {
        d.set_item(*k, v)?;
    }
    Ok(d)
}

/// `Name(p=…, …)`.
pub fn repr<S: Parameters>(name: &str, scene: &S) -> String {
    let args: Vec<String> = S::NAMES
        .iter()
        .zip(scene.values())
        .map(|(k, v)| format!("{k}={v:?}"))
        .collect();
    format!("{name}({})", args.join(", "))
}

fn vec<const N: usize>(x: &[f64]) -> SVector<f64, N> {
    SVector::from_column_slice(x)
}

/// The arguments `(q, v, …)` of a kernel call, read and checked against each other.
fn read<S: Mechanism<N>, const N: usize>(
    name: &str,
    args: &[(&str, &Bound<'_, PyAny>)],
) -> PyResult<Vec<States>> {
    let joints: Vec<&str> = S::JOINTS.to_vec();
    let read: Vec<States> = args
        .iter()
        .map(|(what, x)| states(name, what, x, &joints))
        .collect::<PyResult<_>>()?;
    let pairs: Vec<(&str, &States)> = args.iter().map(|a| a.0).zip(&read).collect();
    same_batch(name, &pairs)?;
    Ok(read)
}

/// `tau` or zeros shaped like `like`.
fn or_zeros<const N: usize>(
    name: &str,
    joints: &[&str],
    tau: Option<&Bound<'_, PyAny>>,
    like: &States,
) -> PyResult<States> {
    match tau {
        Some(t) => {
            let s = states(name, "tau", t, joints)?;
            same_batch(name, &[("q", like), ("tau", &s)])?;
            Ok(s)
        }
        None => Ok(States {
            data: vec![0.0; like.count() * N],
            batch: like.batch,
        }),
    }
}

/// `M(q)`: shape `(n, n)`, or `(batch, n, n)`.
pub fn mass_matrix<'py, S: Mechanism<N>, const N: usize>(
    py: Python<'py>,
    name: &str,
    scene: &S,
    q: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyAny>> {
    let q = read::<S, N>(name, &[("q", q)])?.remove(0);
    let mut out = Vec::with_capacity(q.count() * N * N);
    for i in 0..q.count() {
        let m = scene.mass_matrix(&vec(q.row(i, N)));
        // Row-major, as NumPy reads it.
        out.extend(m.transpose().iter().copied());
    }
    shaped(py, out, q.batch, &[N, N])
}

/// `v̇ = FD(q, v, τ)` (`τ` zero when not given).
pub fn forward_dynamics<'py, S: Mechanism<N>, const N: usize>(
    py: Python<'py>,
    name: &str,
    scene: &S,
    q: &Bound<'py, PyAny>,
    v: &Bound<'py, PyAny>,
    tau: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    let r = read::<S, N>(name, &[("q", q), ("v", v)])?;
    let tau = or_zeros::<N>(name, &S::JOINTS, tau, &r[0])?;
    let mut out = Vec::with_capacity(r[0].count() * N);
    for i in 0..r[0].count() {
        let a = scene.forward_dynamics(
            &vec(r[0].row(i, N)),
            &vec(r[1].row(i, N)),
            &vec(tau.row(i, N)),
        );
        out.extend(a.iter().copied());
    }
    shaped(py, out, r[0].batch, &[N])
}

/// `(v̇, ∂v̇/∂q, ∂v̇/∂v)`, each with the batch's leading axis if batched.
pub fn forward_dynamics_jacobian<'py, S: Mechanism<N>, const N: usize>(
    py: Python<'py>,
    name: &str,
    scene: &S,
    q: &Bound<'py, PyAny>,
    v: &Bound<'py, PyAny>,
    tau: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyTuple>> {
    let r = read::<S, N>(name, &[("q", q), ("v", v)])?;
    let tau = or_zeros::<N>(name, &S::JOINTS, tau, &r[0])?;
    let b = r[0].count();
    let (mut a, mut dq, mut dv) = (
        Vec::with_capacity(b * N),
        Vec::with_capacity(b * N * N),
        Vec::with_capacity(b * N * N),
    );
    for i in 0..b {
        let j = scene.forward_dynamics_jacobian(
            &vec(r[0].row(i, N)),
            &vec(r[1].row(i, N)),
            &vec(tau.row(i, N)),
        );
        a.extend(j.acceleration.iter().copied());
        dq.extend(j.d_dq.transpose().iter().copied());
        dv.extend(j.d_dv.transpose().iter().copied());
    }
    let batch = r[0].batch;
    PyTuple::new(
        py,
        [
            shaped(py, a, batch, &[N])?,
            shaped(py, dq, batch, &[N, N])?,
            shaped(py, dv, batch, &[N, N])?,
        ],
    )
}

/// `τ = ID(q, v, a)`.
pub fn inverse_dynamics<'py, S, const N: usize>(
    py: Python<'py>,
    name: &str,
    scene: &S,
    q: &Bound<'py, PyAny>,
    v: &Bound<'py, PyAny>,
    a: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyAny>>
where
    S: Mechanism<N> + InverseDynamics<N>,
{
    let r = read::<S, N>(name, &[("q", q), ("v", v), ("a", a)])?;
    let mut out = Vec::with_capacity(r[0].count() * N);
    for i in 0..r[0].count() {
        let t = scene.inverse_dynamics(
            &vec(r[0].row(i, N)),
            &vec(r[1].row(i, N)),
            &vec(r[2].row(i, N)),
        );
        out.extend(t.iter().copied());
    }
    shaped(py, out, r[0].batch, &[N])
}

fn frame_id<S: Kinematics<N>, const N: usize>(
    name: &str,
    frame: &str,
) -> PyResult<filippov_runtime::kernels::FrameId<S>> {
    S::frame(frame).ok_or_else(|| {
        PyKeyError::new_err(format!(
            "{name} has no frame `{frame}`; its frames are {}",
            S::FRAMES.join(", ")
        ))
    })
}

/// `kernel(frame, q)` of each state, each result `shape` long, shaped like `q`.
fn per_frame<'py, S, const N: usize>(
    py: Python<'py>,
    name: &str,
    frame: &str,
    q: &Bound<'py, PyAny>,
    shape: &[usize],
    kernel: impl Fn(filippov_runtime::kernels::FrameId<S>, &SVector<f64, N>) -> Vec<f64>,
) -> PyResult<Bound<'py, PyAny>>
where
    S: Mechanism<N> + Kinematics<N>,
{
    let id = frame_id::<S, N>(name, frame)?;
    let q = read::<S, N>(name, &[("q", q)])?.remove(0);
    let mut out = Vec::with_capacity(q.count() * shape.iter().product::<usize>());
    for i in 0..q.count() {
        out.extend(kernel(id, &vec(q.row(i, N))));
    }
    shaped(py, out, q.batch, shape)
}

/// The world pose of `frame` as a 4 × 4 homogeneous matrix (`(batch, 4, 4)` batched).
pub fn frame_pose<'py, S, const N: usize>(
    py: Python<'py>,
    name: &str,
    scene: &S,
    frame: &str,
    q: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyAny>>
where
    S: Mechanism<N> + Kinematics<N>,
{
    per_frame(py, name, frame, q, &[4, 4], |id, q| {
        let h = scene.frame_pose(id, q).to_homogeneous();
        h.transpose().iter().copied().collect()
    })
}

/// The frame's Jacobian, rows `(ṗ, ω)` in world axes: `(6, n)` (`(batch, 6, n)`).
pub fn frame_jacobian<'py, S, const N: usize>(
    py: Python<'py>,
    name: &str,
    scene: &S,
    frame: &str,
    q: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyAny>>
where
    S: Mechanism<N> + Kinematics<N>,
{
    per_frame(py, name, frame, q, &[6, N], |id, q| {
        scene
            .frame_jacobian(id, q)
            .transpose()
            .iter()
            .copied()
            .collect()
    })
}

/// One initial state `(q0, v0)`, `v0` zero when not given.
fn initial<S: Mechanism<N>, const N: usize>(
    name: &str,
    q0: &Bound<'_, PyAny>,
    v0: Option<&Bound<'_, PyAny>>,
) -> PyResult<(SVector<f64, N>, SVector<f64, N>)> {
    let joints: Vec<&str> = S::JOINTS.to_vec();
    let one = |what: &str, x: &Bound<'_, PyAny>| -> PyResult<SVector<f64, N>> {
        let s = states(name, what, x, &joints)?;
        if s.batch.is_some() {
            return Err(PyValueError::new_err(format!(
                "{name}: {what} must be one state of shape ({N},); a run starts from one state"
            )));
        }
        Ok(vec(&s.data))
    };
    let q = one("q0", q0)?;
    let v = match v0 {
        Some(v) => one("v0", v)?,
        None => SVector::zeros(),
    };
    Ok((q, v))
}

/// A smooth run from `(q0, v0)` to `t_end`, the GIL released while it integrates.
pub fn solve<S, const N: usize>(
    py: Python<'_>,
    name: &str,
    scene: &S,
    t_end: f64,
    q0: &Bound<'_, PyAny>,
    v0: Option<&Bound<'_, PyAny>>,
    opts: Option<&Bound<'_, PyDict>>,
) -> PyResult<PySolution>
where
    S: Mechanism<N> + Sync,
{
    let (q, v) = initial::<S, N>(name, q0, v0)?;
    let (method, common) = options::smooth(N, opts)?;
    let mut y0 = q.as_slice().to_vec();
    y0.extend_from_slice(v.as_slice());
    let problem = Problem::new(common.t0, t_end, y0).with_output(common.output);
    let tau: SVector<f64, N> = common.tau.as_deref().map_or(SVector::zeros(), vec);
    let run = py.detach(|| {
        let sys = MechanicalSystem::new(
            scene,
            |_t: f64, _q: &SVector<f64, N>, _v: &SVector<f64, N>| tau,
        );
        solve_smooth(&sys, &problem, &method)
    });
    run.map(PySolution::from)
        .map_err(|e| from_solve_error(py, e))
}

/// The non-smooth problem and method from the Python arguments.
fn nonsmooth_problem<S: Mechanism<N>, const N: usize>(
    call: &str,
    name: &str,
    t_end: f64,
    q0: &Bound<'_, PyAny>,
    v0: Option<&Bound<'_, PyAny>>,
    opts: Option<&Bound<'_, PyDict>>,
) -> PyResult<(
    NonSmoothProblem<N>,
    filippov_runtime::NonSmoothMethod,
    SVector<f64, N>,
)> {
    let (q, v) = initial::<S, N>(name, q0, v0)?;
    let (method, common) = options::nonsmooth(call, N, opts)?;
    let problem = NonSmoothProblem::new(common.t0, t_end, q, v).with_output(common.output);
    let tau: SVector<f64, N> = common.tau.as_deref().map_or(SVector::zeros(), vec);
    Ok((problem, method, tau))
}

/// A non-smooth run (event-driven by default), the GIL released while it integrates.
pub fn solve_nonsmooth<S, const N: usize>(
    py: Python<'_>,
    name: &str,
    scene: &S,
    t_end: f64,
    q0: &Bound<'_, PyAny>,
    v0: Option<&Bound<'_, PyAny>>,
    opts: Option<&Bound<'_, PyDict>>,
) -> PyResult<PySolution>
where
    S: NonSmooth<N> + Sync,
{
    let (problem, method, tau) =
        nonsmooth_problem::<S, N>("solve_nonsmooth", name, t_end, q0, v0, opts)?;
    let run = py.detach(|| {
        let input = move |_t: f64, _q: &SVector<f64, N>, _v: &SVector<f64, N>| tau;
        solve_ns(scene, &input, &problem, &method)
    });
    run.map(PySolution::from)
        .map_err(|e| from_solve_error(py, e))
}

/// A step-level non-smooth run for a controller loop.
pub fn integrator<S, const N: usize>(
    py: Python<'_>,
    name: &str,
    scene: &S,
    t_end: f64,
    q0: &Bound<'_, PyAny>,
    v0: Option<&Bound<'_, PyAny>>,
    opts: Option<&Bound<'_, PyDict>>,
) -> PyResult<PyIntegrator>
where
    S: NonSmooth<N> + Parameters + Send + Sync + 'static,
{
    let (problem, method, tau) =
        nonsmooth_problem::<S, N>("integrator", name, t_end, q0, v0, opts)?;
    // The run owns its scene: a copy, built from the parameters.
    let owned = S::from_values(&scene.values()).expect("one value per parameter");
    PyIntegrator::start::<S, N>(py, name, owned, &problem, &method, tau)
}

/// The coordinates' names.
pub fn joints<S: Mechanism<N>, const N: usize>() -> Vec<&'static str> {
    S::JOINTS.to_vec()
}

/// The non-smooth elements' names.
pub fn elements<S: Mechanism<N>, const N: usize>() -> Vec<&'static str> {
    S::NON_SMOOTH_ELEMENTS.to_vec()
}

/// The frames `frame_pose` takes.
pub fn frames<S: Kinematics<N>, const N: usize>() -> Vec<&'static str> {
    S::FRAMES.to_vec()
}
