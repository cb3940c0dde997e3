use filippov::Mechanism;

#[derive(Mechanism)]
#[body(block, mass = m)]
#[joint(x: prismatic(x), parent = world, child = block)]
#[spring(x, potential = 0.5 * k * v * v, k = 2.0)]
struct Block { m: f64, k: f64 }

fn main() {}
