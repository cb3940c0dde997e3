//! Geometry below everything that moves: rotations as unit quaternions and the maps of
//! SO(3) (exponential, logarithm, the derivatives of the exponential). The Lie-group
//! methods ([`crate::liegroup`]) and the numeric reference ([`crate::numeric`]) both
//! build on it; it imports neither.

pub mod so3;

pub use so3::UnitQuat;
