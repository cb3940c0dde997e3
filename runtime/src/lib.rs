//! Runtime of filippov.
//!
//! * [`system`]: the [`Mechanism`](system::Mechanism) trait generated kernels implement.
//! * [`numeric`]: an independent plain numeric implementation of the same physics
//!   (RNEA, CRBA, exact mass-matrix derivatives) over a runtime [`numeric::Model`].
pub mod numeric;
pub mod system;
