//! The table of a compact tree (`runtime::compact`): per body its place in the tree and
//! its constants in a frame aligned with its joint, as graph nodes, so that parameters
//! and URDF values enter it as they enter every other kernel.
//!
//! Each link's frame `L` is turned by a constant rotation `A` whose third column is the
//! joint's axis: the body frame `B = L A` moves along its own `z`. Then (theory,
//! "Compact kernels") the joint's placement on its parent's body frame is
//! `Trans(A_pᵀ origin) · Rot(A_pᵀ R_rpy A) · J_z(q)`, and the link's inertia reads
//! `h = Aᵀ h_L`, `Ī = Aᵀ Ī_L A`.

use super::kinematics::{lower3, rpy_rotation};
use super::spatial::{Inertia, M3, V3, mat_mul, mat_t_vec, transpose};
use crate::model::{JointKind, Model};
use crate::sym::{Graph, Id};

/// How a body of the table moves (mirrors `runtime::compact::Joint`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Joint {
    Revolute(usize),
    Prismatic(usize),
    Fixed,
}

/// One body's entries, in the order of `runtime::compact::Body`'s fields.
pub struct Body {
    pub rotation: M3,
    pub translation: V3,
    pub mass: Id,
    pub first_moment: V3,
    /// `[xx, yy, zz, xy, xz, yz]` about the body frame's origin.
    pub inertia: [Id; 6],
}

impl Body {
    /// Every entry, in field order (22).
    pub fn entries(&self) -> Vec<Id> {
        let mut out: Vec<Id> = self.rotation.iter().flatten().copied().collect();
        out.extend(self.translation);
        out.push(self.mass);
        out.extend(self.first_moment);
        out.extend(self.inertia);
        out
    }
}

/// Entries per body in [`Body::entries`].
pub const ENTRIES: usize = 22;

pub struct Tree {
    /// Per body: its parent and joint.
    pub nodes: Vec<(Option<usize>, Joint)>,
    pub bodies: Vec<Body>,
    /// Gravity in the world frame (zero when the scene has none).
    pub gravity: V3,
}

/// A rotation whose third column is the unit vector `a`: the identity for `z`, an exact
/// signed permutation for the other coordinate axes, so that axis-aligned robots keep
/// their exact zeros.
pub fn aligned(a: [f64; 3]) -> [[f64; 3]; 3] {
    if a == [0.0, 0.0, 1.0] {
        return [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    }
    let cross = |u: [f64; 3], v: [f64; 3]| {
        [
            u[1] * v[2] - u[2] * v[1],
            u[2] * v[0] - u[0] * v[2],
            u[0] * v[1] - u[1] * v[0],
        ]
    };
    // The coordinate axis least along `a`, made perpendicular by a cross product.
    let k = (0..3)
        .min_by(|&i, &j| a[i].abs().total_cmp(&a[j].abs()))
        .unwrap_or(0);
    let mut e = [0.0; 3];
    e[k] = 1.0;
    let x = cross(a, e);
    let norm = (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt();
    let x = x.map(|c| c / norm);
    let y = cross(a, x);
    [[x[0], y[0], a[0]], [x[1], y[1], a[1]], [x[2], y[2], a[2]]]
}

fn constant(g: &mut Graph, m: [[f64; 3]; 3]) -> M3 {
    m.map(|r| r.map(|x| g.constant(x)))
}

/// The table of `model` (which [`Model::compact_unsupported`] accepts), `inertia` the
/// links' inertias in their own frames.
pub fn tree(g: &mut Graph, model: &Model, inertia: &[Inertia]) -> Tree {
    let align: Vec<[[f64; 3]; 3]> = model
        .links
        .iter()
        .map(|l| match l.kind {
            JointKind::Revolute(a) | JointKind::Prismatic(a) => aligned(a),
            _ => aligned([0.0, 0.0, 1.0]),
        })
        .collect();
    let mut nodes = Vec::with_capacity(model.links.len());
    let mut bodies = Vec::with_capacity(model.links.len());
    for (i, l) in model.links.iter().enumerate() {
        let joint = match (l.kind, l.coordinate) {
            (JointKind::Revolute(_), Some(c)) => Joint::Revolute(c),
            (JointKind::Prismatic(_), Some(c)) => Joint::Prismatic(c),
            _ => Joint::Fixed,
        };
        nodes.push((l.parent, joint));
        let a = constant(g, align[i]);
        let a_parent = constant(g, l.parent.map_or(align_identity(), |p| align[p]));
        let origin = lower3(g, &l.origin);
        let rpy = rpy_rotation(g, &l.rpy);
        let pr = mat_mul(g, &transpose(&a_parent), &rpy);
        let rotation = mat_mul(g, &pr, &a);
        let translation = mat_t_vec(g, &a_parent, origin);
        let li = &inertia[i];
        let first_moment = mat_t_vec(g, &a, li.h);
        let at_i = mat_mul(g, &transpose(&a), &li.ibar);
        let ib = mat_mul(g, &at_i, &a);
        bodies.push(Body {
            rotation,
            translation,
            mass: li.m,
            first_moment,
            inertia: [ib[0][0], ib[1][1], ib[2][2], ib[0][1], ib[0][2], ib[1][2]],
        });
    }
    let gravity = match &model.gravity {
        Some(gv) => lower3(g, gv),
        None => [g.zero(); 3],
    };
    Tree {
        nodes,
        bodies,
        gravity,
    }
}

fn align_identity() -> [[f64; 3]; 3] {
    aligned([0.0, 0.0, 1.0])
}

#[cfg(test)]
mod tests {
    use super::aligned;

    #[test]
    fn aligned_is_a_rotation_with_the_axis_third() {
        let s = 1.0 / 3f64.sqrt();
        for a in [
            [1.0, 0.0, 0.0],
            [0.0, -1.0, 0.0],
            [0.0, 0.0, -1.0],
            [0.0, 0.0, 1.0],
            [s, s, s],
            [0.6, 0.0, -0.8],
        ] {
            let r = aligned(a);
            for i in 0..3 {
                assert_eq!(r[i][2], a[i]);
                for j in 0..3 {
                    let d: f64 = (0..3).map(|k| r[k][i] * r[k][j]).sum();
                    let want = if i == j { 1.0 } else { 0.0 };
                    assert!((d - want).abs() < 1e-15, "{a:?}: column {i}·{j} = {d}");
                }
            }
            // Right-handed: x × y = z.
            let (x, y) = ([r[0][0], r[1][0], r[2][0]], [r[0][1], r[1][1], r[2][1]]);
            let z = [
                x[1] * y[2] - x[2] * y[1],
                x[2] * y[0] - x[0] * y[2],
                x[0] * y[1] - x[1] * y[0],
            ];
            for k in 0..3 {
                assert!((z[k] - a[k]).abs() < 1e-15);
            }
        }
    }
}
