//! `M⁻¹ b` by the articulated-body algorithm (Featherstone 2008, §7.3, Table 7.1), on
//! the DAG, unrolled per link: linear in the number of links where the `LᵀDL` solve of
//! [`ltdl`](super::ltdl) is quadratic in the depth of the tree (and its factor cubic).
//!
//! [`Articulated::new`] runs the part that depends on `q` only — articulated inertias
//! `I^A_i`, `U_i = I^A_i S_i`, `D_i⁻¹ = (S_iᵀ U_i)⁻¹` — once; every [`Articulated::solve`]
//! (forward dynamics, each column of its Jacobian, each column of `M⁻¹`) then costs two
//! passes of 6-vector arithmetic per link and shares those nodes. Each joint's motion
//! subspace is a constant unit twist in link coordinates, so `S_iᵀ` and `S_i ·` pick
//! entries and the folding constructors drop the structural zeros of every joint and
//! inertia.

use super::kinematics::Kinematics;
use super::spatial::{
    Force, Inertia, M3, Motion, V3, Xform, add3, mat_add, mat_mul, mat_vec, scale3, transpose,
};
use crate::model::Model;
use crate::sym::{Graph, Id};

/// A symmetric spatial inertia that need not be a rigid body's, in 3×3 blocks acting
/// on a motion `(ω, v)`: `n = A ω + B v`, `f = Bᵀ ω + C v` (`A`, `C` symmetric).
#[derive(Clone, Copy)]
pub struct Spatial6 {
    pub a: M3,
    pub b: M3,
    pub c: M3,
}

fn skew(g: &mut Graph, r: V3) -> M3 {
    let z = g.zero();
    let n = |g: &mut Graph, x: Id| g.neg(x);
    [
        [z, n(g, r[2]), r[1]],
        [r[2], z, n(g, r[0])],
        [n(g, r[1]), r[0], z],
    ]
}

/// `Eᵀ S E` for symmetric `S`: the upper triangle computed, the lower mirrored.
fn rotate_sym(g: &mut Graph, e: &M3, s: &M3) -> M3 {
    let se = mat_mul(g, s, e);
    let et = transpose(e);
    let mut out = *s;
    for i in 0..3 {
        for j in i..3 {
            let col = [se[0][j], se[1][j], se[2][j]];
            out[i][j] = g.dot(&et[i], &col);
            out[j][i] = out[i][j];
        }
    }
    out
}

fn sym_sub_outer(g: &mut Graph, s: &mut M3, x: &[Id], y: &[Id]) {
    for i in 0..3 {
        for j in i..3 {
            let t = g.mul(x[i], y[j]);
            s[i][j] = g.sub(s[i][j], t);
            s[j][i] = s[i][j];
        }
    }
}

impl Spatial6 {
    pub fn from_rigid(g: &mut Graph, i: &Inertia) -> Spatial6 {
        let z = g.zero();
        let mut c = [[z; 3]; 3];
        for (k, row) in c.iter_mut().enumerate() {
            row[k] = i.m;
        }
        Spatial6 {
            a: i.ibar,
            b: skew(g, i.h),
            c,
        }
    }

    pub fn apply(&self, g: &mut Graph, m: Motion) -> Force {
        let bt = transpose(&self.b);
        let aw = mat_vec(g, &self.a, m.w);
        let bv = mat_vec(g, &self.b, m.v);
        let btw = mat_vec(g, &bt, m.w);
        let cv = mat_vec(g, &self.c, m.v);
        Force {
            n: add3(g, aw, bv),
            f: add3(g, btw, cv),
        }
    }

