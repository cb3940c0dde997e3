//! Forward kinematics: the pose of every link frame from the joint coordinates.
//!
//! Frame convention of [`Link`] (URDF): link frame = parent frame · Trans(origin_xyz) ·
//! Rot(origin_rpy) · joint motion(q), with `Rot(rpy) = Rz(yaw) Ry(pitch) Rx(roll)`.
//! Revolute motion is the rotation by `q` about the joint axis (Rodrigues' formula),
//! prismatic motion the translation by `q` along it, spherical motion the rotation of
//! the unit quaternion in its four slots, translation motion the translation by the
//! vector in its three slots (joint-frame axes). Featherstone, *Rigid Body Dynamics
//! Algorithms* (2008), §4.1–4.4 (joint models) and §2.8 (coordinate transforms).

use nalgebra::{DVector, Matrix3, Matrix6, Vector3, Vector6};

use super::spatial;
use super::{JointKind, Model};
use crate::geometry::UnitQuat;

/// A rigid transform: the link frame's orientation and origin, in the world frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    pub rotation: Matrix3<f64>,
    pub translation: Vector3<f64>,
}

/// To nalgebra's isometry (rotation then translation, as `Pose` applies them).
impl From<Pose> for nalgebra::Isometry3<f64> {
    fn from(p: Pose) -> Self {
        let r = nalgebra::Rotation3::from_matrix_unchecked(p.rotation);
        nalgebra::Isometry3::from_parts(
            nalgebra::Translation3::from(p.translation),
            nalgebra::UnitQuaternion::from_rotation_matrix(&r),
        )
    }
}

