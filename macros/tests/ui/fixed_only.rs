use filippov::Mechanism;

#[derive(Mechanism)]
#[body(link, mass = 1.0)]
#[joint(weld: fixed, parent = world, child = link)]
#[spring(weld, k = 1.0)]
struct Statue {}

fn main() {}
