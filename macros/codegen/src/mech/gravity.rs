//! The generalised gravity force from composite first moments: for coordinate `i`,
//! `g_i = −S_i · (h_i × γ_i, m_i γ_i)` with `m_i`, `h_i` the mass and first moment of the
//! subtree at link `i` (from the composite inertias of [`super::crba`]) and `γ_i` the
//! gravity vector in link `i`'s coordinates (`γ_i = E_i γ_λ(i)`, one rotation per link).
//!
//! This is what RNEA computes with a base acceleration `−γ`, without carrying gravity
//! down the tree as an acceleration and back up as forces: those rotations cancel
//! (`Eᵀ E = 1`), but only numerically, so RNEA's symbolic result is several times larger.

use super::kinematics::{Kinematics, project};
use super::spatial::{Force, Inertia, V3, cross, mat_vec, scale3};
use crate::model::Model;
use crate::sym::{Graph, Id};

pub fn gravity_forces(
    g: &mut Graph,
    model: &Model,
    kin: &Kinematics,
    composite: &[Inertia],
    gravity: Option<V3>,
) -> Vec<Id> {
    let mut out = vec![g.zero(); model.dof()];
    let Some(gw) = gravity else { return out };
    let mut gamma: Vec<V3> = Vec::with_capacity(model.links.len());
    for (i, link) in model.links.iter().enumerate() {
        let gp = link.parent.map_or(gw, |p| gamma[p]);
        gamma.push(mat_vec(g, &kin.xform[i].e, gp));
        if let Some(c) = link.coordinate {
            let ci = &composite[i];
            let wrench = Force {
                n: cross(g, ci.h, gamma[i]),
                f: scale3(g, ci.m, gamma[i]),
            };
            for (k, s) in kin.subspace[i].iter().enumerate() {
                let p = project(g, s, wrench);
                out[c + k] = g.neg(p);
            }
        }
    }
    out
}
