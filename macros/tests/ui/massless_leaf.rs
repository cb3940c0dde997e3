use filippov::Mechanism;

// A massless body is an intermediate frame; as a leaf nothing gives its joint inertia.
#[derive(Mechanism)]
#[body(frame, mass = 0.0)]
#[joint(yaw: revolute(z), parent = world, child = frame)]
#[body(hand, mass = 0.0)]
#[joint(pitch: revolute(y), parent = frame, child = hand)]
struct Gimbal;

fn main() {}
