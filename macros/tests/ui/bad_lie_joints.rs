use filippov::Mechanism;

// Elements act on one coordinate; spherical and free joints have three and six.
#[derive(Mechanism)]
#[mechanism(inputs = [float, hinge])]
#[body(base, mass = 10.0, inertia = diag(1.0, 2.0, 3.0))]
#[joint(float: free, parent = world, child = base)]
#[body(arm, mass = 1.0, com = [0.5, 0.0, 0.0], inertia = rod(1.0, 1.0))]
#[joint(hinge: revolute(z), parent = base, child = arm)]
#[body(tip, mass = 0.1, inertia = sphere(0.1, 0.05))]
#[joint(wrist: spherical, parent = arm, child = tip, origin = [1.0, 0.0, 0.0])]
#[spring(wrist, k = 1.0)]
#[damper(float, c = 0.1)]
#[friction(hinge, f_crit = 0.5)]
struct Satellite;

fn main() {}
