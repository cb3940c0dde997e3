use filippov::Mechanism;

#[derive(Mechanism)]
#[body(block, mass = m)]
#[joint(x: prismatic(x), parent = world, child = block)]
#[bingham(x, f_crit = 1.0, law = gamma * v * v, select = fastest)]
#[stop(y, restitution = 0.5)]
struct Block { m: f64, gamma: f64 }

fn main() {}
