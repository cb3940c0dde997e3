use filippov::Mechanism;

#[derive(Mechanism)]
#[body(a, mass = m)]
#[body(b, mass = m)]
#[joint(hinge: revolute(z), parent = world, child = a)]
#[joint(hinge: revolute(z), parent = a, child = b)]
struct Chain { m: f64 }

fn main() {}
