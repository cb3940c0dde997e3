//! The report's code paths run on a tiny configuration (timings are not checked here:
//! they belong in the report itself). Its sections run as two reports, one per test, so
//! that the test harness runs them side by side. (`cargo test --example report`: the
//! report is a test target of its own, see `Cargo.toml`.)

use crate as report;

/// The report of `sections` on the tiny configuration: it runs, every run in it
/// succeeds, and it has the headings `expected`. Returns its directory.
fn tiny(name: &str, sections: &[&str], expected: &[&str]) -> std::path::PathBuf {
    // Where cargo puts integration tests' scratch files (`CARGO_TARGET_TMPDIR`, which it
    // sets for those only).
    let dir = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("target/tmp")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    let mut config = report::Config::tiny(dir.clone());
    config.only = Some(sections.iter().map(|s| s.to_string()).collect());
    let path = report::run(&config).expect("report runs");
    let text = std::fs::read_to_string(path).expect("report written");
    for section in std::iter::once(&"## Summary").chain(expected) {
        assert!(text.contains(section), "missing section {section}");
    }
    assert!(
        !text.contains("**failed**"),
        "a run failed on the tiny configuration:\n{text}"
    );
    dir
}

/// Every section is in one of the two tests.
#[test]
fn the_two_halves_cover_every_section() {
    let mut all: Vec<&str> = FIRST.iter().chain(SECOND).copied().collect();
    all.sort_unstable();
    let mut sections = report::SECTIONS.to_vec();
    sections.sort_unstable();
    assert_eq!(all, sections);
}

const FIRST: &[&str] = &[
    "smooth",
    "nonsmooth",
    "dense",
    "agreement",
    "s9",
    "lie",
    "ensembles",
];
const SECOND: &[&str] = &[
    "loops",
    "contacts",
    "kernels",
    "expansion",
    "compile",
    "scaling",
    "chains",
    "urdf",
    "ops",
    "scalars",
    "flags",
];

#[test]
fn report_runs_the_integrators_sections() {
    let dir = tiny(
        "report-tiny-runs",
        FIRST,
        &["## Work-precision", "## Ensembles in lockstep"],
    );
    assert!(
        dir.join("wp_doublependulum.svg").exists(),
        "work-precision plot written"
    );
}

#[test]
fn report_runs_the_kernels_sections() {
    tiny(
        "report-tiny-kernels",
        SECOND,
        &[
            "## Kernels",
            "## Expansion",
            "## Release compile time",
            "## Operation counts per kernel",
        ],
    );
}
