use filippov::Mechanism;

#[derive(Mechanism)]
#[mechanism(inputs = [hinge, elbow, hinge, weld])]
#[body(link, mass = m)]
#[joint(hinge: revolute(z), parent = world, child = link)]
#[body(tip, mass = m)]
#[joint(weld: fixed, parent = link, child = tip)]
struct Pendulum { m: f64 }

fn main() {}
