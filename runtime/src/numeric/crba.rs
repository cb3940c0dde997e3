//! Composite-rigid-body algorithm: the joint-space mass matrix `M(q)`.
//!
//! Featherstone, *Rigid Body Dynamics Algorithms* (2008), §6.2, Table 6.2, in world
//! coordinates: `M_ij = S_iᵀ I^c_i S_j` for `j` an ancestor of (or equal to) `i`, where
//! `I^c_i` is the composite inertia of the subtree rooted at link `i`. A spherical or
//! translation joint has three columns `S_i` (its 3 × 3 diagonal block is
//! `S_iᵀ I^c_i S_i`); `M` is then the mass matrix of the quasi-velocities.

use nalgebra::{DMatrix, DVector, Matrix6};

use super::Model;
use super::kinematics::WorldTree;

/// Mass matrix `M(q)` by the composite-rigid-body algorithm.
///
/// # Panics
/// If `q` is shorter than [`Model::config_dim`].
pub fn crba(model: &Model, q: &DVector<f64>) -> DMatrix<f64> {
    let tree = WorldTree::new(model, q);
    let composite = composite_inertias(model, &tree);
    crba_in(model, &tree, &composite)
}

/// `I^c_i`: the spatial inertia of the subtree rooted at each link (world frame).
pub(crate) fn composite_inertias(model: &Model, tree: &WorldTree) -> Vec<Matrix6<f64>> {
    let mut composite = tree.inertia.clone();
    for (i, link) in model.links.iter().enumerate().rev() {
        if let Some(p) = link.parent {
            let ci = composite[i];
            composite[p] += ci;
        }
    }
    composite
}

pub(crate) fn crba_in(model: &Model, tree: &WorldTree, composite: &[Matrix6<f64>]) -> DMatrix<f64> {
    let n = model.dof();
    let mut mass = DMatrix::zeros(n, n);
    for (i, link) in model.links.iter().enumerate() {
        let Some(ki) = link.coordinate else {
            continue;
        };
        for (ci, si) in tree.subspace[i].iter().enumerate() {
            let f = composite[i] * si;
            // The joint's own block, then the ancestors'.
            for (cj, sj) in tree.subspace[i].iter().enumerate() {
                mass[(ki + ci, ki + cj)] = sj.dot(&f);
            }
            let mut ancestor = link.parent;
            while let Some(j) = ancestor {
                if let Some(kj) = model.links[j].coordinate {
                    for (cj, sj) in tree.subspace[j].iter().enumerate() {
                        let mij = sj.dot(&f);
                        mass[(ki + ci, kj + cj)] = mij;
                        mass[(kj + cj, ki + ci)] = mij;
                    }
                }
                ancestor = model.links[j].parent;
            }
        }
    }
    mass
}

#[cfg(test)]
mod tests {
    use super::super::rnea::rnea;
    use super::super::test_models::*;
    use super::*;

    /// Pinocchio's `unittest/crba.cpp` idea: column j of M is RNEA(q, 0, e_j) − RNEA(q, 0, 0).
    #[test]
    fn columns_equal_rnea_differences() {
        for model in [
            double_pendulum(1.0, 1.0, 0.5, 0.7),
            cart_pole(2.0, 0.5, 1.0),
            spatial_chain(),
        ] {
            let n = model.dof();
            let q = DVector::from_fn(n, |i, _| 0.3 + 0.45 * i as f64);
            let zero = DVector::zeros(n);
            let mass = crba(&model, &q);
            let g = rnea(&model, &q, &zero, &zero);
            for j in 0..n {
                let col = rnea(
                    &model,
                    &q,
                    &zero,
                    &DVector::from_fn(n, |i, _| f64::from(i == j)),
                ) - &g;
                assert!((mass.column(j) - col).norm() < 1e-12, "column {j}");
            }
            assert!((&mass - mass.transpose()).norm() < 1e-12);
            assert!(mass.clone().cholesky().is_some());
        }
    }

    #[test]
    fn double_pendulum_matches_closed_form() {
        let (m1, l1, m2, l2) = (1.0, 1.0, 0.5, 0.7);
        let model = double_pendulum(m1, l1, m2, l2);
        for (t1, t2) in [(0.0, 0.0), (0.3, -1.2), (2.0, 2.5)] {
            let q = DVector::from_vec(vec![t1, t2]);
            let (expected, _) = double_pendulum_closed_form(m1, l1, m2, l2, t1, t2);
            assert!((crba(&model, &q) - expected).norm() < 1e-13);
        }
    }

    #[test]
    fn cart_pole_matches_closed_form() {
        let (mc, mp, l) = (2.0, 0.5, 1.0);
        let model = cart_pole(mc, mp, l);
        let q = DVector::from_vec(vec![0.4_f64, 0.9]);
        let ip = mp * l * l / 12.0;
        let off = -mp * l / 2.0 * q[1].sin();
        let expected = DMatrix::from_row_slice(2, 2, &[mc + mp, off, off, mp * l * l / 4.0 + ip]);
        assert!((crba(&model, &q) - expected).norm() < 1e-13);
    }
}
