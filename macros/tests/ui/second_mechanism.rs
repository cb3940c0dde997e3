use filippov::Mechanism;

#[derive(Mechanism)]
#[mechanism(inputs = [hinge])]
#[mechanism(gravity = [0.0, -9.81, 0.0])]
#[body(link, mass = m)]
#[joint(hinge: revolute(z), parent = world, child = link)]
struct Pendulum { m: f64 }

fn main() {}
