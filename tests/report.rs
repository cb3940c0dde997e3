//! The report's code paths run on a tiny configuration (timings are not checked here:
//! they belong in the report itself).

#[path = "../examples/report/main.rs"]
mod report;

#[test]
fn report_runs_on_a_tiny_configuration() {
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("report-tiny");
    let _ = std::fs::remove_dir_all(&dir);
    let path = report::run(&report::Config::tiny(dir.clone())).expect("report runs");
    let text = std::fs::read_to_string(path).expect("report written");
    for section in [
        "## Summary",
        "## Work-precision",
        "## Kernels",
        "## Expansion",
        "## Release compile time",
    ] {
        assert!(text.contains(section), "missing section {section}");
    }
    assert!(
        !text.contains("**failed**"),
        "a run failed on the tiny configuration:\n{text}"
    );
    assert!(
        dir.join("wp_doublependulum.svg").exists(),
        "work-precision plot written"
    );
}
