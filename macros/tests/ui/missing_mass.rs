use filippov::Mechanism;

#[derive(Mechanism)]
#[body(link, com = [0.5, 0.0, 0.0])]
#[joint(hinge: revolute(z), parent = world, child = link)]
struct Pendulum { l: f64 }

fn main() {}
