//! Ensembles in lockstep (`runtime::lockstep`): many runs of one scene integrated
//! together in SIMD lanes (`f64x4` and `f64x2`), against the same driver one run at a time (`f64`)
//! and against the library's own integrator per run, all in this run of the report,
//! as runs per second on one core:
//! - smooth: the Panda swinging freely from random states, DOPRI5 with the batch
//!   stepping by its worst lane (`lockstep`); the library's `solve` per run beside it;
//! - non-smooth: the Panda falling onto its joint limits (rigid stops, restitution
//!   drawn per run) with Coulomb friction on every joint (drawn per run), by
//!   time-stepping with each lane's run keeping its own steps and element solve
//!   (`time_stepping_lockstep`); the library's `time_stepping` per run beside it.

use std::time::Instant;

use filippov::runtime::lockstep::{
    Final, LockstepOptions, NonSmoothRun, Run, lockstep, time_stepping_lockstep,
};
use filippov::runtime::nonsmooth::time_stepping;
use filippov::runtime::real::{F64Lanes, Lanes, f64x2, f64x4};
use filippov::runtime::{
    MechanicalSystem, Method, NonSmoothProblem, Options, Problem, Solution, SolveError, solve,
};

use super::agreement_support::Rng;
use super::config::Config;
use super::markdown::{Page, headline, sci};
use super::panda_limits::{PandaOnLimits, V7, release_pose, zero};
use super::scalars::lanes_name;
use super::timing::{Timing, in_rounds};
use super::urdf::PandaUrdf;

#[derive(Default)]
pub struct Section {
    pub page: Page,
    pub summary: Vec<String>,
}

/// One ensemble's four ways: lanes of `f64x4` and of `f64x2`, one run at a time, the
/// library per run.
struct Measured {
    runs: usize,
    /// Seconds per ensemble (median over rounds, fastest, slowest) of each way in that
    /// order; `None` if a way failed.
    times: Vec<Option<Timing>>,
    /// The largest difference between the end states in the lanes the runtime
    /// recommends ([`F64Lanes`]) and the library's, relative to max(|x|, 1).
    difference: f64,
    /// What the runs did (steps per run, switches), for the table.
    note: String,
}

/// One timing of `job` (its wall time as median, min and max), `None` if it failed;
/// [`in_rounds`] interleaves the ways and combines their rounds.
fn once(job: impl FnOnce() -> bool) -> Option<Timing> {
    let start = Instant::now();
    let ok = job();
    let s = start.elapsed().as_secs_f64();
    ok.then_some(Timing {
        median: s,
        min: s,
        max: s,
    })
}

/// Of a result in `f64x2` lanes and one in `f64x4` lanes, the one in the lanes the
/// runtime recommends ([`F64Lanes`]).
fn register_width<'a, T>(two: &'a T, four: &'a T) -> &'a T {
    if F64Lanes::LANES == 2 { two } else { four }
}

fn largest_difference(a: impl Iterator<Item = f64>, b: impl Iterator<Item = f64>) -> f64 {
    a.zip(b)
        .map(|(x, y)| (x - y).abs() / y.abs().max(1.0))
        .fold(0.0, f64::max)
}

/// The free Panda: random states, DOPRI5 at rtol 1e-8.
fn smooth(config: &Config) -> Measured {
    let count = if config.name == "tiny" { 5 } else { 200 };
    let t_end = config.horizon;
    let mut rng = Rng::new(41);
    let runs: Vec<Run<7, 0>> = (0..count)
        .map(|_| Run {
            parameters: [],
            q0: std::array::from_fn(|_| rng.uniform(-1.0, 1.0)),
            v0: std::array::from_fn(|_| rng.uniform(-0.5, 0.5)),
        })
        .collect();
    let options = LockstepOptions {
        rtol: 1e-8,
        atol: 1e-10,
        ..LockstepOptions::default()
    };
    let method = Method::Dopri5(Options::tolerances(1e-8, 1e-10));
    let (mut lanes, mut single): (Vec<Final<7>>, Vec<Final<7>>) = (Vec::new(), Vec::new());
    let mut halves: Vec<Final<7>> = Vec::new();
    let mut library: Vec<Vec<f64>> = Vec::new();
    let times = in_rounds(
        config.repeats.max(1),
        &mut [
            &mut || {
                once(|| {
                    lanes = lockstep::<PandaUrdf, f64x4, 7, 0>(&runs, t_end, &options)
                        .unwrap_or_default();
                    lanes.len() == runs.len()
                })
            },
            &mut || {
                once(|| {
                    halves = lockstep::<PandaUrdf, f64x2, 7, 0>(&runs, t_end, &options)
                        .unwrap_or_default();
                    halves.len() == runs.len()
                })
            },
            &mut || {
                once(|| {
                    single = lockstep::<PandaUrdf, f64, 7, 0>(&runs, t_end, &options)
                        .unwrap_or_default();
                    single.len() == runs.len()
                })
            },
            &mut || {
                once(|| {
                    library = runs
                        .iter()
                        .filter_map(|r| {
                            let y0: Vec<f64> = r.q0.iter().chain(&r.v0).copied().collect();
                            let sol = solve(
                                &MechanicalSystem::unforced(&PandaUrdf),
                                &Problem::new(0.0, t_end, y0),
                                &method,
                            )
                            .ok()?;
                            sol.last().map(|(_, y)| y.to_vec())
                        })
                        .collect();
                    library.len() == runs.len()
                })
            },
        ],
    );
    let ends = |f: &[Final<7>]| -> Vec<f64> {
        f.iter()
            .flat_map(|x| x.q.iter().chain(&x.v).copied())
            .collect()
    };
    let own = register_width(&halves, &lanes);
    let lane_ends = ends(own);
    let difference =
        largest_difference(lane_ends.iter().copied(), library.iter().flatten().copied());
    let steps =
        |f: &[Final<7>]| f.iter().map(|x| x.steps).sum::<usize>() as f64 / f.len().max(1) as f64;
    Measured {
        runs: count,
        times,
        difference,
        note: format!(
            "{:.0} steps per run in f64x4 lanes (the batch's), {:.0} in f64x2, {:.0} one at a time",
            steps(&lanes),
            steps(&halves),
            steps(&single)
        ),
    }
}

