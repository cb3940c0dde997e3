//! The randomized agreement suite for contacts (`examples/support/contact_agreement.rs`):
//! random boxes launched along inclines, balls dropped spinning and rods tipping over,
//! event-driven against
//! time-stepping at three steps, passivity and no penetration.

#[path = "../examples/support/contact_agreement.rs"]
mod contact_agreement;

#[test]
fn random_contact_scenes_agree_and_stay_passive() {
    let results: Vec<_> = (0..30).map(contact_agreement::run).collect();
    for r in &results {
        eprintln!(
            "seed {:>2} {:<4}: energy rise {:.1e}, penetration {:.1e}, time-stepping {:.1e} → {:.1e} → {:.1e}, {} switches{}",
            r.seed,
            r.kind,
            r.energy_rise,
            r.penetration,
            r.distance[0],
            r.distance[1],
            r.distance[2],
            r.switches,
            r.failure
                .as_deref()
                .map(|f| format!(" FAILED: {f}"))
                .unwrap_or_default()
        );
    }
    let failed: Vec<u64> = results
        .iter()
        .filter(|r| !r.passed())
        .map(|r| r.seed)
        .collect();
    assert!(failed.is_empty(), "scenes {failed:?} failed");
}
