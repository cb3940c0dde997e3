use filippov::Mechanism;

// A ball joint turns about every axis: an axis is a mistake.
#[derive(Mechanism)]
#[body(top, mass = 1.0, inertia = diag(1.0, 2.0, 3.0))]
#[joint(ball: spherical(z), parent = world, child = top)]
struct Top;

fn main() {}
