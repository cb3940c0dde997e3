//! The mass matrix of a compact tree by the composite-rigid-body algorithm
//! (Featherstone, *Rigid Body Dynamics Algorithms*, §6.2), in the world frame: each
//! body's inertia and joint motion subspace `S` are written there once; the composite
//! inertias are then plain sums inwards, each joint's force `I_c S` is taken from its
//! composite, and the entries of `M` are dot products `S_jᵀ I_c S_i`.
//!
//! Only the bodies' frames and the composites' sums need the tree's order. Turning each
//! body's inertia into the world and each joint's force out of its composite are
//! independent from body to body, so those loops run over arrays kept component by
//! component (a structure of arrays, `compact::columns`), which the compiler turns into
//! vector instructions over several bodies at once.

use super::algebra::{Rigid, Spatial, add, cross, dot6, flat, m3, mat_mul, mul};
use super::columns::{Columns, body};
use super::{Body, Joint, Node, Pair, placement};
use crate::real::Real;

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
    // Per body, component by component (structure of arrays), so that the loops whose
    // bodies are independent run over several bodies at once in vector registers.
    // Each is written for every body by the loop that makes it, before any read (not
    // zeroed first).
    let mut rot = Columns::<T, B, 9>::new();
    let mut pos = Columns::<T, B, 3>::new();
    let mut subspace = Columns::<T, B, 6>::new();
    let mut composite = Columns::<T, B, 10>::new();
    let mut force = Columns::<T, B, 6>::new();
    let mut diagonal = Columns::<T, B, 1>::new();
    let trig = T::sin_cos_n(*q);
    // Outwards, one body after another: each body's axes and origin in the world, and
    // its joint's motion subspace there.
    for i in 0..B {
        let (r, p) = placement(&bodies[i], nodes[i].joint, q, &trig);
        let (w, o) = match nodes[i].parent {
            Some(pa) => {
                assert!(pa < i, "a parent after its child in the table");
                // SAFETY: the loop wrote entry `pa < i` in an earlier turn.
                let (wp, op) = unsafe { (m3(rot.read(pa)), pos.read(pa)) };
                (mat_mul(&wp, &r), add(op, mul(&wp, p)))
            }
            None => (r, p),
        };
        rot.set(i, flat(&w));
        pos.set(i, o);
        let z = [w[0][2], w[1][2], w[2][2]];
        let s = match nodes[i].joint {
            Joint::Revolute(_) => Spatial {
                w: z,
                l: cross(o, z),
            },
            Joint::Prismatic(_) => Spatial { w: [zero; 3], l: z },
            Joint::Fixed => Spatial::zero(),
        };
        subspace.set(i, s.array());
    }
    // SAFETY: the loop above wrote every body's entries.
    let (rot, pos, subspace) = unsafe { (rot.whole(), pos.whole(), subspace.whole()) };
    // Every body's inertia in the world (about its origin): independent of the others'.
    for (i, b) in bodies.iter().enumerate() {
        let own = Rigid {
            m: b.mass,
            h: b.first_moment,
            i: b.inertia,
        };
        composite.set(i, own.in_parent(&m3(body(rot, i)), body(pos, i)).array());
    }
    // SAFETY: the loop above wrote every body's entries.
    let composite = unsafe { composite.whole_mut() };
    // Inwards: in the world frame a composite is a sum, nothing to transform.
    for i in (0..B).rev() {
        if let Some(pa) = nodes[i].parent {
            for c in composite.iter_mut() {
                c[pa] = c[pa] + c[i];
            }
        }
    }
    // Each joint's force `I_c S` and the diagonal `Sᵀ I_c S`: independent again.
    for i in 0..B {
        let s = Spatial::of(body(subspace, i));
        let f = Rigid::of(body(composite, i)).times(s);
        diagonal.set(i, [dot6(s.array(), f.array())]);
        force.set(i, f.array());
    }
    // SAFETY: the loop above wrote every body's entries.
    let (force, diagonal) = unsafe { (force.whole(), &diagonal.whole()[0]) };
    assemble(nodes, diagonal, subspace, force, pairs, out)
}

/// `M` from its diagonal (`diagonal[i]` that of body `i`'s joint, not read for a fixed
/// joint) and, off it, one dot product per pair of the constant table. The pairs of one
/// joint are consecutive, and its force is loaded once for them all. (Its own function,
/// so that the matrix, zeroed and filled here alone, is built in the caller's place
/// rather than copied there; `out` gives its entries the caller's scalar, `f64` for the
/// fused twin's.)
#[inline(always)]
fn assemble<T: Real, U: Copy, const B: usize, const N: usize>(
    nodes: &[Node; B],
    diagonal: &[T; B],
    subspace: &[[T; B]; 6],
    force: &[[T; B]; 6],
    pairs: &[Pair],
    out: impl Fn(T) -> U,
) -> [[U; N]; N] {
    let mut m = [[out(T::cst(0.0)); N]; N];
    for (node, d) in nodes.iter().zip(diagonal) {
        if let Some(k) = node.joint.coordinate() {
            m[k][k] = out(*d);
        }
    }
    let mut k = 0;
    while k < pairs.len() {
        let ci = pairs[k].row as usize;
        debug_assert_eq!(
            nodes[pairs[k].row_body as usize].joint.coordinate(),
            Some(ci),
            "a pair's body and coordinate disagree"
        );
        let f = body(force, pairs[k].row_body as usize);
        while k < pairs.len() && pairs[k].row as usize == ci {
            let cj = pairs[k].col as usize;
            debug_assert_eq!(
                nodes[pairs[k].col_body as usize].joint.coordinate(),
                Some(cj),
                "a pair's body and coordinate disagree"
            );
            let x = out(dot6(body(subspace, pairs[k].col_body as usize), f));
            m[ci][cj] = x;
            m[cj][ci] = x;
            k += 1;
        }
    }
    m
}
