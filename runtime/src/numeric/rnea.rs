//! Recursive Newton–Euler algorithm: inverse dynamics `M(q) a + C(q, v) v + g(q)`.
//!
//! Featherstone, *Rigid Body Dynamics Algorithms* (2008), §5.3, Table 5.1, written in
//! world coordinates (so no link-to-link transforms are needed; `Ṡ_i = v_i ×ₘ S_i`).
//! Gravity enters as a fictitious base acceleration `a_0 = −gravity` (§5.3). Springs
//! and dampers are *not* included: see [`super::inverse_dynamics`].
//!
//! Spherical and translation joints have three motion-subspace columns, each a motion
//! vector fixed in the link (see `kinematics.rs`), so the joint's velocity-product term
//! is the same `v_i ×ₘ S v_J` as for one-dof joints (no separate `Ṡ` term), and `v`, `a`
//! are the quasi-velocities (body angular velocity) and their time derivatives.

use nalgebra::{DVector, Vector6};

use super::Model;
use super::kinematics::WorldTree;
use super::spatial::{crf, crm};

/// `τ = M(q) a + C(q, v) v + g(q)` by the recursive Newton–Euler algorithm.
///
/// # Panics
/// If `q` is shorter than [`Model::config_dim`], or `v` or `a` shorter than
/// [`Model::dof`].
pub fn rnea(model: &Model, q: &DVector<f64>, v: &DVector<f64>, a: &DVector<f64>) -> DVector<f64> {
    let tree = WorldTree::new(model, q);
    rnea_in(model, &tree, v, a)
}

pub(crate) fn rnea_in(
    model: &Model,
    tree: &WorldTree,
    v: &DVector<f64>,
    a: &DVector<f64>,
) -> DVector<f64> {
    let n = model.links.len();
    let g = model.gravity;
    let base_acceleration = Vector6::new(0.0, 0.0, 0.0, -g.x, -g.y, -g.z);
    let mut vel = vec![Vector6::zeros(); n];
    let mut acc = vec![Vector6::zeros(); n];
    let mut force = vec![Vector6::zeros(); n];
    // Forward pass: velocities and accelerations from the base outwards.
    for (i, link) in model.links.iter().enumerate() {
        let (mut vi, mut ai) = match link.parent {
            Some(p) => (vel[p], acc[p]),
            None => (Vector6::zeros(), base_acceleration),
        };
        // Zero for links without a coordinate.
        let vj = tree.joint_motion(model, i, v);
        vi += vj;
        ai += tree.joint_motion(model, i, a) + crm(&vi) * vj;
        let inertia = &tree.inertia[i];
        force[i] = inertia * ai + crf(&vi) * (inertia * vi);
        vel[i] = vi;
        acc[i] = ai;
    }
    // Backward pass: project and accumulate the forces towards the base.
    let mut tau = DVector::zeros(model.dof());
    for (i, link) in model.links.iter().enumerate().rev() {
        if let Some(k) = link.coordinate {
            for (c, s) in tree.subspace[i].iter().enumerate() {
                tau[k + c] = s.dot(&force[i]);
            }
        }
        if let Some(p) = link.parent {
            let fi = force[i];
            force[p] += fi;
        }
    }
    tau
}

#[cfg(test)]
mod tests {
    use super::super::test_models::*;
    use super::*;

    #[test]
    fn double_pendulum_matches_closed_form_equations_of_motion() {
        let (m1, l1, m2, l2) = (1.0, 1.0, 0.5, 0.7);
        let model = double_pendulum(m1, l1, m2, l2);
        let q = DVector::from_vec(vec![0.3, -1.2]);
        let v = DVector::from_vec(vec![0.7, 1.9]);
        let a = DVector::from_vec(vec![-0.4, 2.5]);
        let (mm, g) = double_pendulum_closed_form(m1, l1, m2, l2, q[0], q[1]);
        // Coriolis/centrifugal terms of the double pendulum (h = m2 l1 l2/2 sin θ2).
        let h = m2 * l1 * l2 / 2.0 * q[1].sin();
        let cv = DVector::from_vec(vec![
            -h * (2.0 * v[0] * v[1] + v[1] * v[1]),
            h * v[0] * v[0],
        ]);
        let expected = mm * &a + cv + g;
        let tau = rnea(&model, &q, &v, &a);
        assert!((tau - expected).norm() < 1e-12);
    }
}
