//! The two long runs of the extreme suite: many stick–slip cycles of S5 (does the
//! periodic orbit drift?) and the chaotic double pendulum over a long horizon (does the
//! energy?). Both run in chunks, so memory stays flat however long they are.

use std::time::Instant;

use filippov::nalgebra::SVector;
use filippov::prelude::*;
use filippov::runtime::{
    MechanicalSystem, Method, NonSmoothMethod, NonSmoothProblem, Options, Output, Problem, solve,
    solve_nonsmooth_with,
};
use filippov_scenes::{CoulombOscillator, DoublePendulum};
use indicatif::ProgressBar;

use super::markdown::sci;

type V1 = SVector<f64, 1>;

/// S5 (forced Coulomb stick–slip, period T = 4π) for `cycles` forcing periods,
/// event-driven at rtol 1e-10, in chunks of 1,000 periods restarted from the last row
/// (with its friction force when stuck). Drift: the largest change of `x(kT)` from
/// `x(k₀T)` for `k ≥ k₀ = cycles / 10` (after the transient) — on the exact periodic
/// orbit it is zero; the transient `|x(k₀T) − x(T)|` is reported beside it.
///
/// Each chunk keeps only the rows at `kT` (`Output::Times`) and reports its progress to
/// the report's progress bar through an observer.
pub fn stick_slip(cycles: usize, progress: &ProgressBar) -> Vec<String> {
    let s = CoulombOscillator {
        m: 1.0,
        k: 1.0,
        f_crit: 0.5,
    };
    let period = 4.0 * std::f64::consts::PI;
    let input = |t: f64, _q: &V1, _v: &V1| V1::new(1.2 * (0.5 * t).sin());
    let method = NonSmoothMethod::EventDriven(Method::Dopri5(Options {
        max_steps: usize::MAX,
        ..Options::tolerances(1e-10, 1e-12)
    }));
    let start = Instant::now();
    let (mut q, mut v, mut force) = (0.25, 0.0, Some(-0.25));
    let (mut events, mut steps) = (0usize, 0usize);
    let k0 = (cycles / 10).max(1);
    let (mut x_k0, mut x_1) = (f64::NAN, f64::NAN);
    let mut drift = 0.0f64;
    let mut done = 0usize;
    let chunk = 1000;
    while done < cycles {
        let n = chunk.min(cycles - done);
        let (t0, t1) = (done as f64 * period, (done + n) as f64 * period);
        let grid: Vec<f64> = (done..=done + n).map(|k| k as f64 * period).collect();
        let p = NonSmoothProblem::new(t0, t1, V1::new(q), V1::new(v))
            .with_forces(vec![force])
            .with_output(Output::Times(grid));
        let total = cycles as f64 * period;
        let mut seen = 0usize;
        let mut observe = |t: f64, _y: &[f64]| {
            seen += 1;
            if seen % 20_000 == 0 {
                progress.set_message(format!(
                    "stick–slip: {:.0} of {cycles} forcing periods",
                    t / total * cycles as f64
                ));
            }
            std::ops::ControlFlow::Continue(())
        };
        let traj = match solve_nonsmooth_with(&s, &input, &p, &method, &mut observe) {
            Ok(t) => t,
            Err(e) => {
                return vec![
                    format!("{cycles} stick–slip cycles (S5, forced Coulomb)"),
                    "event-driven rtol 1e-10".into(),
                    format!("typed error: {}", e.kind),
                    format!("after {done} cycles"),
                    format!("{:.1}", start.elapsed().as_secs_f64() * 1e3),
                ];
            }
        };
        events += traj.stats.events;
        steps += traj.stats.steps;
        for k in done..=done + n {
            let Some(y) = traj.at(k as f64 * period) else {
                continue;
            };
            if k == 1 {
                x_1 = y[0];
            }
            if k == k0 {
                x_k0 = y[0];
            } else if k > k0 {
                drift = drift.max((y[0] - x_k0).abs());
            }
        }
        // The last kept row is at t1 (the chunk's end is on the grid).
        let (_, y) = traj.last().expect("rows");
        (q, v) = (y[0], y[1]);
        force = (v == 0.0).then_some(y[2]);
        done += n;
    }
    vec![
        format!("{cycles} stick–slip cycles (S5, forced Coulomb), chunks of {chunk}"),
        "event-driven rtol 1e-10".into(),
        "completed".into(),
        format!(
            "drift of x(kT) from x({k0}T) over k ≥ {k0}: {} (transient x({k0}T) − x(T): {}); {steps} steps, {events} events",
            sci(drift),
            sci((x_k0 - x_1).abs())
        ),
        format!("{:.1}", start.elapsed().as_secs_f64() * 1e3),
    ]
}

/// The double pendulum (S8) from a chaotic start (both rods horizontal-ish, at rest)
/// over `horizon` seconds, DOPRI5 at two tolerances, in chunks of 100 s: the largest
/// relative energy error.
pub fn chaotic_pendulum(horizon: f64) -> Vec<Vec<String>> {
    let p = DoublePendulum::default();
    let sys = MechanicalSystem::unforced(&p);
    let energy = |y: &[f64]| {
        let q = SVector::<f64, 2>::from_column_slice(&y[..2]);
        let v = SVector::<f64, 2>::from_column_slice(&y[2..]);
        p.kinetic_energy(&q, &v) + p.potential_energy(&q)
    };
    let y0 = [2.0, 2.5, 0.0, 0.0];
    let e0 = energy(&y0);
    let mut rows = Vec::new();
    for rtol in [1e-8, 1e-11] {
        let start = Instant::now();
        let method = Method::Dopri5(Options {
            max_steps: usize::MAX,
            ..Options::tolerances(rtol, rtol * 1e-2)
        });
        let mut y = y0.to_vec();
        let (mut t, mut worst, mut steps) = (0.0, 0.0f64, 0usize);
        let mut failure = None;
        while t < horizon && failure.is_none() {
            let t1 = (t + 100.0).min(horizon);
            match solve(&sys, &Problem::new(t, t1, y.clone()), &method) {
                Ok(traj) => {
                    steps += traj.stats.steps;
                    for i in 0..traj.len() {
                        worst = worst.max((energy(traj.state(i)) - e0).abs() / e0.abs());
                    }
                    y = traj.last().expect("rows").1.to_vec();
                    t = t1;
                }
                Err(e) => failure = Some(format!("typed error at t ≈ {t}: {}", e.kind)),
            }
        }
        rows.push(vec![
            format!("chaotic double pendulum (S8, q0 = (2, 2.5)), t ∈ [0, {horizon}]"),
            format!("DOPRI5 rtol {rtol:.0e}"),
            failure.unwrap_or_else(|| "completed".into()),
            format!("max relative energy error {}; {steps} steps", sci(worst)),
            format!("{:.1}", start.elapsed().as_secs_f64() * 1e3),
        ]);
    }
    rows
}
