use filippov::Mechanism;

#[derive(Mechanism)]
#[body(link, mass = 1.0)]
#[joint(hinge: revolute(z), parent = world, child = link)]
struct Pendulum(f64, f64);

fn main() {}
