//! Spatial (6D) vector algebra in Plücker coordinates, all expressed in the world frame.
//!
//! A motion vector is `(ω, v_O)`: angular velocity and the velocity of the body-fixed
//! point currently at the world origin; a force vector is `(n_O, f)`: moment about the
//! origin and force. Featherstone, *Rigid Body Dynamics Algorithms* (2008), §2.1–2.13:
//! `crm` is the motion cross product `v×` (eq. 2.31), `crf = −crmᵀ` the force cross
//! product `v×*` (eq. 2.32), and `inertia` the spatial inertia of eq. 2.63.

use nalgebra::{Matrix3, Matrix6, Vector3, Vector6};

/// `v̂` with `v̂ w = v × w`.
pub(crate) fn skew(v: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -v.z, v.y, v.z, 0.0, -v.x, -v.y, v.x, 0.0)
}

/// Motion cross product matrix `crm(v)`, `crm(v) m = v ×ₘ m`.
pub(crate) fn crm(v: &Vector6<f64>) -> Matrix6<f64> {
    let w = skew(&v.fixed_rows::<3>(0).into_owned());
    let u = skew(&v.fixed_rows::<3>(3).into_owned());
    let mut out = Matrix6::zeros();
    out.fixed_view_mut::<3, 3>(0, 0).copy_from(&w);
    out.fixed_view_mut::<3, 3>(3, 0).copy_from(&u);
    out.fixed_view_mut::<3, 3>(3, 3).copy_from(&w);
    out
}

/// Force cross product matrix `crf(v) = −crm(v)ᵀ`.
pub(crate) fn crf(v: &Vector6<f64>) -> Matrix6<f64> {
    -crm(v).transpose()
}

/// Spatial inertia about the world origin of a body of mass `m` whose centre of mass is
/// at `c` (world) with rotational inertia `i_c` about the centre of mass (world axes):
/// `[[I_c + m ĉ ĉᵀ, m ĉ], [m ĉᵀ, m 𝟙]]`.
pub(crate) fn inertia(m: f64, c: &Vector3<f64>, i_c: &Matrix3<f64>) -> Matrix6<f64> {
    let cx = skew(c);
    let mut out = Matrix6::zeros();
    out.fixed_view_mut::<3, 3>(0, 0)
        .copy_from(&(i_c + cx * cx.transpose() * m));
    out.fixed_view_mut::<3, 3>(0, 3).copy_from(&(cx * m));
    out.fixed_view_mut::<3, 3>(3, 0)
        .copy_from(&(cx.transpose() * m));
    out.fixed_view_mut::<3, 3>(3, 3)
        .copy_from(&(Matrix3::identity() * m));
    out
}
