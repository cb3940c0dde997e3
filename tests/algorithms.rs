//! The two ways the derive solves with the mass matrix — the articulated-body algorithm
//! (`forward_dynamics = aba`) and the CRBA mass matrix with its sparse `LᵀDL`
//! (`forward_dynamics = crba`) — on the same scenes: forward dynamics against the
//! numeric implementation, the Jacobians of both against each other and against central
//! differences of forward dynamics, and `M⁻¹` against the inverse of the numeric mass
//! matrix. The scenes cover what changes the algorithm's code: planar and 3D chains,
//! branches, oblique axes, prismatic, fixed, spherical and free joints, springs, dampers
//! and non-smooth elements.

// clippy's duplicated_attributes misreads repeated derive-helper attributes.
#![allow(clippy::duplicated_attributes)]

mod common;

use common::{Rng, assert_close, dvec};
use filippov::nalgebra::{DVector, SMatrix, SVector, UnitQuaternion, Vector3};
use filippov::prelude::*;
use filippov::runtime::liegroup::LieMechanism;
use filippov::runtime::nonsmooth::NonSmooth;
use filippov::runtime::numeric;
use filippov::runtime::system::ForwardJacobian;

/// Declares the same scene twice, once per algorithm.
macro_rules! both {
    ($aba:ident, $crba:ident, $fields:tt, [$($mech:tt)*], $($attrs:tt)*) => {
        #[derive(Mechanism, Clone, Copy)]
        #[mechanism(forward_dynamics = aba, $($mech)*)]
        $($attrs)*
        struct $aba $fields

        #[derive(Mechanism, Clone, Copy)]
        #[mechanism(forward_dynamics = crba, $($mech)*)]
        $($attrs)*
        struct $crba $fields
    };
}

both!(ChainAba, ChainCrba, { m: f64, l: f64, k: f64 }, [gravity = [0.0, -9.81, 0.0]],
    #[body(b0: revolute(z), parent = world, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
    #[body(b1: revolute(z), parent = b0, origin = [l, 0.0, 0.0], mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
    #[body(b2: revolute(z), parent = b1, origin = [l, 0.0, 0.0], mass = 2.0 * m, com = [l / 2.0, 0.0, 0.0], inertia = rod(2.0 * m, l))]
    #[body(b3: revolute(z), parent = b2, origin = [l, 0.0, 0.0], mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
    #[body(b4: revolute(z), parent = b3, origin = [l, 0.0, 0.0], mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
    #[body(b5: revolute(z), parent = b4, origin = [l, 0.0, 0.0], mass = m / 2.0, com = [l / 2.0, 0.0, 0.0], inertia = rod(m / 2.0, l))]
    #[body(b6: revolute(z), parent = b5, origin = [l, 0.0, 0.0], mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
    #[body(b7: revolute(z), parent = b6, origin = [l, 0.0, 0.0], mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
    #[body(b8: revolute(z), parent = b7, origin = [l, 0.0, 0.0], mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
    #[spring(b3, k = k, rest = 0.2)]
    #[damper(b6, c = 0.3)]
);

both!(TreeAba, TreeCrba, { m: f64, l: f64 }, [gravity = [0.3, -1.0, -9.81]],
    #[body(base: revolute(z), parent = world, mass = m, com = [0.0, 0.0, l / 2.0], inertia = cuboid(m, 0.2, 0.1, l))]
    #[body(slider: prismatic([0.6, 0.0, 0.8]), parent = base, origin = [0.1, 0.0, l], mass = m, com = [0.05, 0.02, 0.1], inertia = cuboid(m, 0.1, 0.1, 0.2))]
    #[body(left: revolute(x), parent = slider, origin = [0.0, 0.1, 0.2], rpy = [0.3, -0.2, 0.5], mass = m, com = [0.0, 0.1, l / 2.0], inertia = cylinder(m, 0.05, l))]
    #[body(lhand: fixed, parent = left, origin = [0.0, 0.0, l], rpy = [0.0, 0.4, 0.0], mass = m / 3.0, com = [0.02, 0.0, 0.03], inertia = cuboid(m / 3.0, 0.05, 0.05, 0.05))]
    #[body(lfinger: revolute(-y), parent = lhand, origin = [0.0, 0.0, 0.05], mass = m / 5.0, com = [0.0, 0.0, 0.03], inertia = rod(m / 5.0, 0.06))]
    #[body(right: revolute([1.0, 2.0, 2.0]), parent = slider, origin = [0.0, -0.1, 0.2], rpy = [-0.3, 0.1, 0.2], mass = m, com = [0.01, -0.1, l / 2.0], inertia = cuboid(m, 0.05, 0.07, l))]
    #[body(rslide: prismatic(y), parent = right, origin = [0.0, 0.0, l], mass = m / 2.0, com = [0.0, 0.03, 0.0], inertia = cuboid(m / 2.0, 0.05, 0.05, 0.05))]
    #[body(rtip: revolute(z), parent = rslide, origin = [0.02, 0.0, 0.05], mass = m / 4.0, com = [0.03, 0.0, 0.0], inertia = rod(m / 4.0, 0.06))]
    #[damper(rslide, c = 0.2)]
);

