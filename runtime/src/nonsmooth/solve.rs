//! The entry points of a non-smooth run: the step-level [`Integrator`] run to the end
//! (event-driven, [`super::event`], or time-stepping, [`super::timestepping`]).

use nalgebra::SVector;

use super::integrator::Integrator;
use super::{NonSmoothMethod, NonSmoothProblem};
use crate::element::NonSmooth;
use crate::solve::{Observer, unobserved};
use crate::{Solution, SolveError};

/// Integrates `problem` with the chosen non-smooth method.
///
/// `system` is a scene with friction, dash-pots or stops (the derive implements
/// [`NonSmooth`] for it; here the numeric [`Scene`](crate::numeric::Scene) stands in);
/// `input(t, q, v)` gives the applied generalised forces (a derived scene with
/// `#[mechanism(inputs = [joint, …])]` maps actuator values to them with
/// `Scene::input_forces(&u)`); [`NonSmoothMethod::default`] is event-driven DOPRI5 at
/// rtol 1e-8. The [`Solution`] has the columns `q_<joint>`, `v_<joint>`, `f_<element>`,
/// two rows at every switch, and the log of every switch in
/// [`switches`](Solution::switches).
///
/// A block on a tilted rail (gravity pulls it along with 3 N), Coulomb friction up to 5 N,
/// pushed at 2 m/s: it slides, stops, and stays exactly where it stopped — the friction
/// holds it without creep.
///
/// ```
/// use nalgebra::{Matrix3, SVector, Vector3};
/// use filippov_runtime::nonsmooth::{Element, ElementKind, Law};
/// use filippov_runtime::numeric::{JointKind, Link, Model, Scene};
/// use filippov_runtime::{Mode, NonSmoothMethod, NonSmoothProblem, SwitchKind, solve_nonsmooth};
///
/// let block = Link {
///     name: "x".into(),
///     parent: None,
///     joint: JointKind::Prismatic { axis: Vector3::x() },
///     coordinate: Some(0),
///     origin_xyz: Vector3::zeros(),
///     origin_rpy: Vector3::zeros(),
///     mass: 1.0,
///     com: Vector3::zeros(),
///     inertia: Matrix3::zeros(),
/// };
/// let model = Model {
///     gravity: Vector3::new(3.0, 0.0, 0.0),
///     links: vec![block],
///     springs: vec![],
///     dampers: vec![],
///     point_springs: vec![],
/// };
/// let friction = Element {
///     name: "friction_x",
///     coordinate: 0,
///     kind: ElementKind::DashPot { law: Law::Coulomb, f_crit: 5.0 },
/// };
/// let scene = Scene::<1, 1>::new(model, [friction]).unwrap();
/// let problem = NonSmoothProblem::new(0.0, 3.0, SVector::from([0.0]), SVector::from([2.0]));
/// let no_force = |_t: f64, _q: &SVector<f64, 1>, _v: &SVector<f64, 1>| SVector::zeros();
/// let sol = solve_nonsmooth(&scene, &no_force, &problem, &NonSmoothMethod::default()).unwrap();
/// // Decelerating at 5 − 3 = 2 m/s², it sticks at t = 1 after 1 m, and stays.
/// let stick = &sol.switches[0];
/// assert_eq!((stick.kind, stick.to), (SwitchKind::Mode, Some(Mode::Stick)));
/// assert!((stick.t - 1.0).abs() < 1e-9);
/// let (t, y) = sol.last().unwrap();
/// assert_eq!(t, 3.0);
/// assert!((y[0] - 1.0).abs() < 1e-9 && y[1] == 0.0);
/// // Named columns (a numeric scene's coordinates are numbered; a derived scene's are
/// // named after its joints, `q_x`).
/// assert_eq!(sol.names(), ["q0", "v0", "f_friction_x"]);
/// assert!((y[2] - 3.0).abs() < 1e-9); // the friction holds the 3 N of gravity
/// ```
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
