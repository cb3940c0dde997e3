//! Compact kernels for large trees: one loop over the bodies, their geometry a table.
//!
//! Fully unrolled code is the fastest a small robot can get, but its size grows with
//! the number of operations, and past the instruction cache (32 KiB of L1i on common
//! x86 cores) a kernel spends its time fetching itself. For such trees the derive emits
//! a table of the bodies' constants instead ([`Body`], [`Node`]) and calls the loops
//! here, which are small enough to stay in the cache whatever the tree's size
//! (`#[mechanism(forward_dynamics = compact)]`, or `auto` past a size; see the guide).
//!
//! Every body's frame is *aligned with its joint* when the derive builds the table: the
//! joint turns about, or slides along, the body frame's `z` axis, so the motion subspace
//! is a unit vector and the joint's rotation `Rz(q)` costs one `sin_cos` and a handful
//! of products, whatever the URDF's axis. The link's own frame is a constant rotation
//! away and never appears at run time.
//!
//! - [`algebra`]: 3-vectors, 3×3 blocks, rigid and articulated inertias on any [`Real`];
//! - `columns` (crate-private): values kept per body component by component, for the
//!   loops over independent bodies that run several at once in vector registers;
//! - [`aba`]: forward dynamics by the articulated-body algorithm;
//! - [`crba`]: the mass matrix by the composite-rigid-body algorithm, its entries off the
//!   diagonal from the tree's constant table of [`pairs`];
//! - [`jacobian`]: its Jacobian with respect to `(q, v)`, by dual numbers through it;
//! - [`fused`]: the forward dynamics and mass matrix with fused multiply–adds on `f64`
//!   and on four lanes of states, for processors with AVX2 and FMA.

pub mod aba;
pub mod algebra;
pub(crate) mod columns;
pub mod crba;
pub mod fused;
pub mod jacobian;

use crate::real::Real;
use algebra::{M3, V3, add, turn_z};

/// How a body moves relative to its parent, along its own frame's `z` axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Joint {
    /// Turns about `z` by coordinate `.0`.
    Revolute(usize),
    /// Slides along `z` by coordinate `.0`.
    Prismatic(usize),
    /// Welded to its parent.
    Fixed,
}

impl Joint {
    /// The joint's coordinate (`None` for a fixed joint).
    pub const fn coordinate(self) -> Option<usize> {
        match self {
            Joint::Revolute(k) | Joint::Prismatic(k) => Some(k),
            Joint::Fixed => None,
        }
    }
}

/// A body's place in the tree: its parent (`None`: the world) and its joint. Parents
/// come before their children in a tree's table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Node {
    pub parent: Option<usize>,
    pub joint: Joint,
}

/// A body's constants, in its joint-aligned frame: where its joint sits on the parent
/// and its inertia.
///
/// The body frame is `parent · Trans(translation) · Rot(rotation) · J(q)`, `J` the
/// joint's motion along `z`.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct Body<T> {
    /// The joint frame's axes in the parent's frame (columns), row-major.
    pub rotation: [[T; 3]; 3],
    /// The joint frame's origin in the parent's frame.
    pub translation: [T; 3],
    pub mass: T,
    /// `h = m c`, `c` the centre of mass in the body frame.
    pub first_moment: [T; 3],
    /// Rotational inertia about the body frame's origin: `[xx, yy, zz, xy, xz, yz]`.
    pub inertia: [T; 6],
}

impl<T: Copy> Body<T> {
    /// The same table with `f` applied to every entry.
    pub fn map<U>(&self, f: impl Fn(T) -> U) -> Body<U> {
        Body {
            rotation: self.rotation.map(|r| r.map(&f)),
            translation: self.translation.map(&f),
            mass: f(self.mass),
            first_moment: self.first_moment.map(&f),
            inertia: self.inertia.map(&f),
        }
    }
}

impl Body<f64> {
    /// The same constants in another scalar.
    pub fn lift<T: Real>(&self) -> Body<T> {
        self.map(T::cst)
    }
}

