//! The randomized agreement suite (see `examples/support/agreement.rs`) at scale:
//! N random scenes, each event-driven against time-stepping and checked for passivity;
//! counts, and every typed error and failure with its seed and scene.

use super::agreement_support as agreement;
use super::config::Config;
use super::markdown::Page;
use super::workprecision::Section;

pub fn agreement(config: &Config) -> Section {
    let mut page = Page::empty();
    let count: u64 = match config.name {
        "tiny" => 12,
        "long" => 5000,
        _ => 1000,
    };
    page.h2("Randomized agreement suite");
    page.para(&format!(
        "{count} random scenes (seeds 1–{count}): planar or spatial chains of 1–7 revolute or prismatic joints with gravity, springs and dampers at random, \
         one or two non-smooth elements (Coulomb friction, linear, cubic or non-monotone Bingham — S4's law under either selection —, rigid stops with restitution, spring-backed stops) and a sinusoidal force or none; \
         initial states moving, stuck, at rest on a stop, or penetrating a rigid stop (which both integrators must refuse). \
         Each runs event-driven (DOPRI5, rtol 1e-8, ≤ 20,000 step attempts) and time-stepping (θ = 1) over [0, 1] at h = 1e-3, 2.5e-4, … refined by 4× down to 3.9e-6 while \
         the runs are pre-asymptotic; it passes when both complete, time-stepping converges to the event-driven end state (a refinement that shrinks the distance to ≤ 0.6× \
         and to a new minimum, or a distance below 1e-4 from the second step on), and the event-driven run is passive \
         (energy gained ≤ work of the force + 1e-3 of the energy scale). The scenes are numeric models (`runtime::numeric::Scene`), not derived ones, so thousands can be generated."
    ));
    let start = std::time::Instant::now();
    let (passed, typed, failed) = agreement::suite(1, count);
    let secs = start.elapsed().as_secs_f64();
    page.table(
        &["scenes", "passed", "typed errors", "failures", "time [s]"],
        &[vec![
            count.to_string(),
            passed.to_string(),
            typed.len().to_string(),
            failed.len().to_string(),
            format!("{secs:.1}"),
        ]],
    );
    if !typed.is_empty() {
        page.para("Typed errors (event-driven gave up and said why; time-stepping integrates these runs):");
        let rows: Vec<Vec<String>> = typed
            .iter()
            .map(|(seed, m)| vec![seed.to_string(), m.clone(), agreement::summary(*seed)])
            .collect();
        page.table(&["seed", "error", "scene"], &rows);
    }
    if !failed.is_empty() {
        page.para("**Failures** (each a seed to reproduce with `examples/support/agreement.rs`):");
        let rows: Vec<Vec<String>> = failed
            .iter()
            .map(|(seed, m)| vec![seed.to_string(), m.clone(), agreement::summary(*seed)])
            .collect();
        page.table(&["seed", "what failed", "scene"], &rows);
    }
    super::markdown::headline(
        "Event-driven and time-stepping agree on random non-smooth scenes (1–7 joints, friction, dash-pots, stops)",
        format!("{passed} of {count} agree"),
        "Moreau time-stepping refined as h → 0",
        format!("{} typed errors, {} failures", typed.len(), failed.len()),
        "independent methods on the same scene; see the agreement section for the criterion",
    );
    let summary = vec![format!(
        "Randomized agreement suite: {count} random scenes, {passed} passed, {} typed errors, {} failures{} ({secs:.0} s)",
        typed.len(),
        failed.len(),
        if failed.is_empty() {
            String::new()
        } else {
            format!(
                " (seeds {})",
                failed
                    .iter()
                    .map(|(s, _)| s.to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        }
    )];
    Section { page, summary }
}
