use filippov::Mechanism;

/// A small branched tree in 3D: a turntable carrying two branches, one with a hinge and
/// a slider, the other tilted by a roll-pitch-yaw origin with a hinge and a rigidly
/// attached tip mass (fixed joint).
#[derive(Mechanism, Clone, Copy, Debug, PartialEq)]
#[mechanism(emit = all, gravity = [0.0, 0.0, -9.81], inputs = [turn, slide])]
#[body(base, mass = 2.0, com = [0.0, 0.0, 0.1], inertia = cylinder(2.0, 0.2, 0.2))]
#[joint(turn: revolute(z), parent = world, child = base)]
#[body(left, mass = m, com = [0.0, 0.0, l / 2.0], inertia = cuboid(m, 0.05, 0.05, l))]
#[joint(tilt: revolute(y), parent = base, child = left, origin = [0.1, 0.0, 0.2])]
#[body(slider, mass = m / 2.0, com = [0.0, 0.0, 0.0], inertia = sphere(m / 2.0, 0.05))]
#[joint(slide: prismatic(z), parent = left, child = slider, origin = [0.0, 0.0, l])]
#[body(right, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[joint(swing: revolute([0.0, 0.6, 0.8]), parent = base, child = right, origin = [-0.1, 0.0, 0.2], rpy = [0.3, -0.2, PI / 4.0])]
#[body(tip, mass = 0.3, com = [0.0, 0.0, 0.0], inertia = sphere(0.3, 0.04))]
#[joint(weld: fixed, parent = right, child = tip, origin = [l, 0.0, 0.0])]
#[spring(slide, k = k, rest = 0.1)]
pub struct BranchedTree {
    pub m: f64,
    pub l: f64,
    pub k: f64,
}

impl Default for BranchedTree {
    fn default() -> Self {
        BranchedTree {
            m: 1.0,
            l: 0.4,
            k: 50.0,
        }
    }
}
