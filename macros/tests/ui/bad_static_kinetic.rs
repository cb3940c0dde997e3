use filippov::Mechanism;

// Kinetic friction above the static one.
#[derive(Mechanism)]
#[body(block, mass = m)]
#[joint(x: prismatic(x), parent = world, child = block)]
#[friction(x, f_static = 0.5, f_kinetic = 0.8)]
struct Faster { m: f64 }

// Both laws at once.
#[derive(Mechanism)]
#[body(block, mass = m)]
#[joint(x: prismatic(x), parent = world, child = block)]
#[friction(x, f_crit = 0.5, f_static = 0.6, f_kinetic = 0.4)]
struct Both { m: f64 }

// Half a static/kinetic law.
#[derive(Mechanism)]
#[body(block, mass = m)]
#[joint(x: prismatic(x), parent = world, child = block)]
#[friction(x, f_static = 0.6)]
struct Half { m: f64 }

// A negative static force.
#[derive(Mechanism)]
#[body(block, mass = m)]
#[joint(x: prismatic(x), parent = world, child = block)]
#[friction(x, f_static = -0.6, f_kinetic = 0.4)]
struct Negative { m: f64 }

fn main() {}
