use filippov::Mechanism;

#[derive(Mechanism)]
#[body(a, mass = 1.0, inertia = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 5.0]])]
#[joint(j1: revolute(z), parent = world, child = a)]
#[body(b, mass = 1.0, inertia = [[1.0, 0.2, 0.0], [0.3, 1.0, 0.0], [0.0, 0.0, 1.0]])]
#[joint(j2: revolute(z), parent = a, child = b)]
#[body(c, mass = 1.0, inertia = rod(1.0))]
#[joint(j3: revolute(z), parent = b, child = c)]
struct Arm { l: f64 }

fn main() {}
