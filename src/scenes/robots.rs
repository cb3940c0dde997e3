//! Robots read from the URDF files in `robots/` (features `scenes` and `urdf`): the UR5,
//! and a three-link arm whose limits are stops and whose joint friction is Coulomb's.
//! The Python wheel ships them; the Panda, declared with attributes, is
//! [`Panda`](super::Panda).

use crate::Mechanism;

/// The UR5 (`robots/ur5.urdf`), with its frames and inverse dynamics.
#[derive(Mechanism)]
#[mechanism(
    urdf = "robots/ur5.urdf",
    gravity = [0.0, 0.0, -9.81],
    emit = [kinematics, inverse_dynamics]
)]
pub struct Ur5;

/// A three-link arm (`robots/three_link_arm.urdf`): its limits become two-sided stops
/// with restitution 0.2, its `<dynamics friction>` Coulomb friction.
#[derive(Mechanism)]
#[mechanism(
    urdf = "robots/three_link_arm.urdf",
    limits = stops(restitution = 0.2),
    joint_friction = true,
    gravity = [0.0, 0.0, -9.81],
    emit = [kinematics, inverse_dynamics]
)]
pub struct ThreeLinkArm;
