//! The randomized agreement suite (see `examples/support/agreement.rs`): random chains
//! with random non-smooth elements, event-driven against time-stepping and passivity.
//! A small count here; the report runs a thousand and more.

#[path = "../examples/support/agreement.rs"]
mod agreement;

#[test]
fn random_scenes_agree() {
    let count = std::env::var("FILIPPOV_AGREEMENT_SCENES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(60);
    let (passed, typed, failed) = agreement::suite(1, count);
    eprintln!(
        "{count} random scenes: {passed} passed, {} typed errors, {} failures",
        typed.len(),
        failed.len()
    );
    for (seed, m) in &typed {
        eprintln!("  typed error, seed {seed}: {m}");
    }
    let described: Vec<String> = failed
        .iter()
        .map(|(seed, m)| format!("seed {seed}: {m}\n  {}", agreement::summary(*seed)))
        .collect();
    assert!(failed.is_empty(), "failures:\n{}", described.join("\n"));
}
