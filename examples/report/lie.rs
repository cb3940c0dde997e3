//! Lie-group scenes: S10 (the free body through its flips) by Rkmk5, error against run
//! time and the drift of its invariants over many periods; kernel costs of the
//! satellite with an arm and the ball-joint chain, generated against numeric.
//!
//! The reference for S10 is a *different* method: DOPRI5 at rtol 1e-13 on the embedded
//! ODE in ℝ⁷ (`q̇ = ½ q ⊗ (0, ω)`, `I ω̇ = −ω × I ω`, not on the group). Errors: the
//! angle of `R_refᵀ R` and `|ω − ω_ref|`, at the final time and as the maximum over a
//! grid of 200 times from each run's dense output.

use std::hint::black_box as bb;

use filippov::nalgebra::{DVector, Matrix3, SVector, Vector3};
use filippov::prelude::*;
use filippov::runtime::liegroup::{LieMechanical, LieMechanism, so3};
use filippov::runtime::{
    FnSystem, LieProblem, LieSdirk, LieTrajectory, Method, Options, Problem, Rkmk5, Solution,
    SolveError, UnitQuat, numeric, solve,
};
use filippov_scenes::{BallChain, FreeBody, Satellite};

use super::config::Config;
use super::lie_support::{flip_period, s10_initial, s10_run};
use super::markdown::{Page, sci};
use super::support::{Scale, Series, line_plot};
use super::timing::{Timing, ns_timed, timed};
use super::workprecision::Section;

/// The embedded reference: state `(w, x, y, z, ω)`.
fn reference(body: &FreeBody, t_end: f64) -> Solution {
    let i = Vector3::new(body.i1, body.i2, body.i3);
    let sys = FnSystem::new(7, move |_t, y: &[f64], dy: &mut [f64]| {
        let (w, x, yy, z) = (y[0], y[1], y[2], y[3]);
        let om = Vector3::new(y[4], y[5], y[6]);
        // ½ q ⊗ (0, ω)
        dy[0] = -0.5 * (x * om[0] + yy * om[1] + z * om[2]);
        dy[1] = 0.5 * (w * om[0] + yy * om[2] - z * om[1]);
        dy[2] = 0.5 * (w * om[1] + z * om[0] - x * om[2]);
        dy[3] = 0.5 * (w * om[2] + x * om[1] - yy * om[0]);
        let iw = i.component_mul(&om);
        let dw = (-om.cross(&iw)).component_div(&i);
        dy[4..7].copy_from_slice(dw.as_slice());
    });
    let y0 = [1.0, 0.0, 0.0, 0.0, 0.01, 1.0, 0.0];
    solve(
        &sys,
        &Problem::new(0.0, t_end, y0),
        &Method::Dopri5(Options::tolerances(1e-13, 1e-15)),
    )
    .expect("reference run")
}

fn ref_at(traj: &Solution, t: f64) -> (Matrix3<f64>, Vector3<f64>) {
    let y = traj.at(t).expect("reference covers the grid");
    let q = UnitQuat::try_new(y[0], y[1], y[2], y[3]).expect("unit");
    (q.to_matrix(), Vector3::new(y[4], y[5], y[6]))
}

fn lie_at(traj: &LieTrajectory, t: f64) -> Option<(Matrix3<f64>, Vector3<f64>)> {
    traj.at(t).map(|y| {
        (
            y.rotations[0].to_matrix(),
            // LieState velocity order: ω of the rotation first, then ṗ.
            Vector3::new(y.velocity[0], y.velocity[1], y.velocity[2]),
        )
    })
}

/// `(final-time error, max over the grid)`: the larger of the rotation angle and the ω
/// difference.
fn errors(traj: &LieTrajectory, reference: &Solution, t_end: f64) -> (f64, f64) {
    let err = |t: f64| {
        lie_at(traj, t).map(|(r, w)| {
            let (rr, wr) = ref_at(reference, t);
            so3::log(&(rr.transpose() * r)).norm().max((w - wr).norm())
        })
    };
    let fin = err(t_end).unwrap_or(f64::NAN);
    let dense = (0..=200)
        .filter_map(|k| err(t_end * k as f64 / 200.0))
        .fold(0.0, f64::max);
    (fin, dense)
}

