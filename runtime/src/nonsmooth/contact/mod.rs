//! Contacts between bodies and planes (`#[contact(…)]`, theory §8): the mode selection
//! of closed planar contacts as a linear complementarity problem ([`planar`]).

pub(crate) mod planar;
