//! diffsol (crates.io) as a peer of filippov, measured in one run and written as a TSV.
//!
//! * Smooth scenes (the double pendulum of S8 and the Panda arm), with the generated
//!   kernels and their symbolic Jacobian handed to diffsol's closure API: diffsol BDF,
//!   ESDIRK34, TR-BDF2 and TSIT45 against filippov's DOPRI5, SDIRK4 and BDF on the same
//!   problems, same tolerances, same timing.
//!   The double pendulum, the Panda and a stiff three-link arm (stiff, damped joint
//!   springs), at tolerances from 1e-4 to 1e-9, every row against one reference.
//! * S6 and S5 with the friction regularised as `f_crit·tanh(v/ε)` for a sweep of ε
//!   (diffsol BDF, ESDIRK34 and TSIT45, each ε at the event-driven runs' tolerances),
//!   against the exact non-smooth solution, next to filippov's event-driven integrator on
//!   the non-smooth law itself.
//!
//! Usage: `filippov-peer-diffsol [OUT.tsv]` (default `target/report/peers/diffsol.tsv`
//! under the repository root). See README.md for the columns.

mod exact;
mod ode;
mod run;

use std::fmt::Write as _;
use std::path::PathBuf;

use filippov::Mechanism;
use filippov::nalgebra::SVector;
use filippov::runtime::{
    MechanicalSystem, Method, NonSmoothMethod, NonSmoothProblem, Options, Output, Problem,
    Solution, Stats, solve, solve_nonsmooth,
};
use filippov_scenes::{CoulombOscillator, DoublePendulum, Panda, PlanarArm3};

use exact::CoulombFreeDecay;
use ode::{Mechanical, Regularised};
use run::{Solver, Wall, interleaved};

/// Timed repetitions after one warm-up.
const REPEATS: usize = 5;
/// Grid intervals for the dense error (grid of `GRID + 1` times, ends included).
const GRID: usize = 200;
/// Tolerances of the smooth sweeps, half a decade apart from 1e-4 to 1e-9 for every
/// solver: a work-precision verdict ("fastest to an error ≤ …") is then not decided by
/// which solver happens to land just under the threshold on a coarse grid.
const SMOOTH_RTOLS: [f64; 11] = [
    1e-4, 3e-5, 1e-5, 3e-6, 1e-6, 3e-7, 1e-7, 3e-8, 1e-8, 3e-9, 1e-9,
];
const EPSILONS: [f64; 5] = [1e-1, 1e-2, 1e-3, 1e-4, 1e-5];
/// Tolerances of filippov's event-driven runs on S5/S6, and of diffsol's regularised
/// runs at every ε (atol = rtol·1e-2).
const EVENT_RTOLS: [f64; 4] = [1e-4, 1e-6, 1e-8, 1e-10];

struct Row {
    scene: &'static str,
    solver: String,
    setting: String,
    /// Wall time in milliseconds, median (min–max) of the repetitions.
    time: Wall,
    steps: Option<usize>,
    final_error: f64,
    max_grid_error: f64,
    notes: String,
}

impl Row {
    /// A run that finished: `errors` are (final, max over the grid).
    fn measured(
        scene: &'static str,
        solver: &str,
        setting: String,
        time: Wall,
        steps: usize,
        (final_error, max_grid_error): (f64, f64),
        notes: String,
    ) -> Row {
        Row {
            scene,
            solver: solver.into(),
            setting,
            time,
            steps: Some(steps),
            final_error,
            max_grid_error,
            notes,
        }
    }

    fn failed(scene: &'static str, solver: &str, setting: String, why: &str) -> Row {
        Row {
            scene,
            solver: solver.into(),
            setting,
            time: Wall::NONE,
            steps: None,
            final_error: f64::NAN,
            max_grid_error: f64::NAN,
            notes: format!("failed: {}", why.replace(['\t', '\n'], " ")),
        }
    }
}

