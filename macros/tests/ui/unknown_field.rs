use filippov::Mechanism;

#[derive(Mechanism)]
#[body(link, mass = mass, com = [length / 2.0, 0.0, 0.0])]
#[joint(hinge: revolute(z), parent = world, child = link)]
struct Pendulum { m: f64, l: f64 }

fn main() {}
