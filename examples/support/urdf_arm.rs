//! The arm of `robots/three_link_arm.urdf` with its limits as stops (restitution 0.3)
//! and its joint friction and damping as elements, shared by `examples/urdf_arm.rs` and
//! `tests/urdf.rs`.

use filippov::Mechanism;

#[derive(Mechanism)]
#[mechanism(
    urdf = "robots/three_link_arm.urdf",
    limits = stops(restitution = 0.3),
    joint_friction = true,
    joint_damping = true,
    gravity = [0.0, 0.0, -9.81]
)]
pub struct Arm;
