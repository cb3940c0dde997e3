//! Contacts between bodies and planes (`#[contact(…)]`, theory §8): the mode selection
//! of closed planar contacts as a linear complementarity problem ([`planar`]), and
//! Moreau–Jean time-stepping with it ([`stepping`]), and event-driven integration with
//! exact switching ([`event`]).

pub(crate) mod cone;
pub(crate) mod event;
pub(crate) mod planar;
pub(crate) mod stepping;
