//! Joint transforms and motion subspaces of every link, on the DAG.
//!
//! Link `i`'s transform from its parent is `X_J(q_i) · X_T` (Featherstone §4.1): `X_T`
//! the constant origin (translation, then roll-pitch-yaw), `X_J` the joint motion. Each
//! revolute coordinate gets exactly one `sin`/`cos` pair.

use super::spatial::{
    M3, Motion, V3, Xform, axis_rotation, identity, mat_mul, transpose, v3_const, v3_zero,
};
use crate::model::{JointKind, Model, PExpr};
use crate::sym::{Graph, Id, InputKind};

/// Per-link kinematic data.
pub struct Kinematics {
    /// Parent → link transform.
    pub xform: Vec<Xform>,
    /// Motion subspace (a unit twist in link coordinates); `None` for fixed joints.
    pub subspace: Vec<Option<Motion>>,
}

fn lower3(g: &mut Graph, v: &[PExpr; 3]) -> V3 {
    [v[0].lower(g), v[1].lower(g), v[2].lower(g)]
}

/// `Rz(yaw) Ry(pitch) Rx(roll)`.
fn rpy_rotation(g: &mut Graph, rpy: &[PExpr; 3]) -> M3 {
    let mut r = identity(g);
    for (k, axis) in [
        (2, [0.0, 0.0, 1.0]),
        (1, [0.0, 1.0, 0.0]),
        (0, [1.0, 0.0, 0.0]),
    ] {
        let a = rpy[k].lower(g);
        let (s, c) = (g.sin(a), g.cos(a));
        let rk = axis_rotation(g, axis, s, c);
        r = mat_mul(g, &r, &rk);
    }
    r
}

pub fn kinematics(g: &mut Graph, model: &Model) -> Kinematics {
    let mut xform = Vec::new();
    let mut subspace = Vec::new();
    for link in &model.links {
        let origin = lower3(g, &link.origin);
        let e_t = transpose(&rpy_rotation(g, &link.rpy));
        let (x, s) = match (link.kind, link.coordinate) {
            (JointKind::Revolute(a), Some(i)) => {
                let q = g.input(InputKind::Q, i);
                let (sn, cs) = (g.sin(q), g.cos(q));
                let e_j = transpose(&axis_rotation(g, a, sn, cs));
                let e = mat_mul(g, &e_j, &e_t);
                let w = v3_const(g, a);
                (Xform { e, r: origin }, Some(Motion { w, v: v3_zero(g) }))
            }
            (JointKind::Prismatic(a), Some(i)) => {
                let q = g.input(InputKind::Q, i);
                // r = r_T + E_Tᵀ (a q)
                let aq: V3 = a.map(|c| {
                    let k = g.constant(c);
                    g.mul(k, q)
                });
                let shift = super::spatial::mat_t_vec(g, &e_t, aq);
                let r = super::spatial::add3(g, origin, shift);
                let v = v3_const(g, a);
                (Xform { e: e_t, r }, Some(Motion { w: v3_zero(g), v }))
            }
            _ => (Xform { e: e_t, r: origin }, None),
        };
        xform.push(x);
        subspace.push(s);
    }
    Kinematics { xform, subspace }
}

/// The motion subspace dotted with a force: the generalised force of coordinate `i`.
pub fn project(g: &mut Graph, s: &Motion, f: super::spatial::Force) -> Id {
    s.dot_force(g, f)
}