struct Point {
    label: String,
    time: Timing,
    steps: usize,
    rejected: usize,
    evals: usize,
    final_err: f64,
    dense_err: f64,
}

pub fn lie(config: &Config) -> Section {
    let mut page = Page::empty();
    let mut summary = Vec::new();
    let body = FreeBody::default();
    let sys = LieMechanical::free(&body);
    let period = flip_period(200.0).unwrap_or(f64::NAN);
    let t_end = (3.0 * period * config.horizon).max(1.0);
    let reference = reference(&body, t_end);

    // Work-precision: tolerance sweeps (explicit Rkmk5, implicit LieSdirk) and fixed
    // steps.
    let point = |label: String, time: Timing, run: Result<LieTrajectory, SolveError>| match run {
        Ok(traj) => {
            let (final_err, dense_err) = errors(&traj, &reference, t_end);
            let s = traj.stats;
            Point {
                label,
                time,
                steps: s.steps,
                rejected: s.rejected_steps,
                evals: s.rhs_evaluations,
                final_err,
                dense_err,
            }
        }
        Err(e) => Point {
            label: format!("{label}: failed ({})", e.kind),
            time,
            steps: 0,
            rejected: 0,
            evals: 0,
            final_err: f64::NAN,
            dense_err: f64::NAN,
        },
    };
    let problem = LieProblem::new(0.0, t_end, s10_initial());
    let mut adaptive = Vec::new();
    let mut implicit = Vec::new();
    // Down to rtol 1e-12 beyond the run's sweep (not on `--tiny`): whether the methods
    // keep following the tolerance where round-off and Newton errors would show.
    let mut tolerances = config.tolerances.clone();
    if config.name != "tiny" {
        for t in [1e-11, 1e-12] {
            if !tolerances.contains(&t) {
                tolerances.push(t);
            }
        }
    }
    for &tol in &tolerances {
        let options = Options::tolerances(tol, tol * 1e-3);
        let method = Rkmk5::new(options);
        let (time, run) = timed(config.repeats, || method.solve(&sys, &problem));
        adaptive.push(point(format!("rtol {tol:.0e}"), time, run));
        let method = LieSdirk::new(options);
        let (time, run) = timed(config.repeats, || method.solve(&sys, &problem));
        implicit.push(point(format!("rtol {tol:.0e}"), time, run));
    }
    let mut fixed = Vec::new();
    for &n in &config.rk4_steps {
        let h = t_end / n as f64;
        let method = Rkmk5::fixed(h);
        let problem = LieProblem::new(0.0, t_end, s10_initial());
        let (time, run) = timed(config.repeats, || method.solve(&sys, &problem));
        fixed.push(match run {
            Ok(traj) => {
                let (final_err, dense_err) = errors(&traj, &reference, t_end);
                let s = traj.stats;
                Point {
                    label: format!("h = {}", sci(h)),
                    time,
                    steps: s.steps,
                    rejected: 0,
                    evals: s.rhs_evaluations,
                    final_err,
                    dense_err,
                }
            }
            Err(e) => Point {
                label: format!("h = {}: failed ({})", sci(h), e.kind),
                time,
                steps: 0,
                rejected: 0,
                evals: 0,
                final_err: f64::NAN,
                dense_err: f64::NAN,
            },
        });
    }
    let order = {
        let xy: Vec<(f64, f64)> = fixed
            .iter()
            .filter(|p| p.final_err > 1e-11 && p.final_err.is_finite())
            .map(|p| ((p.steps as f64).ln(), p.final_err.ln()))
            .collect();
        (xy.len() >= 2).then(|| {
            let n = xy.len() as f64;
            let mx = xy.iter().map(|p| p.0).sum::<f64>() / n;
            let my = xy.iter().map(|p| p.1).sum::<f64>() / n;
            let sxy: f64 = xy.iter().map(|(x, y)| (x - mx) * (y - my)).sum();
            let sxx: f64 = xy.iter().map(|(x, _)| (x - mx) * (x - mx)).sum();
            -sxy / sxx
        })
    };
    page.h2("S10: free body on SO(3) × ℝ³ (Lie-group integration)");
    page.para(&format!(
        "`FreeBody` (derive, `free` joint), I = diag(1, 2, 3), ω0 = (0.01, 1, 0); flip period T = {period:.4} \
         (from a tight run). Horizon {t_end:.2} (three flips at the default horizon). Rkmk5 (Munthe-Kaas RK on the \
         Dormand–Prince tableau), adaptive and at fixed steps, and LieSdirk (SDIRK4 on the group, \
         Newton with the generated Jacobian in local coordinates), adaptive. Errors (rotation angle of R_refᵀR, or |ω − ω_ref| if \
         larger) against DOPRI5 at rtol 1e-13 on the embedded quaternion ODE in ℝ⁷ — a different method. Observed order \
         of the fixed-step runs: {}.",
        order.map_or("n/a".into(), |p| format!("{p:.2}"))
    ));
    let rows: Vec<Vec<String>> = adaptive
        .iter()
        .map(|p| ("Rkmk5 adaptive", p))
        .chain(implicit.iter().map(|p| ("LieSdirk adaptive", p)))
        .chain(fixed.iter().map(|p| ("Rkmk5 fixed", p)))
        .map(|(m, p)| {
            vec![
                m.into(),
                p.label.clone(),
                p.time.scaled(1e3).show(3),
                p.steps.to_string(),
                p.rejected.to_string(),
                p.evals.to_string(),
                sci(p.final_err),
                sci(p.dense_err),
            ]
        })
        .collect();
    page.table(
        &[
            "method",
            "setting",
            "time [ms], median (min–max)",
            "steps",
            "rejected",
            "evaluations",
            "final error",
            "max error on grid",
        ],
        &rows,
    );
    let series = vec![
        Series::new(
            "Rkmk5 adaptive",
            adaptive
                .iter()
                .map(|p| (p.time.median * 1e3, p.dense_err))
                .collect(),
        ),
        Series::new(
            "LieSdirk adaptive",
            implicit
                .iter()
                .map(|p| (p.time.median * 1e3, p.dense_err))
                .collect(),
        ),
        Series::new(
            "Rkmk5 fixed step",
            fixed
                .iter()
                .map(|p| (p.time.median * 1e3, p.dense_err))
                .collect(),
        ),
    ];
    line_plot(
        &config.out_dir.join("s10_work_precision.svg"),
        "S10: error against run time",
        "time [ms]",
        "max error on grid",
        &series,
        Scale::Log,
        Scale::Log,
    );
    page.image("S10 work-precision", "s10_work_precision.svg");
    if let Some(p) = adaptive
        .iter()
        .find(|p| p.dense_err <= 1e-6 && p.dense_err.is_finite())
    {
        summary.push(format!(
            "S10 (free body, Lie group): error ≤ 1e-6 over three flips in {:.3} ms ({}, {} steps)",
            p.time.median * 1e3,
            p.label,
            p.steps
        ));
    }
    if let Some(p) = implicit.last() {
        summary.push(format!(
            "S10: LieSdirk at the tightest tolerance ({}): final error {}, max on the grid {} ({} steps, {:.1} ms); Rkmk5 there: {} and {}",
            p.label,
            sci(p.final_err),
            sci(p.dense_err),
            p.steps,
            p.time.median * 1e3,
            adaptive.last().map_or("—".into(), |a| sci(a.final_err)),
            adaptive.last().map_or("—".into(), |a| sci(a.dense_err)),
        ));
    }

    // Invariants over many periods.
    let periods = if config.name == "long" {
        1e4
    } else if config.name == "tiny" {
        2.0
    } else {
        1e3
    };
    let mut rows = Vec::new();
    let mut drift_series = Vec::new();
    for rtol in [1e-6, 1e-9] {
        match s10_run(rtol, periods, period, 20) {
            Ok(run) => {
                rows.push(vec![
                    format!("{rtol:.0e}"),
                    format!("{periods:.0}"),
                    run.steps.to_string(),
                    sci(run.energy_drift),
                    sci(run.momentum_drift),
                    format!("{:.3}", run.seconds),
                ]);
                drift_series.push(Series::new(
                    format!("energy, rtol {rtol:.0e}"),
                    run.history.iter().map(|&(t, e, _)| (t, e)).collect(),
                ));
                drift_series.push(Series::new(
                    format!("angular momentum, rtol {rtol:.0e}"),
                    run.history.iter().map(|&(t, _, l)| (t, l)).collect(),
                ));
                summary.push(format!(
                    "S10 over {periods:.0} flip periods at rtol {rtol:.0e}: energy drift {}, angular-momentum drift {} (relative), {:.2} s",
                    sci(run.energy_drift),
                    sci(run.momentum_drift),
                    run.seconds
                ));
            }
            Err(e) => rows.push(vec![
                format!("{rtol:.0e}"),
                format!("{periods:.0}"),
                format!("failed: {}", e.kind),
                String::new(),
                String::new(),
                String::new(),
            ]),
        }
    }
    page.h3("Invariants over many flip periods");
    page.para(
        "Largest relative drift of the kinetic energy and of the spatial angular momentum at the accepted steps; \
         one run (the example `s10_free_body` runs 10⁴ periods).",
    );
    page.table(
        &[
            "rtol",
            "periods",
            "steps",
            "energy drift",
            "momentum drift",
            "time [s]",
        ],
        &rows,
    );
    line_plot(
        &config.out_dir.join("s10_drift.svg"),
        "S10: invariants' drift",
        "t [s]",
        "relative drift",
        &drift_series,
        Scale::Linear,
        Scale::Log,
    );
    page.image("S10 drift", "s10_drift.svg");

    // Kernels of the Lie scenes.
    let mut rows = Vec::new();
    lie_row(
        config,
        "Satellite (free base + 2-link arm)",
        &Satellite::default(),
        &mut rows,
        &mut summary,
    );
    lie_row(
        config,
        "BallChain (hinge, ball, hinge)",
        &BallChain::default(),
        &mut rows,
        &mut summary,
    );
    page.h3("Kernels of the Lie-group scenes");
    page.para("ns per call, generated / numeric (speed-up), each median (min–max) of batches; a ratio's range pairs the slowest batch of one with the fastest of the other; the numeric Coriolis matrix differentiates M along exponential directions.");
    page.table(&["scene", "dof", "M", "C", "forward dynamics"], &rows);
    Section { page, summary }
}

