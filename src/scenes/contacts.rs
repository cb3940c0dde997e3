use filippov::Mechanism;

/// A box in the x–y plane on the ground, which is tilted by `phi` about z (0: level; an
/// incline rising along +x for `phi > 0`): the box slides (`x`, `y` along the world
/// axes) and turns (`angle`), and touches the ground at its two bottom corners, each a
/// contact with Coulomb friction `mu` and restitution `e` (theory §8). Half-width `a`,
/// half-height `b`.
#[derive(Mechanism, Clone, Copy, Debug, PartialEq)]
#[mechanism(gravity = [0.0, -g, 0.0])]
#[body(slider_x, mass = 0.0)]
#[joint(x: prismatic(x), parent = world, child = slider_x)]
#[body(slider_y, mass = 0.0)]
#[joint(y: prismatic(y), parent = slider_x, child = slider_y)]
#[body(block, mass = m, inertia = cuboid(m, 2.0 * a, 2.0 * b, 0.1))]
#[joint(angle: revolute(z), parent = slider_y, child = block)]
#[contact(rear: point, body = block, at = [-a, -b, 0.0], plane = world, rpy = [0.0, 0.0, phi],
          normal = y, mu = mu, restitution = e)]
#[contact(front: point, body = block, at = [a, -b, 0.0], plane = world, rpy = [0.0, 0.0, phi],
          normal = y, mu = mu, restitution = e)]
pub struct SlidingBox {
    pub m: f64,
    pub a: f64,
    pub b: f64,
    pub mu: f64,
    pub e: f64,
    pub phi: f64,
    pub g: f64,
}

impl Default for SlidingBox {
    /// A 1 kg box, 0.4 m × 0.2 m, on level ground, `μ = 0.5`, no bounce.
    fn default() -> Self {
        SlidingBox {
            m: 1.0,
            a: 0.2,
            b: 0.1,
            mu: 0.5,
            e: 0.0,
            phi: 0.0,
            g: 9.81,
        }
    }
}

/// A ball of radius `r` in the x–y plane (`x`, `y`, `spin` about z) above level ground,
/// touching it with Coulomb friction `mu` and restitution `e`: dropped spinning, it
/// slips until it rolls (theory §8).
#[derive(Mechanism, Clone, Copy, Debug, PartialEq)]
#[mechanism(gravity = [0.0, -g, 0.0])]
#[body(slider_x, mass = 0.0)]
#[joint(x: prismatic(x), parent = world, child = slider_x)]
#[body(slider_y, mass = 0.0)]
#[joint(y: prismatic(y), parent = slider_x, child = slider_y)]
#[body(ball, mass = m, inertia = sphere(m, r))]
#[joint(spin: revolute(z), parent = slider_y, child = ball)]
#[contact(bottom: sphere(r), body = ball, plane = world, normal = y, mu = mu, restitution = e)]
pub struct SpinningBall {
    pub m: f64,
    pub r: f64,
    pub mu: f64,
    pub e: f64,
    pub g: f64,
}

impl Default for SpinningBall {
    /// A 1 kg ball of radius 0.1 m, `μ = 0.3`, `e = 0.5`.
    fn default() -> Self {
        SpinningBall {
            m: 1.0,
            r: 0.1,
            mu: 0.3,
            e: 0.5,
            g: 9.81,
        }
    }
}
