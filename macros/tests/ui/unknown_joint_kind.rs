use filippov::Mechanism;

#[derive(Mechanism)]
#[body(link, mass = m)]
#[joint(hinge: rotary(z), parent = world, child = link)]
struct Pendulum { m: f64 }

fn main() {}
