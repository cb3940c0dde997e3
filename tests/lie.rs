//! Scenes with spherical and free joints (theory §2), on random states:
//! - generated kernels against the independent numeric implementation extended to these
//!   joints (runtime `numeric`), the numeric Coriolis matrix from `D_k M` included;
//! - closed forms: a body on a ball joint (`I ω̇ + ω × I ω = τ`), a free body
//!   (`M = diag(m 𝟙, I)`);
//! - `M` symmetric positive definite, `C v + g` = RNEA bias, `Ṁ − 2C` skew-symmetric
//!   along the motion (`Ṁ` by central differences along `q · exp(±h v)`);
//! - inverse ∘ forward dynamics = identity; the Jacobian in local exponential
//!   coordinates against central differences along `q · exp(±h e_k)`;
//! - conservation: the satellite with an arm keeps energy and spatial momentum.

mod common;

use common::{Rng, assert_close};
use filippov::nalgebra::{DVector, SMatrix, SVector, Vector3};
use filippov::prelude::*;
use filippov::runtime::liegroup::{LieMechanical, LieMechanism};
use filippov::runtime::{LieProblem, Options, Output, Rkmk5, UnitQuat, numeric};
use filippov_scenes::{BallChain, FreeBody, Satellite, SphericalBody};

fn dv<const N: usize>(v: &SVector<f64, N>) -> DVector<f64> {
    DVector::from_column_slice(v.as_slice())
}

/// A random configuration: unit quaternions in the rotation slots, numbers elsewhere.
fn random_config<S: LieMechanism<N, NQ>, const N: usize, const NQ: usize>(
    rng: &mut Rng,
) -> SVector<f64, NQ> {
    let mut q: SVector<f64, NQ> = rng.vector(2.0);
    for &(s, _) in S::ROTATIONS {
        let r = UnitQuat::try_new(q[s], q[s + 1], q[s + 2], q[s + 3])
            .unwrap_or_default()
            .coords();
        q.fixed_rows_mut::<4>(s).copy_from_slice(&r);
    }
    q
}

/// `q · exp(h d)`: rotations right-multiplied by `exp(h d_ω)`, Euclidean slots moved by
/// `h d`.
fn retract<S: LieMechanism<N, NQ>, const N: usize, const NQ: usize>(
    q: &SVector<f64, NQ>,
    d: &SVector<f64, N>,
    h: f64,
) -> SVector<f64, NQ> {
    let mut out = *q;
    for &(s, c) in S::ROTATIONS {
        let r = UnitQuat::try_new(q[s], q[s + 1], q[s + 2], q[s + 3]).expect("unit");
        let w = Vector3::new(d[c], d[c + 1], d[c + 2]) * h;
        let moved = (r * UnitQuat::exp(&w)).coords();
        out.fixed_rows_mut::<4>(s).copy_from_slice(&moved);
    }
    for &(s, c) in S::EUCLID {
        out[s] += h * d[c];
    }
    out
}

fn check<
    S: LieMechanism<N, NQ>
        + Coriolis<N, NQ>
        + Gravity<N, NQ>
        + Bias<N, NQ>
        + InverseDynamics<N, NQ>
        + Energy<N, NQ>,
    const N: usize,
    const NQ: usize,
