//! Theory S9: a 7-dof arm (Franka Panda kinematics and identified inertial data) with
//! Coulomb friction on five joints and rigid stops at the upper limits of j2 and j4,
//! swayed by joint torques under gravity. Event-driven integration; the check is the
//! energy balance `E(t) − E(0) = W_in − D_friction − L_impacts`, each term computed
//! independently of the integrator.
//!
//! Run: `cargo run --release --example s9_arm` (plots `target/plots/s9_angles.svg`,
//! `target/plots/s9_energy.svg`).

#[path = "support/s9.rs"]
mod s9;
#[path = "support/mod.rs"]
mod support;

use std::time::Instant;

use filippov::prelude::*;
use filippov::runtime::{Method, NonSmoothMethod, Options};
use filippov::scenes::PandaS9;
use s9::{V7, s9_balance, s9_run, s9_torque};
use support::{Series, plot_over_time, time_series};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let arm = PandaS9::default();
    let t_end = 3.0;
    println!(
        "S9: 7-dof arm, friction on j1, j3, j5, j6, j7, stops at the j2 and j4 limits (e = {}), t ∈ [0, {t_end}]",
        arm.e
    );
    println!(
        "{:>8} {:>8} {:>8} {:>8} {:>6} {:>10} {:>10} {:>10} {:>11} {:>9}",
        "rtol",
        "steps",
        "events",
        "impacts",
        "zeno",
        "work in",
        "friction",
        "impacts",
        "residual",
        "time [ms]"
    );
    let mut last = None;
    for rtol in [1e-6, 1e-8, 1e-10] {
        let method =
            NonSmoothMethod::EventDriven(Method::Dopri5(Options::tolerances(rtol, rtol * 1e-2)));
        let start = Instant::now();
        let traj = s9_run(&arm, t_end, &method)?;
        let ms = start.elapsed().as_secs_f64() * 1e3;
        let b = s9_balance(&arm, &traj, 16);
        println!(
            "{:>8.0e} {:>8} {:>8} {:>8} {:>6} {:>10.4} {:>10.4} {:>10.4} {:>11.3e} {:>9.2}",
            rtol,
            traj.stats.steps,
            traj.stats.events,
            b.impacts,
            traj.stats.zeno_detected,
            b.work_in,
            b.friction_dissipation,
            b.impact_loss,
            b.relative_residual,
            ms
        );
        last = Some(traj);
    }
    let traj = last.expect("three runs");
    let names: Vec<String> = PandaS9::JOINTS.iter().map(|j| format!("q_{j}")).collect();
    let labels: Vec<&str> = names.iter().map(String::as_str).collect();
    plot_over_time(
        "s9_angles",
        "S9: joint angles (j2 and j4 meet their upper limits)",
        "q [rad]",
        &time_series(&traj, &labels),
    );

    // Energy terms against time on a grid (dense output).
    let energy = |y: &[f64]| {
        let q = V7::from_column_slice(&y[..7]);
        let v = V7::from_column_slice(&y[7..14]);
        arm.kinetic_energy(&q, &v) + arm.potential_energy(&q)
    };
    let e0 = energy(traj.state(0));
    let mut rows = (Vec::new(), Vec::new());
    let mut work = 0.0;
    let dt = 1e-3;
    let mut prev = traj.at(0.0).expect("start");
    let mut t = 0.0;
    while t + dt <= t_end {
        let y = traj.at(t + dt).expect("inside");
        let p = |t: f64, y: &[f64]| s9_torque(t).dot(&V7::from_column_slice(&y[7..14]));
        work += 0.5 * dt * (p(t, &prev) + p(t + dt, &y));
        t += dt;
        rows.0.push((t, energy(&y) - e0));
        rows.1.push((t, work));
        prev = y;
    }
    plot_over_time(
        "s9_energy",
        "S9: E(t) − E(0) and the work of the applied torques (the gap is friction and impacts)",
        "energy [J]",
        &[
            Series::new("E(t) − E(0)", rows.0),
            Series::new("work in", rows.1),
        ],
    );
    Ok(())
}
