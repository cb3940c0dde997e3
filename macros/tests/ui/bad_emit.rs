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

// An algorithm that does not exist, and one written as a string.
#[derive(Mechanism)]
#[mechanism(forward_dynamics = featherstone)]
#[body(link, mass = m, com = [0.5, 0.0, 0.0], inertia = rod(m, 1.0))]
#[joint(hinge: revolute(z), parent = world, child = link)]
struct Third { m: f64 }

#[derive(Mechanism)]
#[mechanism(forward_dynamics = "aba")]
#[body(link, mass = m, com = [0.5, 0.0, 0.0], inertia = rod(m, 1.0))]
#[joint(hinge: revolute(z), parent = world, child = link)]
struct Fourth { m: f64 }

// The compact kernels take trees of one-dof joints: not a ball joint.
#[derive(Mechanism)]
#[mechanism(forward_dynamics = compact)]
#[body(link, mass = m, com = [0.5, 0.0, 0.0], inertia = rod(m, 1.0))]
#[joint(shoulder: spherical, parent = world, child = link)]
struct Fifth { m: f64 }

fn main() {}
