//! The adapter [`LieMechanical`] with [`LieMechanism`]s implemented by the numeric
//! reference (standing in for generated code): conservation laws of free bodies, the
//! state layout, and the right-hand side against the numeric forward dynamics.

use std::marker::PhantomData;

use nalgebra::{DMatrix, DVector, Matrix3, SMatrix, SVector, Vector3};

use super::*;
use crate::Options;
use crate::liegroup::{LieProblem, LieTrajectory, Rkmk5};
use crate::numeric::{self, test_models};

/// The coordinate layout of a [`Reference`] mechanism (what the derive writes as
/// associated constants).
trait Layout<const N: usize, const NQ: usize> {
    const COORDINATES: [&'static str; N];
    const ROTATIONS: &'static [(usize, usize)];
    const EUCLID: &'static [(usize, usize)];
}

/// A [`LieMechanism`] whose every method calls the numeric reference on its model.
struct Reference<L> {
    model: Model,
    layout: PhantomData<L>,
}

impl<L> Reference<L> {
    fn new(model: Model) -> Self {
        Reference {
            model,
            layout: PhantomData,
        }
    }
}

fn d<const R: usize>(x: &SVector<f64, R>) -> DVector<f64> {
    DVector::from_column_slice(x.as_slice())
}

fn s<const R: usize>(x: &DVector<f64>) -> SVector<f64, R> {
    SVector::from_column_slice(x.as_slice())
}

fn sm<const R: usize>(x: &DMatrix<f64>) -> SMatrix<f64, R, R> {
    SMatrix::from_column_slice(x.as_slice())
}

impl<L: Layout<N, NQ>, const N: usize, const NQ: usize> LieMechanism<N, NQ> for Reference<L> {
    const COORDINATES: [&'static str; N] = L::COORDINATES;
    const ROTATIONS: &'static [(usize, usize)] = L::ROTATIONS;
    const EUCLID: &'static [(usize, usize)] = L::EUCLID;

    fn mass_matrix(&self, q: &SVector<f64, NQ>) -> SMatrix<f64, N, N> {
        sm(&numeric::crba(&self.model, &d(q)))
    }
    fn forward_dynamics(
        &self,
        q: &SVector<f64, NQ>,
        v: &SVector<f64, N>,
        tau: &SVector<f64, N>,
    ) -> SVector<f64, N> {
        s(&numeric::forward_dynamics(
            &self.model,
            &d(q),
            &d(v),
            &d(tau),
        ))
    }
    /// Central differences along `q ⊕ (±h e_j)` and `v ± h e_j` (a stand-in for the
    /// symbolic Jacobian).
    fn forward_dynamics_jacobian(
        &self,
        q: &SVector<f64, NQ>,
        v: &SVector<f64, N>,
        tau: &SVector<f64, N>,
    ) -> ForwardJacobian<N> {
        let h = 1e-6;
        let e = |j: usize| SVector::<f64, N>::from_fn(|i, _| if i == j { h } else { 0.0 });
        let fd = |q: &SVector<f64, NQ>, v: &SVector<f64, N>| self.forward_dynamics(q, v, tau);
        let d_dq = SMatrix::<f64, N, N>::from_fn(|i, j| {
            let (qp, qm) = (Self::retract(q, &e(j)), Self::retract(q, &(-e(j))));
            (fd(&qp, v)[i] - fd(&qm, v)[i]) / (2.0 * h)
        });
        let d_dv = SMatrix::<f64, N, N>::from_fn(|i, j| {
            (fd(q, &(v + e(j)))[i] - fd(q, &(v - e(j)))[i]) / (2.0 * h)
        });
        ForwardJacobian {
            acceleration: fd(q, v),
            d_dq,
            d_dv,
        }
    }
    fn model(&self) -> Model {
        self.model.clone()
    }
}

impl<L: Layout<N, NQ>, const N: usize, const NQ: usize> crate::kernels::Coriolis<N, NQ>
    for Reference<L>
{
    fn coriolis_matrix(&self, q: &SVector<f64, NQ>, v: &SVector<f64, N>) -> SMatrix<f64, N, N> {
        sm(&numeric::lie_coriolis_matrix(&self.model, &d(q), &d(v)))
    }
}

impl<L: Layout<N, NQ>, const N: usize, const NQ: usize> crate::kernels::Gravity<N, NQ>
    for Reference<L>
{
    fn gravity(&self, q: &SVector<f64, NQ>) -> SVector<f64, N> {
        s(&numeric::gravity(&self.model, &d(q)))
    }
}

impl<L: Layout<N, NQ>, const N: usize, const NQ: usize> crate::kernels::Bias<N, NQ>
    for Reference<L>
{
    fn bias(&self, q: &SVector<f64, NQ>, v: &SVector<f64, N>) -> SVector<f64, N> {
        s(&numeric::bias(&self.model, &d(q), &d(v)))
    }
}

impl<L: Layout<N, NQ>, const N: usize, const NQ: usize> crate::kernels::PassiveForces<N, NQ>
    for Reference<L>
{
    fn passive_forces(&self, q: &SVector<f64, NQ>, v: &SVector<f64, N>) -> SVector<f64, N> {
        s(&numeric::passive_forces(&self.model, &d(q), &d(v)))
    }
}

impl<L: Layout<N, NQ>, const N: usize, const NQ: usize> crate::kernels::InverseDynamics<N, NQ>
    for Reference<L>
{
    fn inverse_dynamics(
        &self,
        q: &SVector<f64, NQ>,
        v: &SVector<f64, N>,
        a: &SVector<f64, N>,
    ) -> SVector<f64, N> {
        s(&numeric::inverse_dynamics(&self.model, &d(q), &d(v), &d(a)))
    }
}

impl<L: Layout<N, NQ>, const N: usize, const NQ: usize> crate::kernels::Energy<N, NQ>
    for Reference<L>
{
    fn kinetic_energy(&self, q: &SVector<f64, NQ>, v: &SVector<f64, N>) -> f64 {
        numeric::kinetic_energy(&self.model, &d(q), &d(v))
    }
    fn potential_energy(&self, q: &SVector<f64, NQ>) -> f64 {
        numeric::potential_energy(&self.model, &d(q))
    }
}

/// A free joint: `q = (p, quaternion)`, `v = (ṗ, ω)`.
struct FreeLayout;

impl Layout<6, 7> for FreeLayout {
    const COORDINATES: [&'static str; 6] = [
        "body.x", "body.y", "body.z", "body.wx", "body.wy", "body.wz",
    ];
    const ROTATIONS: &'static [(usize, usize)] = &[(3, 3)];
    const EUCLID: &'static [(usize, usize)] = &[(0, 0), (1, 1), (2, 2)];
}

/// A free bus with a two-link arm: `q = (p, quaternion, q₁, q₂)`, `v = (ṗ, ω, q̇₁, q̇₂)`.
struct SatelliteLayout;

impl Layout<8, 9> for SatelliteLayout {
    const COORDINATES: [&'static str; 8] = [
        "bus.x", "bus.y", "bus.z", "bus.wx", "bus.wy", "bus.wz", "arm1", "arm2",
    ];
    const ROTATIONS: &'static [(usize, usize)] = &[(3, 3)];
    const EUCLID: &'static [(usize, usize)] = &[(0, 0), (1, 1), (2, 2), (7, 6), (8, 7)];
}

/// The satellite's layout with the rotation in the wrong slots.
struct WrongLayout;

impl Layout<8, 9> for WrongLayout {
    const COORDINATES: [&'static str; 8] = SatelliteLayout::COORDINATES;
    const ROTATIONS: &'static [(usize, usize)] = &[(0, 0)];
    const EUCLID: &'static [(usize, usize)] = &[(4, 3), (5, 4), (6, 5), (7, 6), (8, 7)];
}

/// Principal moments of the free body (as S10).
const INERTIA: [f64; 3] = [1.0, 2.0, 3.0];
const MASS: f64 = 2.0;

fn free_body() -> Reference<FreeLayout> {
    Reference::new(test_models::free_body(
        MASS,
        Vector3::zeros(),
        Matrix3::from_diagonal(&Vector3::from(INERTIA)),
        Vector3::zeros(),
    ))
}

fn free_body_state() -> LieState {
    LieState::new(
        vec![UnitQuat::exp(&Vector3::new(0.3, -0.2, 0.1))],
        vec![1.0, -2.0, 0.5],
        vec![0.01, 1.0, 0.2, 0.3, 0.1, -0.2],
    )
}

/// Largest relative deviation of `f` from its initial value over the stored points.
fn drift<T>(traj: &LieTrajectory, f: impl Fn(&LieState) -> T, dist: impl Fn(&T, &T) -> f64) -> f64 {
    let f0 = f(&traj.state(0));
    (0..traj.len())
        .map(|i| dist(&f(&traj.state(i)), &f0))
        .fold(0.0, f64::max)
}

/// The layout conversions: rotations first in the state's velocity, Euclidean
/// coordinates after, quaternions normalised, and back.
#[test]
fn state_and_configuration_round_trip() {
    type Sat = Reference<SatelliteLayout>;
    let q = SVector::<f64, 9>::from_column_slice(&[0.1, 0.2, 0.3, 2.0, 0.0, 0.0, 0.0, 0.7, -0.4]);
    let v = SVector::<f64, 8>::from_fn(|i, _| i as f64 + 1.0);
    let y = Sat::qv_to_state(&q, &v);
    assert_eq!(y.rotations, [UnitQuat::IDENTITY]);
    assert_eq!(y.euclid, [0.1, 0.2, 0.3, 0.7, -0.4]);
    assert_eq!(y.velocity, [4.0, 5.0, 6.0, 1.0, 2.0, 3.0, 7.0, 8.0]);
    let (q2, v2) = Sat::state_to_qv(&y);
    assert_eq!(v2, v);
    let mut unit = q;
    unit[3] = 1.0;
    assert_eq!(q2, unit);
    let mut ordered = [0.0; 8];
    Sat::velocity_to_state_order(&v, &mut ordered);
    assert_eq!(ordered.as_slice(), y.velocity.as_slice());
    // The trait's retraction is the model's.
    let sat = Sat::new(test_models::satellite(Vector3::zeros()));
    let q = Sat::retract(&unit, &SVector::from_fn(|i, _| 0.3 - 0.1 * i as f64));
    let phi = SVector::<f64, 8>::from_fn(|i, _| (i as f64).cos());
    let expected = sat.model.retract(&d(&q), &d(&phi));
    assert!((d(&Sat::retract(&q, &phi)) - expected).norm() < 1e-15);
    assert_eq!(
        Sat::identity_configuration(),
        s::<9>(&sat.model.identity_configuration())
    );
}

/// The right-hand side is the numeric forward dynamics with the input `τ(t, q, v)`,
/// reordered into the state's velocity order; validation checks the layout.
#[test]
fn rhs_is_forward_dynamics_in_state_order() {
    let sat =
        Reference::<SatelliteLayout>::new(test_models::satellite(Vector3::new(0.2, 0.1, -9.81)));
    let input = |t: f64, q: &SVector<f64, 9>, v: &SVector<f64, 8>| {
        SVector::<f64, 8>::from_fn(|i, _| (t + i as f64).sin() + 0.1 * q[i] - 0.2 * v[i])
    };
    let system = LieMechanical::new(&sat, input);
    assert_eq!(
        (system.n_rot(), system.n_euclid(), system.n_velocity()),
        (1, 5, 8)
    );
    assert_eq!(system.validate(), Ok(()));
    let y = LieState::new(
        vec![UnitQuat::exp(&Vector3::new(1.0, -0.5, 2.0))],
        vec![0.3, -0.2, 0.9, 0.4, -1.1],
        vec![0.5, -0.7, 1.2, 0.1, 0.2, -0.3, 0.8, -0.6],
    );
    let mut dv = [0.0; 8];
    system.rhs(0.7, &y, &mut dv);
    let r = y.rotations[0].coords();
    let q = DVector::from_vec(vec![0.3, -0.2, 0.9, r[0], r[1], r[2], r[3], 0.4, -1.1]);
    let v = DVector::from_vec(vec![0.1, 0.2, -0.3, 0.5, -0.7, 1.2, 0.8, -0.6]);
    let tau = d(&input(0.7, &s(&q), &s(&v)));
    let a = numeric::forward_dynamics(&sat.model, &q, &v, &tau);
    let expected = [a[3], a[4], a[5], a[0], a[1], a[2], a[6], a[7]];
    for (x, e) in dv.iter().zip(expected) {
        assert!((x - e).abs() < 1e-14, "{dv:?} vs {expected:?}");
    }
    let wrong = Reference::<WrongLayout>::new(sat.model.clone());
    assert!(LieMechanical::free(&wrong).validate().is_err());
}

/// A free body, `I = diag(1, 2, 3)`, no gravity: the rotational part follows Euler's
/// equations (checked on the right-hand side), kinetic energy and spatial angular
/// momentum `R I ω` are conserved, and the body's origin (its centre of mass) moves
/// with constant velocity.
#[test]
fn free_body_conserves_energy_and_momentum_and_drifts_uniformly() {
    let body = free_body();
    let system = LieMechanical::free(&body);
    assert_eq!(system.validate(), Ok(()));
    let y0 = free_body_state();
    let inertia = Matrix3::from_diagonal(&Vector3::from(INERTIA));
    let mut dv = [0.0; 6];
    system.rhs(0.0, &y0, &mut dv);
    let w = y0.omega(0);
    let euler = inertia.try_inverse().unwrap() * -w.cross(&(inertia * w));
    assert!((Vector3::new(dv[0], dv[1], dv[2]) - euler).norm() < 1e-14);
    assert!(dv[3..].iter().all(|x| x.abs() < 1e-15));

    let tf = 20.0;
    let traj = Rkmk5::new(Options::tolerances(1e-10, 1e-12))
        .solve(&system, &LieProblem::new(0.0, tf, y0.clone()))
        .unwrap();
    let e0 = system.energy(&y0);
    let de = drift(&traj, |y| system.energy(y), |a, b| (a - b).abs() / e0);
    let momentum = |y: &LieState| y.rotation_matrix(0) * inertia * y.omega(0);
    let l0 = momentum(&y0).norm();
    let dl = drift(&traj, momentum, |a, b| (a - b).norm() / l0);
    // The numeric reference's spatial momentum: m ṗ and, about the world origin,
    // p × m ṗ + R I ω.
    let numeric_momentum = |y: &LieState| {
        let (q, v) = Reference::<FreeLayout>::state_to_qv(y);
        numeric::spatial_momentum(&body.model, &d(&q), &d(&v))
    };
    let dh = drift(&traj, numeric_momentum, |a, b| {
        ((a.0 - b.0).norm() + (a.1 - b.1).norm()) / l0
    });
    eprintln!("free body: |ΔE|/E {de:.1e}, |ΔL|/|L| {dl:.1e}, spatial momentum {dh:.1e}");
    assert!(de < 1e-8 && dl < 1e-8 && dh < 1e-8, "{de:e} {dl:e} {dh:e}");
    let u = &y0.velocity[3..];
    for i in 0..traj.len() {
        let (t, y) = (traj.times()[i], traj.state(i));
        for (k, uk) in u.iter().enumerate() {
            assert!((y.euclid[k] - (y0.euclid[k] + uk * t)).abs() < 1e-12);
            assert!((y.velocity[3 + k] - uk).abs() < 1e-13);
        }
    }
    assert!(traj.len() > 10);
}

/// With a constant world force `F` on the translation coordinates (the centre of mass
/// is the body origin) the origin moves as `p₀ + u₀ t + F t² / 2m`; the rotation stays
/// torque-free.
#[test]
fn constant_force_accelerates_the_free_body_uniformly() {
    let body = free_body();
    let force = Vector3::new(0.4, -1.0, 2.5);
    let system = LieMechanical::new(&body, |_t, _q: &SVector<f64, 7>, _v: &SVector<f64, 6>| {
        SVector::<f64, 6>::new(force.x, force.y, force.z, 0.0, 0.0, 0.0)
    });
    let y0 = free_body_state();
    let tf = 5.0;
    let traj = Rkmk5::new(Options::tolerances(1e-10, 1e-12))
        .solve(&system, &LieProblem::new(0.0, tf, y0.clone()))
        .unwrap();
    let (_, y) = traj.last().unwrap();
    for k in 0..3 {
        let (p0, u0, acc) = (y0.euclid[k], y0.velocity[3 + k], force[k] / MASS);
        assert!((y.euclid[k] - (p0 + u0 * tf + 0.5 * acc * tf * tf)).abs() < 1e-10);
        assert!((y.velocity[3 + k] - (u0 + acc * tf)).abs() < 1e-10);
    }
    let inertia = Vector3::from(INERTIA);
    let rot_energy = |w: Vector3<f64>| 0.5 * w.component_mul(&inertia).dot(&w);
    assert!((rot_energy(y.omega(0)) - rot_energy(y0.omega(0))).abs() < 1e-9);
}

/// A satellite (free bus, two-link arm) in zero gravity: the spatial momentum
/// (linear, and angular about the world origin) and the energy are constants of the
/// motion, and the integration keeps them to about the tolerance.
#[test]
fn satellite_conserves_spatial_momentum_and_energy() {
    let sat = Reference::<SatelliteLayout>::new(test_models::satellite(Vector3::zeros()));
    let system = LieMechanical::free(&sat);
    let q0 = Reference::<SatelliteLayout>::retract(
        &Reference::<SatelliteLayout>::identity_configuration(),
        &SVector::from_column_slice(&[0.2, -0.1, 0.3, 0.5, -0.8, 1.2, 0.4, -0.9]),
    );
    let v0 = SVector::<f64, 8>::from_column_slice(&[0.3, -0.2, 0.1, 0.4, 0.7, -0.5, 2.0, -1.5]);
    let y0 = Reference::<SatelliteLayout>::qv_to_state(&q0, &v0);
    let traj = Rkmk5::new(Options::tolerances(1e-11, 1e-13))
        .solve(&system, &LieProblem::new(0.0, 10.0, y0.clone()))
        .unwrap();
    let e0 = system.energy(&y0);
    let de = drift(&traj, |y| system.energy(y), |a, b| (a - b).abs() / e0);
    let momentum = |y: &LieState| {
        let (q, v) = Reference::<SatelliteLayout>::state_to_qv(y);
        numeric::spatial_momentum(&sat.model, &d(&q), &d(&v))
    };
    let h0 = momentum(&y0);
    let scale = h0.0.norm() + h0.1.norm();
    let dh = drift(&traj, momentum, |a, b| {
        ((a.0 - b.0).norm() + (a.1 - b.1).norm()) / scale
    });
    // The arm really moves (the test is not a rigid tumble).
    let (_, last) = traj.last().unwrap();
    let arm_travel = (last.euclid[3] - y0.euclid[3]).abs();
    eprintln!(
        "satellite: |ΔE|/E {de:.1e}, |Δh|/|h| {dh:.1e}, arm1 moved {arm_travel:.2} rad, {}",
        traj.stats
    );
    assert!(de < 1e-8 && dh < 1e-8, "{de:e} {dh:e}");
    assert!(arm_travel > 0.5);
}

/// Central differences of a [`LieSystem`]'s right-hand side in the state's order:
/// along `state · exp(±δ e_j)` (rotation `j / 3` about its body axis `j % 3`, or the
/// Euclidean coordinate `j − 3m`) and `v ± δ e_j`.
fn rhs_differences(system: &impl LieSystem, t: f64, y: &LieState) -> (DMatrix<f64>, DMatrix<f64>) {
    let n = system.n_velocity();
    let m = system.n_rot();
    let delta = 1e-5;
    let f = |y: &LieState| {
        let mut dv = vec![0.0; n];
        system.rhs(t, y, &mut dv);
        DVector::from_vec(dv)
    };
    let shifted = |j: usize, s: f64| {
        let mut y = y.clone();
        if j < 3 * m {
            let mut e = Vector3::zeros();
            e[j % 3] = s;
            y.rotations[j / 3] = y.rotations[j / 3] * UnitQuat::exp(&e);
        } else {
            y.euclid[j - 3 * m] += s;
        }
        y
    };
    let mut dq = DMatrix::zeros(n, n);
    let mut dv = DMatrix::zeros(n, n);
    for j in 0..n {
        let col = (f(&shifted(j, delta)) - f(&shifted(j, -delta))) / (2.0 * delta);
        dq.set_column(j, &col);
        let (mut yp, mut ym) = (y.clone(), y.clone());
        yp.velocity[j] += delta;
        ym.velocity[j] -= delta;
        dv.set_column(j, &((f(&yp) - f(&ym)) / (2.0 * delta)));
    }
    (dq, dv)
}

/// (c) `LieMechanical::jacobian` is the mechanism's `forward_dynamics_jacobian` moved
/// into the state's order: it equals central differences of `rhs` (taken here along
/// the state's own coordinates). The satellite's layout puts the translation first in
/// `v` and the rotation first in the state, so an unpermuted copy would not match
/// (checked, so that the comparison can fail).
#[test]
fn jacobian_is_forward_dynamics_jacobian_in_state_order() {
    let sat =
        Reference::<SatelliteLayout>::new(test_models::satellite(Vector3::new(0.3, -0.5, -9.81)));
    // An input that depends on t only (the Jacobian holds τ fixed).
    let input = |t: f64, _q: &SVector<f64, 9>, _v: &SVector<f64, 8>| {
        SVector::<f64, 8>::from_fn(|i, _| (t + i as f64).sin())
    };
    let system = LieMechanical::new(&sat, input);
    let y = LieState::new(
        vec![UnitQuat::exp(&Vector3::new(1.0, -0.5, 2.0))],
        vec![0.3, -0.2, 0.9, 0.4, -1.1],
        vec![0.5, -0.7, 1.2, 0.1, 0.2, -0.3, 0.8, -0.6],
    );
    let (mut dq, mut dv) = ([0.0; 64], [0.0; 64]);
    assert!(system.jacobian(0.7, &y, &mut dq, &mut dv));
    let dq = DMatrix::from_row_slice(8, 8, &dq);
    let dv = DMatrix::from_row_slice(8, 8, &dv);
    let (fq, fv) = rhs_differences(&system, 0.7, &y);
    let scale = fq.amax().max(fv.amax());
    let (eq, ev) = ((&dq - &fq).amax() / scale, (&dv - &fv).amax() / scale);
    eprintln!("LieMechanical::jacobian vs differences of rhs: {eq:.1e}, {ev:.1e} (relative)");
    assert!(eq < 1e-7 && ev < 1e-7, "{eq:e} {ev:e}");
    // Both blocks carry information (gravity and arm coupling; Coriolis).
    assert!(fq.amax() > 0.1 && fv.amax() > 0.1);
    // Unpermuted: the velocity layout's matrices as if they were in state order.
    let (q, v) = Reference::<SatelliteLayout>::state_to_qv(&y);
    let raw = sat.forward_dynamics_jacobian(&q, &v, &input(0.7, &q, &v));
    let raw_q = DMatrix::from_column_slice(8, 8, raw.d_dq.as_slice());
    let raw_v = DMatrix::from_column_slice(8, 8, raw.d_dv.as_slice());
    assert!((raw_q - &fq).amax() > 1e-2 * scale);
    assert!((raw_v - &fv).amax() > 1e-2 * scale);
}

/// LieSdirk on a generated-like scene uses the scene's Jacobian (no finite
/// differences) and keeps the satellite's energy and spatial momentum to about the
/// tolerance.
#[test]
fn lie_sdirk_integrates_the_satellite_with_its_jacobian() {
    let sat = Reference::<SatelliteLayout>::new(test_models::satellite(Vector3::zeros()));
    let system = LieMechanical::free(&sat);
    let q0 = Reference::<SatelliteLayout>::retract(
        &Reference::<SatelliteLayout>::identity_configuration(),
        &SVector::from_column_slice(&[0.2, -0.1, 0.3, 0.5, -0.8, 1.2, 0.4, -0.9]),
    );
    let v0 = SVector::<f64, 8>::from_column_slice(&[0.3, -0.2, 0.1, 0.4, 0.7, -0.5, 2.0, -1.5]);
    let y0 = Reference::<SatelliteLayout>::qv_to_state(&q0, &v0);
    let traj = crate::liegroup::LieSdirk::new(Options::tolerances(1e-9, 1e-12))
        .solve(&system, &LieProblem::new(0.0, 5.0, y0.clone()))
        .unwrap();
    let e0 = system.energy(&y0);
    let de = drift(&traj, |y| system.energy(y), |a, b| (a - b).abs() / e0);
    let momentum = |y: &LieState| {
        let (q, v) = Reference::<SatelliteLayout>::state_to_qv(y);
        numeric::spatial_momentum(&sat.model, &d(&q), &d(&v))
    };
    let h0 = momentum(&y0);
    let scale = h0.0.norm() + h0.1.norm();
    let dh = drift(&traj, momentum, |a, b| {
        ((a.0 - b.0).norm() + (a.1 - b.1).norm()) / scale
    });
    let stats = traj.stats;
    eprintln!("satellite LieSdirk: |ΔE|/E {de:.1e}, |Δh|/|h| {dh:.1e}, {stats}");
    assert!(de < 1e-6 && dh < 1e-6, "{de:e} {dh:e}");
    assert!(stats.jacobian_evaluations > 0 && stats.finite_difference_jacobians == 0);
}