fn grid(t0: f64, tf: f64) -> Vec<f64> {
    (0..=GRID)
        .map(|i| {
            if i == GRID {
                tf
            } else {
                t0 + (tf - t0) * i as f64 / GRID as f64
            }
        })
        .collect()
}

/// (final error, max error over the grid) over the components `comps` of each state.
fn errors(values: &[Vec<f64>], reference: &[Vec<f64>], comps: usize) -> (f64, f64) {
    if values.len() != reference.len() {
        return (f64::INFINITY, f64::INFINITY);
    }
    let diff =
        |a: &Vec<f64>, b: &Vec<f64>| (0..comps).map(|j| (a[j] - b[j]).abs()).fold(0.0, f64::max);
    let last = values.len() - 1;
    let fin = diff(&values[last], &reference[last]);
    let max = values
        .iter()
        .zip(reference)
        .map(|(a, b)| diff(a, b))
        .fold(0.0, f64::max);
    (fin, max)
}

/// A filippov trajectory at the grid times (NaN outside its range).
fn on_grid(traj: &Solution, grid: &[f64]) -> Vec<Vec<f64>> {
    grid.iter()
        .map(|&t| traj.at(t).unwrap_or_else(|| vec![f64::NAN; traj.dim()]))
        .collect()
}

fn sci(x: f64) -> String {
    format!("{x:.3e}")
}

