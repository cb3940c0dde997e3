//! An arm that comes to rest on its joint limit: two links in a vertical plane, a lower
//! limit `lim` with restitution `e` on the shoulder, which gravity presses the arm onto,
//! and Coulomb friction `fc` on the elbow. The `ensemble` example sweeps its friction
//! and restitution.

use crate::Mechanism;

/// The README's arm with its limit, friction and restitution as parameters.
#[derive(Mechanism, Clone, Copy)]
#[mechanism(gravity = [0.0, -9.81, 0.0])]
#[body(upper, mass = m1, com = [l1 / 2.0, 0.0, 0.0], inertia = rod(m1, l1))]
#[joint(shoulder: revolute(z), parent = world, child = upper)]
#[body(lower, mass = m2, com = [l2 / 2.0, 0.0, 0.0], inertia = rod(m2, l2))]
#[joint(elbow: revolute(z), parent = upper, child = lower, origin = [l1, 0.0, 0.0])]
#[friction(elbow, f_crit = fc)]
#[stop(shoulder, min = lim, restitution = e)]
pub struct RestingArm {
    pub m1: f64,
    pub l1: f64,
    pub m2: f64,
    pub l2: f64,
    pub fc: f64,
    pub lim: f64,
    pub e: f64,
}
