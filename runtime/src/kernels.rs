//! Kernels no integrator calls, which the derive emits only when a scene asks for them
//! by name: `#[mechanism(emit = [coriolis, energy, …])]`, or `emit = all`.
//!
//! Each is its own trait so that a scene that did not ask has no such code at all (the
//! Christoffel symbols alone are O(n³) expressions: most of a long chain's code), and a
//! program that needs one fails to compile with a message naming the option. The core
//! traits, [`Mechanism`](crate::Mechanism) and [`LieMechanism`](crate::LieMechanism),
//! carry what the integrators call: the mass matrix, forward dynamics and its Jacobian.
//!
//! | `emit = [...]` | trait | methods |
//! |---|---|---|
//! | `christoffel` | [`Christoffel`] | `christoffel_symbols` (not for Lie-group scenes) |
//! | `coriolis` | [`Coriolis`] | `coriolis_matrix` |
//! | `gravity` | [`Gravity`] | `gravity` |
//! | `bias` | [`Bias`] | `bias` |
//! | `passive_forces` | [`PassiveForces`] | `passive_forces` |
//! | `inverse_dynamics` | [`InverseDynamics`] | `inverse_dynamics` |
//! | `energy` | [`Energy`] | `kinetic_energy`, `potential_energy` |
//! | `delassus` | inherent | `delassus` (scenes with non-smooth elements) |
//! | `dae_residuals` | inherent | `momentum_residual`, `constitutive_residual` |
//! | `switching_functions` | inherent | `switching_functions` |
//!
//! The traits take the number of velocity coordinates `N` and of configuration slots
//! `NQ` (equal to `N` unless the scene has spherical or free joints, whose quaternions
//! take four slots for three velocities).

use nalgebra::{SMatrix, SVector};

/// Christoffel symbols of the first kind, `#[mechanism(emit = [christoffel])]`.
#[diagnostic::on_unimplemented(
    message = "`{Self}` has no Christoffel symbols: they are emitted only on request",
    label = "needs `christoffel_symbols`",
    note = "add `emit = [christoffel]` (or `emit = all`) to the scene's `#[mechanism(...)]`"
)]
pub trait Christoffel<const N: usize> {
    /// `out[i][(j, k)] = c_ijk = ½ (∂M_ij/∂q_k + ∂M_ik/∂q_j − ∂M_jk/∂q_i)`.
    fn christoffel_symbols(&self, q: &SVector<f64, N>) -> [SMatrix<f64, N, N>; N];
}

/// The Coriolis matrix, `#[mechanism(emit = [coriolis])]`.
#[diagnostic::on_unimplemented(
    message = "`{Self}` has no Coriolis matrix: it is emitted only on request",
    label = "needs `coriolis_matrix`",
    note = "add `emit = [coriolis]` (or `emit = all`) to the scene's `#[mechanism(...)]`"
)]
pub trait Coriolis<const N: usize, const NQ: usize = N> {
    /// `C_ij = Σ_k c_ijk v_k` (for Lie-group scenes plus `(M v)·[e_i, e_j]`, see
    /// [`LieMechanism`](crate::LieMechanism)); `Ṁ − 2C` is skew-symmetric.
    fn coriolis_matrix(&self, q: &SVector<f64, NQ>, v: &SVector<f64, N>) -> SMatrix<f64, N, N>;
}

/// Generalised gravity forces, `#[mechanism(emit = [gravity])]`.
#[diagnostic::on_unimplemented(
    message = "`{Self}` has no `gravity` kernel: it is emitted only on request",
    label = "needs `gravity`",
    note = "add `emit = [gravity]` (or `emit = all`) to the scene's `#[mechanism(...)]`"
)]
pub trait Gravity<const N: usize, const NQ: usize = N> {
    /// `g(q) = ∂U_gravity/∂q`.
    fn gravity(&self, q: &SVector<f64, NQ>) -> SVector<f64, N>;
}

/// Bias forces, `#[mechanism(emit = [bias])]`.
#[diagnostic::on_unimplemented(
    message = "`{Self}` has no `bias` kernel: it is emitted only on request",
    label = "needs `bias`",
    note = "add `emit = [bias]` (or `emit = all`) to the scene's `#[mechanism(...)]`"
)]
pub trait Bias<const N: usize, const NQ: usize = N> {
    /// `C(q, v) v + g(q)`.
    fn bias(&self, q: &SVector<f64, NQ>, v: &SVector<f64, N>) -> SVector<f64, N>;
}

/// Spring and damper forces, `#[mechanism(emit = [passive_forces])]`.
#[diagnostic::on_unimplemented(
    message = "`{Self}` has no `passive_forces` kernel: it is emitted only on request",
    label = "needs `passive_forces`",
    note = "add `emit = [passive_forces]` (or `emit = all`) to the scene's `#[mechanism(...)]`"
)]
pub trait PassiveForces<const N: usize, const NQ: usize = N> {
    /// Passive forces of springs and dampers on joint coordinates, `τ_p(q, v)`.
    fn passive_forces(&self, q: &SVector<f64, NQ>, v: &SVector<f64, N>) -> SVector<f64, N>;
}

/// Inverse dynamics, `#[mechanism(emit = [inverse_dynamics])]`.
#[diagnostic::on_unimplemented(
    message = "`{Self}` has no `inverse_dynamics` kernel: it is emitted only on request",
    label = "needs `inverse_dynamics`",
    note = "add `emit = [inverse_dynamics]` (or `emit = all`) to the scene's `#[mechanism(...)]`"
)]
pub trait InverseDynamics<const N: usize, const NQ: usize = N> {
    /// `τ = M a + C v + g − τ_p`: the input forces that produce acceleration `a`.
    fn inverse_dynamics(
        &self,
        q: &SVector<f64, NQ>,
        v: &SVector<f64, N>,
        a: &SVector<f64, N>,
    ) -> SVector<f64, N>;
}

/// Kinetic and potential energy, `#[mechanism(emit = [energy])]`.
#[diagnostic::on_unimplemented(
    message = "`{Self}` has no energy kernels: they are emitted only on request",
    label = "needs `kinetic_energy` and `potential_energy`",
    note = "add `emit = [energy]` (or `emit = all`) to the scene's `#[mechanism(...)]`"
)]
pub trait Energy<const N: usize, const NQ: usize = N> {
    /// Kinetic energy `½ vᵀ M v`.
    fn kinetic_energy(&self, q: &SVector<f64, NQ>, v: &SVector<f64, N>) -> f64;
    /// Potential energy of gravity and springs.
    fn potential_energy(&self, q: &SVector<f64, NQ>) -> f64;
    /// `kinetic_energy + potential_energy`.
    fn total_energy(&self, q: &SVector<f64, NQ>, v: &SVector<f64, N>) -> f64 {
        self.kinetic_energy(q, v) + self.potential_energy(q)
    }
}