/// The smooth scene `sys` from `y0` over `[0, tf]`.
fn smooth<S: Mechanism<N>, const N: usize>(
    rows: &mut Vec<Row>,
    header: &mut Vec<String>,
    scene: &'static str,
    sys: &S,
    y0: Vec<f64>,
    tf: f64,
) {
    eprintln!("== {scene}");
    let grid = grid(0.0, tf);
    let system = MechanicalSystem::unforced(sys);
    let problem = Problem::new(0.0, tf, y0.clone());
    let ref_dopri = solve(
        &system,
        &problem,
        &Method::Dopri5(Options::tolerances(1e-13, 1e-15)),
    );
    let h = 1e-5;
    let ref_rk4 = solve(&system, &problem, &Method::Rk4 { h });
    let (Ok(ref_dopri), Ok(ref_rk4)) = (ref_dopri, ref_rk4) else {
        header.push(format!("{scene}: the reference runs failed; no rows"));
        return;
    };
    let (ref_dopri, reference) = (on_grid(&ref_dopri, &grid), on_grid(&ref_rk4, &grid));
    let agree = errors(&ref_dopri, &reference, 2 * N).1;
    header.push(format!(
        "{scene}: y0 = {y0:?}, t in [0, {tf}]; every row, diffsol's and filippov's, is measured against one reference, classical RK4 at the fixed step h = {h:e} (a method no row uses); filippov DOPRI5 at rtol 1e-13 (atol 1e-15) agrees with it to {} over the grid, so errors below that are not resolved",
        sci(agree)
    ));
    let ode = Mechanical::new(sys);
    let diffsol_settings: Vec<(Solver, f64)> = [
        Solver::Bdf,
        Solver::Esdirk34,
        Solver::TrBdf2,
        Solver::Tsit45,
    ]
    .into_iter()
    .flat_map(|solver| SMOOTH_RTOLS.map(|rtol| (solver, rtol)))
    .collect();
    // Our runs keep only the grid's rows (`Output::Times`, each evaluated on the method's
    // dense output as the integration passes it), as diffsol's interpolate to the grid.
    let on_the_grid = problem.clone().with_output(Output::Times(grid.clone()));
    type Make = fn(Options) -> Method;
    let ours: [(&str, Make); 3] = [
        ("filippov DOPRI5", Method::Dopri5),
        ("filippov SDIRK4", Method::Sdirk4),
        ("filippov BDF", Method::Bdf),
    ];
    let our_settings: Vec<(&str, Make, f64)> = ours
        .into_iter()
        .flat_map(|(name, make)| SMOOTH_RTOLS.map(|rtol| (name, make, rtol)))
        .collect();
    // Every run of the scene, diffsol's and ours, timed in rounds (see `interleaved`):
    // a change of the machine's load during the scene reaches all of them alike.
    type Ours = Result<(Vec<Vec<f64>>, Stats), String>;
    let mut theirs: Vec<Option<Result<run::Run, String>>> =
        diffsol_settings.iter().map(|_| None).collect();
    let mut mine: Vec<Option<Ours>> = our_settings.iter().map(|_| None).collect();
    let times = {
        let mut jobs: Vec<Box<dyn FnMut() + '_>> = Vec::new();
        for (slot, &(solver, rtol)) in theirs.iter_mut().zip(&diffsol_settings) {
            let (ode, y0, grid) = (&ode, &y0, &grid);
            jobs.push(Box::new(move || {
                *slot = Some(run::solve(
                    ode,
                    solver,
                    rtol,
                    rtol * 1e-2,
                    0.0,
                    y0,
                    grid,
                    false,
                ));
            }));
        }
        for (slot, &(_, make, rtol)) in mine.iter_mut().zip(&our_settings) {
            let method = make(Options::tolerances(rtol, rtol * 1e-2));
            let (system, on_the_grid, grid) = (&system, &on_the_grid, &grid);
            jobs.push(Box::new(move || {
                *slot = Some(
                    solve(system, on_the_grid, &method)
                        .map(|t| (on_grid(&t, grid), t.stats))
                        .map_err(|e| e.to_string()),
                );
            }));
        }
        interleaved(REPEATS, &mut jobs)
    };
    let (their_times, our_times) = times.split_at(diffsol_settings.len());
    for ((&(solver, rtol), result), &time) in diffsol_settings.iter().zip(theirs).zip(their_times) {
        let atol = rtol * 1e-2;
        let setting = format!("rtol={rtol:.0e}");
        rows.push(match result.expect("run") {
            Ok(r) => {
                let notes = format!(
                    "atol={atol:.0e}; {} error-test failures, {} rhs calls, {} Jacobians ({} LU setups, {} Newton iterations)",
                    r.error_test_failures, r.rhs_calls, r.jacobians, r.lu_setups, r.newton_iterations
                );
                let errors = errors(&r.values, &reference, 2 * N);
                Row::measured(scene, solver.name(), setting, time, r.steps, errors, notes)
            }
            Err(e) => Row::failed(scene, solver.name(), setting, &e),
        });
    }
    for ((&(name, _, rtol), result), &time) in our_settings.iter().zip(mine).zip(our_times) {
        let atol = rtol * 1e-2;
        let setting = format!("rtol={rtol:.0e}");
        rows.push(match result.expect("run") {
            Ok((values, s)) => {
                let notes = format!(
                    "atol={atol:.0e}; {} rejected, {} rhs calls, {} Jacobians ({} LU setups, {} Newton iterations)",
                    s.rejected_steps,
                    s.rhs_evaluations,
                    s.jacobian_evaluations,
                    s.lu_factorisations,
                    s.newton_iterations
                );
                let errors = errors(&values, &reference, 2 * N);
                Row::measured(scene, name, setting, time, s.steps, errors, notes)
            }
            Err(e) => Row::failed(scene, name, setting, &e),
        });
    }
}

/// The largest time or position error of the turning points of a run against the exact
/// ones (infinite when the run has fewer).
fn switch_error(found: &[(f64, f64)], exact: &[(f64, f64)]) -> f64 {
    let mut worst = 0.0f64;
    for (i, (te, xe)) in exact.iter().enumerate() {
        match found.get(i) {
            Some((t, x)) => worst = worst.max((t - te).abs()).max((x - xe).abs()),
            None => return f64::INFINITY,
        }
    }
    worst
}

