//! An ensemble: a two-link arm under gravity dropped onto its shoulder limit, swept over
//! the elbow's friction and the limit's restitution (an 8 × 24 grid), on every core
//! with a progress bar (`runtime::ensemble`, feature `parallel`). For each run: the time
//! the arm settles on its limit (the switch log's `Settled` entry) and the elbow angle it
//! comes to rest at. Failed runs stay in the table with their error.
//!
//! Run: `cargo run --release --features parallel --example ensemble` (plots in
//! `target/plots/`).

#[path = "support/mod.rs"]
mod support;

use filippov::runtime::SwitchKind;
use filippov::runtime::ensemble::{Draw, Ensemble};
use filippov::scenes::RestingArm;
use support::{Scale, Series, line_plot, plot_path};

fn main() {
    let restitutions: Vec<f64> = (0..24).map(|i| 0.04 * i as f64).collect();
    let frictions = vec![0.5, 1.0, 2.0, 4.0, 8.0, 12.0, 16.0, 20.0];
    let fixed = Draw::Fixed;
    // m1, l1, m2, l2, fc, lim, e: the grids' product, friction varying slowest.
    let parameters = vec![
        fixed(1.0),
        fixed(1.0),
        fixed(0.5),
        fixed(0.7),
        Draw::Grid(frictions.clone()),
        fixed(-1.0),
        Draw::Grid(restitutions.clone()),
    ];
    let ens = Ensemble::<RestingArm, 2>::new(
        parameters,
        vec![fixed(0.2), fixed(-0.5)],
        vec![fixed(0.0), fixed(0.0)],
        1,
        0,
        5.0,
    )
    .expect("a valid ensemble");
    // Per run: when the arm settled (NaN if it did not; with e = 0 the impact itself),
    // and the elbow angle at the end.
    let names = vec!["settled".to_string(), "elbow".to_string()];
    let reduce = |sol: &filippov::runtime::Solution| {
        let settled = sol
            .switches
            .iter()
            .rev()
            .find(|s| s.kind == SwitchKind::Settled)
            .map_or(f64::NAN, |s| s.t);
        vec![settled, sol.last().expect("rows").1[1]]
    };
    let start = std::time::Instant::now();
    let table = ens.table_with(0..ens.len(), names, &reduce, None, true);
    let failed: Vec<usize> = (0..table.runs.len())
        .filter(|&k| table.errors[k].is_some())
        .collect();
    println!(
        "{} runs in {:.2} s; {} ended with a typed error",
        table.runs.len(),
        start.elapsed().as_secs_f64(),
        failed.len()
    );
    let (fc_col, e_col) = (4, 6);
    for &k in &failed {
        let x = table.input_row(k);
        let err = table.errors[k].as_ref().expect("failed");
        println!(
            "  e = {:.2}, f_crit = {}: {} ({})",
            x[e_col], x[fc_col], err.message, err.kind
        );
    }
    let mut settle = Vec::new();
    let mut angle = Vec::new();
    for &fc in &frictions {
        let pts = |j: usize| -> Vec<(f64, f64)> {
            (0..table.runs.len())
                .filter(|&k| table.input_row(k)[fc_col] == fc && table.errors[k].is_none())
                .map(|k| (table.input_row(k)[e_col], table.output_row(k)[j]))
                .collect()
        };
        let times = pts(0);
        let finite: Vec<f64> = times
            .iter()
            .map(|p| p.1)
            .filter(|t| t.is_finite())
            .collect();
        println!(
            "elbow f_crit = {fc:>4}: settles after {:.3}–{:.3} s over e = 0…0.92 ({} of {} runs settle)",
            finite.iter().copied().fold(f64::INFINITY, f64::min),
            finite.iter().copied().fold(0.0, f64::max),
            finite.len(),
            times.len()
        );
        settle.push(Series::new(format!("elbow f_crit = {fc}"), times));
        angle.push(Series::new(format!("elbow f_crit = {fc}"), pts(1)));
    }
    let (a, b) = (
        plot_path("ensemble_settle_time"),
        plot_path("ensemble_elbow_angle"),
    );
    line_plot(
        &a,
        "Dropped arm: time to settle on the shoulder limit",
        "restitution e",
        "settle time [s]",
        &settle,
        Scale::Linear,
        Scale::Linear,
    );
    line_plot(
        &b,
        "Dropped arm: elbow angle at rest",
        "restitution e",
        "elbow angle at t = 5 s [rad]",
        &angle,
        Scale::Linear,
        Scale::Linear,
    );
    println!("plots: {} and {}", a.display(), b.display());
}
