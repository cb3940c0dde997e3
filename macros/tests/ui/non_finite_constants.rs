use filippov::Mechanism;

// Numbers and constant expressions that are not finite f64, in every kind of value.
#[derive(Mechanism)]
#[mechanism(gravity = [0.0, -1e400, 0.0])]
#[body(link, mass = m, com = [ln(0.0), 0.0, 0.0], inertia = rod(m, l))]
#[joint(hinge: revolute(z), parent = world, child = link, origin = [sqrt(-1.0), 0.0, 0.0])]
#[spring(hinge, k = exp(1000.0), rest = 0.0)]
#[friction(hinge, f_crit = 1e400)]
struct Pendulum { m: f64, l: f64 }

fn main() {}
