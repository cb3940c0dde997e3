//! Exact mass-matrix derivatives, Christoffel symbols and the Coriolis matrix.
//!
//! `M_ij = S_uᵀ I^c_d S_d`, where `d` is the deeper of the two coordinates' links and
//! `u` the other (an ancestor of `d`; `M_ij = 0` when neither supports the other). A
//! coordinate `q_k` moves everything it supports rigidly, so (world frame) a motion
//! vector fixed in a moved body changes as `∂S/∂q_k = S_k ×ₘ S` and a moved spatial
//! inertia as `∂I/∂q_k = S_k ×* I − I (S_k ×ₘ)` (Featherstone, *Rigid Body Dynamics
//! Algorithms* (2008), §2.9–2.13, eqs. 2.31–2.32 and 2.65; the same identities give the
//! derivative algorithms of Carpentier & Mansard, RSS 2018). Product rule gives
//! `∂M_ij/∂q_k` exactly; the Christoffel symbols of the first kind
//! `c_ijk = ½ (∂M_ij/∂q_k + ∂M_ik/∂q_j − ∂M_jk/∂q_i)` and `C_ij = Σ_k c_ijk v_k` follow
//! (theory.md §2). Cost is O(n³) 6×6 products: a reference, not a fast path.

use nalgebra::{DMatrix, DVector, Matrix6, Vector6};

use super::Model;
use super::crba::composite_inertias;
use super::kinematics::WorldTree;
use super::spatial::{crf, crm};

/// `∂M/∂q_k` for every coordinate `k` (index `k` of the returned vector).
pub fn mass_matrix_derivatives(model: &Model, q: &DVector<f64>) -> Vec<DMatrix<f64>> {
    let tree = WorldTree::new(model, q);
    let composite = composite_inertias(model, &tree);
    let n = model.dof();
    // Link of each coordinate, and the ancestry relation between links.
    let mut link_of = vec![0; n];
    for (i, link) in model.links.iter().enumerate() {
        if let Some(k) = link.coordinate {
            link_of[k] = i;
        }
    }
    let supports = |anc: usize, desc: usize| -> bool {
        let mut cur = Some(desc);
        while let Some(c) = cur {
            if c == anc {
                return true;
            }
            cur = model.links[c].parent;
        }
        false
    };
    let s = |k: usize| -> Vector6<f64> { tree.subspace[link_of[k]].unwrap_or_else(Vector6::zeros) };
    let moved_inertia = |sk: &Vector6<f64>, inertia: &Matrix6<f64>| -> Matrix6<f64> {
        crf(sk) * inertia - inertia * crm(sk)
    };

    let mut out = vec![DMatrix::zeros(n, n); n];
    for i in 0..n {
        for j in 0..=i {
            let (li, lj) = (link_of[i], link_of[j]);
            let (u, d) = if supports(li, lj) {
                (li, lj)
            } else if supports(lj, li) {
                (lj, li)
            } else {
                continue;
            };
            let (su, sd) = (
                s(if u == li { i } else { j }),
                s(if d == li { i } else { j }),
            );
            for (k, dm) in out.iter_mut().enumerate() {
                let lk = link_of[k];
                let sk = s(k);
                let dsu = if supports(lk, u) {
                    crm(&sk) * su
                } else {
                    Vector6::zeros()
                };
                let dsd = if supports(lk, d) {
                    crm(&sk) * sd
                } else {
                    Vector6::zeros()
                };
                let dic = if supports(lk, d) {
                    moved_inertia(&sk, &composite[d])
                } else if supports(d, lk) {
                    moved_inertia(&sk, &composite[lk])
                } else {
                    Matrix6::zeros()
                };
                let value = dsu.dot(&(composite[d] * sd))
                    + su.dot(&(dic * sd))
                    + su.dot(&(composite[d] * dsd));
                dm[(i, j)] = value;
                dm[(j, i)] = value;
            }
        }
    }
    out
}

/// Christoffel symbols of the first kind, `out[i][(j, k)] = c_ijk` (the layout of
/// [`crate::system::Mechanism::christoffel_symbols`]).
pub fn christoffel_symbols(model: &Model, q: &DVector<f64>) -> Vec<DMatrix<f64>> {
    let dm = mass_matrix_derivatives(model, q);
    let n = dm.len();
    (0..n)
        .map(|i| {
            DMatrix::from_fn(n, n, |j, k| {
                0.5 * (dm[k][(i, j)] + dm[j][(i, k)] - dm[i][(j, k)])
            })
        })
        .collect()
}

/// Coriolis matrix in Christoffel form, `C_ij = Σ_k c_ijk v_k`, so that `Ṁ − 2C` is
/// skew-symmetric.
pub fn coriolis_matrix(model: &Model, q: &DVector<f64>, v: &DVector<f64>) -> DMatrix<f64> {
    let symbols = christoffel_symbols(model, q);
    let n = symbols.len();
    DMatrix::from_fn(n, n, |i, j| symbols[i].row(j).dot(&v.transpose()))
}

#[cfg(test)]
mod tests {
    use super::super::test_models::*;
    use super::super::{bias, crba, gravity};
    use super::*;

    fn models() -> Vec<Model> {
        vec![
            double_pendulum(1.0, 1.0, 0.5, 0.7),
            cart_pole(2.0, 0.5, 1.0),
            spatial_chain(),
        ]
    }

    #[test]
    fn derivatives_match_central_differences_of_crba() {
        for model in models() {
            let n = model.dof();
            let q = DVector::from_fn(n, |i, _| 0.2 - 0.37 * i as f64);
            let dm = mass_matrix_derivatives(&model, &q);
            let h = 1e-6;
            for (k, dmk) in dm.iter().enumerate() {
                let mut qp = q.clone();
                let mut qm = q.clone();
                qp[k] += h;
                qm[k] -= h;
                let fd = (crba(&model, &qp) - crba(&model, &qm)) / (2.0 * h);
                assert!((dmk - &fd).norm() < 1e-8, "k = {k}: {dmk} vs {fd}");
            }
        }
    }

    #[test]
    fn coriolis_times_v_is_bias_minus_gravity_and_passivity_holds() {
        for model in models() {
            let n = model.dof();
            let q = DVector::from_fn(n, |i, _| 0.5 + 0.3 * i as f64);
            let v = DVector::from_fn(n, |i, _| 1.1 - 0.8 * i as f64);
            let c = coriolis_matrix(&model, &q, &v);
            let cv = bias(&model, &q, &v) - gravity(&model, &q);
            assert!((&c * &v - cv).norm() < 1e-11);
            let dm = mass_matrix_derivatives(&model, &q);
            let mdot = dm
                .iter()
                .zip(v.iter())
                .fold(DMatrix::zeros(n, n), |acc, (d, vk)| acc + d * *vk);
            let s = mdot - 2.0 * c;
            assert!((&s + s.transpose()).norm() < 1e-11);
        }
    }
}
