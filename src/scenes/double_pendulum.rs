use filippov::Mechanism;

/// Theory S8: two uniform rods hinged at their ends, swinging in the x–y plane under
/// gravity along −y. Angles are measured from the x axis.
#[derive(Mechanism, Clone, Copy, Debug, PartialEq)]
#[mechanism(emit = all, gravity = [0.0, -g, 0.0])]
#[body(upper, mass = m1, com = [l1 / 2.0, 0.0, 0.0], inertia = rod(m1, l1))]
#[joint(shoulder: revolute(z), parent = world, child = upper)]
#[body(lower, mass = m2, com = [l2 / 2.0, 0.0, 0.0], inertia = rod(m2, l2))]
#[joint(elbow: revolute(z), parent = upper, child = lower, origin = [l1, 0.0, 0.0])]
pub struct DoublePendulum {
    pub m1: f64,
    pub l1: f64,
    pub m2: f64,
    pub l2: f64,
    pub g: f64,
}

impl Default for DoublePendulum {
    /// The parameters of theory S8.
    fn default() -> Self {
        DoublePendulum {
            m1: 1.0,
            l1: 1.0,
            m2: 0.5,
            l2: 0.7,
            g: 9.81,
        }
    }
}
