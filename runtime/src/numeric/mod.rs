//! Plain numeric dynamics over a runtime [`Model`].
mod model;
pub use model::*;
