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
//!
//! Contacts (`#[contact]`) act along their gap's and slip's Jacobian rows instead; the
//! selection of their modes (closed or lifting off, stuck or breaking away) is a linear
//! complementarity problem (`contact`).

#[allow(dead_code)] // parts of the contact problem the event-driven integrator will read
mod bearing;
mod contact;
mod event;
mod integrator;
mod kind;
mod mode;
mod problem;
mod solve;

pub use crate::element::{
    Element, ElementKind, Law, Mode, NonSmooth, Relation, Selection, Side, StopKind,
};
pub use contact::event::contact_event_driven;
pub use contact::stepping::contact_time_stepping;
pub use event::event_driven;
pub use event::resting::{RESTING_DRIFT, RESTING_PERIODS, resting_periods};
pub use integrator::{Integrator, NoInput, Stepped};
pub use problem::*;
pub use solve::{solve_nonsmooth, solve_nonsmooth_with};
pub mod law;
pub mod lockstep;
mod timestepping;

pub use timestepping::time_stepping;
