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
//! - [`algebra`]: 3-vectors, 3×3 blocks and articulated inertias on any [`Real`];
//! - [`aba`]: forward dynamics by the articulated-body algorithm;
//! - [`crba`]: the mass matrix by the composite-rigid-body algorithm;
//! - [`jacobian`]: its Jacobian with respect to `(q, v)`, by dual numbers through it;
//! - [`fused`]: the forward dynamics and mass matrix on `f64` with fused multiply–adds,
//!   for processors with AVX2 and FMA.

pub mod aba;
pub mod algebra;
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
    pub fn coordinate(self) -> Option<usize> {
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
