use filippov::Mechanism;

// The same element declared five times: one message, at the first copy too many.
#[derive(Mechanism)]
#[body(link, mass = m)]
#[joint(hinge: revolute(z), parent = world, child = link)]
#[friction(hinge, f_crit = 0.5)]
#[friction(hinge, f_crit = 0.5)]
#[friction(hinge, f_crit = 0.5)]
#[friction(hinge, f_crit = 0.5)]
#[friction(hinge, f_crit = 0.5)]
struct Pendulum { m: f64 }

fn main() {}
