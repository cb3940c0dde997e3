//! filippov: compile-time specialised simulators for rigid multibody systems.
pub use filippov_runtime as runtime;
