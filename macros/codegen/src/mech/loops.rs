//! The constraints of the joints that close kinematic loops (theory §7): residual
//! `Φ(q)`, its Jacobian `G = ∂Φ/∂q` and the acceleration term `γ = −Ġ v`, so that
//! `G v̇ = γ` on the constraint manifold.
//!
//! A loop joint holds its parent-side frame `A` and child-side frame `B` together; with
//! `d = p_B − p_A` (world axes) and the unit vectors `u₁, u₂` normal to the joint's axis
//! `a` (in `A`'s axes), its rows are
//!
//! | kind | rows |
//! |---|---|
//! | spherical | `d` (3, world axes) |
//! | revolute(a) | `d`, and `(R_A uᵢ)·(R_B a)` (the axes stay aligned) |
//! | prismatic(a) | `d·(R_A uᵢ)` (no motion across the axis), and the three of fixed |
//! | fixed | `d`, and `(R_A x)·(R_B y)`, `(R_A y)·(R_B z)`, `(R_A z)·(R_B x)` |
//!
//! each zero when the joint is closed. A row that folds to an exact zero is dropped: in
//! a planar mechanism (every axis along `z`, every origin in the plane) a revolute loop
//! joint keeps its two in-plane rows, a prismatic one its normal and angle rows. A
//! small rotation `θ` of `B` from `A` makes the orientation rows `±θ` components,
//! named after the axis they lock.

use super::frames::{offset_pose, world_poses};
use super::kinematics::Kinematics;
use super::spatial::{V3, dot3, mat_vec, sub3, v3_const};
use crate::model::{JointKind, Model};
use crate::sym::{Graph, Id, Input, InputKind};

/// The loop constraints' kernels.
pub struct LoopKernels {
    /// Row names, `<joint>.<component>`: `x`, `y`, `z` for positions (world axes, or
    /// the parent-side frame's axes on a prismatic joint), `rx`, `ry`, `rz` for the
    /// rotation a row locks (`1`, `2` for an oblique axis).
    pub names: Vec<String>,
    /// `Φ(q)`, one node per row.
    pub residual: Vec<Id>,
    /// `G = ∂Φ/∂q`, row-major `m × n`.
    pub jacobian: Vec<Id>,
    /// `γ = −Ġ v`.
    pub gamma: Vec<Id>,
}

impl LoopKernels {
    pub fn rows(&self) -> usize {
        self.residual.len()
    }
}

/// The two unit vectors normal to the unit axis `a`, with the names of their axes
/// (`x`/`y`/`z` where `a` is a coordinate axis, else `1`/`2`): the other two coordinate
/// axes in cyclic order after `a`'s, or `a × e` (normalised, `e` the coordinate axis
/// least aligned with `a`) and `a × u₁`.
fn normals(a: [f64; 3]) -> [([f64; 3], &'static str); 2] {
    const AXES: [&str; 3] = ["x", "y", "z"];
    let unit = |k: usize| {
        let mut e = [0.0; 3];
        e[k] = 1.0;
        e
    };
    if let Some(k) = (0..3).find(|&k| a[k].abs() == 1.0) {
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        return [(unit(i), AXES[i]), (unit(j), AXES[j])];
    }
    let cross = |x: [f64; 3], y: [f64; 3]| {
        [
            x[1] * y[2] - x[2] * y[1],
            x[2] * y[0] - x[0] * y[2],
            x[0] * y[1] - x[1] * y[0],
        ]
    };
    let k = (0..3)
        .min_by(|&i, &j| a[i].abs().total_cmp(&a[j].abs()))
        .unwrap_or(0);
    let u = cross(a, unit(k));
    let norm = (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]).sqrt();
    let u1 = u.map(|c| c / norm);
    [(u1, "1"), (cross(a, u1), "2")]
}

/// The axis a small rotation about which the row `(R_A e_i)·(R_B e_k)` measures, for
/// coordinate axes named `i` and `k`: the third one.
fn locked(i: &str, k: &str) -> &'static str {
    match (i, k) {
        ("x", "y") | ("y", "x") => "rz",
        ("y", "z") | ("z", "y") => "rx",
        ("z", "x") | ("x", "z") => "ry",
        _ => "",
    }
}

