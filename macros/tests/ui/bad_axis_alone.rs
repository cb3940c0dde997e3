use filippov::Mechanism;

// A joint with a bad axis: one message, at the axis (the body it carries is not also
// reported as unattached).
#[derive(Mechanism)]
#[body(link, mass = m)]
#[joint(hinge: revolute(w), parent = world, child = link)]
struct Pendulum { m: f64 }

fn main() {}
