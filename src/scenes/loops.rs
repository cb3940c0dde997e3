use filippov::Mechanism;

/// A Grashof crank-rocker four-bar in the x–y plane under gravity along −y, without
/// losses: the crank (`a`) turns about the origin, the coupler (`b`) hangs from its end,
/// the rocker (`c`) turns about `(d, 0)`, and a loop joint pins the coupler's end to the
/// rocker's (theory §7). The tree's coordinates are the crank angle, the coupler's angle
/// relative to the crank and the rocker's angle; the loop joint adds two constraints.
#[derive(Mechanism, Clone, Copy, Debug, PartialEq)]
#[mechanism(emit = [energy], gravity = [0.0, -g, 0.0])]
#[body(crank, mass = ma, com = [a / 2.0, 0.0, 0.0], inertia = rod(ma, a))]
#[joint(crank_pivot: revolute(z), parent = world, child = crank)]
#[body(coupler, mass = mb, com = [b / 2.0, 0.0, 0.0], inertia = rod(mb, b))]
#[joint(crank_pin: revolute(z), parent = crank, child = coupler, origin = [a, 0.0, 0.0])]
#[body(rocker, mass = mc, com = [c / 2.0, 0.0, 0.0], inertia = rod(mc, c))]
#[joint(rocker_pivot: revolute(z), parent = world, child = rocker, origin = [d, 0.0, 0.0])]
#[loop_joint(rocker_pin: revolute(z), parent = coupler, child = rocker, origin = [b, 0.0, 0.0], child_origin = [c, 0.0, 0.0])]
pub struct FourBar {
    pub a: f64,
    pub b: f64,
    pub c: f64,
    pub d: f64,
    pub ma: f64,
    pub mb: f64,
    pub mc: f64,
    pub g: f64,
}

impl Default for FourBar {
    /// A crank-rocker: shortest link the crank, `a + b ≤ c + d` (Grashof).
    fn default() -> Self {
        FourBar {
            a: 0.3,
            b: 1.1,
            c: 0.8,
            d: 1.0,
            ma: 1.0,
            mb: 1.5,
            mc: 1.2,
            g: 9.81,
        }
    }
}

/// A slider-crank in the x–y plane: the crank (`r`) turns about the origin, the
/// connecting rod (`l`) hangs from its end, the slider runs along x on a prismatic
/// joint, and a loop joint pins the rod's end to the slider (two constraints).
#[derive(Mechanism, Clone, Copy, Debug, PartialEq)]
#[mechanism(emit = [energy], gravity = [0.0, -g, 0.0], inputs = [crank])]
#[body(crank_arm, mass = mc, com = [r / 2.0, 0.0, 0.0], inertia = rod(mc, r))]
#[joint(crank: revolute(z), parent = world, child = crank_arm)]
#[body(rod, mass = mr, com = [l / 2.0, 0.0, 0.0], inertia = rod(mr, l))]
#[joint(crank_pin: revolute(z), parent = crank_arm, child = rod, origin = [r, 0.0, 0.0])]
#[body(slider, mass = ms, com = [0.0, 0.0, 0.0], inertia = sphere(ms, 0.02))]
#[joint(stroke: prismatic(x), parent = world, child = slider)]
#[loop_joint(wrist_pin: revolute(z), parent = rod, child = slider, origin = [l, 0.0, 0.0])]
pub struct SliderCrank {
    pub r: f64,
    pub l: f64,
    pub mc: f64,
    pub mr: f64,
    pub ms: f64,
    pub g: f64,
}

impl Default for SliderCrank {
    fn default() -> Self {
        SliderCrank {
            r: 0.1,
            l: 0.35,
            mc: 0.5,
            mr: 0.4,
            ms: 1.0,
            g: 9.81,
        }
    }
}
