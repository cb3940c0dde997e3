//! The load-dependent part of bearing friction's limit, `c |F_⊥|` (`c = μ` on a
//! prismatic joint, `μ r` on a revolute one): `F_⊥` is the linear force the joint
//! transmits to its child, from [`rnea_forces`] with gravity
//! as the base's acceleration, less its component along the axis. In link coordinates
//! with the unit axis `s`, `|F_⊥| = |s × f|`, a sum of squares (never negative by
//! rounding).

use super::kinematics::Kinematics;
use super::rnea::rnea_forces;
use super::spatial::{cross, dot3, v3_const};
use crate::model::{JointKind, Model};
use crate::sym::{Graph, Id, Unary};

/// One node per bearing, in the order of `model.elements`; empty where there is none.
pub fn bearing_limits(
    g: &mut Graph,
    model: &Model,
    kin: &Kinematics,
    gravity: Option<[Id; 3]>,
    v: &[Id],
    a: &[Id],
) -> Vec<Id> {
    if model.elements.iter().all(|e| e.bearing.is_none()) {
        return Vec::new();
    }
    let (_, force) = rnea_forces(g, model, kin, gravity, v, a);
    let mut out = Vec::new();
    for el in &model.elements {
        let Some(bearing) = &el.bearing else {
            continue;
        };
        let link = model
            .links
            .iter()
            .position(|l| l.coordinate == Some(el.coordinate))
            .expect("an element's coordinate belongs to a link");
        let axis = match model.links[link].kind {
            JointKind::Revolute(s) | JointKind::Prismatic(s) => s,
            _ => unreachable!("elements act on revolute and prismatic joints"),
        };
        let norm = axis.iter().map(|x| x * x).sum::<f64>().sqrt();
        let s = v3_const(g, axis.map(|x| x / norm));
        let across = cross(g, s, force[link].f);
        let squared = dot3(g, across, across);
        let load = g.unary(Unary::Sqrt, squared);
        let c = bearing.coefficient.lower(g);
        out.push(g.mul(c, load));
    }
    out
}
