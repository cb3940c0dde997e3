//! Mechanisms with closed kinematic loops: the constraints of their loop joints
//! (`#[loop_joint(…)]`), which the derive writes out like the other kernels.
//!
//! A loop joint cuts the mechanism's graph into its spanning tree, whose joint
//! coordinates `q` are the state, and a constraint `Φ(q) = 0` (theory §7). The derive
//! emits `Φ`, its Jacobian `G = ∂Φ/∂q` and the acceleration term `γ = −Ġ v` (so that
//! `G v̇ = γ` keeps `G v = 0`), each straight-line code with the rows that fold to zero
//! left out: a revolute loop joint of a planar mechanism has two rows, not five.

mod assemble;
pub mod error;
mod manifold;

pub use assemble::assemble;
pub use error::LoopError;
pub use manifold::{ROUND_OFF, SINGULAR_PIVOT, conditioning, project};

use nalgebra::{SMatrix, SVector};

use crate::system::Mechanism;

/// The constraints of a mechanism's loop joints, `M` rows on `N` tree coordinates.
#[diagnostic::on_unimplemented(
    message = "`{Self}` has no loop constraints: it declares no `#[loop_joint(…)]`",
    label = "needs loop constraints",
    note = "a joint that closes a kinematic loop is declared with `#[loop_joint(<name>: <kind>, parent = <body>, child = <body>, origin = …, child_origin = …)]`"
)]
pub trait LoopConstraints<const N: usize, const M: usize>: Mechanism<N> {
    /// The rows' names, `<loop joint>.<component>`: `x`, `y`, `z` for the distance
    /// between the joint's two frames (world axes; on a prismatic joint, the axes of
    /// its parent-side frame normal to its axis), `rx`, `ry`, `rz` for the small
    /// rotation a row locks (`r1`, `r2` about an oblique axis).
    const CONSTRAINTS: [&'static str; M];

    /// `Φ(q)`: zero where every loop is closed.
    fn constraint_residual(&self, q: &SVector<f64, N>) -> SVector<f64, M>;

    /// `G(q) = ∂Φ/∂q`.
    fn constraint_jacobian(&self, q: &SVector<f64, N>) -> SMatrix<f64, M, N>;

    /// `γ(q, v) = −Ġ v`: the constraint accelerations satisfy `G v̇ = γ`.
    fn constraint_gamma(&self, q: &SVector<f64, N>, v: &SVector<f64, N>) -> SVector<f64, M>;

    /// The accelerations of the closed mechanism and its constraint forces `λ`:
    /// `M v̇ = τ + τ_p − C v − g + Gᵀ λ` with `G v̇ = γ`. The accelerations are
    /// [`Mechanism::forward_dynamics`]'s.
    fn constrained_forward_dynamics(
        &self,
        q: &SVector<f64, N>,
        v: &SVector<f64, N>,
        tau: &SVector<f64, N>,
    ) -> (SVector<f64, N>, SVector<f64, M>);
}
