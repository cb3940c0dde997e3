use filippov::Mechanism;

#[derive(Mechanism)]
#[body(link, mass = m)]
#[joint(hinge: revolute(z), parent = world, child = link)]
struct Pendulum<T> { m: f64, tag: T }

fn main() {}
