use filippov::Mechanism;

#[derive(Mechanism)]
#[body(link, mass = m)]
#[joint(hinge: revolute(z), parent = world, child = link)]
struct Pendulum { m: f32, n: usize }

fn main() {}