pub fn loop_constraints(g: &mut Graph, model: &Model, kin: &Kinematics) -> LoopKernels {
    let n = model.dof();
    let (rot, pos) = world_poses(g, model, kin);
    let mut names = Vec::new();
    let mut residual = Vec::new();
    let mut push = |g: &Graph, name: String, row: Id| {
        if !g.is_zero(row) {
            names.push(name);
            residual.push(row);
        }
    };
    for lj in &model.loops {
        let (ra, pa) = offset_pose(
            g,
            lj.parent.map(|l| (&rot[l], pos[l])),
            &[(lj.origin.clone(), lj.rpy.clone())],
        );
        let (rb, pb) = offset_pose(
            g,
            Some((&rot[lj.child], pos[lj.child])),
            &[(lj.child_origin.clone(), lj.child_rpy.clone())],
        );
        let d = sub3(g, pb, pa);
        let world = |g: &mut Graph, r: &super::spatial::M3, e: [f64; 3]| -> V3 {
            let e = v3_const(g, e);
            mat_vec(g, r, e)
        };
        let positions = |g: &mut Graph, push: &mut dyn FnMut(&Graph, String, Id)| {
            for (k, c) in ["x", "y", "z"].iter().enumerate() {
                push(g, format!("{}.{c}", lj.name), d[k]);
            }
        };
        let orientation = |g: &mut Graph, push: &mut dyn FnMut(&Graph, String, Id)| {
            for (i, k) in [(0, 1), (1, 2), (2, 0)] {
                let (mut ei, mut ek) = ([0.0; 3], [0.0; 3]);
                ei[i] = 1.0;
                ek[k] = 1.0;
                let (ai, bk) = (world(g, &ra, ei), world(g, &rb, ek));
                let row = dot3(g, ai, bk);
                let axes = ["x", "y", "z"];
                push(g, format!("{}.{}", lj.name, locked(axes[i], axes[k])), row);
            }
        };
        match lj.kind {
            JointKind::Spherical => positions(g, &mut push),
            JointKind::Fixed => {
                positions(g, &mut push);
                orientation(g, &mut push);
            }
            JointKind::Revolute(a) => {
                positions(g, &mut push);
                let axis_b = world(g, &rb, a);
                for (u, un) in normals(a) {
                    let ua = world(g, &ra, u);
                    let row = dot3(g, ua, axis_b);
                    let what = match un {
                        "1" | "2" => format!("r{un}"),
                        _ => {
                            let an = ["x", "y", "z"][(0..3).find(|&k| a[k] != 0.0).unwrap_or(2)];
                            locked(un, an).to_string()
                        }
                    };
                    push(g, format!("{}.{what}", lj.name), row);
                }
            }
            JointKind::Prismatic(a) => {
                for (u, un) in normals(a) {
                    let ua = world(g, &ra, u);
                    let row = dot3(g, d, ua);
                    push(g, format!("{}.{un}", lj.name), row);
                }
                orientation(g, &mut push);
            }
            // Refused when read (`loops::read`).
            JointKind::Free | JointKind::Translation => {}
        }
    }
    // G = ∂Φ/∂q and γ = −Σ_k ∂(G v)/∂q_k v_k (q̇ = v: the tree has no Lie-group joints).
    let q = |k: usize| Input {
        kind: InputKind::Q,
        index: k as u16,
    };
    let v: Vec<Id> = (0..n).map(|k| g.input(InputKind::V, k)).collect();
    let mut jacobian = Vec::with_capacity(residual.len() * n);
    let mut gamma = Vec::with_capacity(residual.len());
    for &row in &residual {
        let grad: Vec<Id> = (0..n).map(|k| g.diff(row, q(k))).collect();
        let gv = g.dot(&grad, &v);
        let dgv: Vec<Id> = (0..n).map(|k| g.diff(gv, q(k))).collect();
        let gdot_v = g.dot(&dgv, &v);
        gamma.push(g.neg(gdot_v));
        jacobian.extend(grad);
    }
    LoopKernels {
        names,
        residual,
        jacobian,
        gamma,
    }
}

/// The `LᵀDL`-free dense factor `A = L D Lᵀ` (`L` unit lower triangular) of the
/// symmetric `m × m` matrix `A = G M⁻¹ Gᵀ`, unrolled without pivoting: `A` is positive
/// definite wherever `G` has full rank, and where it has not the pivots vanish (the
/// runtime checks the rank before it integrates, see `runtime::loops`).
pub struct Ldl {
    /// `l[i][j]`, `j < i`.
    l: Vec<Vec<Id>>,
    d: Vec<Id>,
}

