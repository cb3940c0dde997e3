//! Non-smooth elements on joint coordinates (theory.md §1, §3): Bingham dash-pots,
//! Coulomb friction and unilateral stops, and what an integrator needs of them.
//!
//! Each element `e` acts along one joint coordinate `c = e.coordinate` and carries a
//! force `f_e`; the momentum balance is
//!
//! ```text
//! M(q) v̇ + C(q, v) v + g(q) = τ(t, q, v) + τ_p(q, v) − Σ_e f_e · e_c
//! ```
//!
//! so a positive dash-pot force resists a positive velocity, and a stop's contact force
//! pushes the coordinate back into its admissible side. Because the elements act on
//! coordinates, their Delassus operator `W = J M⁻¹ Jᵀ` is the submatrix of
//! [`NonSmooth::inverse_mass_matrix`] at their coordinates.

mod element;
mod event;
mod mode;
mod problem;

pub use element::*;
pub use event::{event_driven, solve_nonsmooth, solve_nonsmooth_with};
pub use mode::Mode;
pub use problem::*;
pub mod law;
mod timestepping;

pub use timestepping::time_stepping;
