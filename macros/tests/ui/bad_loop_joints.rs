use filippov::Mechanism;

// Each loop joint has one mistake; each is reported once, at its tokens.
#[derive(Mechanism)]
#[body(crank, mass = m, com = [0.1, 0.0, 0.0])]
#[joint(pivot: revolute(z), parent = world, child = crank)]
#[body(rocker, mass = m, com = [0.1, 0.0, 0.0])]
#[joint(rocker_pivot: revolute(z), parent = world, child = rocker, origin = [1.0, 0.0, 0.0])]
#[loop_joint(floating: free, parent = crank, child = rocker)]
#[loop_joint(pivot: revolute(z), parent = crank, child = rocker)]
#[loop_joint(to_self: revolute(z), parent = rocker, child = rocker)]
#[loop_joint(nowhere: spherical, parent = crank, child = coupler)]
#[loop_joint(upside: spherical, parent = crank, child = world)]
#[loop_joint(typo: revolute(z), parent = crank, child = rocker, child_orign = [0.2, 0.0, 0.0])]
#[loop_joint(bare, parent = crank, child = rocker)]
struct FourBar {
    m: f64,
}

fn main() {}
