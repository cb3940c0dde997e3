//! Contacts of points and spheres with planes (theory §8): the gap `g_N(q)`, its
//! Jacobian `W_N = ∂g_N/∂q`, the tangential velocity Jacobians `W_T` and the
//! acceleration terms `γ = −Ẇ v`.
//!
//! With the plane's frame `(R_P, p_P)`, its unit normal `n = R_P ν` (`ν` the declared
//! axis), the sphere's centre `x = p_b + R_b a` and radius `r`:
//!
//! - the gap is `g_N = n·(x − p_P) − r` (`≥ 0` apart);
//! - the contact point is `c = x − r n`; its relative velocity `u` is that of the body's
//!   material point at `c` minus that of the plane's (`0` for the world), a material
//!   point moving as `ṗ + Ṙ Rᵀ (c − p)` with its body;
//! - the normal velocity `n·u` equals `ġ_N`, so `W_N = ∂g_N/∂q`; each tangent
//!   `t = R_P τ` (`τ` one of the frame's other two axes) gives a row `W_T = ∂(t·u)/∂v`.
//!   A sphere rolling on the plane has `t·u = 0`: the tangential rows are velocities,
//!   not derivatives of positions;
//! - `γ = −Σ_k ∂(W v)/∂q_k v_k` for every row, so that a contact that stays closed
//!   (`W_N v̇ = γ_N`) or stuck (`W_T v̇ = γ_T`) keeps its velocity at zero.
//!
//! A tangential row that folds to an exact zero is dropped: in a planar mechanism (every
//! axis along `z`, every point in the plane) a contact keeps its in-plane tangent.

use super::frames::{offset_pose, world_poses};
use super::kinematics::{Kinematics, lower3};
use super::spatial::{M3, V3, add3, dot3, mat_t_vec, mat_vec, scale3, sub3, v3_const, v3_zero};
use crate::model::Model;
use crate::sym::{Graph, Id, Input, InputKind};

/// The contacts' kernels.
pub struct ContactKernels {
    /// The contacts' names, one gap each.
    pub names: Vec<String>,
    /// `g_N(q)`, one per contact.
    pub gaps: Vec<Id>,
    /// `W_N`, row-major `k × n`.
    pub normal: Vec<Id>,
    /// `γ_N`, one per contact.
    pub normal_gamma: Vec<Id>,
    /// Tangent rows' names, `<contact>.<axis of the plane's frame>`.
    pub tangent_names: Vec<String>,
    /// The contact each tangent row belongs to.
    pub tangent_of: Vec<usize>,
    /// `W_T`, row-major `t × n`.
    pub tangent: Vec<Id>,
    /// `γ_T`, one per tangent row.
    pub tangent_gamma: Vec<Id>,
}

impl ContactKernels {
    pub fn contacts(&self) -> usize {
        self.gaps.len()
    }
    pub fn tangents(&self) -> usize {
        self.tangent_of.len()
    }
}

/// `Ṙ = Σ_k ∂R/∂q_k v_k` and `ṗ` of a link's pose.
fn pose_rate(g: &mut Graph, rot: &M3, pos: V3, n: usize) -> (M3, V3) {
    let v: Vec<Id> = (0..n).map(|k| g.input(InputKind::V, k)).collect();
    let rate = |g: &mut Graph, x: Id| {
        let grad: Vec<Id> = (0..n).map(|k| g.diff(x, q_input(k))).collect();
        g.dot(&grad, &v)
    };
    let mut r_dot = [[g.zero(); 3]; 3];
    for (i, row) in rot.iter().enumerate() {
        for (j, &x) in row.iter().enumerate() {
            r_dot[i][j] = rate(g, x);
        }
    }
    let p_dot = [rate(g, pos[0]), rate(g, pos[1]), rate(g, pos[2])];
    (r_dot, p_dot)
}

fn q_input(k: usize) -> Input {
    Input {
        kind: InputKind::Q,
        index: k as u16,
    }
}

/// The velocity of the material point at `local` (body coordinates) of a body with pose
/// rate `(r_dot, p_dot)`: `ṗ + Ṙ local`.
fn material_velocity(g: &mut Graph, (r_dot, p_dot): (&M3, V3), local: V3) -> V3 {
    let turn = mat_vec(g, r_dot, local);
    add3(g, p_dot, turn)
}