/// An entry `M[row][col]` off the mass matrix's diagonal that a tree can make nonzero:
/// `col` the coordinate of a joint between `row`'s joint and the root (and `M[col][row]`
/// its mirror); `row_body` and `col_body` the bodies the two joints move, where the
/// kernel keeps their terms. The entries of two joints on different branches are zero.
/// (`u16` indices: a compact tree has at most 65,535 bodies, which [`pairs`] asserts.)
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Pair {
    pub row: u16,
    pub col: u16,
    pub row_body: u16,
    pub col_body: u16,
}

/// How many [`Pair`]s the tree `nodes` has: over its joints, the jointed bodies between
/// each and the root.
pub const fn pair_count<const B: usize>(nodes: &[Node; B]) -> usize {
    fill_pairs(nodes, &mut [])
}

/// The [`Pair`]s of the tree `nodes`, body by body and each body's from its parent
/// towards the root: the constant table that lets the mass matrix's off-diagonal loop
/// run without walking the tree. `P` must be [`pair_count`]: evaluated in a `const`, a
/// wrong `P` is a compile error.
pub const fn pairs<const B: usize, const P: usize>(nodes: &[Node; B]) -> [Pair; P] {
    let mut out = [Pair {
        row: 0,
        col: 0,
        row_body: 0,
        col_body: 0,
    }; P];
    assert!(
        B <= u16::MAX as usize,
        "a compact tree has at most 65,535 bodies"
    );
    let n = fill_pairs(nodes, &mut out);
    assert!(n == P, "`P` must be `pair_count(nodes)`");
    out
}

/// Writes the tree's pairs into `out` as far as it reaches; returns how many there are.
const fn fill_pairs<const B: usize>(nodes: &[Node; B], out: &mut [Pair]) -> usize {
    let mut n = 0;
    let mut i = 0;
    while i < B {
        if let Some(ci) = nodes[i].joint.coordinate() {
            let mut j = i;
            while let Some(pa) = nodes[j].parent {
                j = pa;
                if let Some(cj) = nodes[j].joint.coordinate() {
                    if n < out.len() {
                        assert!(
                            i <= u16::MAX as usize
                                && ci <= u16::MAX as usize
                                && cj <= u16::MAX as usize,
                            "a compact tree has at most 65,535 bodies and coordinates"
                        );
                        out[n] = Pair {
                            row: ci as u16,
                            col: cj as u16,
                            row_body: i as u16,
                            col_body: j as u16,
                        };
                    }
                    n += 1;
                }
            }
        }
        i += 1;
    }
    n
}

/// A body's transform from its parent: its axes `R` in the parent's frame and its
/// origin `p` there. `trig` holds `(sin q, cos q)` of every coordinate
/// ([`Real::sin_cos_n`], taken once per call of a kernel).
#[inline(always)]
pub fn placement<T: Real, const N: usize>(
    body: &Body<T>,
    joint: Joint,
    q: &[T; N],
    trig: &([T; N], [T; N]),
) -> (M3<T>, V3<T>) {
    match joint {
        Joint::Revolute(k) => (
            turn_z(&body.rotation, trig.0[k], trig.1[k]),
            body.translation,
        ),
        Joint::Prismatic(k) => {
            let r = &body.rotation;
            let z = [r[0][2], r[1][2], r[2][2]];
            (
                *r,
                add(body.translation, [z[0] * q[k], z[1] * q[k], z[2] * q[k]]),
            )
        }
        Joint::Fixed => (body.rotation, body.translation),
    }
}

#[cfg(test)]
mod tests {
    use super::{Joint, Node, Pair, fill_pairs, pair_count, pairs};
    use std::collections::BTreeSet;

