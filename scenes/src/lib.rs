//! The canonical scenes, for the tests, benchmarks, peers and report: the `scenes` module
//! of the main crate (feature `scenes`), re-exported under the name they have always
//! used here.

pub use filippov::scenes::*;
