use filippov::Mechanism;

#[derive(Mechanism)]
#[body(root, mass = m)]
#[joint(j0: revolute(z), parent = world, child = root)]
#[body(a, mass = m)]
#[body(b, mass = m)]
#[joint(j1: revolute(z), parent = b, child = a)]
#[joint(j2: revolute(z), parent = a, child = b)]
struct Loop { m: f64 }

fn main() {}
