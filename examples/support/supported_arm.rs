//! The arm resting on a spring-backed limit with a stiff support, shared by
//! `tests/resting.rs` and the report's resting table: three links in a vertical plane,
//! the shoulder on a lower limit backed by a spring of stiffness `ks`, Coulomb friction
//! `fc` on the elbow, the wrist free.

use filippov::nalgebra::SVector;
use filippov::{Gravity, Mechanism};

pub type V3 = SVector<f64, 3>;

#[derive(Mechanism, Clone, Copy)]
#[mechanism(emit = [energy, gravity], gravity = [0.0, -9.81, 0.0])]
#[body(upper, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[joint(shoulder: revolute(z), parent = world, child = upper)]
#[body(fore, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[joint(elbow: revolute(z), parent = upper, child = fore, origin = [l, 0.0, 0.0])]
#[body(hand, mass = m / 2.0, com = [l / 4.0, 0.0, 0.0], inertia = rod(m / 2.0, l / 2.0))]
#[joint(wrist: revolute(z), parent = fore, child = hand, origin = [l, 0.0, 0.0])]
#[friction(elbow, f_crit = fc)]
#[stop(shoulder, min = lim, k_support = ks)]
pub struct SupportedArm {
    pub m: f64,
    pub l: f64,
    pub fc: f64,
    pub lim: f64,
    pub ks: f64,
}

impl SupportedArm {
    /// The arm with unit mass, half-metre links, its limit at −0.5 rad, elbow
    /// friction `fc` and support stiffness `ks`.
    pub fn new(fc: f64, ks: f64) -> Self {
        SupportedArm {
            m: 1.0,
            l: 0.5,
            fc,
            lim: -0.5,
            ks,
        }
    }

    /// The static start on the support: the elbow at 0.3 rad, the hand hanging turned
    /// by `wrist` from the vertical, the shoulder at the support's static compression
    /// under gravity (fixed point, 50 iterations).
    pub fn static_start(&self, wrist: f64) -> V3 {
        let mut q0 = V3::new(self.lim, 0.3, 0.0);
        for _ in 0..50 {
            q0[2] = -std::f64::consts::FRAC_PI_2 - q0[0] - q0[1] + wrist;
            q0[0] = self.lim - self.gravity(&q0)[0] / self.ks;
        }
        q0
    }
}

/// No applied force.
pub fn zero(_t: f64, _q: &V3, _v: &V3) -> V3 {
    V3::zeros()
}