both!(BallAba, BallCrba, { m: f64, l: f64 }, [gravity = [0.0, 0.0, -9.81]],
    #[body(upper: revolute(y), parent = world, mass = m, com = [0.0, 0.0, -l / 2.0], inertia = cuboid(m, 0.1, 0.08, l))]
    #[body(middle: spherical, parent = upper, origin = [0.0, 0.05, -l], rpy = [0.2, 0.0, 0.3], mass = m, com = [0.02, 0.0, -l / 2.0], inertia = cuboid(m, 0.1, 0.12, l))]
    #[body(lower: revolute(x), parent = middle, origin = [0.0, 0.0, -l], mass = m / 2.0, com = [0.0, 0.01, -l / 2.0], inertia = cuboid(m / 2.0, 0.06, 0.06, l))]
    #[body(tip: spherical, parent = lower, origin = [0.0, 0.0, -l], mass = m / 4.0, com = [0.01, 0.02, -0.05], inertia = cuboid(m / 4.0, 0.05, 0.06, 0.1))]
);

both!(FloatAba, FloatCrba, { m: f64, l: f64 }, [gravity = [0.0, 0.0, -9.81]],
    #[body(base: free, parent = world, mass = 4.0 * m, com = [0.01, 0.0, 0.02], inertia = cuboid(4.0 * m, 0.6, 0.4, 0.2))]
    #[body(upper: revolute(z), parent = base, origin = [0.3, 0.1, 0.1], mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
    #[body(fore: revolute(y), parent = upper, origin = [l, 0.0, 0.0], mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
    #[body(leg: prismatic(-z), parent = base, origin = [-0.3, 0.0, -0.1], mass = m / 2.0, com = [0.0, 0.0, -0.1], inertia = cuboid(m / 2.0, 0.05, 0.05, 0.2))]
);

both!(StopsAba, StopsCrba, { m: f64, l: f64, mu: f64 }, [gravity = [0.0, 0.0, -9.81]],
    #[body(shoulder: revolute(z), parent = world, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
    #[body(elbow: revolute(y), parent = shoulder, origin = [l, 0.0, 0.0], mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
    #[body(wrist: revolute(x), parent = elbow, origin = [l, 0.0, 0.0], mass = m / 2.0, com = [0.05, 0.02, 0.0], inertia = cuboid(m / 2.0, 0.1, 0.05, 0.05))]
    #[friction(elbow, f_crit = mu)]
    #[stop(shoulder, max = 1.0, restitution = 0.5)]
);

const STATES: usize = 12;

/// Both algorithms' forward dynamics against the numeric implementation, and their
/// Jacobians (the `v̇` they return too) against each other.
fn agree<const N: usize>(
    (fa, fc): (SVector<f64, N>, SVector<f64, N>),
    (ja, jc): (&ForwardJacobian<N>, &ForwardJacobian<N>),
    reference: &DVector<f64>,
) {
    let r = reference.as_slice();
    assert_close(fa.as_slice(), r, 1e-11, 1e-9, "FD (aba) vs numeric");
    assert_close(fc.as_slice(), r, 1e-11, 1e-9, "FD (crba) vs numeric");
    let acc = ja.acceleration.as_slice();
    assert_close(acc, r, 1e-11, 1e-9, "v̇ of the Jacobian kernel");
    let (a, c) = (ja.d_dq.as_slice(), jc.d_dq.as_slice());
    assert_close(a, c, 1e-10, 1e-9, "∂v̇/∂q aba vs crba");
    let (a, c) = (ja.d_dv.as_slice(), jc.d_dv.as_slice());
    assert_close(a, c, 1e-10, 1e-9, "∂v̇/∂v aba vs crba");
}

/// A Jacobian against central differences of `f(k, h)`, forward dynamics a step `h`
/// along coordinate `k`, relative to the whole Jacobian (rounding in a difference
/// scales with the largest acceleration, not with each column).
fn vs_differences<const N: usize>(
    jacobian: &SMatrix<f64, N, N>,
    f: impl Fn(usize, f64) -> SVector<f64, N>,
    what: &str,
) {
    let h = 1e-6;
    let d = SMatrix::<f64, N, N>::from_fn(|i, k| (f(k, h)[i] - f(k, -h)[i]) / (2.0 * h));
    assert_close(jacobian.as_slice(), d.as_slice(), 1e-6, 1.0, what);
}

