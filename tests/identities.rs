//! Identities every generated mechanism must satisfy, checked on random states for every
//! canonical scene:
//! - generated kernels equal the independent numeric implementation (runtime `numeric`);
//! - `M` symmetric positive definite; `Ṁ − 2C` skew-symmetric (`Ṁ` by finite differences
//!   along `v`); `C v + g` equals the RNEA bias;
//! - inverse ∘ forward dynamics is the identity;
//! - the symbolic Jacobian of the forward dynamics equals central finite differences;
//! - energy: `dE/dt = vᵀ τ + vᵀ τ_damping` along the forward dynamics.

mod common;

use common::{Rng, assert_close, dmat, dvec};
use filippov::Mechanism;
use filippov::nalgebra::SVector;
use filippov::runtime::numeric;
use filippov::scenes::{BranchedTree, DoublePendulum, Panda, PlanarArm3};

const STATES: usize = 25;

fn check<S: Mechanism<N>, const N: usize>(sys: &S, seed: u64) {
    let model = sys.model();
    let mut rng = Rng::new(seed);
    for _ in 0..STATES {
        let q: SVector<f64, N> = rng.vector(3.0);
        let v: SVector<f64, N> = rng.vector(2.0);
        let a: SVector<f64, N> = rng.vector(2.0);
        let tau: SVector<f64, N> = rng.vector(5.0);
        let (qd, vd) = (dvec(&q), dvec(&v));

        // Against the numeric implementation (≤ 1e-12 relative).
        let m = sys.mass_matrix(&q);
        assert_close(
            m.as_slice(),
            numeric::crba(&model, &qd).as_slice(),
            1e-12,
            1e-12,
            "M vs CRBA",
        );
        let c = sys.coriolis_matrix(&q, &v);
        let cn = numeric::coriolis_matrix(&model, &qd, &vd);
        assert_close(
            c.as_slice(),
            cn.as_slice(),
            1e-12,
            1e-9,
            "C vs numeric Christoffel",
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
        let idn = numeric::inverse_dynamics(&model, &qd, &vd, &dvec(&a));
        assert_close(
            id.as_slice(),
            idn.as_slice(),
            1e-12,
            1e-12,
            "inverse dynamics",
        );
        let fd = sys.forward_dynamics(&q, &v, &tau);
        let fdn = numeric::forward_dynamics(&model, &qd, &vd, &dvec(&tau));
        assert_close(
            fd.as_slice(),
            fdn.as_slice(),
            1e-11,
            1e-12,
            "forward dynamics",
        );
        let p = sys.passive_forces(&q, &v);
        assert_close(
            p.as_slice(),
            numeric::passive_forces(&model, &qd, &vd).as_slice(),
            1e-14,
            1e-14,
            "passive",
        );
        let ke = sys.kinetic_energy(&q, &v);
        assert_close(
            &[ke],
            &[numeric::kinetic_energy(&model, &qd, &vd)],
            1e-12,
            1e-12,
            "kinetic energy",
        );
        let pe = sys.potential_energy(&q);
        assert_close(
            &[pe],
            &[numeric::potential_energy(&model, &qd)],
            1e-12,
            1e-9,
            "potential energy",
        );

        // Christoffel symbols assemble the Coriolis matrix.
        let gam = sys.christoffel_symbols(&q);
        for i in 0..N {
            let row: Vec<f64> = (0..N)
                .map(|j| (0..N).map(|k| gam[i][(j, k)] * v[k]).sum())
                .collect();
            let crow: Vec<f64> = (0..N).map(|j| c[(i, j)]).collect();
            assert_close(&row, &crow, 1e-13, 1e-12, "Σ c_ijk v_k = C_ij");
        }

        // M symmetric positive definite.
        assert_eq!(m, m.transpose(), "M must be exactly symmetric");
        assert!(m.cholesky().is_some(), "M must be positive definite");

        // C v + g = bias.
        assert_close(
            (c * v + g).as_slice(),
            b.as_slice(),
            1e-12,
            1e-12,
            "C v + g vs RNEA bias",
        );

        // Ṁ − 2C skew-symmetric, Ṁ by central differences along v.
        let h = 1e-6;
        let mdot = (sys.mass_matrix(&(q + v * h)) - sys.mass_matrix(&(q - v * h))) / (2.0 * h);
        let s = mdot - c * 2.0;
        let skew = s + s.transpose();
        assert!(
            skew.norm() <= 1e-6 * (1.0 + mdot.norm()),
            "Ṁ − 2C not skew: ‖S + Sᵀ‖ = {:.3e}",
            skew.norm()
        );

        // inverse ∘ forward = identity.
        let back = sys.inverse_dynamics(&q, &v, &fd);
        assert_close(
            back.as_slice(),
            tau.as_slice(),
            1e-10,
            1e-10,
            "ID(FD(τ)) = τ",
        );

        // Symbolic Jacobian against central finite differences.
        let jac = sys.forward_dynamics_jacobian(&q, &v, &tau);
        assert_close(
            jac.acceleration.as_slice(),
            fd.as_slice(),
            1e-13,
            1e-13,
            "Jacobian's acceleration",
        );
        let eps = 1e-6;
        let mut dq = dmat(&jac.d_dq) * 0.0;
        let mut dv = dq.clone();
        for k in 0..N {
            let mut e = SVector::<f64, N>::zeros();
            e[k] = eps;
            let col_q = (sys.forward_dynamics(&(q + e), &v, &tau)
                - sys.forward_dynamics(&(q - e), &v, &tau))
                / (2.0 * eps);
            let col_v = (sys.forward_dynamics(&q, &(v + e), &tau)
                - sys.forward_dynamics(&q, &(v - e), &tau))
                / (2.0 * eps);
            dq.set_column(k, &dvec(&col_q));
            dv.set_column(k, &dvec(&col_v));
        }
        assert_close(
            jac.d_dq.as_slice(),
            dq.as_slice(),
            1e-6,
            1.0,
            "∂v̇/∂q vs finite differences",
        );
        assert_close(
            jac.d_dv.as_slice(),
            dv.as_slice(),
            1e-6,
            1.0,
            "∂v̇/∂v vs finite differences",
        );

        // Power balance: d(T + U)/dt = vᵀ (τ + τ_damping), by central differences along
        // the flow (q̇ = v, v̇ = FD).
        let energy = |q: &SVector<f64, N>, v: &SVector<f64, N>| {
            sys.kinetic_energy(q, v) + sys.potential_energy(q)
        };
        let dt = 1e-6;
        let de = (energy(&(q + v * dt), &(v + fd * dt)) - energy(&(q - v * dt), &(v - fd * dt)))
            / (2.0 * dt);
        let damping: f64 = model
            .dampers
            .iter()
            .map(|d| -d.damping * v[d.coordinate] * v[d.coordinate])
            .sum();
        let power = v.dot(&tau) + damping;
        assert!(
            (de - power).abs() <= 1e-5 * (1.0 + power.abs()),
            "dE/dt = {de}, power = {power}"
        );
    }
}

#[test]
fn double_pendulum() {
    check(&DoublePendulum::default(), 1);
}

#[test]
fn planar_arm3() {
    check(&PlanarArm3::default(), 2);
}

#[test]
fn branched_tree() {
    check(&BranchedTree::default(), 3);
}

#[test]
fn panda() {
    check(&Panda::default(), 4);
}

/// Closed form of theory S8 (two uniform rods, angles from the x axis, gravity −y).
#[test]
fn double_pendulum_closed_form() {
    let p = DoublePendulum::default();
    let DoublePendulum { m1, l1, m2, l2, g } = p;
    let mut rng = Rng::new(7);
    for _ in 0..STATES {
        let q: SVector<f64, 2> = rng.vector(3.0);
        let v: SVector<f64, 2> = rng.vector(3.0);
        let (lc1, lc2) = (l1 / 2.0, l2 / 2.0);
        let (i1, i2) = (m1 * l1 * l1 / 12.0, m2 * l2 * l2 / 12.0);
        let (c2, s2) = (q[1].cos(), q[1].sin());
        let m11 = m1 * lc1 * lc1 + i1 + m2 * (l1 * l1 + lc2 * lc2 + 2.0 * l1 * lc2 * c2) + i2;
        let m12 = m2 * (lc2 * lc2 + l1 * lc2 * c2) + i2;
        let m22 = m2 * lc2 * lc2 + i2;
        let h = -m2 * l1 * lc2 * s2;
        let c = [h * v[1], -h * v[0], h * (v[0] + v[1]), 0.0]; // column-major
        let g1 = (m1 * lc1 + m2 * l1) * g * q[0].cos() + m2 * lc2 * g * (q[0] + q[1]).cos();
        let g2 = m2 * lc2 * g * (q[0] + q[1]).cos();
        assert_close(
            p.mass_matrix(&q).as_slice(),
            &[m11, m12, m12, m22],
            1e-14,
            1e-14,
            "M",
        );
        assert_close(p.coriolis_matrix(&q, &v).as_slice(), &c, 1e-14, 1e-14, "C");
        assert_close(p.gravity(&q).as_slice(), &[g1, g2], 1e-14, 1e-14, "g");
    }
}

/// `inputs = [...]` maps an input vector onto the actuated coordinates only.
#[test]
fn input_map_places_inputs_on_actuated_joints() {
    assert_eq!(BranchedTree::INPUTS, [0, 2]);
    let tau = BranchedTree::input_forces(&SVector::<f64, 2>::new(1.5, -2.0));
    assert_eq!(tau, SVector::<f64, 4>::new(1.5, 0.0, -2.0, 0.0));
    assert_eq!(Panda::INPUTS, [0, 1, 2, 3, 4, 5, 6]);
}

mod nonsmooth {
    use super::*;
    use filippov::runtime::nonsmooth::{ElementKind, Law, NonSmooth, Selection, Side, StopKind};
    use filippov::scenes::{
        BinghamOscillator, BouncingBall, CoulombOscillator, CubicBingham,
        NonMonotoneMaxDissipation, NonMonotoneNoJumps, SupportedStop,
    };

    fn inverse_mass_is_inverse<S: NonSmooth<N>, const N: usize>(sys: &S) {
        let mut rng = Rng::new(11);
        for _ in 0..STATES {
            let q: SVector<f64, N> = rng.vector(3.0);
            let prod = sys.inverse_mass_matrix(&q) * sys.mass_matrix(&q);
            let eye = filippov::nalgebra::SMatrix::<f64, N, N>::identity();
            assert_close(prod.as_slice(), eye.as_slice(), 1e-12, 1.0, "M⁻¹ M = 1");
        }
    }

    #[test]
    fn lumped_scenes_are_described_with_their_parameters() {
        let s1 = BinghamOscillator {
            m: 1.0,
            k: 1.0,
            f_crit: 0.1,
            eta: 0.2,
        };
        check(&s1, 21);
        inverse_mass_is_inverse(&s1);
        assert_eq!(BinghamOscillator::ELEMENTS, 1);
        let e = s1.element(0);
        assert_eq!(e.coordinate, 0);
        assert_eq!(
            e.kind,
            ElementKind::DashPot {
                law: Law::BinghamLinear { eta: 0.2 },
                f_crit: 0.1
            }
        );

        let c = CoulombOscillator {
            m: 2.0,
            k: 3.0,
            f_crit: 0.5,
        };
        assert_eq!(
            c.element(0).kind,
            ElementKind::DashPot {
                law: Law::Coulomb,
                f_crit: 0.5
            }
        );
        assert_eq!(c.mass_matrix(&SVector::<f64, 1>::new(0.3))[(0, 0)], 2.0);

        let s7 = SupportedStop {
            m: 1.0,
            k: 1.0,
            f_crit: 0.1,
            eta: 0.2,
            l: 0.5,
            k_support: 100.0,
        };
        assert_eq!(SupportedStop::ELEMENTS, 2);
        assert_eq!(
            s7.element(1).kind,
            ElementKind::Stop {
                side: Side::Upper,
                position: 0.5,
                kind: StopKind::SpringBacked { stiffness: 100.0 }
            }
        );
        let ball = BouncingBall {
            m: 1.0,
            g: 9.81,
            e: 0.5,
        };
        assert_eq!(
            ball.element(0).kind,
            ElementKind::Stop {
                side: Side::Lower,
                position: 0.0,
                kind: StopKind::Rigid { restitution: 0.5 }
            }
        );
        check(&ball, 22);
    }

    /// The user laws: values against the thesis's formulas (independent evaluation here),
    /// odd extension, and the symbolic derivative against central differences.
    #[test]
    fn user_laws_and_their_derivatives() {
        let cubic = CubicBingham {
            m: 1.0,
            k: 1.0,
            f_crit: 1.0,
            gamma: 1.0,
        };
        assert_eq!(
            cubic.element(0).kind,
            ElementKind::DashPot {
                law: Law::BinghamMonotone,
                f_crit: 1.0
            }
        );
        let nm1 = NonMonotoneNoJumps {
            m: 1.0,
            k: 1.0,
            f_crit: 1.0,
        };
        let nm2 = NonMonotoneMaxDissipation {
            m: 1.0,
            k: 1.0,
            f_crit: 1.0,
        };
        assert_eq!(
            nm1.element(0).kind,
            ElementKind::DashPot {
                law: Law::BinghamNonMonotone {
                    selection: Selection::NoVelocityJumps
                },
                f_crit: 1.0
            }
        );
        assert_eq!(
            nm2.element(0).kind,
            ElementKind::DashPot {
                law: Law::BinghamNonMonotone {
                    selection: Selection::MaximalDissipation
                },
                f_crit: 1.0
            }
        );
        let cubic_ref = |f: f64| f * f * (f - f.signum());
        let nm_ref = |f: f64| (1.0 + 0.1 * (f * f - 4.0) * (f * f - 9.0)) * (f - f.signum());
        for f in [-3.7, -2.2, -1.5, 1.2, 1.69072, 2.49909, 3.1] {
            let h = 1e-6;
            for (law, reference) in [
                (&|f| cubic.law(0, f), &cubic_ref as &dyn Fn(f64) -> f64),
                (&|f| nm1.law(0, f), &nm_ref),
            ]
                as [(&dyn Fn(f64) -> (f64, f64), &dyn Fn(f64) -> f64); 2]
            {
                let (v, dv) = law(f);
                assert!(
                    (v - reference(f)).abs() < 1e-12 * (1.0 + v.abs()),
                    "φ({f}) = {v}, expected {}",
                    reference(f)
                );
                let fd = (reference(f + h) - reference(f - h)) / (2.0 * h);
                assert!(
                    (dv - fd).abs() < 1e-6 * (1.0 + fd.abs()),
                    "φ'({f}) = {dv}, finite differences {fd}"
                );
            }
        }
        // theory §3: the non-monotone law has a local maximum 1.17493 at f = 1.69072 and a
        // local minimum 0.57187 at f = 2.49909.
        let (vmax, dmax) = nm2.law(0, 1.69072);
        let (vmin, dmin) = nm2.law(0, 2.49909);
        assert!(
            (vmax - 1.17493).abs() < 1e-5 && dmax.abs() < 1e-4,
            "{vmax} {dmax}"
        );
        assert!(
            (vmin - 0.57187).abs() < 1e-5 && dmin.abs() < 1e-4,
            "{vmin} {dmin}"
        );
    }
}

/// `validate()` accepts the canonical parameters and names every bad one.
#[test]
fn validate_names_bad_parameters() {
    use filippov::scenes::{BouncingBall, CoulombOscillator, SupportedStop};
    assert_eq!(DoublePendulum::default().validate(), Ok(()));
    assert_eq!(Panda::default().validate(), Ok(()));
    assert_eq!(BranchedTree::default().validate(), Ok(()));
    let bad = DoublePendulum {
        m1: -1.0,
        l2: f64::NAN,
        ..DoublePendulum::default()
    };
    let err = bad.validate().expect_err("negative mass and NaN length");
    let text = err.to_string();
    assert!(text.contains("mass of body `upper` (`m1`)"), "{text}");
    assert!(text.contains("field `l2`"), "{text}");
    assert!(err.problems.len() >= 2, "{err:?}");
    let c = CoulombOscillator {
        m: 1.0,
        k: 1.0,
        f_crit: -0.1,
    };
    assert!(
        c.validate()
            .expect_err("negative f_crit")
            .to_string()
            .contains("f_crit of `friction_x`")
    );
    let s = SupportedStop {
        m: 1.0,
        k: 1.0,
        f_crit: 0.1,
        eta: 0.2,
        l: 0.5,
        k_support: 0.0,
    };
    assert!(
        s.validate()
            .expect_err("zero support stiffness")
            .to_string()
            .contains("k_support of `stop_x`")
    );
    let b = BouncingBall {
        m: 1.0,
        g: 9.81,
        e: 1.5,
    };
    assert!(
        b.validate()
            .expect_err("restitution")
            .to_string()
            .contains("restitution of `stop_x`")
    );
}
