//! A small branched tree in 3D (turntable, hinge + slider branch, tilted hinge with a
//! welded tip) moving freely under gravity: energy is conserved to the tolerance.
//!
//! Run: `cargo run --release --example branched_tree` (plots in `target/plots/`).

#[path = "support/mod.rs"]
mod support;

use filippov::nalgebra::SVector;
use filippov::prelude::*;
use filippov::runtime::{MechanicalSystem, Method, Options, Problem, solve};
use filippov::scenes::BranchedTree;
use support::{Scale, Series, line_plot, plot_over_time, plot_path, time_series};

fn main() {
    let tree = BranchedTree::default();
    let sys = MechanicalSystem::unforced(&tree);
    let y0 = [0.0, 0.4, 0.15, -0.3, 2.0, 0.0, 0.0, 0.0];
    let energy = |y: &[f64]| {
        let q = SVector::<f64, 4>::from_column_slice(&y[..4]);
        let v = SVector::<f64, 4>::from_column_slice(&y[4..]);
        tree.kinetic_energy(&q, &v) + tree.potential_energy(&q)
    };
    let e0 = energy(&y0);
    println!("branched tree: joints {:?}", BranchedTree::JOINTS);
    let mut drift_curve = Vec::new();
    for rtol in [1e-5, 1e-7, 1e-9, 1e-11] {
        let traj = solve(
            &sys,
            &Problem::new(0.0, 10.0, y0),
            &Method::Dopri5(Options::tolerances(rtol, rtol * 1e-2)),
        )
        .expect("integrates");
        let drift = (0..traj.len())
            .map(|i| (energy(traj.state(i)) - e0).abs())
            .fold(0.0, f64::max);
        println!(
            "rtol {rtol:.0e}: {:>6} steps, max |ΔE| = {drift:.3e}",
            traj.stats.steps
        );
        drift_curve.push((rtol, drift));
        if rtol == 1e-9 {
            let coords = time_series(&traj, &BranchedTree::JOINTS);
            plot_over_time(
                "branched_tree_coordinates",
                "Branched tree: coordinates",
                "q",
                &coords,
            );
        }
    }
    let path = plot_path("branched_tree_energy_drift");
    line_plot(
        &path,
        "Branched tree: max energy drift over t ∈ [0, 10]",
        "rtol",
        "max |ΔE|",
        &[Series::new("DOPRI5", drift_curve)],
        Scale::Log,
        Scale::Log,
    );
    println!("wrote {}", path.display());
}
