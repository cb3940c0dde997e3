use filippov::Mechanism;

// Non-smooth elements on a closed mechanism are not supported yet: said at the element.
#[derive(Mechanism)]
#[body(crank, mass = m, com = [0.1, 0.0, 0.0])]
#[joint(pivot: revolute(z), parent = world, child = crank)]
#[body(rocker, mass = m, com = [0.1, 0.0, 0.0])]
#[joint(rocker_pivot: revolute(z), parent = world, child = rocker, origin = [1.0, 0.0, 0.0])]
#[loop_joint(pin: revolute(z), parent = crank, child = rocker, origin = [0.3, 0.0, 0.0], child_origin = [0.8, 0.0, 0.0])]
#[friction(pivot, f_crit = 1.0)]
struct FourBar {
    m: f64,
}

fn main() {}
