use filippov::Mechanism;

// Two-sided limits: min must lie below max, and one stop per side.
#[derive(Mechanism)]
#[body(a, mass = m)]
#[joint(ja: prismatic(x), parent = world, child = a)]
#[stop(ja, min = 1.0, max = 0.5, restitution = 0.5)]
#[body(b, mass = m)]
#[joint(jb: prismatic(y), parent = a, child = b)]
#[stop(jb, max = 1.0, restitution = 0.5)]
#[stop(jb, max = 2.0, k_support = 1e3)]
struct Limits { m: f64 }

fn main() {}
