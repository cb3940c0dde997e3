use filippov::Mechanism;

// Three independent mistakes, all reported in one build.
#[derive(Mechanism)]
#[body(upper, mass = m1)]
#[joint(shoulder: revolute(q), parent = world, child = upper)]
#[body(lower, mass = m3)]
#[joint(elbow: revolute(z), parent = uper, child = lower)]
struct DoublePendulum { m1: f64, m2: f64 }

fn main() {}
