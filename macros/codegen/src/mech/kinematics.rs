//! Joint transforms and motion subspaces of every link, on the DAG.
//!
//! Link `i`'s transform from its parent is `X_J(q_i) · X_T` (Featherstone §4.1): `X_T`
//! the constant origin (translation, then roll-pitch-yaw), `X_J` the joint motion. Each
//! revolute coordinate gets exactly one `sin`/`cos` pair; a spherical joint's rotation
//! is the quadratic polynomial of its quaternion (no trigonometry at all).

use super::spatial::{
    M3, Motion, V3, Xform, axis_rotation, identity, mat_mul, transpose, v3_const, v3_zero,
};
use crate::model::{JointKind, Model, PExpr};
use crate::sym::{Graph, Id, InputKind};

/// Per-link kinematic data.
pub struct Kinematics {
    /// Parent → link transform.
    pub xform: Vec<Xform>,
    /// Motion subspace: one unit twist in link coordinates per velocity coordinate
    /// (none for fixed joints, three for spherical and translation joints). All are
    /// constant in link coordinates, so RNEA needs no `Ṡ` term.
    pub subspace: Vec<Vec<Motion>>,
}

pub fn lower3(g: &mut Graph, v: &[PExpr; 3]) -> V3 {
    [v[0].lower(g), v[1].lower(g), v[2].lower(g)]
}

/// `Rz(yaw) Ry(pitch) Rx(roll)`.
pub fn rpy_rotation(g: &mut Graph, rpy: &[PExpr; 3]) -> M3 {
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

/// The rotation matrix of the unit quaternion `(w, x, y, z)`:
/// `R = 1 + 2w û + 2û²` with `u = (x, y, z)`, written out.
pub fn quaternion_rotation(g: &mut Graph, quat: [Id; 4]) -> M3 {
    let [w, x, y, z] = quat;
    let two = g.constant(2.0);
    let one = g.one();
    let mut p = |a: Id, b: Id| {
        let ab = g.mul(a, b);
        g.mul(two, ab)
    };
    let (xx, yy, zz) = (p(x, x), p(y, y), p(z, z));
    let (xy, xz, yz) = (p(x, y), p(x, z), p(y, z));
    let (wx, wy, wz) = (p(w, x), p(w, y), p(w, z));
    let diag = |g: &mut Graph, a: Id, b: Id| {
        let s = g.add(a, b);
        g.sub(one, s)
    };
    let r00 = diag(g, yy, zz);
    let r11 = diag(g, xx, zz);
    let r22 = diag(g, xx, yy);
    [
        [r00, g.sub(xy, wz), g.add(xz, wy)],
        [g.add(xy, wz), r11, g.sub(yz, wx)],
        [g.sub(xz, wy), g.add(yz, wx), r22],
    ]
}

const UNIT: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

pub fn kinematics(g: &mut Graph, model: &Model) -> Kinematics {
    let mut xform = Vec::new();
    let mut subspace = Vec::new();
    for link in &model.links {
        let origin = lower3(g, &link.origin);
        let e_t = transpose(&rpy_rotation(g, &link.rpy));
        let (x, s) = match (link.kind, link.config) {
            (JointKind::Revolute(a), Some(i)) => {
                let q = g.input(InputKind::Q, i);
                let (sn, cs) = (g.sin(q), g.cos(q));
                let e_j = transpose(&axis_rotation(g, a, sn, cs));
                let e = mat_mul(g, &e_j, &e_t);
                let w = v3_const(g, a);
                (Xform { e, r: origin }, vec![Motion { w, v: v3_zero(g) }])
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
                (Xform { e: e_t, r }, vec![Motion { w: v3_zero(g), v }])
            }
            (JointKind::Spherical, Some(i)) => {
                let quat = [0, 1, 2, 3].map(|k| g.input(InputKind::Q, i + k));
                let e_j = transpose(&quaternion_rotation(g, quat));
                let e = mat_mul(g, &e_j, &e_t);
                let cols = UNIT
                    .iter()
                    .map(|a| Motion {
                        w: v3_const(g, *a),
                        v: v3_zero(g),
                    })
                    .collect();
                (Xform { e, r: origin }, cols)
            }
            (JointKind::Translation, Some(i)) => {
                // r = r_T + E_Tᵀ p; the link keeps the joint frame's orientation.
                let p = [0, 1, 2].map(|k| g.input(InputKind::Q, i + k));
                let shift = super::spatial::mat_t_vec(g, &e_t, p);
                let r = super::spatial::add3(g, origin, shift);
                let cols = UNIT
                    .iter()
                    .map(|a| Motion {
                        w: v3_zero(g),
                        v: v3_const(g, *a),
                    })
                    .collect();
                (Xform { e: e_t, r }, cols)
            }
            _ => (Xform { e: e_t, r: origin }, Vec::new()),
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
