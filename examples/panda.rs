//! A 7-dof arm with Franka Panda parameters tracking a joint-space target with PD
//! control plus gravity compensation computed by the generated `gravity(q)`; compares
//! the generated kernels with the numeric reference implementation on the same run.
//!
//! Run: `cargo run --release --example panda` (plots in `target/plots/`).

#[path = "support/mod.rs"]
mod support;

use std::time::Instant;

use filippov::nalgebra::SVector;
use filippov::prelude::*;
use filippov::runtime::{
    MechanicalSystem, Method, NumericSystem, Options, Problem, numeric, solve,
};
use filippov::scenes::Panda;
use support::{plot_over_time, time_series};

type V7 = SVector<f64, 7>;

fn main() {
    let arm = Panda::default();
    let target = V7::from([0.0, -0.5, 0.0, -2.0, 0.0, 1.6, 0.8]);
    let (kp, kd) = (60.0, 12.0);
    let control = |_t: f64, q: &V7, v: &V7| arm.gravity(q) + (target - q) * kp - v * kd;
    let sys = MechanicalSystem::new(&arm, control);
    let mut y0 = vec![0.0; 14];
    y0[3] = -1.0;
    let problem = Problem::new(0.0, 3.0, y0.clone());
    let method = Method::Dopri5(Options::tolerances(1e-8, 1e-10));

    let start = Instant::now();
    let traj = solve(&sys, &problem, &method).expect("integrates");
    let generated = start.elapsed();

    let model = arm.model();
    let numeric_control =
        |_t: f64, q: &filippov::nalgebra::DVector<f64>, v: &filippov::nalgebra::DVector<f64>| {
            let t = filippov::nalgebra::DVector::from_column_slice(target.as_slice());
            numeric::gravity(&model, q) + (t - q) * kp - v * kd
        };
    let start = Instant::now();
    let reference = solve(
        &NumericSystem::new(&model, numeric_control),
        &problem,
        &method,
    )
    .expect("integrates");
    let numeric_time = start.elapsed();

    let (tf, yf) = traj.last().expect("non-empty");
    let err = (V7::from_column_slice(&yf[..7]) - target).norm();
    let diff = yf
        .iter()
        .zip(reference.last().expect("non-empty").1)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    println!("Panda, PD + gravity compensation, kp = {kp}, kd = {kd}, t ∈ [0, {tf}]");
    println!(
        "{} steps, {} rhs evaluations",
        traj.stats.steps, traj.stats.rhs_evaluations
    );
    println!("‖q(tf) − q_target‖ = {err:.3e}");
    println!("generated vs numeric trajectory: max |Δy(tf)| = {diff:.3e}");
    println!(
        "wall time of this run (one sample each, not a benchmark; see `cargo bench`): generated {:.2} ms, numeric {:.2} ms",
        generated.as_secs_f64() * 1e3,
        numeric_time.as_secs_f64() * 1e3
    );
    let angles = time_series(&traj, &Panda::JOINTS);
    plot_over_time(
        "panda_angles",
        "Panda: joint angles under PD + gravity compensation",
        "angle [rad]",
        &angles,
    );
}