/// S5 or S6 with regularised friction (diffsol) and event-driven (filippov), errors in x
/// against `reference` on the grid. diffsol is swept like ours: every solver and ε at
/// each of [`EVENT_RTOLS`], so each (solver, ε) is a work-precision curve beside the
/// event-driven one; all runs of the scene are timed in interleaved rounds.
#[allow(clippy::too_many_arguments)]
fn regularised(
    rows: &mut Vec<Row>,
    scene: &'static str,
    coulomb: CoulombOscillator,
    forcing: fn(f64) -> f64,
    problem: &NonSmoothProblem<1>,
    grid: &[f64],
    reference: &[Vec<f64>],
    turning_points: Option<&[(f64, f64)]>,
) {
    eprintln!("== {scene}: regularised (diffsol) and event-driven (filippov)");
    let y0 = [problem.q0[0], problem.v0[0]];
    let settings: Vec<(Solver, f64, f64)> = [Solver::Bdf, Solver::Esdirk34, Solver::Tsit45]
        .into_iter()
        .flat_map(|solver| {
            EPSILONS
                .into_iter()
                .flat_map(move |eps| EVENT_RTOLS.map(|rtol| (solver, eps, rtol)))
        })
        .collect();
    let odes: Vec<Regularised> = settings
        .iter()
        .map(|&(_, eps, _)| Regularised::new(coulomb, eps, forcing))
        .collect();
    let input = move |t: f64, _q: &SVector<f64, 1>, _v: &SVector<f64, 1>| {
        SVector::<f64, 1>::new(forcing(t))
    };
    type Ours = Result<(Vec<Vec<f64>>, Stats, Vec<(f64, f64)>), String>;
    let mut theirs: Vec<Option<Result<run::Run, String>>> = settings.iter().map(|_| None).collect();
    let mut mine: Vec<Option<Ours>> = EVENT_RTOLS.iter().map(|_| None).collect();
    let times = {
        let mut jobs: Vec<Box<dyn FnMut() + '_>> = Vec::new();
        for ((slot, &(solver, _, rtol)), ode) in theirs.iter_mut().zip(&settings).zip(&odes) {
            let y0 = &y0;
            jobs.push(Box::new(move || {
                *slot = Some(run::solve(
                    ode,
                    solver,
                    rtol,
                    rtol * 1e-2,
                    problem.t0,
                    y0,
                    grid,
                    false,
                ));
            }));
        }
        for (slot, &rtol) in mine.iter_mut().zip(&EVENT_RTOLS) {
            let m = NonSmoothMethod::EventDriven(Method::Dopri5(Options::tolerances(
                rtol,
                rtol * 1e-2,
            )));
            let (input, coulomb) = (&input, &coulomb);
            jobs.push(Box::new(move || {
                *slot = Some(
                    solve_nonsmooth(coulomb, input, problem, &m)
                        .map(|t| (on_grid(&t, grid), t.stats, velocity_zeros(&t)))
                        .map_err(|e| e.to_string()),
                );
            }));
        }
        interleaved(REPEATS, &mut jobs)
    };
    let (their_times, our_times) = times.split_at(settings.len());
    for (((&(solver, eps, rtol), result), &time), ode) in
        settings.iter().zip(theirs).zip(their_times).zip(&odes)
    {
        let atol = rtol * 1e-2;
        let label = format!("{} tanh(v/eps)", solver.name());
        let setting = format!("eps={eps:.0e} rtol={rtol:.0e}");
        rows.push(match result.expect("run") {
            Ok(r) => {
                let (fin, max) = errors(&r.values, reference, 1);
                let mut notes = format!(
                    "atol={atol:.0e}; errors in x; {} error-test failures, {} rhs calls, {} Jacobian-vector products",
                    r.error_test_failures, r.rhs_calls, r.jacobians
                );
                if let Some(tp) = turning_points {
                    // Untimed second solve, stepping manually (same steps) to locate
                    // the velocity zeros.
                    match run::solve(ode, solver, rtol, atol, problem.t0, &y0, grid, true) {
                        Ok(z) => {
                            let _ = write!(
                                notes,
                                "; switch_error={}; {} velocity zeros (exact: {})",
                                sci(switch_error(&z.velocity_zeros, tp)),
                                z.velocity_zeros.len(),
                                tp.len()
                            );
                        }
                        Err(e) => {
                            let _ = write!(notes, "; switch points: failed ({e})");
                        }
                    }
                }
                Row::measured(scene, &label, setting, time, r.steps, (fin, max), notes)
            }
            Err(e) => Row::failed(scene, &label, setting, &e),
        });
    }
    let name = "filippov event-driven DOPRI5";
    for ((&rtol, result), &time) in EVENT_RTOLS.iter().zip(mine).zip(our_times) {
        let atol = rtol * 1e-2;
        let setting = format!("rtol={rtol:.0e}");
        rows.push(match result.expect("run") {
            Ok((values, s, zeros)) => {
                let (fin, max) = errors(&values, reference, 1);
                let mut notes = format!(
                    "atol={atol:.0e}; errors in x; {} steps, {} rhs calls, {} events",
                    s.steps, s.rhs_evaluations, s.events
                );
                if let Some(tp) = turning_points {
                    let _ = write!(
                        notes,
                        "; switch_error={}; {} velocity zeros (exact: {})",
                        sci(switch_error(&zeros, tp)),
                        zeros.len(),
                        tp.len()
                    );
                }
                Row::measured(scene, name, setting, time, s.steps, (fin, max), notes)
            }
            Err(e) => Row::failed(scene, name, setting, &e),
        });
    }
}

