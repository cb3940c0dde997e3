//! Contacts of points and spheres with planes (`#[contact(…)]`, theory §8): the
//! kinematics the derive writes out for each, unrolled like the other kernels.
//!
//! A contact is a point or a sphere on a body and a plane, fixed in the world or carried
//! by another body. Its gap `g_N(q)` is the sphere's distance from the plane (negative in
//! penetration); `W_N = ∂g_N/∂q` gives the normal velocity `W_N v`; the rows of `W_T`
//! give the contact points' relative velocity along the plane's tangent directions (one
//! row per tangent that the mechanism can move along: a planar mechanism keeps one),
//! which for a sphere is its slip, not the motion of its centre. `γ = −Ẇ v` completes
//! each to an acceleration: `W v̇ − γ`.

use nalgebra::{SMatrix, SVector};

use crate::element::Element;
use crate::system::Mechanism;

/// The contacts of a mechanism: `K` contacts on `N` coordinates with `T` tangent rows.
#[diagnostic::on_unimplemented(
    message = "`{Self}` has no contacts: it declares no `#[contact(…)]`",
    label = "needs contacts",
    note = "a contact is declared with `#[contact(<name>: point | sphere(<radius>), body = <body>, at = [...], plane = world, normal = y, mu = …, restitution = …)]`"
)]
pub trait Contacts<const N: usize, const K: usize, const T: usize>: Mechanism<N> {
    /// The contacts' names, as declared.
    const CONTACTS: [&'static str; K];
    /// The tangent rows' names, `<contact>.<axis of the plane's frame>`.
    const TANGENTS: [&'static str; T];
    /// The contact each tangent row belongs to (an index into [`CONTACTS`](Self::CONTACTS)).
    const TANGENT_OF: [usize; T];

    /// Coulomb friction coefficients `μ`, one per contact.
    fn contact_friction(&self) -> [f64; K];
    /// Newton's coefficients of restitution `e`, one per contact.
    fn contact_restitution(&self) -> [f64; K];
    /// Static friction coefficients `μ_s ≥ μ`, one per contact: a stuck contact holds
    /// while `|λ_T| ≤ μ_s λ_N`, a sliding one carries `μ λ_N`. `μ` where a contact gives
    /// no `mu_static`.
    fn contact_static_friction(&self) -> [f64; K] {
        self.contact_friction()
    }

    /// The gaps `g_N(q)`: positive apart, zero touching, negative in penetration.
    fn contact_gaps(&self, q: &SVector<f64, N>) -> SVector<f64, K>;
    /// `W_N(q) = ∂g_N/∂q`.
    fn contact_normal_jacobian(&self, q: &SVector<f64, N>) -> SMatrix<f64, K, N>;
    /// `γ_N(q, v) = −Ẇ_N v`.
    fn contact_normal_gamma(&self, q: &SVector<f64, N>, v: &SVector<f64, N>) -> SVector<f64, K>;
    /// `W_T(q)`: the tangential relative velocities of the contact points are `W_T v`.
    fn contact_tangent_jacobian(&self, q: &SVector<f64, N>) -> SMatrix<f64, T, N>;
    /// `γ_T(q, v) = −Ẇ_T v`.
    fn contact_tangent_gamma(&self, q: &SVector<f64, N>, v: &SVector<f64, N>) -> SVector<f64, T>;

    /// The non-smooth elements on joint coordinates (`#[friction]`, `#[stop]`, …) the
    /// scene declares beside its contacts, with their parameters evaluated.
    fn joint_elements(&self) -> Vec<Element> {
        Vec::new()
    }

    /// Which of [`joint_elements`](Self::joint_elements) are bearing friction (see
    /// [`NonSmooth::BEARINGS`](crate::nonsmooth::NonSmooth::BEARINGS)).
    const JOINT_BEARINGS: &'static [usize] = &[];

    /// Their load-dependent limits (see
    /// [`NonSmooth::bearing_limits`](crate::nonsmooth::NonSmooth::bearing_limits)).
    fn joint_bearing_limits(
        &self,
        _q: &SVector<f64, N>,
        _v: &SVector<f64, N>,
        _a: &SVector<f64, N>,
        _limits: &mut [f64],
    ) {
    }
}
