//! Scenes with Lie-group joints (theory §2): a free body (S10), the same body held by
//! three revolute joints in Euler angles (for the gimbal-lock comparison), a satellite
//! with an arm, and a chain with a ball joint in the middle.

use filippov::Mechanism;

/// S10: a free rigid body, principal inertia `diag(i1, i2, i3)` about its centre of mass,
/// no gravity. Configuration `(x, y, z, w, qx, qy, qz)`, velocity `(ẋ, ẏ, ż, ω)` with `ω`
/// in the body frame.
#[derive(Mechanism, Clone, Copy, Debug, PartialEq)]
#[mechanism(emit = all)]
#[body(body, mass = m, inertia = diag(i1, i2, i3))]
#[joint(float: free, parent = world, child = body)]
pub struct FreeBody {
    pub m: f64,
    pub i1: f64,
    pub i2: f64,
    pub i3: f64,
}

impl Default for FreeBody {
    /// Theory S10: `I = diag(1, 2, 3)`, unit mass.
    fn default() -> Self {
        FreeBody {
            m: 1.0,
            i1: 1.0,
            i2: 2.0,
            i3: 3.0,
        }
    }
}

/// The rotational part of S10 on three revolute joints, `R = Rz(yaw) Ry(pitch) Rx(roll)`
/// (ZYX Euler angles, massless intermediate frames): singular at pitch = ±90°, where
/// the yaw and roll axes align.
// Clippy reads the two massless frames' `mass = 0.0` as one attribute repeated.
#[allow(clippy::duplicated_attributes)]
#[derive(Mechanism, Clone, Copy, Debug, PartialEq)]
#[mechanism(emit = all)]
#[body(yaw_frame, mass = 0.0)]
#[joint(yaw: revolute(z), parent = world, child = yaw_frame)]
#[body(pitch_frame, mass = 0.0)]
#[joint(pitch: revolute(y), parent = yaw_frame, child = pitch_frame)]
#[body(body, mass = 1.0, inertia = diag(i1, i2, i3))]
#[joint(roll: revolute(x), parent = pitch_frame, child = body)]
pub struct EulerBody {
    pub i1: f64,
    pub i2: f64,
    pub i3: f64,
}

impl Default for EulerBody {
    fn default() -> Self {
        EulerBody {
            i1: 1.0,
            i2: 2.0,
            i3: 3.0,
        }
    }
}

/// The rotational part of S10 on a spherical joint (a body turning about a fixed
/// point at its centre of mass): `I ω̇ + ω × I ω = τ`.
#[derive(Mechanism, Clone, Copy, Debug, PartialEq)]
#[mechanism(emit = all)]
#[body(body, mass = 1.0, inertia = diag(i1, i2, i3))]
#[joint(ball: spherical, parent = world, child = body)]
pub struct SphericalBody {
    pub i1: f64,
    pub i2: f64,
    pub i3: f64,
}

impl Default for SphericalBody {
    fn default() -> Self {
        SphericalBody {
            i1: 1.0,
            i2: 2.0,
            i3: 3.0,
        }
    }
}

/// A satellite (free base, a box) carrying a two-link arm on revolute joints, the
/// shoulder off the base's centre; no gravity, so linear and angular momentum are
/// conserved.
#[derive(Mechanism, Clone, Copy, Debug, PartialEq)]
#[mechanism(emit = all)]
#[body(base, mass = m0, com = [0.0, 0.0, 0.0], inertia = cuboid(m0, 1.0, 0.8, 0.6))]
#[joint(float: free, parent = world, child = base)]
#[body(upper, mass = m1, com = [l1 / 2.0, 0.0, 0.0], inertia = rod(m1, l1))]
#[joint(shoulder: revolute(z), parent = base, child = upper, origin = [0.5, 0.1, 0.2])]
#[body(fore, mass = m2, com = [l2 / 2.0, 0.0, 0.0], inertia = rod(m2, l2))]
#[joint(elbow: revolute(y), parent = upper, child = fore, origin = [l1, 0.0, 0.0])]
pub struct Satellite {
    pub m0: f64,
    pub m1: f64,
    pub l1: f64,
    pub m2: f64,
    pub l2: f64,
}

impl Default for Satellite {
    fn default() -> Self {
        Satellite {
            m0: 20.0,
            m1: 2.0,
            l1: 0.8,
            m2: 1.5,
            l2: 0.6,
        }
    }
}

/// A pendulum chain under gravity with a ball joint in the middle: a hinge, a spherical
/// joint, a hinge with a spring, off-centre masses and oblique origins.
#[derive(Mechanism, Clone, Copy, Debug, PartialEq)]
#[mechanism(emit = all, gravity = [0.0, 0.0, -g])]
#[body(upper, mass = m, com = [0.0, 0.0, -l / 2.0], inertia = cuboid(m, 0.1, 0.08, l))]
#[joint(hip: revolute(y), parent = world, child = upper)]
#[body(middle, mass = m, com = [0.02, 0.0, -l / 2.0], inertia = cuboid(m, 0.1, 0.12, l))]
#[joint(ball: spherical, parent = upper, child = middle, origin = [0.0, 0.05, -l], rpy = [0.2, 0.0, 0.3])]
#[body(lower, mass = m / 2.0, com = [0.0, 0.01, -l / 2.0], inertia = cuboid(m / 2.0, 0.06, 0.06, l))]
#[joint(knee: revolute(x), parent = middle, child = lower, origin = [0.0, 0.0, -l])]
#[spring(knee, k = k, rest = 0.2)]
pub struct BallChain {
    pub m: f64,
    pub l: f64,
    pub g: f64,
    pub k: f64,
}

impl Default for BallChain {
    fn default() -> Self {
        BallChain {
            m: 1.0,
            l: 0.5,
            g: 9.81,
            k: 3.0,
        }
    }
}
