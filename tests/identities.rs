//! Identities every generated mechanism must satisfy, checked on random states for every
//! canonical scene:
//! - generated kernels equal the independent numeric implementation (runtime `numeric`);
//! - `M` symmetric positive definite; `Ṁ − 2C` skew-symmetric (`Ṁ` by finite differences
//!   along `v`); `C v + g` equals the RNEA bias;
//! - inverse ∘ forward dynamics is the identity;
//! - the symbolic Jacobian of the forward dynamics equals central finite differences;
//! - energy: `dE/dt = vᵀ τ + vᵀ τ_damping` along the forward dynamics.

mod common;

use common::{Rng, assert_close};
use filippov::nalgebra::SVector;
use filippov::prelude::*;
use filippov_scenes::{BranchedTree, DoublePendulum, Panda, PlanarArm3};

use common::{STATES, check};

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
    use filippov_scenes::{
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
    use filippov_scenes::{BouncingBall, CoulombOscillator, SupportedStop};
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