fn lie_row<S: LieMechanism<N, NQ> + Coriolis<N, NQ>, const N: usize, const NQ: usize>(
    config: &Config,
    name: &str,
    s: &S,
    rows: &mut Vec<Vec<String>>,
    summary: &mut Vec<String>,
) {
    let mut q = S::identity_configuration();
    for &(slot, _) in S::ROTATIONS {
        let r = UnitQuat::exp(&Vector3::new(0.3, -0.5, 0.8)).coords();
        q.fixed_rows_mut::<4>(slot).copy_from_slice(&r);
    }
    for &(slot, c) in S::EUCLID {
        q[slot] = 0.3 + 0.7 * (c as f64).sin();
    }
    let v = SVector::<f64, N>::from_fn(|i, _| 0.5 - 0.4 * (i as f64).cos());
    let tau = SVector::<f64, N>::from_fn(|i, _| 0.2 * i as f64);
    let model = s.model();
    let (qd, vd, td) = (
        DVector::from_column_slice(q.as_slice()),
        DVector::from_column_slice(v.as_slice()),
        DVector::from_column_slice(tau.as_slice()),
    );
    let (r, c) = (config.repeats.max(3), config.kernel_calls);
    let m = (
        ns_timed(r, c, || s.mass_matrix(bb(&q))),
        ns_timed(r, c / 10, || numeric::crba(&model, bb(&qd))),
    );
    let cor = (
        ns_timed(r, c, || s.coriolis_matrix(bb(&q), bb(&v))),
        ns_timed(r, c / 50, || {
            numeric::lie_coriolis_matrix(&model, bb(&qd), bb(&vd))
        }),
    );
    let fd = (
        ns_timed(r, c, || s.forward_dynamics(bb(&q), bb(&v), bb(&tau))),
        ns_timed(r, c / 10, || {
            numeric::forward_dynamics(&model, bb(&qd), bb(&vd), bb(&td))
        }),
    );
    let cell =
        |(a, b): (Timing, Timing)| format!("{} / {} ({})", a.show(1), b.show(1), b.ratio_to(&a, 1));
    rows.push(vec![
        name.into(),
        N.to_string(),
        cell(m),
        cell(cor),
        cell(fd),
    ]);
    summary.push(format!(
        "{name}: generated forward dynamics {} ns vs numeric {} ns per call ({} faster)",
        fd.0.show(1),
        fd.1.show(1),
        fd.1.ratio_to(&fd.0, 1)
    ));
}
