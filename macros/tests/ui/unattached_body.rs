use filippov::Mechanism;

#[derive(Mechanism)]
#[body(link, mass = m)]
#[body(loose, mass = m)]
#[joint(hinge: revolute(z), parent = world, child = link)]
struct Pendulum { m: f64 }

fn main() {}
