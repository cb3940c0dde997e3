use filippov::Mechanism;

#[derive(Mechanism)]
#[body(a, mass = m)]
#[joint(j1: revolute(w), parent = world, child = a)]
#[body(b, mass = m)]
#[joint(j2: prismatic([1.0, 0.0]), parent = a, child = b)]
#[body(c, mass = m)]
#[joint(j3: revolute([0.0, 0.0, 0.0]), parent = b, child = c)]
struct Arm { m: f64 }

fn main() {}
