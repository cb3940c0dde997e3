//! Runtime of filippov.
pub mod numeric;
pub mod system;
