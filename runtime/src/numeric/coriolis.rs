//! Exact mass-matrix derivatives, Christoffel symbols and the Coriolis matrix.
//!
//! `M_ij = S_uᵀ I^c_d S_d`, where `d` is the deeper of the two coordinates' links and
//! `u` the other (an ancestor of `d`, or `d` itself for two components of one spherical
//! or translation joint; `M_ij = 0` when neither link supports the other). A
//! coordinate `k` moves everything it supports rigidly with the twist `S_k`, so (world
//! frame) a motion vector fixed in a moved body changes as `D_k S = S_k ×ₘ S` and a
//! moved spatial inertia as `D_k I = S_k ×* I − I (S_k ×ₘ)` (Featherstone, *Rigid Body
//! Dynamics Algorithms* (2008), §2.9–2.13, eqs. 2.31–2.32 and 2.65; the same identities
//! give the derivative algorithms of Carpentier & Mansard, RSS 2018). Product rule
//! gives `D_k M_ij` exactly.
//!
//! `D_k` is the derivative along velocity coordinate `k` (theory.md §2, "Lie-group
//! joints"): `∂/∂q_k` for a Euclidean coordinate, and for component `a` of a spherical
//! joint with quaternion `R₀` the derivative of `M(R₀ exp(t ê_a))` at `t = 0`. Moving
//! along `R₀ exp(t ê_a)` turns the joint's link and all its descendants with the twist
//! `S_a` (the link's axis `a` through its origin), exactly as a revolute joint does, and
//! also turns the joint's own other columns, `D_a S_b = S_a ×ₘ S_b` — which is why the
//! same identities give all of them.
//!
//! The Christoffel symbols of the first kind
//! `c_ijk = ½ (D_k M_ij + D_j M_ik − D_i M_jk)` and `C_ij = Σ_k c_ijk v_k` follow
//! (theory.md §2); with Lie-group joints [`lie_coriolis_matrix`] adds the `ad` term.
//! Cost is O(n³) 6×6 products: a reference, not a fast path.

use nalgebra::{DMatrix, DVector, Matrix6, Vector6};

use super::crba::{composite_inertias, crba_in};
use super::kinematics::WorldTree;
use super::spatial::{crf, crm};
use super::{JointKind, Model};

/// `D_k M` for every velocity coordinate `k` (index `k` of the returned vector): `∂M/∂q_k`
/// for Euclidean coordinates, the derivative along `R₀ exp(t ê_a)` for component `a` of
/// a spherical joint (see the module documentation). `q` in the configuration layout
/// ([`Model::config_slots`]).
pub fn mass_matrix_derivatives(model: &Model, q: &DVector<f64>) -> Vec<DMatrix<f64>> {
    let tree = WorldTree::new(model, q);
    let composite = composite_inertias(model, &tree);
    let n = model.dof();
    // Link and motion-subspace column of each coordinate.
    let columns = tree.columns(model);
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
    let moved_inertia = |sk: &Vector6<f64>, inertia: &Matrix6<f64>| -> Matrix6<f64> {
        crf(sk) * inertia - inertia * crm(sk)
    };

    let mut out = vec![DMatrix::zeros(n, n); n];
    for i in 0..n {
        for j in 0..=i {
            let ((li, si), (lj, sj)) = (columns[i], columns[j]);
            // M_ij = su · I^c_d sd with u an ancestor of (or equal to) d.
            let ((u, su), (d, sd)) = if supports(li, lj) {
                ((li, si), (lj, sj))
            } else if supports(lj, li) {
                ((lj, sj), (li, si))
            } else {
                continue;
            };
            for (k, dm) in out.iter_mut().enumerate() {
                let (lk, sk) = columns[k];
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
/// [`crate::kernels::Christoffel::christoffel_symbols`]), with `D_k` of
/// [`mass_matrix_derivatives`].
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
///
/// This is the Coriolis matrix of models with revolute, prismatic, fixed and
/// translation joints only. With spherical joints it lacks the `ad` term (`C v` is not
/// the bias): use [`lie_coriolis_matrix`].
pub fn coriolis_matrix(model: &Model, q: &DVector<f64>, v: &DVector<f64>) -> DMatrix<f64> {
    let symbols = christoffel_symbols(model, q);
    let n = symbols.len();
    DMatrix::from_fn(n, n, |i, j| symbols[i].row(j).dot(&v.transpose()))
}

/// Coriolis matrix in the quasi-velocities of a model with Lie-group joints
/// ([`crate::kernels::Coriolis::coriolis_matrix`]):
///
/// ```text
/// C_ij = Σ_k ½ (D_k M_ij + D_j M_ik − D_i M_jk) v_k + X_ij,   X_ij = (M v)·[e_i, e_j]
/// ```
///
/// with `D_k` of [`mass_matrix_derivatives`]. The bracket is nonzero only for two
/// components `a`, `b` of one spherical joint, `[e_a, e_b] = ε_abc e_c`, so `X` is
/// block diagonal with the block `−p̂` on each spherical joint, `p` the joint's three
/// components of `M v`.
///
/// * Same `C v` as theory.md §2's `C_ij = Σ_k (D_k M_ij − ½ D_i M_jk) v_k − [ad_vᵀ M]_ij`:
///   the first two Christoffel terms are symmetric in `j, k`, and
///   `(X v)_i = (M v)·[e_i, v] = −(ad_vᵀ M v)_i`. So `C v + g` is the bias of RNEA.
/// * `Ṁ − 2C` is skew-symmetric for `Ṁ = Σ_k D_k M v_k`: `Ṁ − 2 c v` is
///   `Σ_k (D_i M_jk − D_j M_ik) v_k`, and `X` is skew.
/// * For models without spherical joints `X = 0` and this is [`coriolis_matrix`].
pub fn lie_coriolis_matrix(model: &Model, q: &DVector<f64>, v: &DVector<f64>) -> DMatrix<f64> {
    let mut c = coriolis_matrix(model, q, v);
    let tree = WorldTree::new(model, q);
    let composite = composite_inertias(model, &tree);
    let p = crba_in(model, &tree, &composite) * v;
    for link in &model.links {
        if let (JointKind::Spherical, Some(k)) = (link.joint, link.coordinate) {
            // X_ab = ε_abc p_c: −p̂ on the joint's block.
            let (x, y, z) = (p[k], p[k + 1], p[k + 2]);
            c[(k, k + 1)] += z;
            c[(k + 1, k)] -= z;
            c[(k + 1, k + 2)] += x;
            c[(k + 2, k + 1)] -= x;
            c[(k + 2, k)] += y;
            c[(k, k + 2)] -= y;
        }
    }
    c
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
