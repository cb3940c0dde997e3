//! The arm that comes to rest on its joint limit (`filippov::scenes::RestingArm`), with
//! what `tests/resting.rs`, `tests/time_stepping.rs`, the report and the `ensemble`
//! example use beside it.

use filippov::nalgebra::SVector;
pub use filippov::scenes::RestingArm;

pub type V2 = SVector<f64, 2>;

/// No applied force.
pub fn zero(_t: f64, _q: &V2, _v: &V2) -> V2 {
    V2::zeros()
}
