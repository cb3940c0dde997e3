use filippov::Mechanism;

// A misspelt kernel, one listed twice, and a kernel the scene has nothing for.
#[derive(Mechanism)]
#[mechanism(emit = [coriolis, corilis, energy, energy, delassus])]
#[body(link, mass = m, com = [0.5, 0.0, 0.0], inertia = rod(m, 1.0))]
#[joint(hinge: revolute(z), parent = world, child = link)]
struct Pendulum { m: f64 }

// Not a list.
#[derive(Mechanism)]
#[mechanism(emit = "coriolis")]
#[body(link, mass = m, com = [0.5, 0.0, 0.0], inertia = rod(m, 1.0))]
#[joint(hinge: revolute(z), parent = world, child = link)]
struct Other { m: f64 }

fn main() {}
