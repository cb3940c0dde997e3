use filippov::Mechanism;

#[derive(Mechanism)]
#[body(link, mass = m)]
#[joint(hinge: revolute(z), parent = link, child = world)]
#[joint(other: revolute(z), parent = world, child = link)]
struct Pendulum { m: f64 }

fn main() {}
