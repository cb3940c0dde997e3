//! Theory S8: the free double pendulum. Energy drift against tolerance for the adaptive
//! explicit and stiff implicit methods, and against step size for RK4.
//!
//! Run: `cargo run --release --example double_pendulum` (plots in `target/plots/`).

#[path = "support/mod.rs"]
mod support;

use std::time::Instant;

use filippov::nalgebra::SVector;
use filippov::prelude::*;
use filippov::runtime::{MechanicalSystem, Method, Options, Problem, Solution, solve};
use filippov::scenes::DoublePendulum;
use support::{Scale, Series, line_plot, plot_over_time, plot_path, time_series};

fn energy(p: &DoublePendulum, y: &[f64]) -> f64 {
    let q = SVector::<f64, 2>::from_column_slice(&y[..2]);
    let v = SVector::<f64, 2>::from_column_slice(&y[2..]);
    p.kinetic_energy(&q, &v) + p.potential_energy(&q)
}

fn max_drift(p: &DoublePendulum, traj: &Solution, e0: f64) -> f64 {
    (0..traj.len())
        .map(|i| (energy(p, traj.state(i)) - e0).abs())
        .fold(0.0, f64::max)
}

fn main() {
    let p = DoublePendulum::default();
    let sys = MechanicalSystem::unforced(&p);
    let y0 = [1.2, -0.6, 0.0, 0.0];
    let e0 = energy(&p, &y0);
    let problem = Problem::new(0.0, 20.0, y0);
    println!(
        "double pendulum (S8): m1 = {}, l1 = {}, m2 = {}, l2 = {}, t ∈ [0, 20], E0 = {e0:.6}",
        p.m1, p.l1, p.m2, p.l2
    );
    println!(
        "{:<8} {:>10} {:>8} {:>10} {:>12} {:>10}",
        "method", "tol / h", "steps", "rhs evals", "max |ΔE|", "time [ms]"
    );

    let mut curves: Vec<Series> = Vec::new();
    /// A method's name, how to build it from its tolerance or step, and the sweep.
    type Sweep = (&'static str, fn(f64) -> Method, Vec<f64>);
    let methods: [Sweep; 3] = [
        (
            "DOPRI5",
            |t| Method::Dopri5(Options::tolerances(t, t * 1e-2)),
            vec![1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10],
        ),
        (
            "SDIRK4",
            |t| Method::Sdirk4(Options::tolerances(t, t * 1e-2)),
            vec![1e-4, 1e-5, 1e-6, 1e-7, 1e-8],
        ),
        (
            "RK4",
            |h| Method::Rk4 { h },
            vec![0.02, 0.01, 0.005, 0.0025, 0.00125],
        ),
    ];
    let mut reference = None;
    for (name, make, params) in methods {
        let mut pts = Vec::new();
        for x in params {
            let start = Instant::now();
            match solve(&sys, &problem, &make(x)) {
                Ok(traj) => {
                    let ms = start.elapsed().as_secs_f64() * 1e3;
                    let d = max_drift(&p, &traj, e0);
                    println!(
                        "{name:<8} {x:>10.1e} {:>8} {:>10} {d:>12.3e} {ms:>10.2}",
                        traj.stats.steps, traj.stats.rhs_evaluations
                    );
                    pts.push((x, d));
                    if name == "DOPRI5" && x == 1e-10 {
                        reference = Some(traj);
                    }
                }
                Err(e) => println!("{name:<8} {x:>10.1e}  failed: {e}"),
            }
        }
        curves.push(Series::new(name, pts));
    }
    let path = plot_path("double_pendulum_energy_drift");
    line_plot(
        &path,
        "Double pendulum: max energy drift over t ∈ [0, 20]",
        "tolerance (DOPRI5, SDIRK4) / step h (RK4)",
        "max |E(t) − E(0)|",
        &curves,
        Scale::Log,
        Scale::Log,
    );
    println!("wrote {}", path.display());

    if let Some(traj) = reference {
        let angles = time_series(&traj, &DoublePendulum::JOINTS);
        plot_over_time(
            "double_pendulum_angles",
            "Double pendulum: joint angles (DOPRI5, rtol 1e-10)",
            "angle [rad]",
            &angles,
        );
    }
}
