use filippov::prelude::*;

#[derive(Mechanism)]
#[body(link, mass = 1.0, com = [0.5, 0.0, 0.0], inertia = rod(1.0, 1.0))]
#[joint(hinge: revolute(z), parent = world, child = link)]
#[frame(tool, parent = hand, origin = [0.0, 0.0, 0.1])]
#[frame(link, parent = world)]
#[frame(a, parent = b)]
#[frame(b, parent = a)]
#[frame(c: fixed, parent = link)]
#[frame(d)]
#[frame(e, parent = link, offset = [0.0, 0.0, 1.0])]
#[frame(a, parent = link)]
struct Pendulum;

fn main() {}