>(
    sys: &S,
    seed: u64,
) {
    let model = sys.model();
    let mut rng = Rng::new(seed);
    for _ in 0..common::STATES {
        let q = random_config::<S, N, NQ>(&mut rng);
        let v: SVector<f64, N> = rng.vector(2.0);
        let a: SVector<f64, N> = rng.vector(2.0);
        let tau: SVector<f64, N> = rng.vector(5.0);
        let (qd, vd) = (dv(&q), dv(&v));

        let m = sys.mass_matrix(&q);
        assert_close(
            m.as_slice(),
            numeric::crba(&model, &qd).as_slice(),
            1e-12,
            1e-12,
            "M vs CRBA",
        );
        let c = sys.coriolis_matrix(&q, &v);
        assert_close(
            c.as_slice(),
            numeric::lie_coriolis_matrix(&model, &qd, &vd).as_slice(),
            1e-11,
            1e-9,
            "C vs numeric (D_k M and the bracket term)",
        );
        let g = sys.gravity(&q);
        assert_close(
            g.as_slice(),
            numeric::gravity(&model, &qd).as_slice(),
            1e-12,
            1e-12,
            "g",
        );
        let b = sys.bias(&q, &v);
        assert_close(
            b.as_slice(),
            numeric::bias(&model, &qd, &vd).as_slice(),
            1e-12,
            1e-12,
            "bias",
        );
        let id = sys.inverse_dynamics(&q, &v, &a);
        assert_close(
            id.as_slice(),
            numeric::inverse_dynamics(&model, &qd, &vd, &dv(&a)).as_slice(),
            1e-12,
            1e-12,
            "inverse dynamics",
        );
        let fd = sys.forward_dynamics(&q, &v, &tau);
        assert_close(
            fd.as_slice(),
            numeric::forward_dynamics(&model, &qd, &vd, &dv(&tau)).as_slice(),
            1e-11,
            1e-12,
            "forward dynamics",
        );
        assert_close(
            &[sys.kinetic_energy(&q, &v)],
            &[numeric::kinetic_energy(&model, &qd, &vd)],
            1e-12,
            1e-12,
            "kinetic energy",
        );
        assert_close(
            &[sys.potential_energy(&q)],
            &[numeric::potential_energy(&model, &qd)],
            1e-12,
            1e-9,
            "potential energy",
        );

        assert_eq!(m, m.transpose(), "M must be exactly symmetric");
        assert!(m.cholesky().is_some(), "M must be positive definite");
        assert_close(
            (c * v + g).as_slice(),
            b.as_slice(),
            1e-12,
            1e-12,
            "C v + g vs RNEA bias",
        );

        // Ṁ − 2C skew, Ṁ along the motion g · exp(±h v).
        let h = 1e-6;
        let mdot = (sys.mass_matrix(&retract::<S, N, NQ>(&q, &v, h))
            - sys.mass_matrix(&retract::<S, N, NQ>(&q, &v, -h)))
            / (2.0 * h);
        let s = mdot - c * 2.0;
        assert!(
            (s + s.transpose()).norm() <= 1e-6 * (1.0 + mdot.norm()),
            "Ṁ − 2C not skew: {:.3e}",
            (s + s.transpose()).norm()
        );

        let back = sys.inverse_dynamics(&q, &v, &fd);
        assert_close(
            back.as_slice(),
            tau.as_slice(),
            1e-10,
            1e-10,
            "ID(FD(τ)) = τ",
        );

        // The Jacobian in local exponential coordinates against central differences.
        let jac = sys.forward_dynamics_jacobian(&q, &v, &tau);
        assert_close(
            jac.acceleration.as_slice(),
            fd.as_slice(),
            1e-13,
            1e-13,
            "Jacobian's acceleration",
        );
        let h = 1e-6;
        let mut dq = SMatrix::<f64, N, N>::zeros();
        let mut dvv = SMatrix::<f64, N, N>::zeros();
        for k in 0..N {
            let e = SVector::<f64, N>::from_fn(|i, _| if i == k { 1.0 } else { 0.0 });
            let plus = sys.forward_dynamics(&retract::<S, N, NQ>(&q, &e, h), &v, &tau);
            let minus = sys.forward_dynamics(&retract::<S, N, NQ>(&q, &e, -h), &v, &tau);
            dq.set_column(k, &((plus - minus) / (2.0 * h)));
            let plus = sys.forward_dynamics(&q, &(v + e * h), &tau);
            let minus = sys.forward_dynamics(&q, &(v - e * h), &tau);
            dvv.set_column(k, &((plus - minus) / (2.0 * h)));
        }
        assert_close(jac.d_dq.as_slice(), dq.as_slice(), 1e-6, 1.0, "∂v̇/∂φ");
        assert_close(jac.d_dv.as_slice(), dvv.as_slice(), 1e-6, 1.0, "∂v̇/∂v");
    }
}

#[test]
fn spherical_body_identities() {
    check(&SphericalBody::default(), 11);
}

#[test]
fn free_body_identities() {
    check(&FreeBody::default(), 12);
}

#[test]
fn satellite_with_arm_identities() {
    check(&Satellite::default(), 13);
}

#[test]
fn ball_joint_in_a_chain_identities() {
    check(&BallChain::default(), 14);
}

