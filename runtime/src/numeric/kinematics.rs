//! Forward kinematics: the pose of every link frame from the joint coordinates.
//!
//! Frame convention of [`Link`] (URDF): link frame = parent frame · Trans(origin_xyz) ·
//! Rot(origin_rpy) · joint motion(q), with `Rot(rpy) = Rz(yaw) Ry(pitch) Rx(roll)`.
//! Revolute motion is the rotation by `q` about the joint axis (Rodrigues' formula),
//! prismatic motion the translation by `q` along it. Featherstone, *Rigid Body Dynamics
//! Algorithms* (2008), §4.1–4.4 (joint models) and §2.8 (coordinate transforms).

use nalgebra::{DVector, Matrix3, Matrix6, Vector3, Vector6};

use super::spatial;
use super::{JointKind, Link, Model};

/// A rigid transform: the link frame's orientation and origin, in the world frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    pub rotation: Matrix3<f64>,
    pub translation: Vector3<f64>,
}

impl Pose {
    /// The world frame.
    pub fn identity() -> Self {
        Pose {
            rotation: Matrix3::identity(),
            translation: Vector3::zeros(),
        }
    }

    /// Maps a point given in this frame to the world frame.
    pub fn transform_point(&self, p: &Vector3<f64>) -> Vector3<f64> {
        self.rotation * p + self.translation
    }
}

impl Model {
    /// Number of joint coordinates (links with a coordinate).
    pub fn dof(&self) -> usize {
        self.links.iter().filter(|l| l.coordinate.is_some()).count()
    }
}

/// `Rz(yaw) · Ry(pitch) · Rx(roll)` for `rpy = (roll, pitch, yaw)`.
pub fn rpy_matrix(rpy: &Vector3<f64>) -> Matrix3<f64> {
    let (sr, cr) = rpy.x.sin_cos();
    let (sp, cp) = rpy.y.sin_cos();
    let (sy, cy) = rpy.z.sin_cos();
    let rx = Matrix3::new(1.0, 0.0, 0.0, 0.0, cr, -sr, 0.0, sr, cr);
    let ry = Matrix3::new(cp, 0.0, sp, 0.0, 1.0, 0.0, -sp, 0.0, cp);
    let rz = Matrix3::new(cy, -sy, 0.0, sy, cy, 0.0, 0.0, 0.0, 1.0);
    rz * ry * rx
}

/// Rotation by `angle` about the unit vector `axis` (Rodrigues):
/// `𝟙 + sin θ â + (1 − cos θ) â²`.
pub fn axis_rotation(axis: &Vector3<f64>, angle: f64) -> Matrix3<f64> {
    let k = spatial::skew(axis);
    let (s, c) = angle.sin_cos();
    Matrix3::identity() + k * s + k * k * (1.0 - c)
}

fn coordinate_value(link: &Link, q: &DVector<f64>) -> f64 {
    link.coordinate.map_or(0.0, |i| q[i])
}

/// World pose of every link frame, in the order of [`Model::links`].
///
/// # Panics
/// If a link's parent index is not smaller than its own, or a coordinate index is out
/// of range of `q`.
pub fn link_poses(model: &Model, q: &DVector<f64>) -> Vec<Pose> {
    let mut poses: Vec<Pose> = Vec::with_capacity(model.links.len());
    for (i, link) in model.links.iter().enumerate() {
        let parent = match link.parent {
            Some(p) => {
                assert!(p < i, "link {i} ({}): parent must come first", link.name);
                poses[p]
            }
            None => Pose::identity(),
        };
        let joint_rotation = parent.rotation * rpy_matrix(&link.origin_rpy);
        let joint_origin = parent.transform_point(&link.origin_xyz);
        let qi = coordinate_value(link, q);
        let pose = match link.joint {
            JointKind::Revolute { axis } => Pose {
                rotation: joint_rotation * axis_rotation(&axis, qi),
                translation: joint_origin,
            },
            JointKind::Prismatic { axis } => Pose {
                rotation: joint_rotation,
                translation: joint_origin + joint_rotation * axis * qi,
            },
            JointKind::Fixed => Pose {
                rotation: joint_rotation,
                translation: joint_origin,
            },
        };
        poses.push(pose);
    }
    poses
}

/// World-frame spatial quantities of every link at one configuration: what RNEA, CRBA
/// and the mass-matrix derivatives share.
pub(crate) struct WorldTree {
    /// Joint motion subspace (Featherstone's `S_i`, §3.5) in world Plücker coordinates,
    /// `None` for fixed joints. It moves with the link: `Ṡ_i = v_i ×ₘ S_i`.
    pub subspace: Vec<Option<Vector6<f64>>>,
    /// Spatial inertia of each link about the world origin.
    pub inertia: Vec<Matrix6<f64>>,
}

impl WorldTree {
    pub fn new(model: &Model, q: &DVector<f64>) -> Self {
        let poses = link_poses(model, q);
        let mut subspace = Vec::with_capacity(poses.len());
        let mut inertia = Vec::with_capacity(poses.len());
        for (link, pose) in model.links.iter().zip(&poses) {
            subspace.push(match link.joint {
                // The axis passes through the link origin; the linear part is the
                // velocity of the point at the world origin, `p × a`.
                JointKind::Revolute { axis } => {
                    let a = pose.rotation * axis;
                    let lin = pose.translation.cross(&a);
                    Some(Vector6::new(a.x, a.y, a.z, lin.x, lin.y, lin.z))
                }
                JointKind::Prismatic { axis } => {
                    let a = pose.rotation * axis;
                    Some(Vector6::new(0.0, 0.0, 0.0, a.x, a.y, a.z))
                }
                JointKind::Fixed => None,
            });
            let c = pose.transform_point(&link.com);
            let i_c = pose.rotation * link.inertia * pose.rotation.transpose();
            inertia.push(spatial::inertia(link.mass, &c, &i_c));
        }
        WorldTree { subspace, inertia }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::FRAC_PI_2;

    #[test]
    fn rpy_is_z_y_x_composition_of_axis_rotations() {
        let rpy = Vector3::new(0.3, -0.7, 1.1);
        let expected = axis_rotation(&Vector3::z(), rpy.z)
            * axis_rotation(&Vector3::y(), rpy.y)
            * axis_rotation(&Vector3::x(), rpy.x);
        assert!((rpy_matrix(&rpy) - expected).norm() < 1e-14);
        let r = rpy_matrix(&Vector3::new(FRAC_PI_2, 0.0, 0.0));
        assert!((r * Vector3::z() - Vector3::new(0.0, -1.0, 0.0)).norm() < 1e-15);
    }

    #[test]
    fn prismatic_and_revolute_poses() {
        let model = super::super::test_models::cart_pole(2.0, 0.5, 1.0);
        let q = DVector::from_vec(vec![0.4, FRAC_PI_2]);
        let poses = link_poses(&model, &q);
        assert!((poses[0].translation - Vector3::new(0.4, 0.0, 0.0)).norm() < 1e-15);
        // The pole's x axis points along world y after a quarter turn about z.
        let tip = poses[1].transform_point(&Vector3::new(1.0, 0.0, 0.0));
        assert!((tip - Vector3::new(0.4, 1.0, 0.0)).norm() < 1e-15);
    }
}
