//! A small branched tree in 3D (turntable, hinge + slider branch, tilted hinge with a
//! welded tip) moving freely under gravity: energy is conserved to the tolerance.
//!
//! Run: `cargo run --release --example branched_tree` (plots in `target/plots/`).

#[path = "support/mod.rs"]
mod support;

use filippov::nalgebra::SVector;
use filippov::prelude::*;
use filippov::runtime::{MechanicalSystem, Method, Options, Problem, solve};
use support::{Scale, Series, line_plot, plot_over_time, plot_path, time_series};

/// A small branched tree in 3D: a turntable carrying two branches, one with a hinge and
/// a slider, the other tilted by a roll-pitch-yaw origin with a hinge and a rigidly
/// attached tip mass (fixed joint).
#[derive(Mechanism, Clone, Copy, Debug, PartialEq)]
#[mechanism(emit = all, gravity = [0.0, 0.0, -9.81], inputs = [turn, slide])]
#[body(base, mass = 2.0, com = [0.0, 0.0, 0.1], inertia = cylinder(2.0, 0.2, 0.2))]
#[joint(turn: revolute(z), parent = world, child = base)]
#[body(left, mass = m, com = [0.0, 0.0, l / 2.0], inertia = cuboid(m, 0.05, 0.05, l))]
#[joint(tilt: revolute(y), parent = base, child = left, origin = [0.1, 0.0, 0.2])]
#[body(slider, mass = m / 2.0, com = [0.0, 0.0, 0.0], inertia = sphere(m / 2.0, 0.05))]
#[joint(slide: prismatic(z), parent = left, child = slider, origin = [0.0, 0.0, l])]
#[body(right, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[joint(swing: revolute([0.0, 0.6, 0.8]), parent = base, child = right, origin = [-0.1, 0.0, 0.2], rpy = [0.3, -0.2, PI / 4.0])]
#[body(tip, mass = 0.3, com = [0.0, 0.0, 0.0], inertia = sphere(0.3, 0.04))]
#[joint(weld: fixed, parent = right, child = tip, origin = [l, 0.0, 0.0])]
#[spring(slide, k = k, rest = 0.1)]
struct BranchedTree {
    m: f64,
    l: f64,
    k: f64,
}

impl Default for BranchedTree {
    fn default() -> Self {
        BranchedTree {
            m: 1.0,
            l: 0.4,
            k: 50.0,
        }
    }
}

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
