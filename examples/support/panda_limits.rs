//! The Panda from its URDF file (`robots/panda.urdf`) with every joint limit a rigid
//! stop and Coulomb friction on every joint, fingers locked: the scene of the
//! `panda_on_limits` example and of the report's extreme suite and ensembles. With
//! `emit = [kinematics]` it has the poses and Jacobians of its links and of the file's
//! tool frame `panda_hand_tcp`; with `generic`, its kernels on any scalar (the lanes of
//! an ensemble).

use filippov::Mechanism;
use filippov::nalgebra::SVector;

pub type V7 = SVector<f64, 7>;

#[derive(Mechanism, Clone, Copy, Debug)]
#[mechanism(
    urdf = "robots/panda.urdf",
    lock = [panda_finger_joint1, panda_finger_joint2],
    limits = stops(restitution = e),
    joint_friction = true,
    gravity = [0.0, 0.0, -9.81],
    emit = [kinematics, generic]
)]
#[urdf_param(
    panda_joint1.friction = fc, panda_joint2.friction = fc, panda_joint3.friction = fc,
    panda_joint4.friction = fc, panda_joint5.friction = fc, panda_joint6.friction = fc,
    panda_joint7.friction = fc
)]
pub struct PandaOnLimits {
    /// Restitution of every limit.
    pub e: f64,
    /// Coulomb friction of every joint [N m].
    pub fc: f64,
}

/// Released at rest from a pose that gravity folds onto several limits.
pub fn release_pose() -> V7 {
    V7::from_column_slice(&[0.0, 1.2, 0.0, -0.4, 0.0, 3.4, 0.5])
}

/// No joint torque.
pub fn zero(_t: f64, _q: &V7, _v: &V7) -> V7 {
    V7::zeros()
}