/// Velocity zeros of a filippov trajectory `[x, v, …]`: rows where v reaches zero or
/// changes sign, located by bisection on the dense output (as the report does).
fn velocity_zeros(traj: &Solution) -> Vec<(f64, f64)> {
    let mut out: Vec<(f64, f64)> = Vec::new();
    for i in 1..traj.len() {
        let (a, b) = (traj.state(i - 1)[1], traj.state(i)[1]);
        if a != 0.0 && (b == 0.0 || a.signum() != b.signum()) {
            let (mut lo, mut hi) = (traj.times()[i - 1], traj.times()[i]);
            if b != 0.0 {
                for _ in 0..60 {
                    let c = 0.5 * (lo + hi);
                    let vc = traj.at(c).map_or(0.0, |y| y[1]);
                    if vc != 0.0 && vc.signum() == a.signum() {
                        lo = c
                    } else {
                        hi = c
                    }
                }
            }
            if out.last().is_none_or(|(tl, _)| hi - tl > 1e-3) {
                out.push((hi, traj.at(hi).map_or(f64::NAN, |y| y[0])));
            }
        }
    }
    out
}

fn nonsmooth(rows: &mut Vec<Row>, header: &mut Vec<String>) {
    let tf = 30.0;
    let grid = grid(0.0, tf);
    let tight = |m: fn(Options) -> Method| {
        NonSmoothMethod::EventDriven(m(Options::tolerances(1e-12, 1e-14)))
    };
    let unforced = |_t: f64, _q: &SVector<f64, 1>, _v: &SVector<f64, 1>| SVector::zeros();

    // S6: closed form, checked against filippov's event-driven solver.
    eprintln!("== S6");
    let s6 = CoulombOscillator {
        m: 1.0,
        k: 1.0,
        f_crit: 0.1,
    };
    let p6 = NonSmoothProblem::new(0.0, tf, SVector::from([1.0]), SVector::from([0.0]));
    let exact = CoulombFreeDecay::new(s6.m, s6.k, s6.f_crit, 0.0, 1.0);
    let exact_grid: Vec<Vec<f64>> = grid
        .iter()
        .map(|&t| {
            let (x, v) = exact.at(t);
            vec![x, v]
        })
        .collect();
    let tp: Vec<(f64, f64)> = exact
        .turning_points()
        .into_iter()
        .filter(|(t, _)| *t <= tf)
        .collect();
    match solve_nonsmooth(&s6, &unforced, &p6, &tight(Method::Dopri5)) {
        Ok(t) => header.push(format!(
            "S6 (m = k = 1, f_crit = 0.1, x0 = 1, v0 = 0, t in [0, 30]): exact piecewise closed form; filippov event-driven DOPRI5 at rtol 1e-12 agrees with it to {} in x and {} in v over the grid, turning points to {}",
            sci(errors(&on_grid(&t, &grid), &exact_grid, 1).1),
            sci(errors(
                &on_grid(&t, &grid).iter().map(|r| vec![r[1]]).collect::<Vec<_>>(),
                &exact_grid.iter().map(|r| vec![r[1]]).collect::<Vec<_>>(),
                1
            ).1),
            sci(switch_error(&velocity_zeros(&t), &tp))
        )),
        Err(e) => header.push(format!("S6: filippov's event-driven check run failed: {e}")),
    }
    regularised(rows, "S6", s6, |_t| 0.0, &p6, &grid, &exact_grid, Some(&tp));

    // S5: filippov's event-driven solution at rtol 1e-12 (SDIRK4 between switches, a
    // different method from the DOPRI5 rows), checked against DOPRI5 at 1e-12.
    eprintln!("== S5");
    let s5 = CoulombOscillator {
        m: 1.0,
        k: 1.0,
        f_crit: 0.5,
    };
    fn forcing5(t: f64) -> f64 {
        1.2 * (0.5 * t).sin()
    }
    let input5 = |t: f64, _q: &SVector<f64, 1>, _v: &SVector<f64, 1>| SVector::from([forcing5(t)]);
    let p5 = NonSmoothProblem::new(0.0, tf, SVector::from([0.25]), SVector::from([0.0]))
        .with_forces(vec![Some(-0.25)]);
    let (r_sdirk, r_dopri) = (
        solve_nonsmooth(&s5, &input5, &p5, &tight(Method::Sdirk4)),
        solve_nonsmooth(&s5, &input5, &p5, &tight(Method::Dopri5)),
    );
    let (Ok(r_sdirk), Ok(r_dopri)) = (r_sdirk, r_dopri) else {
        header.push("S5: the reference runs failed; no rows".into());
        return;
    };
    let (r_sdirk, r_dopri) = (on_grid(&r_sdirk, &grid), on_grid(&r_dopri, &grid));
    header.push(format!(
        "S5 (m = k = 1, f_crit = 0.5, F = 1.2 sin(0.5 t), x0 = 0.25, v0 = 0 stuck, t in [0, 30]): reference filippov event-driven SDIRK4 at rtol 1e-12; event-driven DOPRI5 at rtol 1e-12 agrees with it to {} in x over the grid",
        sci(errors(&r_dopri, &r_sdirk, 1).1)
    ));
    regularised(rows, "S5", s5, forcing5, &p5, &grid, &r_sdirk, None);
}