/// Euler's equations: `I ω̇ = τ − ω × I ω`, whatever the orientation.
#[test]
fn spherical_body_is_euler_equations() {
    let body = SphericalBody::default();
    let i = Vector3::new(body.i1, body.i2, body.i3);
    let mut rng = Rng::new(5);
    for _ in 0..10 {
        let q = random_config::<SphericalBody, 3, 4>(&mut rng);
        let w: SVector<f64, 3> = rng.vector(2.0);
        let tau: SVector<f64, 3> = rng.vector(2.0);
        let iw = i.component_mul(&w);
        let expected = (tau - w.cross(&iw)).component_div(&i);
        let got = body.forward_dynamics(&q, &w, &tau);
        assert_close(got.as_slice(), expected.as_slice(), 1e-14, 1e-14, "Euler");
    }
}

/// A free body at its centre of mass: `M = diag(m 𝟙, I)` in every configuration.
#[test]
fn free_body_mass_matrix_is_constant() {
    let body = FreeBody {
        m: 2.5,
        ..FreeBody::default()
    };
    let mut rng = Rng::new(6);
    for _ in 0..10 {
        let q = random_config::<FreeBody, 6, 7>(&mut rng);
        let m = body.mass_matrix(&q);
        let expected = SMatrix::<f64, 6, 6>::from_diagonal(&SVector::<f64, 6>::from([
            2.5, 2.5, 2.5, body.i1, body.i2, body.i3,
        ]));
        assert_close(m.as_slice(), expected.as_slice(), 1e-14, 1e-14, "M");
    }
}

/// The satellite with its arm in zero gravity keeps its energy and its spatial
/// momentum (linear and angular about the world origin) along a Rkmk5 run.
#[test]
fn satellite_conserves_energy_and_momentum() {
    let sat = Satellite::default();
    let model = sat.model();
    let mut q = Satellite::identity_configuration();
    q[1] = 0.3;
    q[Satellite::CONFIG - 2] = 0.7; // shoulder
    q[Satellite::CONFIG - 1] = -0.4; // elbow
    let v = SVector::<f64, 8>::from([0.1, -0.2, 0.05, 0.3, -0.5, 0.8, 1.5, -2.0]);
    let system = LieMechanical::free(&sat);
    let y0 = Satellite::qv_to_state(&q, &v);
    let problem = LieProblem::new(0.0, 10.0, y0);
    let traj = Rkmk5::new(Options::tolerances(1e-11, 1e-13))
        .solve(&system, &problem)
        .expect("run");
    let (p0, l0) = numeric::spatial_momentum(&model, &dv(&q), &dv(&v));
    let e0 = sat.kinetic_energy(&q, &v);
    for k in 0..traj.len() {
        let (qk, vk) = Satellite::state_to_qv(&traj.state(k));
        let (p, l) = numeric::spatial_momentum(&model, &dv(&qk), &dv(&vk));
        assert!(
            (p - p0).norm() <= 1e-9 * p0.norm().max(1.0),
            "linear momentum drifts: {:.3e}",
            (p - p0).norm()
        );
        assert!(
            (l - l0).norm() <= 1e-9 * l0.norm().max(1.0),
            "angular momentum drifts: {:.3e}",
            (l - l0).norm()
        );
        let e = sat.kinetic_energy(&qk, &vk);
        assert!((e - e0).abs() <= 1e-9 * e0, "energy drifts: {:.3e}", e - e0);
    }
}

