//! The mass matrix of a compact tree by the composite-rigid-body algorithm
//! (Featherstone, *Rigid Body Dynamics Algorithms*, §6.2): composite inertias inwards,
//! then each joint's force `I_c S` and motion subspace `S` in the world frame, whose
//! dot products are the entries of `M`.

use super::algebra::{M3, Spatial, Sym, V3, add, cross, dot, mat_mul, mul, sym_rotate};
use super::{Body, Joint, Node, placement};
use crate::real::Real;

/// A rigid body's inertia `(m, h, Ī)`: mass, first moment, rotational inertia about the
/// frame's origin.
#[derive(Clone, Copy, Debug)]
struct Rigid<T> {
    m: T,
    h: V3<T>,
    i: Sym<T>,
}

impl<T: Real> Rigid<T> {
    /// In the parent's frame: `h' = R h + m p`,
    /// `Ī' = R Ī Rᵀ − (p aᵀ + a pᵀ − 2 (a·p) 1) − m (p pᵀ − |p|² 1)` with `a = R h`.
    #[inline(always)]
    fn in_parent(&self, r: &M3<T>, p: V3<T>) -> Self {
        let a = mul(r, self.h);
        let ri = sym_rotate(r, &self.i);
        let ap = dot(a, p);
        let pp = dot(p, p);
        let two = T::cst(2.0);
        let diag = self.m.mul_add(pp, two * ap);
        let e = |i: usize, j: usize| (self.m * p[i]).mul_add(p[j], a[i].mul_add(p[j], p[i] * a[j]));
        let m = self.m;
        Rigid {
            m,
            h: [
                m.mul_add(p[0], a[0]),
                m.mul_add(p[1], a[1]),
                m.mul_add(p[2], a[2]),
            ],
            i: [
                ri[0] - e(0, 0) + diag,
                ri[1] - e(1, 1) + diag,
                ri[2] - e(2, 2) + diag,
                ri[3] - e(0, 1),
                ri[4] - e(0, 2),
                ri[5] - e(1, 2),
            ],
        }
    }

    #[inline(always)]
    fn plus(&self, o: &Self) -> Self {
        Rigid {
            m: self.m + o.m,
            h: add(self.h, o.h),
            i: std::array::from_fn(|k| self.i[k] + o.i[k]),
        }
    }

    /// `I S` for a joint along `z`: the force a unit motion of the joint needs.
    #[inline(always)]
    fn times_joint(&self, revolute: bool) -> Spatial<T> {
        let z = T::cst(0.0);
        let h = self.h;
        if revolute {
            // (Ī e_z, e_z × h): Ī's third column.
            Spatial {
                w: [self.i[4], self.i[5], self.i[2]],
                l: [-h[1], h[0], z],
            }
        } else {
            // (h × e_z, m e_z).
            Spatial {
                w: [h[1], -h[0], z],
                l: [z, z, self.m],
            }
        }
    }
}

/// `Sᵀ f` of a joint along `z`.
#[inline(always)]
fn joint_part<T: Real>(f: &Spatial<T>, joint: Joint) -> Option<(usize, T)> {
    match joint {
        Joint::Revolute(k) => Some((k, f.w[2])),
        Joint::Prismatic(k) => Some((k, f.l[2])),
        Joint::Fixed => None,
    }
}

/// `M(q)` of the tree `nodes`/`bodies` (parents before children), an array of rows.
///
/// Composite inertias are summed inwards in the bodies' own frames; each joint's force
/// `F = I_c S` and every joint's motion subspace `S` are then written once in the world
/// frame, so that each entry `M_ij = S_jᵀ F_i` is one independent six-term dot product
/// instead of a force carried link by link towards the root.
#[inline(never)]
pub fn mass_matrix<T: Real, const B: usize, const N: usize>(
    nodes: &[Node; B],
    bodies: &[Body<T>; B],
    q: &[T; N],
) -> [[T; N]; N] {
    mass_matrix_in(nodes, bodies, q)
}

/// [`mass_matrix`]'s body, inlined into its callers: the fused twins (`super::fused`)
/// compile it with their target features. (The public function is never inlined: on
/// wide duals its unoptimised frame is over a megabyte, and the Jacobian that calls it
/// in a loop would otherwise carry it in its own.)
#[inline(always)]
pub(crate) fn mass_matrix_in<T: Real, const B: usize, const N: usize>(
    nodes: &[Node; B],
    bodies: &[Body<T>; B],
    q: &[T; N],
) -> [[T; N]; N] {
    let zero = T::cst(0.0);
    let mut rot = [[[zero; 3]; 3]; B];
    let mut pos = [[zero; 3]; B];
    let mut composite: [Rigid<T>; B] = std::array::from_fn(|i| Rigid {
        m: bodies[i].mass,
        h: bodies[i].first_moment,
        i: bodies[i].inertia,
    });
    let trig = T::sin_cos_n(*q);
    for i in 0..B {
        let (r, p) = placement(&bodies[i], nodes[i].joint, q, &trig);
        rot[i] = r;
        pos[i] = p;
    }
    for i in (0..B).rev() {
        if let Some(pa) = nodes[i].parent {
            let moved = composite[i].in_parent(&rot[i], pos[i]);
            composite[pa] = composite[pa].plus(&moved);
        }
    }
    // Outwards: each body's axes and origin in the world, its joint's motion subspace
    // and its composite force there, the diagonal from the force in the body's frame.
    let mut world_rot = [[[zero; 3]; 3]; B];
    let mut world_pos = [[zero; 3]; B];
    let mut subspace = [Spatial::zero(); B];
    let mut force = [Spatial::zero(); B];
    let mut m = [[zero; N]; N];
    for i in 0..B {
        let (w, o) = match nodes[i].parent {
            Some(pa) => (
                mat_mul(&world_rot[pa], &rot[i]),
                add(world_pos[pa], mul(&world_rot[pa], pos[i])),
            ),
            None => (rot[i], pos[i]),
        };
        world_rot[i] = w;
        world_pos[i] = o;
        let joint = nodes[i].joint;
        let Some(ci) = joint.coordinate() else {
            continue;
        };
        let revolute = matches!(joint, Joint::Revolute(_));
        let f = composite[i].times_joint(revolute);
        if let Some((_, d)) = joint_part(&f, joint) {
            m[ci][ci] = d;
        }
        force[i] = f.force_to_parent(&w, o);
        let z = [w[0][2], w[1][2], w[2][2]];
        subspace[i] = if revolute {
            Spatial {
                w: z,
                l: cross(o, z),
            }
        } else {
            Spatial { w: [zero; 3], l: z }
        };
    }
    for i in 0..B {
        let Some(ci) = nodes[i].joint.coordinate() else {
            continue;
        };
        let f = force[i];
        let mut j = i;
        while let Some(pa) = nodes[j].parent {
            j = pa;
            if let Some(cj) = nodes[j].joint.coordinate() {
                let x = subspace[j].dot(f);
                m[ci][cj] = x;
                m[cj][ci] = x;
            }
        }
    }
    m
}