/// The Panda on its limits with joint friction: random restitution, friction and
/// states, time-stepping at h = 1e-3, θ = 1.
fn nonsmooth(config: &Config) -> Measured {
    let count = if config.name == "tiny" { 5 } else { 64 };
    let tf = config.horizon;
    let (h, theta) = (1e-3, 1.0);
    let mut rng = Rng::new(42);
    let runs: Vec<NonSmoothRun<PandaOnLimits, 7>> = (0..count)
        .map(|_| {
            let system = PandaOnLimits {
                e: rng.uniform(0.0, 0.5),
                fc: rng.uniform(0.1, 2.0),
            };
            let q0 = release_pose() + V7::from_fn(|_, _| rng.uniform(-0.25, 0.25));
            let v0 = V7::from_fn(|_, _| rng.uniform(-0.5, 0.5));
            NonSmoothRun {
                system,
                problem: NonSmoothProblem::new(0.0, tf, q0, v0),
            }
        })
        .collect();
    let all_ok =
        |r: &[Result<Solution, SolveError>]| r.len() == count && r.iter().all(Result::is_ok);
    let mut lanes = Vec::new();
    let mut halves = Vec::new();
    let mut single = Vec::new();
    let mut library = Vec::new();
    let times = in_rounds(
        config.repeats.max(1),
        &mut [
            &mut || {
                once(|| {
                    lanes = time_stepping_lockstep::<_, f64x4, _, 7, 2>(&runs, &zero, h, theta);
                    all_ok(&lanes)
                })
            },
            &mut || {
                once(|| {
                    halves = time_stepping_lockstep::<_, f64x2, _, 7, 2>(&runs, &zero, h, theta);
                    all_ok(&halves)
                })
            },
            &mut || {
                once(|| {
                    single = time_stepping_lockstep::<_, f64, _, 7, 2>(&runs, &zero, h, theta);
                    all_ok(&single)
                })
            },
            &mut || {
                once(|| {
                    library = runs
                        .iter()
                        .map(|r| time_stepping(&r.system, &zero, &r.problem, h, theta))
                        .collect();
                    all_ok(&library)
                })
            },
        ],
    );
    let last = |r: &[Result<Solution, SolveError>]| -> Vec<f64> {
        r.iter()
            .filter_map(|s| s.as_ref().ok()?.last().map(|(_, y)| y[..14].to_vec()))
            .flatten()
            .collect()
    };
    let own = register_width(&halves, &lanes);
    let difference = largest_difference(last(own).into_iter(), last(&library).into_iter());
    // The switch logs: a mode decided at the rounding level (a friction sticking, a stop
    // closing, at a velocity that rounds to either side of zero) may switch a step
    // earlier or later when the kernels round differently, with no effect on the states.
    let log = |s: &Solution| -> Vec<String> {
        (s.switches.iter())
            .map(|w| {
                format!(
                    "{} {:?} {:?} {:?} {:?}",
                    w.t, w.kind, w.element, w.from, w.to
                )
            })
            .collect()
    };
    let (mut total, mut same) = (0, 0);
    for (a, b) in own.iter().zip(&library) {
        if let (Ok(a), Ok(b)) = (a, b) {
            total += b.switches.len();
            same += usize::from(log(a) == log(b));
        }
    }
    let sweeps: usize = (library.iter().filter_map(|s| s.as_ref().ok()))
        .map(|s| s.stats.newton_iterations)
        .sum();
    Measured {
        runs: count,
        times,
        difference,
        note: format!(
            "{} steps per run, {:.1} Gauss–Seidel sweeps per step; {total} switches alone; the same switch log in lanes for {same} of {count} runs (the others: a friction sticking or a stop closing a step earlier or later, decided at the rounding level)",
            (tf / h).round(),
            sweeps as f64 / (count as f64 * (tf / h).round())
        ),
    }
}

