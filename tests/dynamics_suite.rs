//! The integration tests of the generated kernels, the smooth and Lie-group integrators,
//! closed loops, URDF robots and ensembles, as one test binary (one build and link, every
//! test in one harness; `Cargo.toml` lists the test targets). Each file is a module:
//! `cargo test --test dynamics_suite lie::` runs one.

#[path = "algorithms.rs"]
mod algorithms;
#[path = "compact.rs"]
mod compact;
#[path = "conservative.rs"]
mod conservative;
#[path = "ensemble.rs"]
mod ensemble;
#[path = "frames.rs"]
mod frames;
#[path = "generic.rs"]
mod generic;
#[path = "identification.rs"]
mod identification;
#[path = "integration.rs"]
mod integration;
#[path = "lie.rs"]
mod lie;
#[path = "lockstep.rs"]
mod lockstep;
#[path = "loops.rs"]
mod loops;
#[path = "mirrored_enums.rs"]
mod mirrored_enums;
#[path = "point_springs.rs"]
mod point_springs;
#[path = "random_trees.rs"]
mod random_trees;
#[path = "solve_regression.rs"]
mod solve_regression;
#[path = "urdf.rs"]
mod urdf;