/// `Output` on a Lie-group run: `Times(ts)` gives exactly `ts`, each state the dense
/// output on the group of the same run kept at every step; `Every(k)` every `k`-th step
/// and the last, equal to those rows. Both methods.
#[test]
fn lie_runs_keep_the_rows_output_asks_for() {
    let sat = Satellite::default();
    let mut q = Satellite::identity_configuration();
    q[1] = 0.3;
    q[Satellite::CONFIG - 2] = 0.7;
    let v = SVector::<f64, 8>::from([0.1, -0.2, 0.05, 0.3, -0.5, 0.8, 1.5, -2.0]);
    let system = LieMechanical::free(&sat);
    let problem = LieProblem::new(0.0, 3.0, Satellite::qv_to_state(&q, &v));
    let ts: Vec<f64> = (0..=30).map(|k| 0.1 * k as f64).collect();
    let flat = |s: &filippov::runtime::LieState| -> Vec<f64> {
        let (q, v) = Satellite::state_to_qv(s);
        q.iter().chain(v.iter()).copied().collect()
    };
    let options = Options::tolerances(1e-9, 1e-11);
    for name in ["RKMK5", "LieSdirk"] {
        let solve = |p: &LieProblem| match name {
            "RKMK5" => Rkmk5::new(options).solve(&system, p).unwrap(),
            _ => filippov::runtime::LieSdirk::new(options)
                .solve(&system, p)
                .unwrap(),
        };
        let steps = solve(&problem);
        let at_times = solve(&problem.clone().with_output(Output::Times(ts.clone())));
        assert_eq!(at_times.times(), &ts[..], "{name}");
        assert_eq!(at_times.flat().times(), &ts[..], "{name}");
        for (i, &t) in ts.iter().enumerate() {
            assert_eq!(
                flat(&at_times.state(i)),
                flat(&steps.at(t).unwrap()),
                "{name}: t = {t}"
            );
            // The dense output still covers every step.
            assert_eq!(at_times.at(t), steps.at(t), "{name}: t = {t}");
        }
        let every = solve(&problem.clone().with_output(Output::Every(3)));
        let n = steps.len();
        let kept: Vec<usize> = (0..n).filter(|&i| i % 3 == 0 || i + 1 == n).collect();
        assert_eq!(every.len(), kept.len(), "{name}");
        for (row, &i) in kept.iter().enumerate() {
            assert_eq!(every.times()[row], steps.times()[i]);
            assert_eq!(flat(&every.state(row)), flat(&steps.state(i)));
        }
        assert_eq!(every.stats, steps.stats, "{name}: the same run");
    }
}

/// `mechanism_rows`: a run's rows in the mechanism's layout are `state_to_qv` of its
/// states, the columns named after the configuration and the coordinates, and each row's
/// velocity derivative the forward dynamics there. On a free base with an arm and on a
/// ball joint between hinges (rotations and Euclidean slots interleaved).
#[test]
fn lie_rows_in_the_mechanism_layout() {
    fn check<S, const N: usize, const NQ: usize>(scene: &S, seed: u64)
    where
        S: LieMechanism<N, NQ>,
    {
        let mut rng = Rng::new(seed);
        let q = random_config::<S, N, NQ>(&mut rng);
        let v: SVector<f64, N> = rng.vector(1.0);
        let traj = Rkmk5::new(Options::tolerances(1e-8, 1e-10))
            .solve(
                &LieMechanical::free(scene),
                &LieProblem::new(0.0, 0.5, S::qv_to_state(&q, &v)),
            )
            .unwrap();
        let rows = filippov::runtime::liegroup::mechanism_rows::<S, N, NQ>(traj.flat()).unwrap();
        let names = S::configuration_names();
        assert_eq!(rows.names().len(), NQ + N);
        for (j, c) in names.iter().enumerate() {
            assert_eq!(rows.names()[j], format!("q_{c}"));
        }
        for (j, c) in S::COORDINATES.iter().enumerate() {
            assert_eq!(rows.names()[NQ + j], format!("v_{c}"));
        }
        for &(s, _) in S::ROTATIONS {
            assert!(names[s].ends_with(".qw") && names[s + 3].ends_with(".qz"));
        }
        assert_eq!(rows.len(), traj.len());
        assert_eq!(rows.stats, traj.stats);
        for i in 0..traj.len() {
            let (qi, vi) = S::state_to_qv(&traj.state(i));
            let expected: Vec<f64> = qi.iter().chain(vi.iter()).copied().collect();
            assert_eq!(rows.state(i), &expected[..], "row {i}");
            let a = scene.forward_dynamics(&qi, &vi, &SVector::zeros());
            assert_close(&rows.derivative(i)[NQ..], a.as_slice(), 1e-12, 1.0, "v̇");
        }
    }
    check(&Satellite::default(), 11);
    check(&BallChain::default(), 12);
    // A run of another mechanism (other columns): no rows.
    let body = SphericalBody::default();
    let traj = Rkmk5::new(Options::default())
        .solve(
            &LieMechanical::free(&body),
            &LieProblem::new(
                0.0,
                0.1,
                SphericalBody::qv_to_state(
                    &SphericalBody::identity_configuration(),
                    &SVector::from([0.1, 1.0, 0.0]),
                ),
            ),
        )
        .unwrap();
    assert!(filippov::runtime::liegroup::mechanism_rows::<Satellite, 8, 9>(traj.flat()).is_none());
}
