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

/// Every file in `tests/` runs: it is one of the test targets `Cargo.toml` lists, or a
/// module of one of the two suites (`autotests = false`, so cargo would not find a new
/// file by itself).
#[test]
fn every_test_file_is_a_target_or_a_suites_module() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let read = |p: &str| std::fs::read_to_string(dir.join(p)).expect(p);
    let manifest = read("Cargo.toml");
    let suites = read("tests/nonsmooth_suite.rs") + &read("tests/dynamics_suite.rs");
    let mut missing = Vec::new();
    for entry in std::fs::read_dir(dir.join("tests")).expect("tests/") {
        let path = entry.expect("entry").path();
        if path.extension().is_none_or(|e| e != "rs") {
            continue;
        }
        let stem = path.file_stem().and_then(|s| s.to_str()).expect("a name");
        let target = manifest.contains(&format!("[[test]]\nname = \"{stem}\""));
        let module = suites.contains(&format!("#[path = \"{stem}.rs\"]\nmod {stem};"));
        if !(target || module) {
            missing.push(stem.to_string());
        }
    }
    assert!(
        missing.is_empty(),
        "tests/{{{}}}.rs run nowhere: add each to tests/nonsmooth_suite.rs or tests/dynamics_suite.rs as a module, or list it as a [[test]] in Cargo.toml",
        missing.join(",")
    );
}
