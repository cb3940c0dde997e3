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

/// A puck (a point mass `m`) on a plane tilted by `phi` about the world x axis (rising
/// along +y for `phi > 0`), free to slide in both directions along it and to lift off
/// (`x`, `y`, `z` along the world axes): one spatial contact, friction on the isotropic
/// cone `mu`, restitution `e` (theory §8, "Spatial contacts").
#[derive(Mechanism, Clone, Copy, Debug, PartialEq)]
#[mechanism(gravity = [0.0, 0.0, -g])]
#[body(slider_x, mass = 0.0)]
#[joint(x: prismatic(x), parent = world, child = slider_x)]
#[body(slider_y, mass = 0.0)]
#[joint(y: prismatic(y), parent = slider_x, child = slider_y)]
#[body(puck, mass = m)]
#[joint(z: prismatic(z), parent = slider_y, child = puck)]
#[contact(bottom: point, body = puck, plane = world, rpy = [phi, 0.0, 0.0], normal = z,
          mu = mu, restitution = e)]
pub struct Puck {
    pub m: f64,
    pub mu: f64,
    pub e: f64,
    pub phi: f64,
    pub g: f64,
}

impl Default for Puck {
    /// A 1 kg puck on level ground, `μ = 0.4`, no bounce.
    fn default() -> Self {
        Puck {
            m: 1.0,
            mu: 0.4,
            e: 0.0,
            phi: 0.0,
            g: 9.81,
        }
    }
}

/// A three-legged table: a slab (mass `m`, side `2 a`, thickness `2 c`) standing on
/// three point legs at radius `r` around its centre and `d` below it, on ground tilted
/// by `phi` about the world x axis. Six coordinates: `x`, `y`, `z` of the centre, then
/// `yaw` (z), `pitch` (y), `roll` (x); three spatial contacts with friction `mu` and
/// restitution `e` (theory §8, "Spatial contacts").
#[derive(Mechanism, Clone, Copy, Debug, PartialEq)]
#[mechanism(gravity = [0.0, 0.0, -g])]
#[body(slider_x, mass = 0.0)]
#[joint(x: prismatic(x), parent = world, child = slider_x)]
#[body(slider_y, mass = 0.0)]
#[joint(y: prismatic(y), parent = slider_x, child = slider_y)]
#[body(slider_z, mass = 0.0)]
#[joint(z: prismatic(z), parent = slider_y, child = slider_z)]
#[body(yawed, mass = 0.0)]
#[joint(yaw: revolute(z), parent = slider_z, child = yawed)]
#[body(pitched, mass = 0.0)]
#[joint(pitch: revolute(y), parent = yawed, child = pitched)]
#[body(slab, mass = m, inertia = cuboid(m, 2.0 * a, 2.0 * a, 2.0 * c))]
#[joint(roll: revolute(x), parent = pitched, child = slab)]
#[contact(leg_a: point, body = slab, at = [r, 0.0, -d], plane = world, rpy = [phi, 0.0, 0.0],
          normal = z, mu = mu, restitution = e)]
#[contact(leg_b: point, body = slab, at = [-0.5 * r, 0.866_025_403_784_438_6 * r, -d],
          plane = world, rpy = [phi, 0.0, 0.0], normal = z, mu = mu, restitution = e)]
#[contact(leg_c: point, body = slab, at = [-0.5 * r, -0.866_025_403_784_438_6 * r, -d],
          plane = world, rpy = [phi, 0.0, 0.0], normal = z, mu = mu, restitution = e)]
pub struct Table {
    pub m: f64,
    pub a: f64,
    pub c: f64,
    pub r: f64,
    pub d: f64,
    pub mu: f64,
    pub e: f64,
    pub phi: f64,
    pub g: f64,
}

impl Default for Table {
    /// A 4 kg slab 0.6 m square and 0.04 m thick, legs 0.25 m from its centre and 0.15 m
    /// below it, on level ground, `μ = 0.5`, no bounce. (With legs much longer than
    /// `r / (2 μ)` the friction's moment tips it onto two legs when it slides.)
    fn default() -> Self {
        Table {
            m: 4.0,
            a: 0.3,
            c: 0.02,
            r: 0.25,
            d: 0.15,
            mu: 0.5,
            e: 0.0,
            phi: 0.0,
            g: 9.81,
        }
    }
}

