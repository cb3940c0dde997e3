//! Forward kinematics of frames: the world pose of every body and every `#[frame]`, and
//! the frame Jacobian mapping the velocity coordinates to the frame's world twist.
//!
//! World poses compose the joint transforms of [`kinematics`](super::kinematics) from
//! the root: `R_i = R_λ(i) E_iᵀ`, `p_i = p_λ(i) + R_λ(i) r_i` (`E_i` rotates parent into
//! link coordinates, `r_i` the link origin in parent coordinates). Column `k` of a frame's
//! Jacobian comes from the motion subspace `s_k = (w, v)` of coordinate `k` on an
//! ancestor link `j`, carried to the frame's origin `p_f` in world axes:
//! `ω = R_j w`, `ṗ = R_j v + ω × (p_f − p_j)` — Pinocchio's `LOCAL_WORLD_ALIGNED`
//! convention, linear rows first. Coordinates not on the frame's path are exact zeros.

use super::kinematics::{Kinematics, lower3, rpy_rotation};
use super::spatial::{M3, V3, add3, cross, identity, mat_mul, mat_vec, sub3, transpose, v3_zero};
use crate::model::{JointKind, Model};
use crate::sym::{Graph, Id};

/// One frame's outputs.
pub struct FrameKernel {
    pub name: String,
    /// Rotation (row-major, frame axes → world axes) then origin: 12 entries.
    pub pose: Vec<Id>,
    /// `6 × n`, row-major: rows `ṗ` (world), then `ω` (world).
    pub jacobian: Vec<Id>,
}

/// The frames a scene's `Kinematics` kernel serves: every body in link order (the
/// massless translation half of a free joint is internal and left out), then the
/// declared frames in declaration order.
pub fn frame_names(model: &Model) -> Vec<String> {
    model
        .links
        .iter()
        .filter(|l| l.kind != JointKind::Translation)
        .map(|l| l.name.clone())
        .chain(model.frames.iter().map(|f| f.name.clone()))
        .collect()
}

/// The world rotation (link axes → world axes) and origin of every link.
pub fn world_poses(g: &mut Graph, model: &Model, kin: &Kinematics) -> (Vec<M3>, Vec<V3>) {
    let mut rot: Vec<M3> = Vec::with_capacity(model.links.len());
    let mut pos: Vec<V3> = Vec::with_capacity(model.links.len());
    for (i, link) in model.links.iter().enumerate() {
        let x = &kin.xform[i];
        let (r, p) = match link.parent {
            Some(pi) => {
                let r = mat_mul(g, &rot[pi], &transpose(&x.e));
                let shift = mat_vec(g, &rot[pi], x.r);
                (r, add3(g, pos[pi], shift))
            }
            None => (transpose(&x.e), x.r),
        };
        rot.push(r);
        pos.push(p);
    }
    (rot, pos)
}

/// `link · Trans(origin) · Rot(rpy)` in world axes, from the link's world pose (the
/// world's, `link = None`).
pub fn offset_pose(
    g: &mut Graph,
    at: Option<(&M3, V3)>,
    offsets: &[(crate::model::Vec3, crate::model::Vec3)],
) -> (M3, V3) {
    let (mut r, mut p) = match at {
        Some((r, p)) => (*r, p),
        None => (identity(g), v3_zero(g)),
    };
    for (origin, rpy) in offsets {
        let o = lower3(g, origin);
        let shift = mat_vec(g, &r, o);
        p = add3(g, p, shift);
        let e = rpy_rotation(g, rpy);
        r = mat_mul(g, &r, &e);
    }
    (r, p)
}

pub fn frames(g: &mut Graph, model: &Model, kin: &Kinematics) -> Vec<FrameKernel> {
    let n = model.dof();
    let (rot, pos) = world_poses(g, model, kin);
    let zero = g.zero();
    let jacobian_at = |g: &mut Graph, link: Option<usize>, p_f: V3| -> Vec<Id> {
        let mut jac = vec![zero; 6 * n];
        let mut at = link;
        while let Some(j) = at {
            if let Some(c0) = model.links[j].coordinate {
                for (k, s) in kin.subspace[j].iter().enumerate() {
                    let w = mat_vec(g, &rot[j], s.w);
                    let v = mat_vec(g, &rot[j], s.v);
                    let arm = sub3(g, p_f, pos[j]);
                    let wxr = cross(g, w, arm);
                    let lin = add3(g, v, wxr);
                    for r in 0..3 {
                        jac[r * n + c0 + k] = lin[r];
                        jac[(3 + r) * n + c0 + k] = w[r];
                    }
                }
            }
            at = model.links[j].parent;
        }
        jac
    };
    let flat = |r: &M3, p: V3| -> Vec<Id> { r.iter().flatten().copied().chain(p).collect() };
    let mut out = Vec::new();
    for (i, link) in model.links.iter().enumerate() {
        if link.kind == JointKind::Translation {
            continue;
        }
        let jacobian = jacobian_at(g, Some(i), pos[i]);
        out.push(FrameKernel {
            name: link.name.clone(),
            pose: flat(&rot[i], pos[i]),
            jacobian,
        });
    }
    for f in &model.frames {
        let (r, p) = offset_pose(g, f.link.map(|l| (&rot[l], pos[l])), &f.offsets);
        let jacobian = jacobian_at(g, f.link, p);
        out.push(FrameKernel {
            name: f.name.clone(),
            pose: flat(&r, p),
            jacobian,
        });
    }
    out
}