/// FD of both against the numeric implementation, their Jacobians against each other
/// and against central differences, on random states.
fn compare<A: Mechanism<N>, B: Mechanism<N>, const N: usize>(aba: &A, crba: &B, seed: u64) {
    let model = aba.model();
    let mut rng = Rng::new(seed);
    for _ in 0..STATES {
        let q: SVector<f64, N> = rng.vector(2.0);
        let v: SVector<f64, N> = rng.vector(2.0);
        let tau: SVector<f64, N> = rng.vector(3.0);
        let reference = numeric::forward_dynamics(&model, &dvec(&q), &dvec(&v), &dvec(&tau));
        let ja = aba.forward_dynamics_jacobian(&q, &v, &tau);
        let jc = crba.forward_dynamics_jacobian(&q, &v, &tau);
        let fd = |q: &SVector<f64, N>, v: &SVector<f64, N>| aba.forward_dynamics(q, v, &tau);
        agree(
            (fd(&q, &v), crba.forward_dynamics(&q, &v, &tau)),
            (&ja, &jc),
            &reference,
        );
        let e = |k: usize| SVector::<f64, N>::from_fn(|i, _| f64::from(i == k));
        let along_q = |k, h| fd(&(q + e(k) * h), &v);
        vs_differences(&ja.d_dq, along_q, "∂v̇/∂q vs differences");
        let along_v = |k, h| fd(&q, &(v + e(k) * h));
        vs_differences(&ja.d_dv, along_v, "∂v̇/∂v vs differences");
    }
}

/// The same for scenes with spherical or free joints: random unit quaternions, and
/// differences along the group's retraction.
fn compare_lie<A, B, const N: usize, const NQ: usize>(aba: &A, crba: &B, seed: u64)
where
    A: LieMechanism<N, NQ>,
    B: LieMechanism<N, NQ>,
{
    let model = aba.model();
    let mut rng = Rng::new(seed);
    for _ in 0..STATES {
        let mut q: SVector<f64, NQ> = rng.vector(2.0);
        for &(s, _) in A::ROTATIONS {
            let axis = Vector3::new(q[s], q[s + 1], q[s + 2]);
            let r = UnitQuaternion::from_scaled_axis(axis);
            q[s] = r.w;
            q[s + 1] = r.i;
            q[s + 2] = r.j;
            q[s + 3] = r.k;
        }
        let v: SVector<f64, N> = rng.vector(2.0);
        let tau: SVector<f64, N> = rng.vector(3.0);
        let qd = DVector::from_column_slice(q.as_slice());
        let reference = numeric::forward_dynamics(&model, &qd, &dvec(&v), &dvec(&tau));
        let ja = aba.forward_dynamics_jacobian(&q, &v, &tau);
        let jc = crba.forward_dynamics_jacobian(&q, &v, &tau);
        let fd = |q: &SVector<f64, NQ>, v: &SVector<f64, N>| aba.forward_dynamics(q, v, &tau);
        agree(
            (fd(&q, &v), crba.forward_dynamics(&q, &v, &tau)),
            (&ja, &jc),
            &reference,
        );
        let e = |k: usize| SVector::<f64, N>::from_fn(|i, _| f64::from(i == k));
        let along_phi = |k, h| fd(&A::retract(&q, &(e(k) * h)), &v);
        vs_differences(&ja.d_dq, along_phi, "∂v̇/∂φ vs differences");
        let along_v = |k, h| fd(&q, &(v + e(k) * h));
        vs_differences(&ja.d_dv, along_v, "∂v̇/∂v vs differences");
    }
}

#[test]
fn planar_chain_by_both_algorithms() {
    let (m, l, k) = (1.3, 0.4, 7.0);
    compare(&ChainAba { m, l, k }, &ChainCrba { m, l, k }, 11);
}

#[test]
fn branched_3d_tree_with_prismatic_fixed_and_oblique_joints_by_both_algorithms() {
    let (m, l) = (0.9, 0.35);
    compare(&TreeAba { m, l }, &TreeCrba { m, l }, 12);
}

#[test]
fn spherical_joints_by_both_algorithms() {
    let (m, l) = (1.1, 0.5);
    compare_lie(&BallAba { m, l }, &BallCrba { m, l }, 13);
}

#[test]
fn free_base_by_both_algorithms() {
    let (m, l) = (1.7, 0.45);
    compare_lie(&FloatAba { m, l }, &FloatCrba { m, l }, 14);
}

#[test]
fn inverse_mass_matrix_by_both_algorithms() {
    let (m, l, mu) = (1.2, 0.6, 0.4);
    let (aba, crba) = (StopsAba { m, l, mu }, StopsCrba { m, l, mu });
    compare(&aba, &crba, 15);
    let model = aba.model();
    let mut rng = Rng::new(16);
    for _ in 0..STATES {
        let q: SVector<f64, 3> = rng.vector(2.0);
        let reference = numeric::crba(&model, &dvec(&q))
            .try_inverse()
            .expect("M is invertible");
        let ia = aba.inverse_mass_matrix(&q);
        let ic = crba.inverse_mass_matrix(&q);
        assert_close(
            ia.as_slice(),
            reference.as_slice(),
            1e-11,
            1e-9,
            "M⁻¹ (aba) vs numeric",
        );
        assert_close(
            ic.as_slice(),
            reference.as_slice(),
            1e-11,
            1e-9,
            "M⁻¹ (crba) vs numeric",
        );
    }
}
