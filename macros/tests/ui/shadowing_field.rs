use filippov::Mechanism;

// `PI` is the constant π in expressions: a field of that name could never be read.
#[derive(Mechanism)]
#[body(link, mass = m, com = [PI, 0.0, 0.0])]
#[joint(hinge: revolute(z), parent = world, child = link)]
struct Pendulum { m: f64, PI: f64 }

fn main() {}
