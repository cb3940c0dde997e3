//! Contacts between bodies and planes (`#[contact(…)]`, theory §8): the mode selection
//! of closed planar contacts as a linear complementarity problem ([`planar`]); a time
//! step's problem with the exact friction cone, and joint friction and stops beside
//! contacts, by Gauss–Seidel ([`cone`]); Moreau–Jean time-stepping with either
//! ([`stepping`]); and event-driven integration of planar contacts with exact switching
//! ([`event`]).

pub(crate) mod cone;
pub(crate) mod event;
pub(crate) mod planar;
pub(crate) mod stepping;
