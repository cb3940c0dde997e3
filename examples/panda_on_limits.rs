//! A Panda read from its URDF file with every joint limit a rigid stop (restitution 0.5),
//! released at rest under gravity: it folds onto several of its limits, bounces, and
//! comes to rest on them. Event-driven (the default method) beside time-stepping at
//! h = 1e-3; prints each run's switch log summary and end state, plots the joint angles
//! and the path of the tool frame (`panda_hand_tcp` from the URDF, by the generated
//! forward kinematics, read back from the solution's dense output on a 1 ms grid).
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
    let mut tool_series = Vec::new();
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
        // Where the tool ends, and how fast it still moves (‖ṗ‖ = ‖J v‖).
        let tcp = PandaOnLimits::frame("panda_hand_tcp").expect("the URDF's tool frame");
        let q = V7::from_column_slice(&y[..7]);
        let v = V7::from_column_slice(&y[7..14]);
        let pose = panda.frame_pose(tcp, &q);
        let (p_dot, _) = panda.frame_velocity(tcp, &q, &v);
        println!(
            "  tool at tf: p = {:.4?} m, |ṗ| = {:.1e} m/s",
            pose.translation.vector.as_slice(),
            p_dot.norm()
        );
        if label == "event-driven" {
            series = support::time_series(&sol, &PandaOnLimits::JOINTS);
            let grid: Vec<f64> = (0..=3000).map(|k| k as f64 * 1e-3).collect();
            let states = sol.sample(&grid).expect("grid inside the run");
            let tool: Vec<[f64; 3]> = states
                .iter()
                .map(|y| {
                    let p = panda.frame_pose(tcp, &V7::from_column_slice(&y[..7]));
                    [p.translation.x, p.translation.y, p.translation.z]
                })
                .collect();
            tool_series = ["x", "y", "z"]
                .iter()
                .enumerate()
                .map(|(k, c)| {
                    support::Series::new(
                        &format!("tool {c}"),
                        grid.iter().zip(&tool).map(|(t, p)| (*t, p[k])).collect(),
                    )
                })
                .collect();
        }
    }
    support::plot_over_time(
        "panda_on_limits",
        "Panda falling onto its joint limits (event-driven)",
        "q [rad]",
        &series,
    );
    support::plot_over_time(
        "panda_on_limits_tool",
        "Panda's tool frame (panda_hand_tcp) falling onto the limits",
        "position [m]",
        &tool_series,
    );
}
