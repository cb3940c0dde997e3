//! Robots read from the URDF files in `robots/` (features `scenes` and `urdf`): the UR5,
//! a three-link arm whose limits are stops and whose joint friction is Coulomb's, and
//! two robots on a free base, the quadruped Solo12 and a 35-dof humanoid (scenes with
//! Lie-group joints: [`LieMechanism`](crate::runtime::LieMechanism), integrated by
//! [`Rkmk5`](crate::runtime::Rkmk5) or [`LieSdirk`](crate::runtime::LieSdirk)).
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

/// Solo12 (`robots/solo12.urdf`), a quadruped of 12 revolute joints on a free base:
/// configuration `(x, y, z, qw, qx, qy, qz, joints…)` (19 slots), velocity
/// `(ẋ, ẏ, ż, ω, joints…)` (18), `ω` in the base frame.
#[derive(Mechanism)]
#[mechanism(
    urdf = "robots/solo12.urdf",
    base = free,
    gravity = [0.0, 0.0, -9.81],
    emit = [kinematics, inverse_dynamics]
)]
pub struct Solo12;

/// A humanoid (`robots/simple_humanoid.urdf`) of 29 revolute joints on a free base: 36
/// configuration slots and 35 velocity coordinates, laid out as [`Solo12`]'s.
#[derive(Mechanism)]
#[mechanism(
    urdf = "robots/simple_humanoid.urdf",
    base = free,
    gravity = [0.0, 0.0, -9.81],
    emit = [kinematics, inverse_dynamics]
)]
pub struct Humanoid;
