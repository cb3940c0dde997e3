//! Through gimbal lock: the body of S10 (`I = diag(1, 2, 3)`, `ω0 = (0.01, 1, 0)`)
//! pitches through ±90° again and again. Side by side:
//!
//! * `SphericalBody`: a spherical joint, quaternion configuration, body angular
//!   velocity, integrated on SO(3) by Rkmk5 — no chart, nothing singular;
//! * `EulerBody`: the same body on three revolute joints in ZYX Euler angles, integrated
//!   by DOPRI5 — its mass matrix `Jᵀ I J` is singular at pitch = ±90°, where yaw and roll
//!   align, so its accelerations blow up there.
//!
//! Both are compared, on a common time grid, against a tight Lie-group reference:
//! orientation error `‖log(R_refᵀ R)‖`, relative energy error, steps and run time.
//!
//! Run: `cargo run --release --example gimbal_lock` (plot `target/plots/gimbal_lock.svg`).

#[path = "support/mod.rs"]
mod support;

use std::time::Instant;

use filippov::nalgebra::{Matrix3, Rotation3, SVector};
use filippov::prelude::*;
use filippov::runtime::liegroup::{LieMechanical, LieMechanism, so3};
use filippov::runtime::{
    LieProblem, LieTrajectory, MechanicalSystem, Method, Options, Problem, Rkmk5, Solution, solve,
};
use filippov::scenes::{EulerBody, SphericalBody};
use support::{Scale, Series, line_plot, plot_path};

const T_END: f64 = 10.0;
const GRID: usize = 400;

fn lie_rotation(traj: &LieTrajectory, t: f64) -> Option<Matrix3<f64>> {
    traj.at(t).map(|y| y.rotations[0].to_matrix())
}

fn euler_rotation(y: &[f64]) -> Matrix3<f64> {
    // State (yaw, pitch, roll, rates): R = Rz(yaw) Ry(pitch) Rx(roll).
    *Rotation3::from_euler_angles(y[2], y[1], y[0]).matrix()
}

struct Row {
    name: String,
    outcome: String,
    max_error: f64,
    energy_error: f64,
    steps: usize,
    seconds: f64,
    curve: Vec<(f64, f64)>,
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let sph = SphericalBody::default();
    let eul = EulerBody::default();
    let w0 = SVector::<f64, 3>::from([0.01, 1.0, 0.0]);
    let q0 = SphericalBody::identity_configuration();
    let y0 = SphericalBody::qv_to_state(&q0, &w0);
    let e0 = sph.kinetic_energy(&q0, &w0);
    let lie_sys = LieMechanical::free(&sph);
    let reference = Rkmk5::new(Options::tolerances(1e-13, 1e-15))
        .solve(&lie_sys, &LieProblem::new(0.0, T_END, y0.clone()))?;
    let grid: Vec<f64> = (0..=GRID).map(|k| T_END * k as f64 / GRID as f64).collect();
    let r_ref: Vec<Matrix3<f64>> = grid
        .iter()
        .map(|&t| lie_rotation(&reference, t).expect("reference covers the grid"))
        .collect();
    let error_curve = |rot: &dyn Fn(f64) -> Option<Matrix3<f64>>| -> Vec<(f64, f64)> {
        grid.iter()
            .zip(&r_ref)
            .map_while(|(&t, r)| rot(t).map(|x| (t, so3::log(&(r.transpose() * x)).norm())))
            .collect()
    };
    println!(
        "gimbal lock: I = diag(1, 2, 3), ω0 = (0.01, 1, 0), t ∈ [0, {T_END}]; pitch passes ±90° at t ≈ {:.2}, {:.2}, …",
        std::f64::consts::FRAC_PI_2,
        3.0 * std::f64::consts::FRAC_PI_2
    );
    let mut rows = Vec::new();
    for rtol in [1e-6, 1e-9] {
        let options = Options::tolerances(rtol, rtol * 1e-3);
        // Lie group.
        let start = Instant::now();
        let traj = Rkmk5::new(options).solve(&lie_sys, &LieProblem::new(0.0, T_END, y0.clone()));
        let seconds = start.elapsed().as_secs_f64();
        let (outcome, curve, energy_error, steps) = match &traj {
            Ok(tr) => {
                let (t, y) = tr.last().expect("non-empty");
                let (q, v) = SphericalBody::state_to_qv(&y);
                let de = (sph.kinetic_energy(&q, &v) - e0).abs() / e0;
                let curve = error_curve(&|t| lie_rotation(tr, t));
                (format!("completed to t = {t}"), curve, de, tr.stats.steps)
            }
            Err(e) => (format!("failed: {e}"), Vec::new(), f64::NAN, 0),
        };
        rows.push(Row {
            name: format!("spherical, Rkmk5, rtol {rtol:.0e}"),
            outcome,
            max_error: curve.iter().map(|p| p.1).fold(0.0, f64::max),
            energy_error,
            steps,
            seconds,
            curve,
        });

        // Euler angles.
        let sys = MechanicalSystem::unforced(&eul);
        let problem = Problem::new(0.0, T_END, [0.0, 0.0, 0.0, w0[2], w0[1], w0[0]]);
        let start = Instant::now();
        let result = solve(&sys, &problem, &Method::Dopri5(options));
        let seconds = start.elapsed().as_secs_f64();
        let (traj, outcome): (Solution, String) = match result {
            Ok(tr) => (tr, "completed".to_string()),
            Err(e) => (
                (*e.solution).clone(),
                format!(
                    "failed at t = {:.4}: {}",
                    e.solution.last().map_or(0.0, |l| l.0),
                    e.kind
                ),
            ),
        };
        let curve = error_curve(&|t| traj.at(t).map(|y| euler_rotation(&y)));
        let energy_error = traj.last().map_or(f64::NAN, |(_, y)| {
            let q = SVector::<f64, 3>::from_column_slice(&y[..3]);
            let v = SVector::<f64, 3>::from_column_slice(&y[3..]);
            (eul.kinetic_energy(&q, &v) - e0).abs() / e0
        });
        rows.push(Row {
            name: format!("Euler ZYX, DOPRI5, rtol {rtol:.0e}"),
            outcome,
            max_error: curve.iter().map(|p| p.1).fold(0.0, f64::max),
            energy_error,
            steps: traj.len().saturating_sub(1),
            seconds,
            curve,
        });
    }
    // The error just before and after the first pass through pitch = 90° (t = π/2).
    let at = |r: &Row, t: f64| r.curve.iter().find(|p| p.0 >= t).map_or(f64::NAN, |p| p.1);
    println!(
        "{:<32} {:>11} {:>11} {:>11} {:>11} {:>7} {:>9}  outcome",
        "model, method", "err t=1.4", "err t=2.0", "max err", "energy err", "steps", "time [ms]"
    );
    for r in &rows {
        println!(
            "{:<32} {:>11.3e} {:>11.3e} {:>11.3e} {:>11.3e} {:>7} {:>9.3}  {}",
            r.name,
            at(r, 1.4),
            at(r, 2.0),
            r.max_error,
            r.energy_error,
            r.steps,
            r.seconds * 1e3,
            r.outcome
        );
    }
    let series: Vec<Series> = rows
        .iter()
        .map(|r| Series::new(r.name.clone(), r.curve.clone()))
        .collect();
    let path = plot_path("gimbal_lock");
    line_plot(
        &path,
        "Orientation error against a tight Lie-group reference",
        "t [s]",
        "‖log(R_refᵀ R)‖ [rad]",
        &series,
        Scale::Linear,
        Scale::Log,
    );
    println!("wrote {}", path.display());
    Ok(())
}