/// A rod of half-length `l` in the x–y plane (`x`, `y` of its centre, `lean` from the
/// vertical, positive towards −x) with both ends touching level ground as contacts
/// `foot` (at −l along the rod) and `head` (at +l), friction `mu`, restitution `e`.
/// Stood on its foot slightly off the vertical it tips over, pivoting on the foot until
/// friction cannot hold it, then slips (theory §8).
#[derive(Mechanism, Clone, Copy, Debug, PartialEq)]
#[mechanism(gravity = [0.0, -g, 0.0])]
#[body(slider_x, mass = 0.0)]
#[joint(x: prismatic(x), parent = world, child = slider_x)]
#[body(slider_y, mass = 0.0)]
#[joint(y: prismatic(y), parent = slider_x, child = slider_y)]
#[body(rod, mass = m, inertia = diag(m * l * l / 3.0, 0.0, m * l * l / 3.0))]
#[joint(lean: revolute(z), parent = slider_y, child = rod)]
#[contact(foot: point, body = rod, at = [0.0, -l, 0.0], plane = world, normal = y, mu = mu,
          restitution = e)]
#[contact(head: point, body = rod, at = [0.0, l, 0.0], plane = world, normal = y, mu = mu,
          restitution = e)]
pub struct FallingRod {
    pub m: f64,
    pub l: f64,
    pub mu: f64,
    pub e: f64,
    pub g: f64,
}

impl Default for FallingRod {
    /// A 1 kg rod 1 m long, `μ = 0.3`, no bounce.
    fn default() -> Self {
        FallingRod {
            m: 1.0,
            l: 0.5,
            mu: 0.3,
            e: 0.0,
            g: 9.81,
        }
    }
}

/// A cart on a rail with a pendulum hanging from it: the cart (mass `mc`, half-length
/// `a`, its skids `b` below its centre) rests on the rail on two skids, contacts `rear`
/// and `front` with friction `mu`; the pendulum (a point mass `mp` on a massless rod of
/// length `l`, `swing` from hanging straight down) hangs from the cart's centre. Four
/// coordinates: `x`, `y`, `pitch` of the cart, `swing`. The rail's friction is `μ`
/// times the skids' normal forces, which carry the swinging pendulum's load (theory §8).
#[derive(Mechanism, Clone, Copy, Debug, PartialEq)]
#[mechanism(gravity = [0.0, -g, 0.0])]
#[body(slider_x, mass = 0.0)]
#[joint(x: prismatic(x), parent = world, child = slider_x)]
#[body(slider_y, mass = 0.0)]
#[joint(y: prismatic(y), parent = slider_x, child = slider_y)]
#[body(cart, mass = mc, inertia = cuboid(mc, 2.0 * a, 2.0 * b, 0.2))]
#[joint(pitch: revolute(z), parent = slider_y, child = cart)]
#[body(bob, mass = mp, com = [0.0, -l, 0.0])]
#[joint(swing: revolute(z), parent = cart, child = bob)]
#[contact(rear: point, body = cart, at = [-a, -b, 0.0], plane = world, normal = y, mu = mu)]
#[contact(front: point, body = cart, at = [a, -b, 0.0], plane = world, normal = y, mu = mu)]
pub struct CartOnRail {
    pub mc: f64,
    pub mp: f64,
    pub a: f64,
    pub b: f64,
    pub l: f64,
    pub mu: f64,
    pub g: f64,
}

impl Default for CartOnRail {
    /// A 2 kg cart 0.6 m long on skids 0.1 m below its centre, a 1 kg pendulum 0.5 m
    /// long, `μ = 0.2`.
    fn default() -> Self {
        CartOnRail {
            mc: 2.0,
            mp: 1.0,
            a: 0.3,
            b: 0.1,
            l: 0.5,
            mu: 0.2,
            g: 9.81,
        }
    }
}
