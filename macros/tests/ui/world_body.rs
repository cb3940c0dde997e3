use filippov::Mechanism;

// `world` is the fixed frame: a body of that name is refused at its name, and nothing
// else is reported about it.
#[derive(Mechanism)]
#[body(world, mass = m)]
#[body(link, mass = m)]
#[joint(hinge: revolute(z), parent = world, child = link)]
struct Pendulum { m: f64 }

fn main() {}
