//! Plain numeric dynamics over a runtime [`Model`]: the independent reference the
//! generated kernels are checked against, and the baseline they are timed against.
//!
//! One algorithm per file, each citing its source (Featherstone, *Rigid Body Dynamics
//! Algorithms*, Springer 2008). Everything is computed in world coordinates with
//! dynamically sized nalgebra types; allocation is accepted here.
//!
//! | function | algorithm |
//! |---|---|
//! | [`link_poses`] | forward kinematics (`kinematics.rs`) |
//! | [`rnea`] | recursive Newton–Euler, `M a + C v + g` (`rnea.rs`) |
//! | [`crba`] | composite-rigid-body mass matrix (`crba.rs`) |
//! | [`mass_matrix_derivatives`], [`christoffel_symbols`], [`coriolis_matrix`], [`lie_coriolis_matrix`] | exact `∂M/∂q` and its Lie-group form `D_k M` (`coriolis.rs`) |
//! | [`gravity`], [`bias`], [`passive_forces`], [`forward_dynamics`], [`inverse_dynamics`], energies, [`spatial_momentum`] | `dynamics.rs` |
//!
//! Joints are revolute, prismatic, fixed, and the Lie-group kinds spherical (SO(3),
//! quaternion configuration, body angular velocity) and translation (ℝ³): `q` has
//! [`Model::config_dim`] slots, `v` has [`Model::dof`] components (see [`Model`]).
mod coriolis;
mod crba;
mod dynamics;
mod kinematics;
#[cfg(test)]
mod lie_tests;
mod rnea;
mod scene;
mod spatial;
#[cfg(test)]
pub(crate) mod test_models;
#[cfg(feature = "urdf")]
mod urdf;

pub use crate::model::*;
pub use coriolis::{
    christoffel_symbols, coriolis_matrix, lie_coriolis_matrix, mass_matrix_derivatives,
};
pub use crba::crba;
pub use dynamics::{
    bias, forward_dynamics, gravity, inverse_dynamics, kinetic_energy, passive_forces,
    potential_energy, spatial_momentum,
};
pub use kinematics::{Pose, axis_rotation, link_poses, rpy_matrix};
pub use rnea::rnea;
pub use scene::{Scene, SlipLaw};

#[cfg(test)]
mod tests {
    //! Two descriptions of one mechanism must give the same dynamics.
    use super::test_models::*;
    use super::*;
    use nalgebra::{DVector, Vector3};

    /// A joint whose origin is rotated by `rpy` is the same as an unrotated joint with
    /// the axis, centre of mass and inertia rotated by `R = Rot(rpy)`; a child of it
    /// then sits at `R · xyz` with the origin rotation `rpy` carried over.
    #[test]
    fn rpy_origin_equals_rotated_axis() {
        let rpy = Vector3::new(0.3, -0.7, 1.1);
        let r = rpy_matrix(&rpy);
        let axis = Vector3::new(0.2, 0.5, 1.0).normalize();
        let mut a = double_pendulum(1.0, 1.0, 0.5, 0.7);
        a.gravity = Vector3::new(0.4, -9.0, 2.0);
        a.links[0].origin_rpy = rpy;
        a.links[0].joint = JointKind::Revolute { axis };
        a.links[0].inertia[(0, 1)] = 0.01;
        a.links[0].inertia[(1, 0)] = 0.01;
        a.links[1].origin_xyz = Vector3::new(1.0, 0.2, -0.1);
        let mut b = a.clone();
        b.links[0].origin_rpy = Vector3::zeros();
        b.links[0].joint = JointKind::Revolute { axis: r * axis };
        b.links[0].com = r * a.links[0].com;
        b.links[0].inertia = r * a.links[0].inertia * r.transpose();
        b.links[1].origin_xyz = r * a.links[1].origin_xyz;
        b.links[1].origin_rpy = rpy;
        let q = DVector::from_vec(vec![0.8, -0.3]);
        let v = DVector::from_vec(vec![-1.0, 0.6]);
        let acc = DVector::from_vec(vec![0.2, 0.9]);
        assert!((crba(&a, &q) - crba(&b, &q)).norm() < 1e-12);
        assert!((rnea(&a, &q, &v, &acc) - rnea(&b, &q, &v, &acc)).norm() < 1e-12);
        assert!((potential_energy(&a, &q) - potential_energy(&b, &q)).abs() < 1e-12);
    }

    /// The Coriolis matrix of the double pendulum against its closed form.
    #[test]
    fn double_pendulum_coriolis_matches_closed_form() {
        let (m2, l1, l2) = (0.5, 1.0, 0.7);
        let model = double_pendulum(1.0, l1, m2, l2);
        let q = DVector::from_vec(vec![0.3_f64, -1.2]);
        let v = DVector::from_vec(vec![0.7, 1.9]);
        let h = m2 * l1 * l2 / 2.0 * q[1].sin();
        let expected = nalgebra::DMatrix::from_row_slice(
            2,
            2,
            &[-h * v[1], -h * (v[0] + v[1]), h * v[0], 0.0],
        );
        assert!((coriolis_matrix(&model, &q, &v) - expected).norm() < 1e-12);
    }
}
