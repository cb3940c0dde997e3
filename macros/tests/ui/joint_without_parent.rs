use filippov::Mechanism;

// The middle joint of a chain lacks `parent`: one error, at that joint, and none for
// the joints below it (they are fine; the chain is cut by that one mistake).
#[derive(Mechanism)]
#[body(upper, mass = 1.0, com = [0.5, 0.0, 0.0], inertia = rod(1.0, 1.0))]
#[joint(shoulder: revolute(z), parent = world, child = upper)]
#[body(fore, mass = 1.0, com = [0.5, 0.0, 0.0], inertia = rod(1.0, 1.0))]
#[joint(elbow: revolute(z), child = fore, origin = [1.0, 0.0, 0.0])]
#[body(hand, mass = 0.5, com = [0.1, 0.0, 0.0], inertia = point)]
#[joint(wrist: revolute(z), parent = fore, child = hand, origin = [1.0, 0.0, 0.0])]
#[friction(wrist, f_crit = 1.0)]
struct Arm;

fn main() {}