/// From nalgebra's isometry.
impl From<nalgebra::Isometry3<f64>> for Pose {
    fn from(iso: nalgebra::Isometry3<f64>) -> Self {
        Pose {
            rotation: iso.rotation.to_rotation_matrix().into_inner(),
            translation: iso.translation.vector,
        }
    }
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

/// The rotation of the quaternion `(w, x, y, z)`, as the quadratic form of
/// [`UnitQuat::to_matrix`] (not renormalised: the quaternion must be unit).
fn quaternion_matrix(q: &[f64]) -> Matrix3<f64> {
    UnitQuat::from_coords_unchecked(q[0], q[1], q[2], q[3]).to_matrix()
}

/// World pose of every link frame, in the order of [`Model::links`]; `q` in the
/// configuration layout ([`Model::config_slots`]).
///
/// # Panics
/// If a link's parent index is not smaller than its own, or `q` is shorter than
/// [`Model::config_dim`].
pub fn link_poses(model: &Model, q: &DVector<f64>) -> Vec<Pose> {
    let mut poses: Vec<Pose> = Vec::with_capacity(model.links.len());
    let mut slot = 0;
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
        // The joint's configuration slots (zeros for a link without a coordinate).
        let n = link.joint.config_dim();
        let slots: &[f64] = match link.coordinate {
            Some(_) => {
                slot += n;
                &q.as_slice()[slot - n..slot]
            }
            None => &[0.0; 4][..n],
        };
        let qi = slots.first().copied().unwrap_or(0.0);
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
            JointKind::Spherical => Pose {
                rotation: joint_rotation
                    * match link.coordinate {
                        Some(_) => quaternion_matrix(slots),
                        None => Matrix3::identity(),
                    },
                translation: joint_origin,
            },
            JointKind::Translation => Pose {
                rotation: joint_rotation,
                translation: joint_origin + joint_rotation * Vector3::from_column_slice(slots),
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
    /// one column per velocity coordinate of the joint (none for fixed joints or links
    /// without a coordinate): column `c` multiplies `v[coordinate + c]`. Every column
    /// is a motion vector fixed in the link, so it moves with it: `Ṡ_i = v_i ×ₘ S_i`.
    /// Spherical: `(a, p × a)` for the link's axes `a = R e_c` through its origin `p`
    /// (angular first, the convention of [`super::spatial`]); translation: `(0, R e_c)`.
    pub subspace: Vec<Vec<Vector6<f64>>>,
    /// Spatial inertia of each link about the world origin.
    pub inertia: Vec<Matrix6<f64>>,
}

impl WorldTree {
    /// `(link, S column)` of every velocity coordinate, indexed by coordinate.
    pub fn columns(&self, model: &Model) -> Vec<(usize, Vector6<f64>)> {
        let mut out = vec![(0, Vector6::zeros()); model.dof()];
        for (i, link) in model.links.iter().enumerate() {
            if let Some(k) = link.coordinate {
                for (c, s) in self.subspace[i].iter().enumerate() {
                    out[k + c] = (i, *s);
                }
            }
        }
        out
    }

    /// The joint velocity `Σ_c S_c v[k + c]` of link `i` (zero without a coordinate).
    pub fn joint_motion(&self, model: &Model, i: usize, v: &DVector<f64>) -> Vector6<f64> {
        match model.links[i].coordinate {
            Some(k) => self.subspace[i]
                .iter()
                .enumerate()
                .fold(Vector6::zeros(), |acc, (c, s)| acc + s * v[k + c]),
            None => Vector6::zeros(),
        }
    }

    /// Spatial velocity of every link (world Plücker coordinates).
    pub fn velocities(&self, model: &Model, v: &DVector<f64>) -> Vec<Vector6<f64>> {
        let mut vel: Vec<Vector6<f64>> = Vec::with_capacity(model.links.len());
        for (i, link) in model.links.iter().enumerate() {
            let parent = link.parent.map_or_else(Vector6::zeros, |p| vel[p]);
            vel.push(parent + self.joint_motion(model, i, v));
        }
        vel
    }

    pub fn new(model: &Model, q: &DVector<f64>) -> Self {
        let poses = link_poses(model, q);
        let mut subspace = Vec::with_capacity(poses.len());
        let mut inertia = Vec::with_capacity(poses.len());
        // The axis passes through the link origin; the linear part is the velocity of
        // the point at the world origin, `p × a`.
        let rotation = |p: &Vector3<f64>, a: Vector3<f64>| {
            let lin = p.cross(&a);
            Vector6::new(a.x, a.y, a.z, lin.x, lin.y, lin.z)
        };
        let translation = |a: Vector3<f64>| Vector6::new(0.0, 0.0, 0.0, a.x, a.y, a.z);
        for (link, pose) in model.links.iter().zip(&poses) {
            let p = &pose.translation;
            subspace.push(match (link.coordinate, link.joint) {
                (None, _) | (_, JointKind::Fixed) => vec![],
                (_, JointKind::Revolute { axis }) => vec![rotation(p, pose.rotation * axis)],
                (_, JointKind::Prismatic { axis }) => vec![translation(pose.rotation * axis)],
                (_, JointKind::Spherical) => (0..3)
                    .map(|c| rotation(p, pose.rotation.column(c).into_owned()))
                    .collect(),
                (_, JointKind::Translation) => (0..3)
                    .map(|c| translation(pose.rotation.column(c).into_owned()))
                    .collect(),
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

#[cfg(test)]
mod conversion_tests {
    use super::*;

    /// A pose and its nalgebra isometry move points the same way, both directions.
    #[test]
    fn pose_and_isometry_agree() {
        let pose = Pose {
            rotation: rpy_matrix(&Vector3::new(0.3, -0.7, 1.1)),
            translation: Vector3::new(1.0, -2.0, 0.5),
        };
        let iso: nalgebra::Isometry3<f64> = pose.into();
        let p = Vector3::new(0.2, 0.4, -0.9);
        let q = iso.transform_point(&nalgebra::Point3::from(p)).coords;
        assert!((q - pose.transform_point(&p)).norm() < 1e-14);
        let back: Pose = iso.into();
        assert!((back.rotation - pose.rotation).norm() < 1e-14);
        assert_eq!(back.translation, pose.translation);
    }
}
