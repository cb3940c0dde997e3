//! The randomized agreement suite for contacts (`examples/support/contact_agreement.rs`):
//! random boxes launched along inclines, balls dropped spinning and rods tipping over,
//! event-driven against time-stepping at three steps, passivity and no penetration; and
//! the spatial suite (`spatial_agreement.rs`) by time-stepping alone.

#[path = "../../examples/support/contact_agreement.rs"]
mod contact_agreement;

/// A scene's line's ending: its failure, if it had one.
fn failed_with(failure: Option<&str>) -> String {
    failure.map(|f| format!(" FAILED: {f}")).unwrap_or_default()
}

/// Fails the test naming the seeds of the scenes that did not pass.
fn assert_none_failed(failed: impl Iterator<Item = u64>) {
    let failed: Vec<u64> = failed.collect();
    assert!(failed.is_empty(), "scenes {failed:?} failed");
}

#[test]
fn random_contact_scenes_agree_and_stay_passive() {
    let results: Vec<_> = (0..30).map(contact_agreement::run).collect();
    for r in &results {
        eprintln!(
            "seed {:>2} {:<4}: energy rise {:.1e}, penetration {:.1e}, beyond the cone {:.1e}, time-stepping {:.1e} → {:.1e} → {:.1e}, {} switches{}",
            r.seed,
            r.kind,
            r.energy_rise,
            r.penetration,
            r.cone_excess,
            r.distance[0],
            r.distance[1],
            r.distance[2],
            r.switches,
            failed_with(r.failure.as_deref())
        );
    }
    let failed = results.iter().filter(|r| !r.passed()).map(|r| r.seed);
    assert_none_failed(failed);
}

#[path = "../../examples/support/spatial_agreement.rs"]
mod spatial_agreement;

/// Random spatial scenes (tables, pucks) by time-stepping on the friction cone: solved,
/// passive, not sinking, first order. Twelve here (each is three runs down to h = 2e-5,
/// slow unoptimised); the report runs 120 and names the seeds that fail.
#[test]
fn random_spatial_scenes_are_solved_passive_and_first_order() {
    let results: Vec<_> = (0..12).map(spatial_agreement::run).collect();
    for r in &results {
        eprintln!(
            "seed {:>2} {:<5}: residual {:.1e}, energy gain {:.1e}, sinking {:.1e} m, \
             distance {:.1e} → {:.1e}{}{}",
            r.seed,
            r.kind,
            r.residual,
            r.energy_gain,
            r.sinking,
            r.distance[0],
            r.distance[1],
            r.finer.map_or(String::new(), |[a, b]| format!(
                " (against h = 4e-6: {a:.1e} → {b:.1e})"
            )),
            failed_with(r.failure.as_deref())
        );
    }
    let failed = results.iter().filter(|r| !r.passed()).map(|r| r.seed);
    assert_none_failed(failed);
}