/// How far DOPRI5 at rtol 1e-13 and at 1e-12 drift apart over `[0, tf]` (max over the
/// grid): the horizon over which the scene's solution can be measured at all.
fn predictability<S: Mechanism<N>, const N: usize>(sys: &S, y0: &[f64], tf: f64) -> String {
    let system = MechanicalSystem::unforced(sys);
    let problem = Problem::new(0.0, tf, y0.to_vec());
    let run = |rtol: f64| {
        solve(
            &system,
            &problem,
            &Method::Dopri5(Options::tolerances(rtol, rtol * 1e-2)),
        )
    };
    let grid = grid(0.0, tf);
    match (run(1e-13), run(1e-12)) {
        (Ok(a), Ok(b)) => format!(
            "DoublePendulum over [0, {tf}]: DOPRI5 at rtol 1e-13 and at 1e-12 differ by up to {} over the grid (chaotic), so the runs below use [0, 5]",
            sci(errors(&on_grid(&a, &grid), &on_grid(&b, &grid), 2 * N).1)
        ),
        _ => format!("DoublePendulum over [0, {tf}]: the predictability check failed"),
    }
}

/// How much the scene amplifies a perturbation of its initial state by `tf`: the largest
/// final deviation over unit perturbations of each component (size 1e-7, DOPRI5 at rtol
/// 1e-13). Every method's error at `tf` is its local errors times about this much, so
/// the errors of different methods at one tolerance can differ by what direction their
/// local errors take.
fn sensitivity<S: Mechanism<N>, const N: usize>(
    scene: &str,
    sys: &S,
    y0: &[f64],
    tf: f64,
) -> String {
    let system = MechanicalSystem::unforced(sys);
    let method = Method::Dopri5(Options::tolerances(1e-13, 1e-15));
    let end = |y: Vec<f64>| {
        solve(&system, &Problem::new(0.0, tf, y), &method)
            .ok()
            .and_then(|s| s.at(tf))
    };
    let Some(base) = end(y0.to_vec()) else {
        return format!("{scene}: the sensitivity check failed");
    };
    let d = 1e-7;
    let mut growth: f64 = 0.0;
    for k in 0..y0.len() {
        let mut y = y0.to_vec();
        y[k] += d;
        let Some(moved) = end(y) else {
            return format!("{scene}: the sensitivity check failed");
        };
        let dev = moved
            .iter()
            .zip(&base)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        growth = growth.max(dev / d);
    }
    format!(
        "{scene}: a perturbation of the initial state grows by up to {} by t = {tf} (largest over the {} components, DOPRI5 at rtol 1e-13), so each method's error at the end is its local errors amplified that much",
        sci(growth),
        y0.len()
    )
}

