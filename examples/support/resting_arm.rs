//! The arm that comes to rest on its joint limit, shared by `tests/resting.rs` and the
//! `ensemble` example: two links in a vertical plane, a lower limit with restitution `e`
//! on the shoulder, which gravity presses the arm onto, and Coulomb friction `fc` on the
//! elbow.

use filippov::Mechanism;
use filippov::nalgebra::SVector;

pub type V2 = SVector<f64, 2>;

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

/// No applied force.
pub fn zero(_t: f64, _q: &V2, _v: &V2) -> V2 {
    V2::zeros()
}