    /// Sets the row and column this inertia maps `s` through to zero, where `s` is a
    /// constant twist along one coordinate axis (angular or linear); any other `s` is
    /// left alone. Valid only where `I s = 0` holds exactly, as for `I^a` and the
    /// joint's own motion subspace.
    fn zero_along(&mut self, g: &mut Graph, s: &Motion) {
        let axis = |v: &[Id; 3]| -> Option<Option<usize>> {
            let nonzero: Vec<usize> = (0..3).filter(|&k| !g.is_zero(v[k])).collect();
            match nonzero[..] {
                [] => Some(None),
                [k] if g.as_const(v[k]).is_some() => Some(Some(k)),
                _ => None,
            }
        };
        let along = (axis(&s.w), axis(&s.v));
        let z = g.zero();
        match along {
            // I (e_k, 0) = (A e_k, Bᵀ e_k) = 0.
            (Some(Some(k)), Some(None)) => {
                for j in 0..3 {
                    self.a[j][k] = z;
                    self.a[k][j] = z;
                    self.b[k][j] = z;
                }
            }
            // I (0, e_k) = (B e_k, C e_k) = 0.
            (Some(None), Some(Some(k))) => {
                for j in 0..3 {
                    self.b[j][k] = z;
                    self.c[j][k] = z;
                    self.c[k][j] = z;
                }
            }
            _ => {}
        }
    }

    pub fn add(&self, g: &mut Graph, o: &Spatial6) -> Spatial6 {
        let a = mat_add(g, &self.a, &o.a);
        let b = mat_add(g, &self.b, &o.b);
        let c = mat_add(g, &self.c, &o.c);
        Spatial6 { a, b, c }
    }

    /// `Xᵀ I X`: this inertia (child coordinates) in the parent's coordinates. With
    /// `A', B', C'` the blocks rotated to parent axes (`Eᵀ · E`) and `R = [r×]`:
    /// `A = A' − (B'R + (B'R)ᵀ) − R C' R`, `B = B' + R C'`, `C = C'`.
    pub fn to_parent(&self, g: &mut Graph, x: &Xform) -> Spatial6 {
        let a1 = rotate_sym(g, &x.e, &self.a);
        let c1 = rotate_sym(g, &x.e, &self.c);
        let be = mat_mul(g, &self.b, &x.e);
        let b1 = mat_mul(g, &transpose(&x.e), &be);
        let r = skew(g, x.r);
        let br = mat_mul(g, &b1, &r);
        let rc = mat_mul(g, &r, &c1);
        let rcr = mat_mul(g, &rc, &r);
        let mut a = a1;
        for i in 0..3 {
            for j in i..3 {
                let s = g.add(br[i][j], br[j][i]);
                let t = g.add(s, rcr[i][j]);
                a[i][j] = g.sub(a1[i][j], t);
                a[j][i] = a[i][j];
            }
        }
        let b = mat_add(g, &b1, &rc);
        Spatial6 { a, b, c: c1 }
    }
}

/// Per-link data of the articulated-body algorithm that depends on `q` only.
struct Joint {
    /// `U_i D_i⁻¹`, one force per column of the motion subspace.
    w: Vec<Force>,
    /// `D_i⁻¹`, `k × k`.
    d_inv: Vec<Vec<Id>>,
}

/// The articulated-body factorisation of a scene at symbolic `q`.
pub struct Articulated<'m> {
    model: &'m Model,
    kin: &'m Kinematics,
    joints: Vec<Option<Joint>>,
}