pub fn contacts(g: &mut Graph, model: &Model, kin: &Kinematics) -> ContactKernels {
    let n = model.dof();
    let (rot, pos) = world_poses(g, model, kin);
    // Pose rates of the links that carry a contact's point or plane, only.
    let mut rates: Vec<Option<(M3, V3)>> = vec![None; rot.len()];
    for c in &model.contacts {
        for l in std::iter::once(c.body).chain(c.plane) {
            if rates[l].is_none() {
                rates[l] = Some(pose_rate(g, &rot[l], pos[l], n));
            }
        }
    }
    let v: Vec<Id> = (0..n).map(|k| g.input(InputKind::V, k)).collect();
    let mut out = ContactKernels {
        names: Vec::new(),
        gaps: Vec::new(),
        normal: Vec::new(),
        normal_gamma: Vec::new(),
        tangent_names: Vec::new(),
        tangent_of: Vec::new(),
        tangent: Vec::new(),
        tangent_gamma: Vec::new(),
    };
    // γ = −Σ_k ∂(W v)/∂q_k v_k of a row `w` (its entries by coordinate).
    let gamma = |g: &mut Graph, w: &[Id]| {
        let wv = g.dot(w, &v);
        let dwv: Vec<Id> = (0..n).map(|k| g.diff(wv, q_input(k))).collect();
        let wdot_v = g.dot(&dwv, &v);
        g.neg(wdot_v)
    };
    for (index, c) in model.contacts.iter().enumerate() {
        let (rp, pp) = offset_pose(
            g,
            c.plane.map(|l| (&rot[l], pos[l])),
            &[(c.origin.clone(), c.rpy.clone())],
        );
        let nu = v3_const(g, c.normal);
        let normal = mat_vec(g, &rp, nu);
        let at = lower3(g, &c.at);
        let local = mat_vec(g, &rot[c.body], at);
        let centre = add3(g, pos[c.body], local);
        let radius = c.radius.lower(g);
        let d = sub3(g, centre, pp);
        let height = dot3(g, normal, d);
        let gap = g.sub(height, radius);
        let w_n: Vec<Id> = (0..n).map(|k| g.diff(gap, q_input(k))).collect();
        out.normal_gamma.push(gamma(g, &w_n));
        out.names.push(c.name.clone());
        out.gaps.push(gap);
        out.normal.extend(w_n);
        // The contact point and its relative velocity.
        let lowered = scale3(g, radius, normal);
        let point = sub3(g, centre, lowered);
        let body = c.body;
        let rate = |l: usize| rates[l].expect("the pose rate of every contact's link");
        // In the body's coordinates the contact point is `at − r Rᵀ n` (for a point,
        // `at` itself: no rotation there and back).
        let n_local = mat_t_vec(g, &rot[body], normal);
        let drop = scale3(g, radius, n_local);
        let local = sub3(g, at, drop);
        let (r_dot, p_dot) = rate(body);
        let u_body = material_velocity(g, (&r_dot, p_dot), local);
        let u_plane = match c.plane {
            Some(l) => {
                let d = sub3(g, point, pos[l]);
                let local = mat_t_vec(g, &rot[l], d);
                let (r_dot, p_dot) = rate(l);
                material_velocity(g, (&r_dot, p_dot), local)
            }
            None => v3_zero(g),
        };
        let u = sub3(g, u_body, u_plane);
        for (k, axis_name) in ["x", "y", "z"].iter().enumerate() {
            if c.normal[k] != 0.0 {
                continue;
            }
            let mut tau = [0.0; 3];
            tau[k] = 1.0;
            let tau = v3_const(g, tau);
            let t = mat_vec(g, &rp, tau);
            let slip = dot3(g, t, u);
            let w_t: Vec<Id> = (0..n)
                .map(|j| {
                    g.diff(
                        slip,
                        Input {
                            kind: InputKind::V,
                            index: j as u16,
                        },
                    )
                })
                .collect();
            if w_t.iter().all(|&x| g.is_zero(x)) {
                continue;
            }
            out.tangent_gamma.push(gamma(g, &w_t));
            out.tangent_names.push(format!("{}.{axis_name}", c.name));
            out.tangent_of.push(index);
            out.tangent.extend(w_t);
        }
    }
    out
}