/// The stiff chain of the smooth sweep (see `main`).
const STIFF_ARM: PlanarArm3 = PlanarArm3 {
    m: 1.0,
    l: 0.5,
    k: 1e4,
    c: 50.0,
};
const STIFF_ARM_Y0: [f64; 6] = [0.5, -0.3, 0.2, 0.0, 0.0, 0.0];

/// The eigenvalues' real parts of the Jacobian of `[q; v]' = [v; FD]` at `y0`, largest and
/// smallest in magnitude: how stiff the scene is.
fn stiffness<S: Mechanism<N>, const N: usize>(sys: &S, y0: &[f64]) -> String {
    let q = SVector::<f64, N>::from_column_slice(&y0[..N]);
    let v = SVector::<f64, N>::from_column_slice(&y0[N..2 * N]);
    let d = sys.forward_dynamics_jacobian(&q, &v, &SVector::zeros());
    let mut j = filippov::nalgebra::DMatrix::<f64>::zeros(2 * N, 2 * N);
    for i in 0..N {
        j[(i, N + i)] = 1.0;
        for k in 0..N {
            j[(N + i, k)] = d.d_dq[(i, k)];
            j[(N + i, N + k)] = d.d_dv[(i, k)];
        }
    }
    let re: Vec<f64> = j.complex_eigenvalues().iter().map(|z| z.re).collect();
    let fast = re.iter().copied().fold(0.0, f64::min);
    let slow = re
        .iter()
        .copied()
        .filter(|x| *x < 0.0)
        .fold(f64::NEG_INFINITY, f64::max);
    format!(
        "at the start the Jacobian's eigenvalues have real parts from {} to {} (ratio {:.0})",
        sci(fast),
        sci(slow),
        fast / slow
    )
}

