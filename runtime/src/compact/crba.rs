//! The mass matrix of a compact tree by the composite-rigid-body algorithm
//! (Featherstone, *Rigid Body Dynamics Algorithms*, §6.2), in the world frame: each
//! body's inertia and joint motion subspace `S` are written there once, outwards; the
//! composite inertias are then plain sums inwards, each joint's force `I_c S` is taken
//! from its composite, and the entries of `M` are dot products `S_jᵀ I_c S_i`.

use super::algebra::{M3, Rigid, Spatial, V3, add, cross, mat_mul, mul};
use super::{Body, Joint, Node, Pair, placement};
use crate::real::Real;
use std::mem::MaybeUninit;

/// `M(q)` of the tree `nodes`/`bodies` (parents before children), an array of rows;
/// `pairs` the tree's [`pairs`](super::pairs).
///
/// Every body's inertia and joint motion subspace are written once in the world frame,
/// where a composite inertia is a sum with nothing to transform, and each entry
/// `M_ij = S_jᵀ F_i` (`F_i = I_c S_i`) is one independent six-term dot product instead of
/// a force carried link by link towards the root.
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
    // Written for every body by the outward loop, in order, before any read (not
    // zeroed first).
    let mut world_rot = [const { MaybeUninit::<M3<T>>::uninit() }; B];
    let mut world_pos = [const { MaybeUninit::<V3<T>>::uninit() }; B];
    let mut composite = [const { MaybeUninit::<Rigid<T>>::uninit() }; B];
    // Per coordinate: its joint's motion subspace and composite force in the world.
    let mut subspace = [Spatial::zero(); N];
    let mut force = [Spatial::zero(); N];
    // Outwards: each body's axes and origin in the world, its joint's motion subspace
    // there, and its inertia there (about the world's origin). Each body's is
    // independent of the others' once its frame is known.
    let trig = T::sin_cos_n(*q);
    for i in 0..B {
        let (r, p) = placement(&bodies[i], nodes[i].joint, q, &trig);
        let (w, o) = match nodes[i].parent {
            Some(pa) => {
                assert!(pa < i, "a parent after its child in the table");
                // SAFETY: the loop wrote entry `pa < i` in an earlier turn.
                let (wp, op) =
                    unsafe { (world_rot[pa].assume_init_ref(), world_pos[pa].assume_init()) };
                (mat_mul(wp, &r), add(op, mul(wp, p)))
            }
            None => (r, p),
        };
        world_rot[i].write(w);
        world_pos[i].write(o);
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
        let own = Rigid {
            m: bodies[i].mass,
            h: bodies[i].first_moment,
            i: bodies[i].inertia,
        };
        composite[i].write(own.in_parent(&w, o));
    }
    // SAFETY: the loop above wrote every entry, and `MaybeUninit<Rigid<T>>` has
    // `Rigid<T>`'s layout, arrays of them alike.
    let composite = unsafe { &mut *composite.as_mut_ptr().cast::<[Rigid<T>; B]>() };
    // Inwards: in the world frame a composite is a sum, nothing to transform. A body's
    // is whole once the loop reaches it (its children come after it), so its joint's
    // force `I_c S` and the diagonal `Sᵀ I_c S` are taken there, before the composite
    // is added to the parent's.
    for i in (0..B).rev() {
        let c = composite[i];
        if let Some(ci) = nodes[i].joint.coordinate() {
            let s = subspace[ci];
            let f = c.times(s);
            diagonal[ci] = s.dot(f);
            force[ci] = f;
        }
        if let Some(pa) = nodes[i].parent {
            composite[pa] = composite[pa].plus(&c);
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