    /// A random tree of `B` bodies, parents before children, some joints fixed, the
    /// coordinates numbered in a shuffled order.
    fn tree<const B: usize>(seed: u64) -> [Node; B] {
        let mut s = seed;
        let mut next = move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            s
        };
        let kinds: Vec<u64> = (0..B).map(|_| next() % 5).collect();
        let jointed = kinds.iter().filter(|&&k| k != 0).count();
        let mut coords: Vec<usize> = (0..jointed).collect();
        for i in (1..jointed).rev() {
            coords.swap(i, (next() % (i as u64 + 1)) as usize);
        }
        let mut c = coords.into_iter();
        std::array::from_fn(|i| Node {
            parent: if i == 0 || next() % 7 == 0 {
                None
            } else {
                Some((next() % i as u64) as usize)
            },
            joint: match kinds[i] {
                0 => Joint::Fixed,
                1 => Joint::Prismatic(c.next().unwrap()),
                _ => Joint::Revolute(c.next().unwrap()),
            },
        })
    }

    /// The tree's pairs in a vector, by `fill_pairs`.
    fn table<const B: usize>(nodes: &[Node; B]) -> Vec<Pair> {
        let zero = Pair {
            row: 0,
            col: 0,
            row_body: 0,
            col_body: 0,
        };
        let mut table = vec![zero; pair_count(nodes)];
        let n = fill_pairs(nodes, &mut table);
        assert_eq!(n, table.len());
        table
    }

    /// The pairs from each body's set of ancestors, built outwards (a different route
    /// from `pairs`' walk towards the root).
    fn by_ancestor_sets<const B: usize>(nodes: &[Node; B]) -> BTreeSet<(usize, usize)> {
        let mut ancestors: Vec<BTreeSet<usize>> = Vec::new();
        for n in nodes {
            let mut a = BTreeSet::new();
            if let Some(p) = n.parent {
                a = ancestors[p].clone();
                a.insert(p);
            }
            ancestors.push(a);
        }
        let mut out = BTreeSet::new();
        for (i, n) in nodes.iter().enumerate() {
            for &j in &ancestors[i] {
                if let (Some(ci), Some(cj)) = (n.joint.coordinate(), nodes[j].joint.coordinate()) {
                    out.insert((ci, cj));
                }
            }
        }
        out
    }

    #[test]
    fn pairs_are_each_joint_against_its_ancestors() {
        for seed in 1..300u64 {
            let nodes = tree::<24>(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15));
            let expected = by_ancestor_sets(&nodes);
            let n = pair_count(&nodes);
            assert_eq!(n, expected.len(), "seed {seed}");
            let table = table(&nodes);
            assert_eq!(table.len(), n);
            for p in &table {
                let coordinate = |b: u16| nodes[b as usize].joint.coordinate();
                assert_eq!(coordinate(p.row_body), Some(p.row as usize), "seed {seed}");
                assert_eq!(coordinate(p.col_body), Some(p.col as usize), "seed {seed}");
            }
            let got: BTreeSet<(usize, usize)> = table
                .iter()
                .map(|p| (p.row as usize, p.col as usize))
                .collect();
            assert_eq!(got.len(), n, "seed {seed}: no pair twice");
            assert_eq!(got, expected, "seed {seed}");
        }
    }

    /// The mass matrix (composite-rigid-body algorithm) times the forward dynamics'
    /// response to a unit torque (the articulated-body algorithm, with no velocity and no
    /// gravity) is that unit vector: two algorithms on 20 random trees of 24 bodies
    /// (several roots, fixed joints, shuffled coordinates, oblique frames).
    #[test]
    fn mass_matrix_inverts_the_forward_dynamics_on_random_trees() {
        use super::{Body, aba, crba};
        use crate::geometry::so3::UnitQuat;
        const B: usize = 24;
        const N: usize = 19;
        let mut found = 0;
        for seed in 1..5000u64 {
            let nodes = tree::<B>(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15));
            if nodes
                .iter()
                .filter(|n| n.joint.coordinate().is_some())
                .count()
                != N
            {
                continue;
            }
            let mut s = seed ^ 0xD1B5_4A32_D192_ED03;
            let mut unit = move || {
                s ^= s << 13;
                s ^= s >> 7;
                s ^= s << 17;
                (s >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
            };
            let bodies: [Body<f64>; B] = std::array::from_fn(|_| {
                let r = UnitQuat::try_new(unit(), unit(), unit(), unit())
                    .expect("a random quaternion")
                    .to_matrix();
                let rotation = std::array::from_fn(|i| std::array::from_fn(|j| r[(i, j)]));
                let m = 1.25 + 0.75 * unit();
                let c = [0.2 * unit(), 0.2 * unit(), 0.2 * unit()];
                let own = [
                    0.055 + 0.045 * unit(),
                    0.055 + 0.045 * unit(),
                    0.055 + 0.045 * unit(),
                ];
                Body {
                    rotation,
                    translation: [0.5 * unit(), 0.5 * unit(), 0.5 * unit()],
                    mass: m,
                    first_moment: [m * c[0], m * c[1], m * c[2]],
                    // About the body's origin: the parallel-axis theorem.
                    inertia: [
                        own[0] + m * (c[1] * c[1] + c[2] * c[2]),
                        own[1] + m * (c[0] * c[0] + c[2] * c[2]),
                        own[2] + m * (c[0] * c[0] + c[1] * c[1]),
                        -m * c[0] * c[1],
                        -m * c[0] * c[2],
                        -m * c[1] * c[2],
                    ],
                }
            });
            let table = table(&nodes);
            let q: [f64; N] = std::array::from_fn(|_| 3.0 * unit());
            let m = crba::mass_matrix(&nodes, &table, &bodies, &q);
            let big = m.iter().flatten().fold(0.0f64, |a, x| a.max(x.abs()));
            for j in 0..N {
                let mut tau = [0.0; N];
                tau[j] = 1.0;
                let x = aba::forward_dynamics(&nodes, &bodies, [0.0; 3], &q, &[0.0; N], &tau);
                let size = x.iter().fold(0.0f64, |a, x| a.max(x.abs()));
                for (i, row) in m.iter().enumerate() {
                    assert_eq!(row[j], m[j][i], "seed {seed}: M symmetric");
                    let mx: f64 = row.iter().zip(&x).map(|(a, b)| a * b).sum();
                    let want = if i == j { 1.0 } else { 0.0 };
                    assert!(
                        (mx - want).abs() <= 1e-11 * big * size * N as f64,
                        "seed {seed}: (M M⁻¹)[{i}][{j}] = {mx}"
                    );
                }
            }
            found += 1;
            if found == 20 {
                break;
            }
        }
        assert_eq!(found, 20, "not enough trees with {N} joints");
    }

    /// The loops read a parent's entries only after writing them, which needs parents
    /// before children: a table that breaks the order is refused with a panic.
    #[test]
    fn a_parent_after_its_child_is_refused() {
        use super::{Body, aba, crba};
        let body = Body {
            rotation: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            translation: [0.0, 0.0, 0.5],
            mass: 1.0,
            first_moment: [0.0, 0.0, 0.2],
            inertia: [0.1, 0.1, 0.05, 0.0, 0.0, 0.0],
        };
        let bad = [
            Node {
                parent: Some(1),
                joint: Joint::Revolute(0),
            },
            Node {
                parent: None,
                joint: Joint::Revolute(1),
            },
        ];
        let good = [
            bad[1],
            Node {
                parent: Some(0),
                ..bad[0]
            },
        ];
        let (q, v, tau): ([f64; 2], [f64; 2], [f64; 2]) = ([0.3, -0.2], [0.1, 0.4], [0.0, 0.0]);
        let g = [0.0, 0.0, -9.81];
        assert!(
            aba::forward_dynamics(&good, &[body; 2], g, &q, &v, &tau)
                .iter()
                .all(|x: &f64| x.is_finite())
        );
        let fd =
            std::panic::catch_unwind(|| aba::forward_dynamics(&bad, &[body; 2], g, &q, &v, &tau));
        assert!(fd.is_err());
        let m = std::panic::catch_unwind(|| crba::mass_matrix(&bad, &[], &[body; 2], &q));
        assert!(m.is_err());
    }

    #[test]
    fn a_wrong_count_is_refused() {
        // Three revolute joints in a chain: pairs (1, 0), (2, 1), (2, 0).
        let chain = [
            Node {
                parent: None,
                joint: Joint::Revolute(0),
            },
            Node {
                parent: Some(0),
                joint: Joint::Revolute(1),
            },
            Node {
                parent: Some(1),
                joint: Joint::Revolute(2),
            },
        ];
        let table = pairs::<3, 3>(&chain);
        assert_eq!(
            table[0],
            Pair {
                row: 1,
                col: 0,
                row_body: 1,
                col_body: 0
            }
        );
        assert!(std::panic::catch_unwind(|| pairs::<3, 2>(&chain)).is_err());
        assert!(std::panic::catch_unwind(|| pairs::<3, 4>(&chain)).is_err());
    }
}
