//! A planar three-link arm with a spring and a damper in every joint, released from a
//! bent pose under gravity: the energy falls by exactly what the dampers dissipate.
//!
//! Run: `cargo run --release --example planar_arm` (plots in `target/plots/`).

#[path = "support/mod.rs"]
mod support;

use filippov::nalgebra::SVector;
use filippov::prelude::*;
use filippov::runtime::{MechanicalSystem, Method, Options, Problem, solve};
use filippov::scenes::PlanarArm3;
use support::{Scale, Series, line_plot, plot_over_time, plot_path, time_series};

fn main() {
    let arm = PlanarArm3::default();
    let sys = MechanicalSystem::unforced(&arm);
    let problem = Problem::new(0.0, 15.0, [0.8, -1.2, 0.6, 0.0, 0.0, 0.0]);
    let traj = solve(
        &sys,
        &problem,
        &Method::Dopri5(Options::tolerances(1e-10, 1e-12)),
    )
    .expect("integrates");
    let split = |y: &[f64]| {
        (
            SVector::<f64, 3>::from_column_slice(&y[..3]),
            SVector::<f64, 3>::from_column_slice(&y[3..]),
        )
    };
    let energy = |y: &[f64]| {
        let (q, v) = split(y);
        arm.kinetic_energy(&q, &v) + arm.potential_energy(&q)
    };
    // Dissipated work ∫ c v² dt by the trapezoidal rule on the accepted steps.
    let t = traj.times();
    let power = |i: usize| {
        let (_, v) = split(traj.state(i));
        arm.c * v.norm_squared()
    };
    let mut dissipated = vec![0.0];
    for i in 1..traj.len() {
        dissipated.push(dissipated[i - 1] + 0.5 * (power(i) + power(i - 1)) * (t[i] - t[i - 1]));
    }
    let e0 = energy(traj.state(0));
    let balance = (0..traj.len())
        .map(|i| (energy(traj.state(i)) + dissipated[i] - e0).abs())
        .fold(0.0, f64::max);
    let (tf, yf) = traj.last().expect("non-empty");
    println!(
        "planar 3-link arm: m = {}, l = {}, k = {}, c = {}",
        arm.m, arm.l, arm.k, arm.c
    );
    println!(
        "{} steps, {} rhs evaluations ({})",
        traj.stats.steps, traj.stats.rhs_evaluations, traj.stats
    );
    println!(
        "E(0) = {e0:.6}, E({tf}) = {:.6}, dissipated = {:.6}",
        energy(yf),
        dissipated[traj.len() - 1]
    );
    println!(
        "max |E(t) + W_diss(t) − E(0)| = {balance:.3e} (trapezoidal quadrature of the dissipation)"
    );

    let angles = time_series(&traj, &PlanarArm3::JOINTS);
    plot_over_time(
        "planar_arm_angles",
        "Planar 3-link arm: joint angles",
        "angle [rad]",
        &angles,
    );
    let e: Vec<(f64, f64)> = (0..traj.len())
        .map(|i| (t[i], energy(traj.state(i))))
        .collect();
    let w: Vec<(f64, f64)> = (0..traj.len())
        .map(|i| (t[i], e0 - dissipated[i]))
        .collect();
    let path = plot_path("planar_arm_energy");
    line_plot(
        &path,
        "Planar 3-link arm: energy and E(0) − dissipated work",
        "t [s]",
        "energy [J]",
        &[Series::new("E(t)", e), Series::new("E(0) − ∫ c v² dt", w)],
        Scale::Linear,
        Scale::Linear,
    );
    println!("wrote {}", path.display());
}
