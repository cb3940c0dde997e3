//! Inverse dynamics by the recursive Newton–Euler algorithm (Featherstone 2008, §5.3,
//! Table 5.1), on the DAG: `RNEA(q, v, a) = M a + C v + g`. With `v = a = 0` it is the
//! generalised gravity force, with `a = 0` the bias force; the folding constructors drop
//! every term a zero input kills.

use super::kinematics::{Kinematics, project};
use super::spatial::{Force, Inertia, Motion, v3_zero};
use crate::model::Model;
use crate::sym::{Graph, Id};

/// `τ = M(q) a + C(q, v) v + g(q)` for symbolic `v`, `a` (one node per coordinate);
/// gravity enters as a base acceleration `−gravity`.
pub fn rnea(
    g: &mut Graph,
    model: &Model,
    kin: &Kinematics,
    inertia: &[Inertia],
    gravity: Option<[Id; 3]>,
    v: &[Id],
    a: &[Id],
) -> Vec<Id> {
    rnea_forces(g, model, kin, inertia, gravity, v, a).0
}

/// [`rnea`]'s `τ`, and the spatial force each link's joint transmits to it from its
/// parent (in link coordinates): what its subtree needs for the motion `(v, a)`.
pub fn rnea_forces(
    g: &mut Graph,
    model: &Model,
    kin: &Kinematics,
    inertia: &[Inertia],
    gravity: Option<[Id; 3]>,
    v: &[Id],
    a: &[Id],
) -> (Vec<Id>, Vec<Force>) {
    let nl = model.links.len();
    let base_acc = match gravity {
        Some(gv) => Motion {
            w: v3_zero(g),
            v: gv.map(|c| g.neg(c)),
        },
        None => Motion::zero(g),
    };
    let base_vel = Motion::zero(g);
    let mut vel = Vec::with_capacity(nl);
    let mut acc = Vec::with_capacity(nl);
    let mut force: Vec<Force> = Vec::with_capacity(nl);
    for (i, link) in model.links.iter().enumerate() {
        let (vp, ap) = match link.parent {
            Some(p) => (vel[p], acc[p]),
            None => (base_vel, base_acc),
        };
        let x = &kin.xform[i];
        let mut vi = x.apply_motion(g, vp);
        let mut ai = x.apply_motion(g, ap);
        if let Some(c) = link.coordinate {
            // v_J = Σ S_k v_k and a_J likewise (S constant in link coordinates).
            let cols = &kin.subspace[i];
            let mut vj = cols[0].scale(g, v[c]);
            for (k, s) in cols.iter().enumerate().skip(1) {
                let t = s.scale(g, v[c + k]);
                vj = vj.add(g, t);
            }
            vi = vi.add(g, vj);
            let mut aj = cols[0].scale(g, a[c]);
            for (k, s) in cols.iter().enumerate().skip(1) {
                let t = s.scale(g, a[c + k]);
                aj = aj.add(g, t);
            }
            ai = ai.add(g, aj);
            let cor = vi.cross_motion(g, vj);
            ai = ai.add(g, cor);
        }
        let iv = inertia[i].apply(g, vi);
        let ia = inertia[i].apply(g, ai);
        let gyro = vi.cross_force(g, iv);
        force.push(ia.add(g, gyro));
        vel.push(vi);
        acc.push(ai);
    }
    let z = g.zero();
    let mut tau = vec![z; model.dof()];
    for i in (0..nl).rev() {
        if let Some(c) = model.links[i].coordinate {
            for (k, s) in kin.subspace[i].iter().enumerate() {
                tau[c + k] = project(g, s, force[i]);
            }
        }
        if let Some(p) = model.links[i].parent {
            let up = kin.xform[i].apply_force_t(g, force[i]);
            force[p] = force[p].add(g, up);
        }
    }
    // Link i's force is final once its own turn has come (children come after parents).
    (tau, force)
}
