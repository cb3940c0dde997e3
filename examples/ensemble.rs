//! An ensemble: a two-link arm under gravity dropped onto its shoulder limit, swept over
//! the limit's restitution and the elbow's friction (a 24 × 8 grid), one integration per
//! task on every core (`std::thread::scope`; scenes, problems and solutions are
//! `Send + Sync`), with a progress bar. For each run: the time the arm settles on its
//! limit (the switch log's `Settled` entry) and the elbow angle it comes to rest at.
//!
//! Run: `cargo run --release --example ensemble` (plots in `target/plots/`).

#[path = "support/resting_arm.rs"]
mod resting_arm;
#[path = "support/mod.rs"]
mod support;

use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

use filippov::runtime::{NonSmoothMethod, NonSmoothProblem, SwitchKind, solve_nonsmooth};
use indicatif::{ProgressBar, ProgressStyle};
use resting_arm::{RestingArm, V2, zero};
use support::{Scale, Series, line_plot, plot_path};

/// What one run came to: settle time and final elbow angle, or the error.
type Outcome = Result<(f64, f64), String>;

fn run(e: f64, fc: f64) -> Outcome {
    let arm = RestingArm {
        m1: 1.0,
        l1: 1.0,
        m2: 0.5,
        l2: 0.7,
        fc,
        lim: -1.0,
        e,
    };
    let p = NonSmoothProblem::new(0.0, 5.0, V2::new(0.2, -0.5), V2::zeros());
    let sol = solve_nonsmooth(&arm, &zero, &p, &NonSmoothMethod::default())
        .map_err(|err| err.to_string())?;
    let settled = sol
        .switches
        .iter()
        .rev()
        .find(|s| s.kind == SwitchKind::Settled || (s.kind == SwitchKind::Impact && e == 0.0))
        .map_or(f64::NAN, |s| s.t);
    Ok((settled, sol.last().expect("rows").1[1]))
}

fn main() {
    let restitutions: Vec<f64> = (0..24).map(|i| 0.04 * i as f64).collect();
    let frictions = [0.5, 1.0, 2.0, 4.0, 8.0, 12.0, 16.0, 20.0];
    let tasks: Vec<(f64, f64)> = frictions
        .iter()
        .flat_map(|&fc| restitutions.iter().map(move |&e| (e, fc)))
        .collect();
    let bar = ProgressBar::new(tasks.len() as u64);
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} runs, {elapsed}").expect("template"),
    );
    let results: Mutex<Vec<(f64, f64, Outcome)>> = Mutex::new(Vec::new());
    let next = AtomicUsize::new(0);
    let workers = std::thread::available_parallelism().map_or(1, |n| n.get());
    let start = std::time::Instant::now();
    std::thread::scope(|scope| {
        for _ in 0..workers {
            scope.spawn(|| {
                while let Some(&(e, fc)) = tasks.get(next.fetch_add(1, Ordering::Relaxed)) {
                    let outcome = run(e, fc);
                    results
                        .lock()
                        .expect("no poisoned lock")
                        .push((e, fc, outcome));
                    bar.inc(1);
                }
            });
        }
    });
    bar.finish();
    let mut results = results.into_inner().expect("no poisoned lock");
    results.sort_by(|a, b| (a.1, a.0).partial_cmp(&(b.1, b.0)).expect("finite"));
    let failed: Vec<_> = results.iter().filter(|r| r.2.is_err()).collect();
    println!(
        "{} runs on {workers} threads in {:.2} s; {} ended with a typed error",
        results.len(),
        start.elapsed().as_secs_f64(),
        failed.len()
    );
    for (e, fc, err) in &failed {
        println!("  e = {e:.2}, f_crit = {fc}: {}", err.as_ref().unwrap_err());
    }
    let mut settle = Vec::new();
    let mut angle = Vec::new();
    for &fc in &frictions {
        let pts = |pick: fn(&(f64, f64)) -> f64| -> Vec<(f64, f64)> {
            results
                .iter()
                .filter(|r| r.1 == fc)
                .filter_map(|r| r.2.as_ref().ok().map(|o| (r.0, pick(o))))
                .collect()
        };
        let times = pts(|o| o.0);
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
        angle.push(Series::new(format!("elbow f_crit = {fc}"), pts(|o| o.1)));
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