/// diffsol's version as resolved in this package's Cargo.lock.
fn diffsol_version() -> String {
    let lock = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/Cargo.lock"))
        .unwrap_or_default();
    let mut lines = lock.lines();
    while let Some(l) = lines.next() {
        if l.trim() == "name = \"diffsol\""
            && let Some(v) = lines
                .next()
                .and_then(|v| v.trim().strip_prefix("version = "))
        {
            return v.trim_matches('"').to_string();
        }
    }
    "unknown".into()
}

fn main() {
    let out = std::env::args_os()
        .nth(1)
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../target/report/peers/diffsol.tsv")
        });
    let started = std::time::Instant::now();
    let mut rows = Vec::new();
    let mut header = vec![format!(
        "diffsol {} (dense nalgebra matrices, NalgebraLU); times median (min–max) of {REPEATS} runs after a warm-up; errors over {} grid times",
        diffsol_version(),
        GRID + 1
    )];
    // The double pendulum of S8 is chaotic from this start: over [0, 20] two tight runs
    // of the same method disagree at the O(1) level, so no error can be measured there.
    // The runs use [0, 5], the report's work-precision horizon; the disagreement over
    // [0, 20] is measured and stated.
    let dp = DoublePendulum::default();
    let dp_y0 = vec![1.2, -0.6, 0.0, 0.0];
    header.push(predictability(&dp, &dp_y0, 20.0));
    header.push(sensitivity("DoublePendulum", &dp, &dp_y0, 5.0));
    smooth(&mut rows, &mut header, "DoublePendulum", &dp, dp_y0, 5.0);
    let mut y0 = vec![0.0; 14];
    y0[..7].copy_from_slice(&[0.0, 0.3, 0.0, -1.5, 0.0, 1.8, 0.8]);
    header.push(sensitivity("Panda", &Panda::default(), &y0, 2.0));
    smooth(&mut rows, &mut header, "Panda", &Panda::default(), y0, 2.0);
    // A stiff chain: the three-link arm with stiff, heavily damped joint springs. Its
    // fastest mode decays at about c / I of the last link (several thousand per second)
    // while the motion lasts seconds, so an explicit method's step is held by stability,
    // not accuracy.
    let stiff = STIFF_ARM;
    header.push(format!(
        "StiffArm3: the planar three-link arm with k = {:e} N m/rad and c = {} N m s/rad in every joint (m = {}, l = {}): {}",
        stiff.k,
        stiff.c,
        stiff.m,
        stiff.l,
        stiffness(&stiff, &STIFF_ARM_Y0)
    ));
    smooth(
        &mut rows,
        &mut header,
        "StiffArm3",
        &stiff,
        STIFF_ARM_Y0.to_vec(),
        2.0,
    );
    nonsmooth(&mut rows, &mut header);
    header.push(format!(
        "whole run {:.1} s",
        started.elapsed().as_secs_f64()
    ));

    let mut text = String::new();
    for h in &header {
        let _ = writeln!(text, "# {h}");
    }
    let _ = writeln!(
        text,
        "scene\tsolver\tsetting\ttime_ms\ttime_min_ms\ttime_max_ms\tsteps\tfinal_error\tmax_grid_error\tnotes"
    );
    for r in &rows {
        let _ = writeln!(
            text,
            "{}\t{}\t{}\t{:.4}\t{:.4}\t{:.4}\t{}\t{}\t{}\t{}",
            r.scene,
            r.solver,
            r.setting,
            r.time.median,
            r.time.min,
            r.time.max,
            r.steps.map_or("-".into(), |s| s.to_string()),
            sci(r.final_error),
            sci(r.max_grid_error),
            r.notes
        );
    }
    if let Some(dir) = out.parent()
        && let Err(e) = std::fs::create_dir_all(dir)
    {
        eprintln!("cannot create {}: {e}", dir.display());
        std::process::exit(1);
    }
    if let Err(e) = std::fs::write(&out, text) {
        eprintln!("cannot write {}: {e}", out.display());
        std::process::exit(1);
    }
    eprintln!("wrote {} ({} rows)", out.display(), rows.len());
}
