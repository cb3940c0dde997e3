use filippov::Mechanism;

#[derive(Mechanism)]
#[body(link, mass = m)]
#[joint(hinge: revolute(z), parent = world, child = link)]
#[spring(elbow, k = k)]
#[damper(hinge)]
struct Pendulum { m: f64, k: f64 }

fn main() {}