/// Runs per second from seconds per ensemble (the range from the slowest and fastest).
fn per_second(runs: usize, t: &Timing) -> Timing {
    let n = runs as f64;
    Timing {
        median: n / t.median,
        min: n / t.max,
        max: n / t.min,
    }
}

pub fn ensembles(config: &Config) -> Section {
    let mut page = Page::empty();
    let mut summary = Vec::new();
    let mut table = Vec::new();
    let cases = [
        (
            "Panda, free swing (DOPRI5, rtol 1e-8)",
            "solve",
            smooth(config),
        ),
        (
            "Panda on its limits with joint friction (time-stepping, h = 1e-3)",
            "time_stepping",
            nonsmooth(config),
        ),
    ];
    // The lanes the runtime recommends (f64x4 on x86-64, f64x2 elsewhere without AVX):
    // the headline's.
    let (own, width) = (*register_width(&1, &0), lanes_name());
    for (name, library, m) in &cases {
        let rate = |i: usize| m.times[i].map(|t| per_second(m.runs, &t));
        let show = |t: Option<Timing>| t.map_or("**failed**".into(), |t| t.show(0));
        let ratio = |a: Option<Timing>, b: Option<Timing>| match (a, b) {
            // Times: the single runs' over the lanes' is the lanes' gain.
            (Some(a), Some(b)) => b.ratio_to(&a, 2),
            _ => "—".into(),
        };
        table.push(vec![
            name.to_string(),
            m.runs.to_string(),
            show(rate(0)),
            show(rate(1)),
            show(rate(2)),
            format!("{} ({library})", show(rate(3))),
            format!(
                "{} / {}",
                ratio(m.times[0], m.times[2]),
                ratio(m.times[1], m.times[2])
            ),
            ratio(m.times[own], m.times[3]),
            sci(m.difference),
            m.note.clone(),
        ]);
        if let (Some(l), Some(s)) = (rate(own), rate(2)) {
            summary.push(format!(
                "Lockstep ensemble, {name}: {} runs/s per core in {width} lanes against {} one at a time ({}).",
                l.show(0),
                s.show(0),
                ratio(m.times[own], m.times[2])
            ));
            headline(
                format!(
                    "Ensemble in lockstep ({width} lanes, `F64Lanes`), {name}: runs per second on one core"
                ),
                format!("{} runs/s", l.show(0)),
                format!("{} runs/s one at a time", s.show(0)),
                ratio(m.times[own], m.times[2]),
                format!(
                    "{} runs, {} interleaved rounds in this run, same build; ratio: lanes' rate / one at a time",
                    m.runs,
                    config.repeats.max(1)
                ),
            );
        }
    }
    page.h2("Ensembles in lockstep");
    page.para(&format!(
        "Many runs of one scene integrated together in SIMD lanes (four runs per call of the scene's generic \
         kernels in `f64x4`, two in `f64x2`), against the same driver one run at a time on `f64` and the \
         library's integrator per run, as runs per second on one core: median over interleaved rounds \
         (min–max), each round one whole ensemble. The headline's lanes are `{width}` \
         (`runtime::real::F64Lanes`): on x86-64 the forward dynamics and mass matrix on `f64x4` run their \
         fused twins, four lanes to an AVX2 register, where the processor has AVX2 and FMA \
         (`runtime::numerics::fused_lanes`); elsewhere lanes wider than the build's register run each \
         operation as two halves. Smooth: the batch steps \
         by its worst lane's error (`lockstep`). Non-smooth: each lane's run keeps its own steps and element \
         solve and a lane whose run ends takes the next (`time_stepping_lockstep`); the lanes share the \
         forward dynamics with its Jacobian and the mass matrix. Difference: the largest difference between \
         the end states in `{width}` lanes and by the library per run, relative to max(|x|, 1).",
    ));
    page.table(
        &[
            "ensemble",
            "runs",
            "f64x4 lanes runs/s",
            "f64x2 lanes runs/s",
            "one at a time runs/s",
            "library per run runs/s",
            "lanes / one at a time (f64x4 / f64x2)",
            &format!("{width} lanes / library"),
            "difference",
            "what the runs did",
        ],
        &table,
    );
    Section { page, summary }
}
