use filippov::Mechanism;

// Loop joints close trees of revolute and prismatic joints; a tree with a ball joint is
// not supported yet, and the message says what is.
#[derive(Mechanism)]
#[body(arm, mass = m, com = [0.1, 0.0, 0.0])]
#[joint(shoulder: spherical, parent = world, child = arm)]
#[loop_joint(tip: spherical, parent = world, child = arm, origin = [0.2, 0.0, 0.0], child_origin = [0.2, 0.0, 0.0])]
struct Tethered {
    m: f64,
}

fn main() {}