/// `D⁻¹` of a small symmetric positive definite block by `LDLᵀ` without pivoting
/// (one division per row; `k` is 1 or 3).
fn inverse_spd(g: &mut Graph, d: &[Vec<Id>]) -> Vec<Vec<Id>> {
    let k = d.len();
    if k == 1 {
        return vec![vec![g.recip(d[0][0])]];
    }
    let z = g.zero();
    // D = L diag(p) Lᵀ, L unit lower triangular.
    let mut l = vec![vec![z; k]; k];
    let mut p_inv = vec![z; k];
    let mut p = vec![z; k];
    for j in 0..k {
        let mut pj = d[j][j];
        for m in 0..j {
            let t = g.mul(l[j][m], l[j][m]);
            let t = g.mul(t, p[m]);
            pj = g.sub(pj, t);
        }
        p[j] = pj;
        p_inv[j] = g.recip(pj);
        l[j][j] = g.one();
        for i in j + 1..k {
            let mut s = d[i][j];
            for m in 0..j {
                let t = g.mul(l[i][m], l[j][m]);
                let t = g.mul(t, p[m]);
                s = g.sub(s, t);
            }
            l[i][j] = g.mul(s, p_inv[j]);
        }
    }
    // Columns of D⁻¹: solve L y = e, y ← y / p, Lᵀ x = y.
    let mut inv = vec![vec![z; k]; k];
    for col in 0..k {
        let mut y: Vec<Id> = (0..k).map(|i| g.constant(f64::from(i == col))).collect();
        for i in 0..k {
            for m in 0..i {
                let t = g.mul(l[i][m], y[m]);
                y[i] = g.sub(y[i], t);
            }
        }
        for i in 0..k {
            y[i] = g.mul(y[i], p_inv[i]);
        }
        for i in (0..k).rev() {
            for m in i + 1..k {
                let t = g.mul(l[m][i], y[m]);
                y[i] = g.sub(y[i], t);
            }
        }
        for i in col..k {
            inv[i][col] = y[i];
            inv[col][i] = y[i];
        }
    }
    inv
}

impl<'m> Articulated<'m> {
    pub fn new(g: &mut Graph, model: &'m Model, kin: &'m Kinematics, inertia: &[Inertia]) -> Self {
        let nl = model.links.len();
        let mut art: Vec<Spatial6> = inertia.iter().map(|i| Spatial6::from_rigid(g, i)).collect();
        let mut joints: Vec<Option<Joint>> = (0..nl).map(|_| None).collect();
        for i in (0..nl).rev() {
            let link = &model.links[i];
            let mut ia = art[i];
            if link.coordinate.is_some() {
                let s = &kin.subspace[i];
                let u: Vec<Force> = s.iter().map(|sa| art[i].apply(g, *sa)).collect();
                let d: Vec<Vec<Id>> = s
                    .iter()
                    .map(|sa| u.iter().map(|ub| sa.dot_force(g, *ub)).collect())
                    .collect();
                let d_inv = inverse_spd(g, &d);
                // W = U D⁻¹.
                let w: Vec<Force> = (0..s.len())
                    .map(|col| {
                        let mut n = [g.zero(); 3];
                        let mut f = [g.zero(); 3];
                        for (row, ub) in u.iter().enumerate() {
                            for c in 0..3 {
                                let tn = g.mul(ub.n[c], d_inv[row][col]);
                                n[c] = g.add(n[c], tn);
                                let tf = g.mul(ub.f[c], d_inv[row][col]);
                                f[c] = g.add(f[c], tf);
                            }
                        }
                        Force { n, f }
                    })
                    .collect();
                if link.parent.is_some() {
                    // I^a = I^A − W Uᵀ (symmetric).
                    for (wa, ua) in w.iter().zip(&u) {
                        sym_sub_outer(g, &mut ia.a, &wa.n, &ua.n);
                        sym_sub_outer(g, &mut ia.c, &wa.f, &ua.f);
                        for r in 0..3 {
                            for c in 0..3 {
                                let t = g.mul(wa.n[r], ua.f[c]);
                                ia.b[r][c] = g.sub(ia.b[r][c], t);
                            }
                        }
                    }
                    // `I^a S = U − U D⁻¹ D = 0` exactly; on a joint along a coordinate
                    // axis those are whole rows and columns, zero only up to rounding
                    // on the DAG. Say so, and everything they would feed folds away.
                    for sa in s {
                        ia.zero_along(g, sa);
                    }
                }
                joints[i] = Some(Joint { w, d_inv });
            }
            if let Some(p) = link.parent {
                let moved = ia.to_parent(g, &kin.xform[i]);
                art[p] = art[p].add(g, &moved);
            }
        }
        Articulated { model, kin, joints }
    }

