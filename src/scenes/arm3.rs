use filippov::Mechanism;

/// A planar three-link arm (rods) under gravity, with a torsional spring and a viscous
/// damper in every joint.
#[derive(Mechanism, Clone, Copy, Debug, PartialEq)]
#[mechanism(emit = all, gravity = [0.0, -9.81, 0.0])]
#[body(link1, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[joint(j1: revolute(z), parent = world, child = link1)]
#[body(link2, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[joint(j2: revolute(z), parent = link1, child = link2, origin = [l, 0.0, 0.0])]
#[body(link3, mass = m / 2.0, com = [l / 4.0, 0.0, 0.0], inertia = rod(m / 2.0, l / 2.0))]
#[joint(j3: revolute(z), parent = link2, child = link3, origin = [l, 0.0, 0.0])]
#[spring(j1, k = k, rest = 0.0)]
#[spring(j2, k = k, rest = 0.0)]
#[spring(j3, k = k, rest = 0.0)]
#[damper(j1, c = c)]
#[damper(j2, c = c)]
#[damper(j3, c = c)]
pub struct PlanarArm3 {
    pub m: f64,
    pub l: f64,
    pub k: f64,
    pub c: f64,
}

impl Default for PlanarArm3 {
    fn default() -> Self {
        PlanarArm3 {
            m: 1.0,
            l: 0.5,
            k: 2.0,
            c: 0.1,
        }
    }
}
