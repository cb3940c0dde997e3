use filippov::Mechanism;

#[derive(Mechanism)]
#[body(block, mass = m)]
#[joint(x: prismatic(x), parent = world, child = block)]
#[friction(x, f_crit = -0.5)]
#[bingham(x, f_crit = 1.0, eta = 0.2, law = f * f)]
#[stop(x, max = 1.0, restitution = 1.5)]
struct Block { m: f64 }

fn main() {}
