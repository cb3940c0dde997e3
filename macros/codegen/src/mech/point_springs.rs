//! The potential of the springs between two points (`#[spring(name: between(a, b), …)]`):
//! `U = Σ ½ k (ℓ − rest)²`, `ℓ = |p_b − p_a|` with the points carried to the world by
//! their links' poses. Its generalised forces `−∂U/∂q` join the passive forces, so that
//! forward and inverse dynamics, their Jacobians and the energy all see the spring.

use super::frames::world_poses;
use super::kinematics::{Kinematics, lower3};
use super::spatial::{add3, dot3, mat_vec, sub3};
use crate::model::Model;
use crate::sym::{Graph, Id};

/// `U`, or `None` for a scene without point springs.
pub fn potential(g: &mut Graph, model: &Model, kin: &Kinematics) -> Option<Id> {
    if model.point_springs.is_empty() {
        return None;
    }
    let (rot, pos) = world_poses(g, model, kin);
    let mut total = g.zero();
    for s in &model.point_springs {
        let world = |g: &mut Graph, end: &(Option<usize>, crate::model::Vec3)| {
            let local = lower3(g, &end.1);
            match end.0 {
                Some(l) => {
                    let r = mat_vec(g, &rot[l], local);
                    add3(g, pos[l], r)
                }
                None => local,
            }
        };
        let (pa, pb) = (world(g, &s.a), world(g, &s.b));
        let d = sub3(g, pb, pa);
        let dd = dot3(g, d, d);
        let length = g.unary(crate::sym::Unary::Sqrt, dd);
        let rest = s.rest.lower(g);
        let stretch = g.sub(length, rest);
        let k = s.k.lower(g);
        let half = g.constant(0.5);
        let e = g.mul(stretch, stretch);
        let e = g.mul(k, e);
        let e = g.mul(half, e);
        total = g.add(total, e);
    }
    Some(total)
}
