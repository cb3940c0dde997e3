//! Local exponential coordinates (theory §2): the derivative of an expression along each
//! velocity coordinate, `∂/∂φ_k`.
//!
//! On a revolute or prismatic coordinate it is the ordinary `∂/∂q_k`. On component `a`
//! of a rotation with quaternion `r` it is the derivative along `r · exp(t ê_a)` at
//! `t = 0`: the quaternion moves with `ṙ = ½ r ⊗ (0, ê_a)`, so by the chain rule
//! `∂f/∂φ_a = Σ_m ∂f/∂r_m · (½ r ⊗ (0, ê_a))_m` — exact for unit `r`, and made of the
//! graph's ordinary derivatives.

use crate::model::{JointKind, Model};
use crate::sym::{Graph, Id, Input, InputKind};

/// What `∂/∂φ_k` differentiates along.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Direction {
    /// `∂/∂q` of configuration slot `slot`.
    Euclid { slot: usize },
    /// The body-frame rotation about axis `axis` of the quaternion at `slot..slot + 4`.
    Rotation { slot: usize, axis: usize },
}

/// One [`Direction`] per velocity coordinate.
pub struct Chart {
    pub directions: Vec<Direction>,
}

/// `(½ r ⊗ (0, ê_a))` as signed components of `r = (w, x, y, z)`: entry `m` is
/// `(sign, index into r)`.
const TANGENT: [[(f64, usize); 4]; 3] = [
    [(-0.5, 1), (0.5, 0), (0.5, 3), (-0.5, 2)],
    [(-0.5, 2), (-0.5, 3), (0.5, 0), (0.5, 1)],
    [(-0.5, 3), (0.5, 2), (-0.5, 1), (0.5, 0)],
];

impl Chart {
    pub fn new(model: &Model) -> Chart {
        let mut directions = vec![Direction::Euclid { slot: 0 }; model.dof()];
        for l in &model.links {
            let (Some(c), Some(s)) = (l.coordinate, l.config) else {
                continue;
            };
            for k in 0..l.kind.dof() {
                directions[c + k] = match l.kind {
                    JointKind::Spherical => Direction::Rotation { slot: s, axis: k },
                    _ => Direction::Euclid { slot: s + k },
                };
            }
        }
        Chart { directions }
    }

    /// `∂f/∂φ_k`.
    pub fn derivative(&self, g: &mut Graph, f: Id, k: usize) -> Id {
        let q = |slot: usize| Input {
            kind: InputKind::Q,
            index: slot as u16,
        };
        match self.directions[k] {
            Direction::Euclid { slot } => g.diff(f, q(slot)),
            Direction::Rotation { slot, axis } => {
                let mut out = g.zero();
                for (m, &(sign, r)) in TANGENT[axis].iter().enumerate() {
                    let d = g.diff(f, q(slot + m));
                    let rm = g.input(InputKind::Q, slot + r);
                    let k = g.constant(sign);
                    let t = g.mul(rm, d);
                    let t = g.mul(k, t);
                    out = g.add(out, t);
                }
                out
            }
        }
    }

    /// The rotation blocks: the first velocity coordinate of each rotation.
    pub fn rotations(&self) -> Vec<usize> {
        (0..self.directions.len())
            .filter(|&k| matches!(self.directions[k], Direction::Rotation { axis: 0, .. }))
            .collect()
    }
}
