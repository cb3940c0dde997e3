//! The mass matrix of a compact tree by the composite-rigid-body algorithm
//! (Featherstone, *Rigid Body Dynamics Algorithms*, §6.2): composite inertias inwards,
//! then each joint's force `I_c S` and motion subspace `S` in the world frame, whose
//! dot products are the entries of `M`.

use super::algebra::{M3, Spatial, Sym, V3, add, cross, dot, mat_mul, mul, sym_rotate};
use super::{Body, Joint, Node, Pair, placement};
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

/// `M(q)` of the tree `nodes`/`bodies` (parents before children), an array of rows;
/// `pairs` the tree's [`pairs`](super::pairs).
///
/// Composite inertias are summed inwards in the bodies' own frames; each joint's force
/// `F = I_c S` and every joint's motion subspace `S` are then written once in the world
/// frame, so that each entry `M_ij = S_jᵀ F_i` is one independent six-term dot product
/// instead of a force carried link by link towards the root.
#[inline(never)]
pub fn mass_matrix<T: Real, const B: usize, const N: usize>(
    nodes: &[Node; B],
    pairs: &[Pair],
    bodies: &[Body<T>; B],
    q: &[T; N],
) -> [[T; N]; N] {
    mass_matrix_in(nodes, pairs, bodies, q, |x| x)
}

/// [`mass_matrix`]'s body, inlined into its callers: the fused twins (`super::fused`)
/// compile it with their target features, and the matrix is built where the caller
/// returns it, without a copy. (The public function is never inlined: on wide duals its
/// unoptimised frame is over a megabyte, and the Jacobian that calls it in a loop would
/// otherwise carry it in its own.)
#[inline(always)]
pub(crate) fn mass_matrix_in<T: Real, U: Copy, const B: usize, const N: usize>(
    nodes: &[Node; B],
    pairs: &[Pair],
    bodies: &[Body<T>; B],
    q: &[T; N],
    out: impl Fn(T) -> U,
) -> [[U; N]; N] {
    let zero = T::cst(0.0);
    let mut diagonal = [zero; N];
    let mut rot = [[[zero; 3]; 3]; B];
    let mut pos = [[zero; 3]; B];
    let mut world_rot = [[[zero; 3]; 3]; B];
    let mut world_pos = [[zero; 3]; B];
    let mut composite = [Rigid {
        m: zero,
        h: [zero; 3],
        i: [zero; 6],
    }; B];
    // Per coordinate: its joint's motion subspace and composite force in the world.
    let mut subspace = [Spatial::zero(); N];
    let mut force = [Spatial::zero(); N];
    // Outwards: each body's placement on its parent, its axes and origin in the world,
    // and its joint's motion subspace there.
    let trig = T::sin_cos_n(*q);
    for i in 0..B {
        let (r, p) = placement(&bodies[i], nodes[i].joint, q, &trig);
        rot[i] = r;
        pos[i] = p;
        composite[i] = Rigid {
            m: bodies[i].mass,
            h: bodies[i].first_moment,
            i: bodies[i].inertia,
        };
        let (w, o) = match nodes[i].parent {
            Some(pa) => (
                mat_mul(&world_rot[pa], &r),
                add(world_pos[pa], mul(&world_rot[pa], p)),
            ),
            None => (r, p),
        };
        world_rot[i] = w;
        world_pos[i] = o;
        let z = [w[0][2], w[1][2], w[2][2]];
        match nodes[i].joint {
            Joint::Revolute(k) => {
                subspace[k] = Spatial {
                    w: z,
                    l: cross(o, z),
                }
            }
            Joint::Prismatic(k) => subspace[k] = Spatial { w: [zero; 3], l: z },
            Joint::Fixed => {}
        }
    }
    // Inwards: a body's composite inertia is whole once the loop reaches it (its
    // children come after it), so its joint's force `I_c S` is taken there — the
    // diagonal from it in the body's frame, and the force in the world for the rest —
    // before the composite is carried to the parent.
    for i in (0..B).rev() {
        let joint = nodes[i].joint;
        if let Some(ci) = joint.coordinate() {
            let revolute = matches!(joint, Joint::Revolute(_));
            let f = composite[i].times_joint(revolute);
            if let Some((_, d)) = joint_part(&f, joint) {
                diagonal[ci] = d;
            }
            force[ci] = f.force_to_parent(&world_rot[i], world_pos[i]);
        }
        if let Some(pa) = nodes[i].parent {
            let moved = composite[i].in_parent(&rot[i], pos[i]);
            composite[pa] = composite[pa].plus(&moved);
        }
    }
    assemble(&diagonal, &subspace, &force, pairs, out)
}

/// `M` from its diagonal and, off it, one dot product per pair of the constant table.
/// The pairs of one joint are consecutive, and its force is loaded once for them all:
/// the loop is bound by its loads. (Its own function, so that the matrix, zeroed and
/// filled here alone, is built in the caller's place rather than copied there; `out`
/// gives its entries the caller's scalar, `f64` for the fused twin's.)
#[inline(always)]
fn assemble<T: Real, U: Copy, const N: usize>(
    diagonal: &[T; N],
    subspace: &[Spatial<T>; N],
    force: &[Spatial<T>; N],
    pairs: &[Pair],
    out: impl Fn(T) -> U,
) -> [[U; N]; N] {
    let mut m = [[out(T::cst(0.0)); N]; N];
    for (k, d) in diagonal.iter().enumerate() {
        m[k][k] = out(*d);
    }
    let mut k = 0;
    while k < pairs.len() {
        let ci = pairs[k].row as usize;
        let f = force[ci];
        while k < pairs.len() && pairs[k].row as usize == ci {
            let cj = pairs[k].col as usize;
            let x = out(subspace[cj].dot(f));
            m[ci][cj] = x;
            m[cj][ci] = x;
            k += 1;
        }
    }
    m
}
