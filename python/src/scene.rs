//! What every scene class does, generic over the scene: the class that
//! [`module!`](crate::module) writes for a scene calls these. A scene is of one of two
//! kinds ([`Scene`]): [`Flat`], on revolute and prismatic joints (`q` and `v` of one
//! length), or [`Lie`](crate::lie::Lie), with spherical or free joints (quaternions in `q`).

use std::marker::PhantomData;

use filippov_runtime::kernels::{FrameId, InverseDynamics, Kinematics};
use filippov_runtime::nonsmooth::NonSmooth;
use filippov_runtime::system::{ForwardJacobian, ParameterError, Parameters};
use filippov_runtime::{
    MechanicalSystem, Mechanism, NonSmoothProblem, Problem, solve as solve_smooth,
    solve_nonsmooth as solve_ns,
};
use nalgebra::{SMatrix, SVector};
use pyo3::exceptions::{PyKeyError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

use crate::arrays::{States, same_batch, shaped, states, states_of};
use crate::errors::{from_solve_error, parameter_error};
use crate::integrator::PyIntegrator;
use crate::options;
use crate::solution::PySolution;

/// What the class of a scene `Self::Inner` needs of it, over its configuration `q`
/// (`NQ` slots) and its velocity coordinates `v` (`N`, as `τ` and `v̇`). Implemented by
/// the kinds [`Flat`] and [`Lie`](crate::lie::Lie), which select the scene's trait.
pub trait Scene<const N: usize, const NQ: usize> {
    /// The scene.
    type Inner: Parameters;
    /// The velocity coordinates' names.
    fn coordinates() -> Vec<&'static str>;
    /// The configuration slots' names.
    fn configuration() -> Vec<String>;
    /// The non-smooth elements' names.
    fn elements() -> Vec<&'static str>;
    /// What is wrong with the configuration `q` (slots in order), if anything.
    fn check_configuration(q: &[f64]) -> Result<(), String>;
    fn validate(scene: &Self::Inner) -> Result<(), ParameterError>;
    fn mass_matrix(scene: &Self::Inner, q: &SVector<f64, NQ>) -> SMatrix<f64, N, N>;
    fn forward_dynamics(
        scene: &Self::Inner,
        q: &SVector<f64, NQ>,
        v: &SVector<f64, N>,
        tau: &SVector<f64, N>,
    ) -> SVector<f64, N>;
    fn forward_dynamics_jacobian(
        scene: &Self::Inner,
        q: &SVector<f64, NQ>,
        v: &SVector<f64, N>,
        tau: &SVector<f64, N>,
    ) -> ForwardJacobian<N>;
    /// A smooth run from `(q0, v0)`, the GIL released while it integrates.
    fn run(
        py: Python<'_>,
        scene: &Self::Inner,
        t_end: f64,
        q0: SVector<f64, NQ>,
        v0: SVector<f64, N>,
        opts: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<PySolution>;
}

/// A scene on revolute and prismatic joints ([`Mechanism`]).
pub struct Flat<S>(PhantomData<S>);

impl<S, const N: usize> Scene<N, N> for Flat<S>
where
    S: Mechanism<N> + Parameters + Sync,
{
    type Inner = S;

    fn coordinates() -> Vec<&'static str> {
        S::JOINTS.to_vec()
    }

    fn configuration() -> Vec<String> {
        S::JOINTS.iter().map(|j| j.to_string()).collect()
    }

    fn elements() -> Vec<&'static str> {
        S::NON_SMOOTH_ELEMENTS.to_vec()
    }

    fn check_configuration(_q: &[f64]) -> Result<(), String> {
        Ok(())
    }

    fn validate(scene: &S) -> Result<(), ParameterError> {
        scene.validate()
    }

    fn mass_matrix(scene: &S, q: &SVector<f64, N>) -> SMatrix<f64, N, N> {
        scene.mass_matrix(q)
    }

    fn forward_dynamics(
        scene: &S,
        q: &SVector<f64, N>,
        v: &SVector<f64, N>,
        tau: &SVector<f64, N>,
    ) -> SVector<f64, N> {
        scene.forward_dynamics(q, v, tau)
    }

    fn forward_dynamics_jacobian(
        scene: &S,
        q: &SVector<f64, N>,
        v: &SVector<f64, N>,
        tau: &SVector<f64, N>,
    ) -> ForwardJacobian<N> {
        scene.forward_dynamics_jacobian(q, v, tau)
    }

    fn run(
        py: Python<'_>,
        scene: &S,
        t_end: f64,
        q: SVector<f64, N>,
        v: SVector<f64, N>,
        opts: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<PySolution> {
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
}

/// The scene built from keyword arguments, one per parameter, and checked.
pub fn new<D, const N: usize, const NQ: usize>(
    name: &str,
    kwargs: Option<&Bound<'_, PyDict>>,
) -> PyResult<D::Inner>
where
    D: Scene<N, NQ>,
{
    let names = <D::Inner as Parameters>::NAMES;
    let mut values = vec![f64::NAN; names.len()];
    let mut given = vec![false; names.len()];
    if let Some(d) = kwargs {
        for (k, v) in d.iter() {
            let k: String = k.extract()?;
            let Some(i) = names.iter().position(|p| *p == k) else {
                let expect = if names.is_empty() {
                    "it takes no parameters".to_string()
                } else {
                    format!("its parameters are {}", names.join(", "))
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
    let missing: Vec<&str> = names
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
            names.join(", ")
        )));
    }
    let scene = D::Inner::from_values(&values).expect("one value per parameter");
    D::validate(&scene).map_err(|e| Python::attach(|py| parameter_error(py, name, &e)))?;
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

pub(crate) fn vec<const N: usize>(x: &[f64]) -> SVector<f64, N> {
    SVector::from_column_slice(x)
}

/// Configurations read as states of the scene's configuration slots, each checked.
fn configurations<D: Scene<N, NQ>, const N: usize, const NQ: usize>(
    name: &str,
    what: &str,
    q: &Bound<'_, PyAny>,
) -> PyResult<States> {
    let slots = D::configuration();
    let slots: Vec<&str> = slots.iter().map(|s| s.as_str()).collect();
    let noun = if NQ == N {
        "coordinates"
    } else {
        "configuration slots"
    };
    let s = states_of(name, what, q, &slots, noun)?;
    for i in 0..s.count() {
        D::check_configuration(s.row(i, NQ)).map_err(|e| {
            let at = if s.batch.is_some() {
                format!(" (state {i})")
            } else {
                String::new()
            };
            PyValueError::new_err(format!("{name}: {what}{at}: {e}"))
        })?;
    }
    Ok(s)
}

/// The arguments `(q, x…)` of a kernel call (`x` in the velocity coordinates: `v`, `τ`,
/// `a`), read and checked against each other.
fn read<D: Scene<N, NQ>, const N: usize, const NQ: usize>(
    name: &str,
    q: &Bound<'_, PyAny>,
    args: &[(&str, &Bound<'_, PyAny>)],
) -> PyResult<Vec<States>> {
    let coordinates = D::coordinates();
    let mut read = vec![configurations::<D, N, NQ>(name, "q", q)?];
    for (what, x) in args {
        read.push(states(name, what, x, &coordinates)?);
    }
    let names: Vec<&str> = std::iter::once("q")
        .chain(args.iter().map(|a| a.0))
        .collect();
    let pairs: Vec<(&str, &States)> = names.into_iter().zip(&read).collect();
    same_batch(name, &pairs)?;
    Ok(read)
}

/// `tau` or zeros shaped like `like`.
fn or_zeros<const N: usize>(
    name: &str,
    coordinates: &[&str],
    tau: Option<&Bound<'_, PyAny>>,
    like: &States,
) -> PyResult<States> {
    match tau {
        Some(t) => {
            let s = states(name, "tau", t, coordinates)?;
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
pub fn mass_matrix<'py, D: Scene<N, NQ>, const N: usize, const NQ: usize>(
    py: Python<'py>,
    name: &str,
    scene: &D::Inner,
    q: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyAny>> {
    let q = read::<D, N, NQ>(name, q, &[])?.remove(0);
    let mut out = Vec::with_capacity(q.count() * N * N);
    for i in 0..q.count() {
        let m = D::mass_matrix(scene, &vec(q.row(i, NQ)));
        // Row-major, as NumPy reads it.
        out.extend(m.transpose().iter().copied());
    }
    shaped(py, out, q.batch, &[N, N])
}

/// `v̇ = FD(q, v, τ)` (`τ` zero when not given).
pub fn forward_dynamics<'py, D: Scene<N, NQ>, const N: usize, const NQ: usize>(
    py: Python<'py>,
    name: &str,
    scene: &D::Inner,
    q: &Bound<'py, PyAny>,
    v: &Bound<'py, PyAny>,
    tau: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    let r = read::<D, N, NQ>(name, q, &[("v", v)])?;
    let tau = or_zeros::<N>(name, &D::coordinates(), tau, &r[0])?;
    let mut out = Vec::with_capacity(r[0].count() * N);
    for i in 0..r[0].count() {
        let a = D::forward_dynamics(
            scene,
            &vec(r[0].row(i, NQ)),
            &vec(r[1].row(i, N)),
            &vec(tau.row(i, N)),
        );
        out.extend(a.iter().copied());
    }
    shaped(py, out, r[0].batch, &[N])
}

/// `(v̇, ∂v̇/∂q, ∂v̇/∂v)`, each with the batch's leading axis if batched.
pub fn forward_dynamics_jacobian<'py, D: Scene<N, NQ>, const N: usize, const NQ: usize>(
    py: Python<'py>,
    name: &str,
    scene: &D::Inner,
    q: &Bound<'py, PyAny>,
    v: &Bound<'py, PyAny>,
    tau: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyTuple>> {
    let r = read::<D, N, NQ>(name, q, &[("v", v)])?;
    let tau = or_zeros::<N>(name, &D::coordinates(), tau, &r[0])?;
    let b = r[0].count();
    let (mut a, mut dq, mut dv) = (
        Vec::with_capacity(b * N),
        Vec::with_capacity(b * N * N),
        Vec::with_capacity(b * N * N),
    );
    for i in 0..b {
        let j = D::forward_dynamics_jacobian(
            scene,
            &vec(r[0].row(i, NQ)),
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
pub fn inverse_dynamics<'py, D, const N: usize, const NQ: usize>(
    py: Python<'py>,
    name: &str,
    scene: &D::Inner,
    q: &Bound<'py, PyAny>,
    v: &Bound<'py, PyAny>,
    a: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyAny>>
where
    D: Scene<N, NQ>,
    D::Inner: InverseDynamics<N, NQ>,
{
    let r = read::<D, N, NQ>(name, q, &[("v", v), ("a", a)])?;
    let mut out = Vec::with_capacity(r[0].count() * N);
    for i in 0..r[0].count() {
        let t = scene.inverse_dynamics(
            &vec(r[0].row(i, NQ)),
            &vec(r[1].row(i, N)),
            &vec(r[2].row(i, N)),
        );
        out.extend(t.iter().copied());
    }
    shaped(py, out, r[0].batch, &[N])
}

fn frame_id<S: Kinematics<N, NQ>, const N: usize, const NQ: usize>(
    name: &str,
    frame: &str,
) -> PyResult<FrameId<S>> {
    S::frame(frame).ok_or_else(|| {
        PyKeyError::new_err(format!(
            "{name} has no frame `{frame}`; its frames are {}",
            S::FRAMES.join(", ")
        ))
    })
}

/// `kernel(frame, q)` of each state, each result `shape` long, shaped like `q`.
fn per_frame<'py, D, const N: usize, const NQ: usize>(
    py: Python<'py>,
    name: &str,
    frame: &str,
    q: &Bound<'py, PyAny>,
    shape: &[usize],
    kernel: impl Fn(FrameId<D::Inner>, &SVector<f64, NQ>) -> Vec<f64>,
) -> PyResult<Bound<'py, PyAny>>
where
    D: Scene<N, NQ>,
    D::Inner: Kinematics<N, NQ>,
{
    let id = frame_id::<D::Inner, N, NQ>(name, frame)?;
    let q = read::<D, N, NQ>(name, q, &[])?.remove(0);
    let mut out = Vec::with_capacity(q.count() * shape.iter().product::<usize>());
    for i in 0..q.count() {
        out.extend(kernel(id, &vec(q.row(i, NQ))));
    }
    shaped(py, out, q.batch, shape)
}

/// The world pose of `frame` as a 4 × 4 homogeneous matrix (`(batch, 4, 4)` batched).
pub fn frame_pose<'py, D, const N: usize, const NQ: usize>(
    py: Python<'py>,
    name: &str,
    scene: &D::Inner,
    frame: &str,
    q: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyAny>>
where
    D: Scene<N, NQ>,
    D::Inner: Kinematics<N, NQ>,
{
    per_frame::<D, N, NQ>(py, name, frame, q, &[4, 4], |id, q| {
        let h = scene.frame_pose(id, q).to_homogeneous();
        h.transpose().iter().copied().collect()
    })
}

/// The frame's Jacobian, rows `(ṗ, ω)` in world axes: `(6, n)` (`(batch, 6, n)`).
pub fn frame_jacobian<'py, D, const N: usize, const NQ: usize>(
    py: Python<'py>,
    name: &str,
    scene: &D::Inner,
    frame: &str,
    q: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyAny>>
where
    D: Scene<N, NQ>,
    D::Inner: Kinematics<N, NQ>,
{
    per_frame::<D, N, NQ>(py, name, frame, q, &[6, N], |id, q| {
        scene
            .frame_jacobian(id, q)
            .transpose()
            .iter()
            .copied()
            .collect()
    })
}

/// One initial state `(q0, v0)`, `v0` zero when not given.
fn initial<D: Scene<N, NQ>, const N: usize, const NQ: usize>(
    name: &str,
    q0: &Bound<'_, PyAny>,
    v0: Option<&Bound<'_, PyAny>>,
) -> PyResult<(SVector<f64, NQ>, SVector<f64, N>)> {
    let single = |what: &str, s: &States, n: usize| -> PyResult<()> {
        if s.batch.is_some() {
            return Err(PyValueError::new_err(format!(
                "{name}: {what} must be one state of shape ({n},); a run starts from one state"
            )));
        }
        Ok(())
    };
    let q = configurations::<D, N, NQ>(name, "q0", q0)?;
    single("q0", &q, NQ)?;
    let v = match v0 {
        Some(v) => {
            let s = states(name, "v0", v, &D::coordinates())?;
            single("v0", &s, N)?;
            vec(&s.data)
        }
        None => SVector::zeros(),
    };
    Ok((vec(&q.data), v))
}

/// A smooth run from `(q0, v0)` (`v0` zero when not given) to `t_end`.
pub fn solve<D: Scene<N, NQ>, const N: usize, const NQ: usize>(
    py: Python<'_>,
    name: &str,
    scene: &D::Inner,
    t_end: f64,
    q0: &Bound<'_, PyAny>,
    v0: Option<&Bound<'_, PyAny>>,
    opts: Option<&Bound<'_, PyDict>>,
) -> PyResult<PySolution> {
    let (q, v) = initial::<D, N, NQ>(name, q0, v0)?;
    D::run(py, scene, t_end, q, v, opts)
}

/// The non-smooth problem and method from the Python arguments.
pub(crate) fn nonsmooth_problem<S: Mechanism<N> + Parameters + Sync, const N: usize>(
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
    let (q, v) = initial::<Flat<S>, N, N>(name, q0, v0)?;
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
    S: NonSmooth<N> + Parameters + Sync,
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

/// The velocity coordinates' names.
pub fn joints<D: Scene<N, NQ>, const N: usize, const NQ: usize>() -> Vec<&'static str> {
    D::coordinates()
}

/// The configuration slots' names.
pub fn configuration<D: Scene<N, NQ>, const N: usize, const NQ: usize>() -> Vec<String> {
    D::configuration()
}

/// The non-smooth elements' names.
pub fn elements<D: Scene<N, NQ>, const N: usize, const NQ: usize>() -> Vec<&'static str> {
    D::elements()
}

/// The frames `frame_pose` takes.
pub fn frames<S: Kinematics<N, NQ>, const N: usize, const NQ: usize>() -> Vec<&'static str> {
    S::FRAMES.to_vec()
}