impl Ldl {
    pub fn factor(g: &mut Graph, a: &[Vec<Id>]) -> Ldl {
        let m = a.len();
        let mut l: Vec<Vec<Id>> = vec![Vec::new(); m];
        let mut d: Vec<Id> = Vec::with_capacity(m);
        for j in 0..m {
            let mut djj = a[j][j];
            for k in 0..j {
                let t = g.mul(l[j][k], l[j][k]);
                let t = g.mul(t, d[k]);
                djj = g.sub(djj, t);
            }
            d.push(djj);
            for i in j + 1..m {
                let mut s = a[i][j];
                for k in 0..j {
                    let t = g.mul(l[i][k], l[j][k]);
                    let t = g.mul(t, d[k]);
                    s = g.sub(s, t);
                }
                let lij = g.div(s, djj);
                l[i].push(lij);
            }
        }
        Ldl { l, d }
    }

    /// `A⁻¹ b`.
    pub fn solve(&self, g: &mut Graph, b: &[Id]) -> Vec<Id> {
        let m = b.len();
        let mut z: Vec<Id> = Vec::with_capacity(m);
        for i in 0..m {
            let mut s = b[i];
            for k in 0..i {
                let t = g.mul(self.l[i][k], z[k]);
                s = g.sub(s, t);
            }
            z.push(s);
        }
        let mut x: Vec<Id> = z.iter().zip(&self.d).map(|(&z, &d)| g.div(z, d)).collect();
        for i in (0..m).rev() {
            for k in i + 1..m {
                let t = g.mul(self.l[k][i], x[k]);
                x[i] = g.sub(x[i], t);
            }
        }
        x
    }
}

/// The constrained forward dynamics built with one solve by `M` (theory §7): the free
/// accelerations `a₀ = M⁻¹(τ + τ_p − C v − g)`, `Y = M⁻¹ Gᵀ` (one solve per row), the
/// Schur complement `A = G Y` factored as [`Ldl`], the constraint forces
/// `λ = A⁻¹ (γ − G a₀)` and `a = a₀ + Y λ`: `M a = τ + τ_p − C v − g + Gᵀ λ`, `G a = γ`.
pub struct Constrained {
    /// `y[r]` = `M⁻¹ G_rᵀ`.
    pub y: Vec<Vec<Id>>,
    pub schur: Ldl,
    pub acceleration: Vec<Id>,
    pub lambda: Vec<Id>,
}

impl Constrained {
    pub fn build(
        g: &mut Graph,
        lk: &LoopKernels,
        free: Vec<Id>,
        solve_m: &mut dyn FnMut(&mut Graph, &[Id]) -> Vec<Id>,
    ) -> Constrained {
        let n = free.len();
        let m = lk.rows();
        let row = |r: usize| &lk.jacobian[r * n..(r + 1) * n];
        let y: Vec<Vec<Id>> = (0..m).map(|r| solve_m(g, row(r))).collect();
        let a: Vec<Vec<Id>> = (0..m)
            .map(|r| (0..m).map(|c| g.dot(row(r), &y[c])).collect())
            .collect();
        let schur = Ldl::factor(g, &a);
        let rhs: Vec<Id> = (0..m)
            .map(|r| {
                let ga = g.dot(row(r), &free);
                g.sub(lk.gamma[r], ga)
            })
            .collect();
        let lambda = schur.solve(g, &rhs);
        let acceleration = Self::combine(g, &y, free, &lambda);
        Constrained {
            y,
            schur,
            acceleration,
            lambda,
        }
    }

    /// `x + Σ_r y_r w_r`.
    fn combine(g: &mut Graph, y: &[Vec<Id>], mut x: Vec<Id>, w: &[Id]) -> Vec<Id> {
        for (yr, &wr) in y.iter().zip(w) {
            for (xi, &yi) in x.iter_mut().zip(yr) {
                let t = g.mul(yi, wr);
                *xi = g.add(*xi, t);
            }
        }
        x
    }

    /// The solution `a'` of the augmented system `M a' − Gᵀ λ' = r₁`, `G a' = r₂`: one
    /// column of the constrained dynamics' Jacobian, with `r₁`, `r₂` the residuals'
    /// partial derivatives at fixed `(a, λ)`, negated.
    pub fn column(
        &self,
        g: &mut Graph,
        lk: &LoopKernels,
        r1: &[Id],
        r2: &[Id],
        solve_m: &mut dyn FnMut(&mut Graph, &[Id]) -> Vec<Id>,
    ) -> Vec<Id> {
        let n = r1.len();
        let y1 = solve_m(g, r1);
        let rhs: Vec<Id> = (0..r2.len())
            .map(|r| {
                let gy = g.dot(&lk.jacobian[r * n..(r + 1) * n], &y1);
                g.sub(r2[r], gy)
            })
            .collect();
        let dl = self.schur.solve(g, &rhs);
        Self::combine(g, &self.y, y1, &dl)
    }
}
