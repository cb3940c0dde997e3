use filippov::Mechanism;

// Each spring between points has one mistake, each reported once at its tokens.
#[derive(Mechanism)]
#[body(arm, mass = m, com = [0.1, 0.0, 0.0])]
#[joint(shoulder: revolute(z), parent = world, child = arm)]
#[spring(lonely: between(arm), k = 1.0)]
#[spring(ghost: between(world, forearm), k = 1.0)]
#[spring(same: between(arm, arm), k = 1.0)]
#[spring(floppy: between(world, arm), rest = 0.1)]
#[spring(typo: between(world, arm), k = 1.0, too = [0.1, 0.0, 0.0])]
struct Arm {
    m: f64,
}

fn main() {}
