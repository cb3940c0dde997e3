//! The trait the derive implements for scenes with Lie-group joints (`spherical`,
//! `free`), and the adapter that integrates such a scene with [`super::Rkmk5`].
//!
//! # Coordinates
//!
//! Links are in topological order and each contributes, in that order, to
//!
//! * the **configuration** `q ∈ ℝ^NQ`: one slot per revolute or prismatic joint, four
//!   slots `(w, x, y, z)` — a unit quaternion, the rotation of the link frame relative
//!   to its joint frame — per spherical joint, and for a free joint three slots (the
//!   position of the body's frame in the joint frame's axes) followed by its quaternion;
//! * the **velocity** `v ∈ ℝ^N`: one per revolute or prismatic joint, the body angular
//!   velocity `ω` (three, in the link frame) per spherical joint, and for a free joint
//!   the translational velocity `ṗ` (three, joint-frame axes) followed by `ω`.
//!
//! A free joint is therefore SO(3) × ℝ³, not SE(3): the translation is a vector space
//! with vanishing structure constants, so the `ad` term of the Coriolis matrix is
//! confined to the 3 × 3 rotation blocks, gravity is a constant force on `ṗ`, and the
//! position integrates as `p ← p + h ṗ` — cheaper than SE(3)'s coupled
//! `ad = [[ω̂, v̂], [0, ω̂]]`, with the same configurations.
//!
//! Around the current configuration, local exponential coordinates `φ`
//! (`R = R₀ exp(φ̂)`, `φ = 0` now; `φ = q` on Euclidean coordinates) are the coordinates
//! of the derivatives: `∂/∂φ_k` is the derivative along `R₀ exp(t ê_k)` at `t = 0`.

use nalgebra::{SMatrix, SVector};

use crate::numeric::Model;
use crate::system::{ForwardJacobian, ParameterError};

/// A rigid multibody tree with Lie-group joints: `N` velocity coordinates and `NQ`
/// configuration slots (see the [module documentation](self) for the layout).
///
/// The equations of motion are, with `v` the body velocities (quasi-velocities),
///
/// ```text
/// M(q) v̇ + C(q, v) v + g(q) = τ + τ_p(q, v)
/// ```
///
/// All methods are straight-line generated code. The quaternions in `q` must be of unit
/// norm (the rotation is formed as a quadratic polynomial in them).
pub trait LieMechanism<const N: usize, const NQ: usize> {
    /// Number of velocity coordinates (degrees of freedom).
    const DOF: usize = N;
    /// Number of configuration slots.
    const CONFIG: usize = NQ;
    /// A name for every velocity coordinate: the joint name, with `.wx`, `.wy`, `.wz`
    /// (body angular velocity) or `.x`, `.y`, `.z` (translation) for three-dof joints.
    const COORDINATES: [&'static str; N];
    /// For every rotation (spherical joints and the rotational part of free joints), in
    /// joint order: `(slot of w in q, index of ω_x in v)`.
    const ROTATIONS: &'static [(usize, usize)];
    /// For every Euclidean coordinate (revolute, prismatic, the translation of free
    /// joints), in joint order: `(slot in q, index in v)`.
    const EUCLID: &'static [(usize, usize)];

    /// Mass matrix `M(q)`, symmetric positive definite.
    fn mass_matrix(&self, q: &SVector<f64, NQ>) -> SMatrix<f64, N, N>;
    /// Coriolis matrix: `C_ij = Σ_k ½ (∂M_ij/∂φ_k + ∂M_ik/∂φ_j − ∂M_jk/∂φ_i) v_k +
    /// (M v)·[e_i, e_j]`. It has the same `C v` as theory §2's
    /// `Σ_k (∂M_ij/∂φ_k − ½ ∂M_jk/∂φ_i) v_k − [ad_vᵀ M]_ij`, and keeps `Ṁ − 2C`
    /// skew-symmetric.
    fn coriolis_matrix(&self, q: &SVector<f64, NQ>, v: &SVector<f64, N>) -> SMatrix<f64, N, N>;
    /// Generalised gravity force `g = ∂U/∂φ`.
    fn gravity(&self, q: &SVector<f64, NQ>) -> SVector<f64, N>;
    /// `C(q, v) v + g(q)`.
    fn bias(&self, q: &SVector<f64, NQ>, v: &SVector<f64, N>) -> SVector<f64, N>;
    /// Passive forces of springs and dampers on the Euclidean coordinates.
    fn passive_forces(&self, q: &SVector<f64, NQ>, v: &SVector<f64, N>) -> SVector<f64, N>;
    /// `τ = M a + C v + g − τ_p`.
    fn inverse_dynamics(
        &self,
        q: &SVector<f64, NQ>,
        v: &SVector<f64, N>,
        a: &SVector<f64, N>,
    ) -> SVector<f64, N>;
    /// `v̇ = M⁻¹ (τ + τ_p − C v − g)`.
    fn forward_dynamics(
        &self,
        q: &SVector<f64, NQ>,
        v: &SVector<f64, N>,
        tau: &SVector<f64, N>,
    ) -> SVector<f64, N>;
    /// Forward dynamics with its Jacobian; `d_dq` is with respect to the local
    /// exponential coordinates `φ` (see the module documentation), `d_dv` to `v`.
    fn forward_dynamics_jacobian(
        &self,
        q: &SVector<f64, NQ>,
        v: &SVector<f64, N>,
        tau: &SVector<f64, N>,
    ) -> ForwardJacobian<N>;
    /// Kinetic energy `½ vᵀ M v`.
    fn kinetic_energy(&self, q: &SVector<f64, NQ>, v: &SVector<f64, N>) -> f64;
    /// Potential energy of gravity and springs.
    fn potential_energy(&self, q: &SVector<f64, NQ>) -> f64;
    /// Checks every parameter; see [`crate::Mechanism::validate`].
    fn validate(&self) -> Result<(), ParameterError> {
        Ok(())
    }
    /// The same system as a plain numeric description (joint kinds
    /// [`JointKind::Spherical`](crate::numeric::JointKind::Spherical) and
    /// [`JointKind::Translation`](crate::numeric::JointKind::Translation) included).
    fn model(&self) -> Model;

    /// The configuration with every coordinate zero and every rotation the identity.
    fn identity_configuration() -> SVector<f64, NQ> {
        let mut q = SVector::<f64, NQ>::zeros();
        for &(s, _) in Self::ROTATIONS {
            q[s] = 1.0;
        }
        q
    }
}