    /// Every node of the factorisation: each joint's `U D⁻¹` and `D⁻¹`.
    pub fn nodes(&self) -> Vec<Id> {
        let mut out = Vec::new();
        for j in self.joints.iter().flatten() {
            for w in &j.w {
                out.extend(w.n.iter().chain(&w.f));
            }
            out.extend(j.d_inv.iter().flatten());
        }
        out
    }

    /// `M⁻¹ (b − bias(base))`: the accelerations under generalised forces `b` when the
    /// base accelerates with `base` (`(0, −γ)` puts gravity in; `None`: at rest) and
    /// every velocity is zero.
    pub fn solve(&self, g: &mut Graph, b: &[Id], base: Option<Motion>) -> Vec<Id> {
        let model = self.model;
        let nl = model.links.len();
        let z = g.zero();
        let zero_force = Force {
            n: [z; 3],
            f: [z; 3],
        };
        let mut p = vec![zero_force; nl];
        let mut u: Vec<Vec<Id>> = vec![Vec::new(); nl];
        for i in (0..nl).rev() {
            let link = &model.links[i];
            let mut pa = p[i];
            if let (Some(c), Some(j)) = (link.coordinate, &self.joints[i]) {
                u[i] = self.kin.subspace[i]
                    .iter()
                    .enumerate()
                    .map(|(k, s)| {
                        let sp = s.dot_force(g, p[i]);
                        g.sub(b[c + k], sp)
                    })
                    .collect();
                for (wk, uk) in j.w.iter().zip(&u[i]) {
                    let n = scale3(g, *uk, wk.n);
                    let f = scale3(g, *uk, wk.f);
                    pa = pa.add(g, Force { n, f });
                }
            }
            if let Some(par) = link.parent {
                let up = self.kin.xform[i].apply_force_t(g, pa);
                p[par] = p[par].add(g, up);
            }
        }
        let mut out = vec![z; b.len()];
        let base = base.unwrap_or_else(|| Motion::zero(g));
        let mut acc: Vec<Motion> = Vec::with_capacity(nl);
        for i in 0..nl {
            let link = &model.links[i];
            let ap = link.parent.map_or(base, |par| acc[par]);
            let mut ai = self.kin.xform[i].apply_motion(g, ap);
            if let (Some(c), Some(j)) = (link.coordinate, &self.joints[i]) {
                let k = self.kin.subspace[i].len();
                for row in 0..k {
                    // q̈ = D⁻¹ u − Wᵀ a.
                    let du: Vec<Id> = (0..k).map(|m| j.d_inv[row][m]).collect();
                    let d = g.dot(&du, &u[i]);
                    let ta = ai.dot_force(g, j.w[row]);
                    out[c + row] = g.sub(d, ta);
                }
                for (row, s) in self.kin.subspace[i].iter().enumerate() {
                    let t = s.scale(g, out[c + row]);
                    ai = ai.add(g, t);
                }
            }
            acc.push(ai);
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inverse_of_a_constant_spd_block() {
        let mut g = Graph::new();
        let m = [[4.0, 1.0, 0.5], [1.0, 3.0, 0.2], [0.5, 0.2, 2.0]];
        let d: Vec<Vec<Id>> = m
            .iter()
            .map(|r| r.iter().map(|&x| g.constant(x)).collect())
            .collect();
        let inv = inverse_spd(&mut g, &d);
        for i in 0..3 {
            for j in 0..3 {
                let s: f64 = (0..3)
                    .map(|k| m[i][k] * g.as_const(inv[k][j]).expect("constant"))
                    .sum();
                assert!((s - f64::from(i == j)).abs() < 1e-14, "{i} {j}: {s}");
            }
        }
    }
}
