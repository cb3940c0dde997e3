//! Theory S10: a free rigid body, `I = diag(1, 2, 3)`, spun near its intermediate axis
//! (`ω0 = (0.01, 1, 0)`): every flip period the body turns over (the Dzhanibekov
//! effect). Integrated on SO(3) × ℝ³ by Munthe-Kaas RK (Rkmk5) from the derive's
//! `FreeBody` scene; kinetic energy and spatial angular momentum are conserved to the
//! tolerance over 10⁴ periods.
//!
//! Run: `cargo run --release --example s10_free_body` (`-- --short` for 10³ periods).
//! Plots in `target/plots/`: `s10_omega.svg` (ω(t) over the first flips) and
//! `s10_drift.svg` (relative drift of the invariants against time, three tolerances).

#[path = "support/lie.rs"]
mod lie;
#[path = "support/mod.rs"]
mod support;

use filippov::runtime::liegroup::LieMechanical;
use filippov::runtime::{LieProblem, Options, Rkmk5};
use filippov::scenes::FreeBody;
use lie::{flip_period, s10_initial, s10_run};
use support::{Scale, Series, line_plot, plot_over_time, plot_path};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let short = std::env::args().any(|a| a == "--short");
    let periods = if short { 1e3 } else { 1e4 };
    let period = flip_period(200.0)?;
    println!("S10: free body, I = diag(1, 2, 3), ω0 = (0.01, 1, 0); flip period T = {period:.6}");

    // ω(t) over the first three flips.
    let body = FreeBody::default();
    let sys = LieMechanical::free(&body);
    let traj = Rkmk5::new(Options::tolerances(1e-10, 1e-12))
        .solve(&sys, &LieProblem::new(0.0, 3.0 * period, s10_initial()))?;
    let series: Vec<Series> = ["ω_x", "ω_y", "ω_z"]
        .iter()
        .enumerate()
        .map(|(j, l)| {
            Series::new(
                *l,
                (0..traj.len())
                    .map(|k| (traj.times()[k], traj.state(k).velocity[j]))
                    .collect(),
            )
        })
        .collect();
    plot_over_time(
        "s10_omega",
        "S10: body angular velocity through three flips",
        "ω [rad/s]",
        &series,
    );

    println!(
        "{:>8} {:>9} {:>10} {:>9} {:>14} {:>14} {:>9}",
        "rtol", "periods", "t_end", "steps", "energy drift", "momentum drift", "time [s]"
    );
    let mut drift = Vec::new();
    for rtol in [1e-6, 1e-9, 1e-12] {
        let run = s10_run(rtol, periods, period, 100)?;
        println!(
            "{:>8.0e} {:>9.0} {:>10.1} {:>9} {:>14.3e} {:>14.3e} {:>9.3}",
            run.rtol,
            run.periods,
            run.t_end,
            run.steps,
            run.energy_drift,
            run.momentum_drift,
            run.seconds
        );
        drift.push(Series::new(
            format!("energy, rtol {rtol:.0e}"),
            run.history.iter().map(|&(t, e, _)| (t, e)).collect(),
        ));
        drift.push(Series::new(
            format!("angular momentum, rtol {rtol:.0e}"),
            run.history.iter().map(|&(t, _, l)| (t, l)).collect(),
        ));
    }
    let path = plot_path("s10_drift");
    line_plot(
        &path,
        "S10: relative drift of the invariants (max over each 1% of the run)",
        "t [s]",
        "relative drift",
        &drift,
        Scale::Linear,
        Scale::Log,
    );
    println!("wrote {}", path.display());
    Ok(())
}
