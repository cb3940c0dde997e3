use filippov::Mechanism;

#[derive(Mechanism)]
#[body(link, mass = m, colour = 1.0)]
#[joint(hinge: revolute(z), parent = world, child = link, offset = [0.0, 0.0, 0.0])]
struct Pendulum { m: f64 }

fn main() {}
