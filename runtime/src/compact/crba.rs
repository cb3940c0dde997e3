//! The mass matrix of a compact tree by the composite-rigid-body algorithm
//! (Featherstone, *Rigid Body Dynamics Algorithms*, §6.2), in the world frame: each
//! body's inertia and joint motion subspace `S` are written there once; the composite
//! inertias are then plain sums inwards, each joint's force `I_c S` is taken from its
//! composite, and the entries of `M` are dot products `S_jᵀ I_c S_i`.
//!
//! Only the bodies' frames and the composites' sums need the tree's order. Turning each
//! body's inertia into the world and each joint's force out of its composite are
//! independent from body to body, so those loops run over arrays kept component by
//! component (a structure of arrays, [`Columns`](super::columns::Columns)), which the compiler turns into vector
//! instructions over several bodies at once.

use super::algebra::{M3, Rigid, Spatial, add, cross, mat_mul, mul};
use super::columns::{Columns, get};
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
    let mut comp = Columns::<T, B, 10>::new();
    let mut force = Columns::<T, B, 6>::new();
    let mut dsum = Columns::<T, B, 1>::new();
    let trig = T::sin_cos_n(*q);
    // Outwards, one body after another: each body's axes and origin in the world, and
    // its joint's motion subspace there.
    for i in 0..B {
        let (r, p) = placement(&bodies[i], nodes[i].joint, q, &trig);
        let (w, o) = match nodes[i].parent {
            Some(pa) => {
                assert!(pa < i, "a parent after its child in the table");
                // SAFETY: the loop wrote entry `pa < i` in an earlier turn.
                let (wp, op) = unsafe { (m3(rot.get(pa)), pos.get(pa)) };
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
    for i in 0..B {
        let own = Rigid {
            m: bodies[i].mass,
            h: bodies[i].first_moment,
            i: bodies[i].inertia,
        };
        let c = own.in_parent(&m3(get(rot, i)), get(pos, i));
        comp.set(
            i,
            [
                c.m, c.h[0], c.h[1], c.h[2], c.i[0], c.i[1], c.i[2], c.i[3], c.i[4], c.i[5],
            ],
        );
    }
    // SAFETY: the loop above wrote every body's entries.
    let comp = unsafe { comp.whole_mut() };
    // Inwards: in the world frame a composite is a sum, nothing to transform.
    for i in (0..B).rev() {
        if let Some(pa) = nodes[i].parent {
            for k in 0..10 {
                comp[k][pa] = comp[k][pa] + comp[k][i];
            }
        }
    }
    // Each joint's force `I_c S` and the diagonal `Sᵀ I_c S`: independent again.
    for i in 0..B {
        let c = get(comp, i);
        let c = Rigid {
            m: c[0],
            h: [c[1], c[2], c[3]],
            i: [c[4], c[5], c[6], c[7], c[8], c[9]],
        };
        let s = Spatial::of(get(subspace, i));
        let f = c.times(s);
        dsum.set(i, [s.dot(f)]);
        force.set(i, f.array());
    }
    // SAFETY: the loop above wrote every body's entries.
    let (force, diagonal) = unsafe { (force.whole(), &dsum.whole()[0]) };
    assemble(nodes, diagonal, subspace, force, pairs, out)
}

#[inline(always)]
fn m3<T: Copy>(x: [T; 9]) -> M3<T> {
    [[x[0], x[1], x[2]], [x[3], x[4], x[5]], [x[6], x[7], x[8]]]
}

#[inline(always)]
fn flat<T: Copy>(x: &M3<T>) -> [T; 9] {
    [
        x[0][0], x[0][1], x[0][2], x[1][0], x[1][1], x[1][2], x[2][0], x[2][1], x[2][2],
    ]
}

/// `M` from its diagonal (`diagonal[i]` that of body `i`'s joint) and, off it, one dot
/// product per pair of the constant table. The pairs of one joint are consecutive, and
/// its force is loaded once for them all. (Its own function, so that the matrix, zeroed
/// and filled here alone, is built in the caller's place rather than copied there;
/// `out` gives its entries the caller's scalar, `f64` for the fused twin's.)
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
        let f = get(force, pairs[k].row_body as usize);
        while k < pairs.len() && pairs[k].row as usize == ci {
            let cj = pairs[k].col as usize;
            let s = get(subspace, pairs[k].col_body as usize);
            // One chain of multiply–adds: fewer instructions than two sums of three.
            let x = out((1..6).fold(s[0] * f[0], |a, n| s[n].mul_add(f[n], a)));
            m[ci][cj] = x;
            m[cj][ci] = x;
            k += 1;
        }
    }
    m
}
