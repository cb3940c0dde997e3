//! A Panda read from its URDF file with every joint limit a rigid stop (restitution 0.5),
//! released at rest under gravity: it folds onto several of its limits, bounces, and
//! comes to rest on them. Event-driven (the default method) beside time-stepping at
//! h = 1e-3; prints each run's switch log summary and end state, plots the joint angles.
//!
//! Run: `cargo run --release --example panda_on_limits`; plot in `target/plots/`.

#[path = "support/mod.rs"]
mod support;

#[path = "support/panda_limits.rs"]
mod panda_limits;

use filippov::prelude::*;
use filippov::runtime::{NonSmoothMethod, NonSmoothProblem, SwitchKind, solve_nonsmooth};
use panda_limits::{PandaOnLimits, V7, release_pose, zero};

fn main() {
    let panda = PandaOnLimits { e: 0.5, fc: 5.0 };
    let p = NonSmoothProblem::new(0.0, 3.0, release_pose(), V7::zeros());
    let mut series = Vec::new();
    for (label, method) in [
        ("event-driven", NonSmoothMethod::default()),
        (
            "time-stepping h = 1e-3",
            NonSmoothMethod::TimeStepping {
                h: 1e-3,
                theta: 1.0,
            },
        ),
    ] {
        let start = std::time::Instant::now();
        let sol = match solve_nonsmooth(&panda, &zero, &p, &method) {
            Ok(s) => s,
            Err(e) => {
                eprintln!("{label}: failed: {e}");
                std::process::exit(1);
            }
        };
        let elapsed = start.elapsed();
        let count = |k: SwitchKind| sol.switches.iter().filter(|s| s.kind == k).count();
        println!(
            "{label}: {:.1} ms, {}; {} impacts, {} settled, {} mode switches, {} hand-overs",
            elapsed.as_secs_f64() * 1e3,
            sol.stats,
            count(SwitchKind::Impact),
            count(SwitchKind::Settled),
            count(SwitchKind::Mode),
            count(SwitchKind::HandOverToTimeStepping),
        );
        let (_, y) = sol.last().unwrap();
        println!("  end q = {:.4?}", &y[..7]);
        println!("  end v = {:?}", &y[7..14]);
        for s in sol
            .switches
            .iter()
            .filter(|s| s.kind != SwitchKind::Mode)
            .take(12)
        {
            println!(
                "  t = {:.6} {:?} {}",
                s.t,
                s.kind,
                s.element.as_deref().unwrap_or("")
            );
        }
        if label == "event-driven" {
            series = support::time_series(&sol, &PandaOnLimits::JOINTS);
        }
    }
    support::plot_over_time(
        "panda_on_limits",
        "Panda falling onto its joint limits (event-driven)",
        "q [rad]",
        &series,
    );
}
