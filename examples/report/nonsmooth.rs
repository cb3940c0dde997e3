//! Work-precision of the non-smooth scenes (theory S1, S5, S6, S7, the belt's
//! static/kinetic stick–slip) with the event-driven and the time-stepping integrators,
//! against closed forms (S1, S6, S7 elastic, the belt) or a
//! semi-analytic piecewise solution (S5, linear in every mode); then the stiff and
//! extreme suite.

use std::f64::consts::PI;

use filippov::nalgebra::SVector;
use filippov::runtime::nonsmooth::Mode;
use filippov::runtime::{
    Method, NonSmoothMethod, NonSmoothProblem, Options, Solution, SwitchKind, solve_nonsmooth,
};
use filippov_scenes::references;
use filippov_scenes::{
    BeltFriction, BilinearOscillator, BinghamOscillator, BouncingBall, CoulombOscillator,
    SupportedStop,
};

use super::config::Config;
use super::markdown::{Page, sci};
use super::support::{Scale, Series, line_plot};
use super::timing::{Timing, timed};
use super::workprecision::Section;

type V1 = SVector<f64, 1>;

fn unforced(_t: f64, _q: &V1, _v: &V1) -> V1 {
    V1::zeros()
}

/// Velocity zeros (time, position) of a 1-dof trajectory [x, v, f…].
fn velocity_zeros(traj: &Solution) -> Vec<(f64, f64)> {
    let mut out: Vec<(f64, f64)> = Vec::new();
    for i in 1..traj.len() {
        let (a, b) = (traj.state(i - 1)[1], traj.state(i)[1]);
        if a != 0.0 && (b == 0.0 || a.signum() != b.signum()) {
            // Locate on the dense output when the row is not exactly at the zero.
            let (mut lo, mut hi) = (traj.times()[i - 1], traj.times()[i]);
            if b != 0.0 {
                for _ in 0..60 {
                    let c = 0.5 * (lo + hi);
                    let vc = traj.at(c).map_or(0.0, |y| y[1]);
                    if vc.signum() == a.signum() && vc != 0.0 {
                        lo = c
                    } else {
                        hi = c
                    }
                }
            }
            let t = hi;
            if out.last().is_none_or(|(tl, _)| t - tl > 1e-3) {
                out.push((t, traj.at(t).map_or(f64::NAN, |y| y[0])));
            }
        }
    }
    out
}

/// Errors of a run against reference switch points and a reference final position:
/// (max switch-time error, max switch-position error, final-position error).
fn switch_errors(traj: &Solution, reference: &[(f64, f64)], x_final: f64) -> (f64, f64, f64) {
    let zeros = velocity_zeros(traj);
    let mut dt = 0.0f64;
    let mut dx = 0.0f64;
    for (i, (te, xe)) in reference.iter().enumerate() {
        match zeros.get(i) {
            Some((t, x)) => {
                dt = dt.max((t - te).abs());
                dx = dx.max((x - xe).abs());
            }
            None => {
                dt = f64::INFINITY;
                dx = f64::INFINITY;
            }
        }
    }
    let xf = traj.last().map_or(f64::NAN, |(_, y)| y[0]);
    (dt, dx, (xf - x_final).abs())
}

/// S6 closed form: turning points (−1)ⁿ (x0 − 2n x_F) at nπ until |x| ≤ x_F.
fn s6_reference() -> Vec<(f64, f64)> {
    (1..=5)
        .map(|n| (n as f64 * PI, (-1f64).powi(n) * (1.0 - 0.2 * n as f64)))
        .collect()
}

/// S1 closed form: damped half-cycles about the offset sgn(x) f_c/k, π/ω_d long.
fn s1_reference() -> Vec<(f64, f64)> {
    let (zeta, fc) = (0.1f64, 0.1);
    let wd = (1.0 - zeta * zeta).sqrt();
    let decay = (-zeta * PI / wd).exp();
    let mut x = 1.0f64;
    let mut out = Vec::new();
    while x.abs() > fc {
        let off = x.signum() * fc;
        x = off - (x - off) * decay;
        out.push(((out.len() + 1) as f64 * PI / wd, x));
    }
    out
}

/// The integrators' labels, indexed by the first field of [`sweep_runs`]: event-driven
/// with each smooth method, then time-stepping (implicit Euler, θ = 1, and the midpoint
/// rule, θ = ½: each race against event-driven takes the faster of the two).
const METHODS: [&str; 5] = [
    "event-driven (DOPRI5)",
    "event-driven (SDIRK4)",
    "event-driven (BDF)",
    "time-stepping (θ = 1)",
    "time-stepping (θ = ½)",
];
/// The smooth methods of the event-driven entries of [`METHODS`].
const SMOOTH: [fn(Options) -> Method; 3] = [Method::Dopri5, Method::Sdirk4, Method::Bdf];

/// The name of a method family (`Method::Dopri5` → "DOPRI5").
fn family(m: fn(Options) -> Method) -> &'static str {
    m(Options::default()).name()
}
/// Index of the first time-stepping entry (θ = 1) in [`METHODS`]; θ = ½ follows it.
const TIME_STEPPING: usize = 3;

/// Every run of a non-smooth sweep: event-driven with each smooth method over the
/// tolerances and time-stepping over the steps, with a label for the setting.
fn sweep_runs(config: &Config) -> Vec<(usize, String, NonSmoothMethod)> {
    let tolerances: Vec<f64> = config
        .tolerances
        .iter()
        .copied()
        .filter(|t| *t >= 1e-11)
        .collect();
    sweep_runs_to(config, &tolerances)
}

/// As [`sweep_runs`], the event-driven rows at the given tolerances.
fn sweep_runs_to(config: &Config, tolerances: &[f64]) -> Vec<(usize, String, NonSmoothMethod)> {
    let mut runs: Vec<(usize, String, NonSmoothMethod)> = Vec::new();
    for (kind, method) in SMOOTH.into_iter().enumerate() {
        for &t in tolerances {
            let options = Options::tolerances(t, t * 1e-2);
            runs.push((
                kind,
                format!("rtol = {t:.0e}"),
                NonSmoothMethod::EventDriven(method(options)),
            ));
        }
    }
    for (offset, theta) in [1.0, 0.5].into_iter().enumerate() {
        for n in &config.rk4_steps {
            let h = 0.5 / *n as f64;
            runs.push((
                TIME_STEPPING + offset,
                format!("h = {}", sci(h)),
                NonSmoothMethod::TimeStepping { h, theta },
            ));
        }
    }
    runs
}

struct Row {
    method: String,
    setting: String,
    outcome: Result<(f64, f64, f64, Timing, String), String>, // (dt, dx, final, time [s], stats)
}

fn sweep<S: filippov::runtime::NonSmooth<1>>(
    config: &Config,
    sys: &S,
    problem: &NonSmoothProblem<1>,
    input: &dyn Fn(f64, &V1, &V1) -> V1,
    reference: &[(f64, f64)],
    x_final: f64,
) -> Vec<Row> {
    let mut rows = Vec::new();
    let methods = sweep_runs(config);
    for (kind, setting, m) in methods {
        let method = METHODS[kind].to_string();
        let (time, result) = timed(config.repeats, || solve_nonsmooth(sys, &input, problem, &m));
        let outcome = match result {
            Ok(traj) => {
                let (dt, dx, df) = switch_errors(&traj, reference, x_final);
                let s = &traj.stats;
                Ok((
                    dt,
                    dx,
                    df,
                    time,
                    format!(
                        "{} steps, {} evals, {} events",
                        s.steps, s.rhs_evaluations, s.events
                    ),
                ))
            }
            Err(e) => Err(e.to_string()),
        };
        rows.push(Row {
            method,
            setting,
            outcome,
        });
    }
    rows
}

fn table(page: &mut Page, rows: &[Row]) {
    let body: Vec<Vec<String>> = rows
        .iter()
        .map(|r| match &r.outcome {
            Ok((dt, dx, df, time, stats)) => vec![
                r.method.clone(),
                r.setting.clone(),
                sci(*dt),
                sci(*dx),
                if df.is_nan() { "—".into() } else { sci(*df) },
                time.scaled(1e3).show(3),
                stats.clone(),
            ],
            Err(e) => vec![
                r.method.clone(),
                r.setting.clone(),
                format!("**failed**: {e}"),
                String::new(),
                String::new(),
                String::new(),
                String::new(),
            ],
        })
        .collect();
    page.table(
        &[
            "method",
            "setting",
            "switch-time error",
            "switch-position error",
            "final error",
            "time [ms], median (min–max)",
            "work",
        ],
        &body,
    );
}

fn plot(config: &Config, file: &str, title: &str, rows: &[Row]) {
    plot_with(config, file, title, rows, Vec::new());
}

/// [`plot`] with extra series of another metric (S6: diffsol's regularised runs and the
/// event-driven runs of the same peer program, max |x − x_ref| over the run).
fn plot_with(config: &Config, file: &str, title: &str, rows: &[Row], extra: Vec<Series>) {
    let mut curves = Vec::new();
    for m in METHODS {
        let pts: Vec<(f64, f64)> = rows
            .iter()
            .filter(|r| r.method == m)
            .filter_map(|r| {
                r.outcome
                    .as_ref()
                    .ok()
                    .map(|(dt, dx, _, t, _)| (t.median * 1e3, dt.max(*dx)))
            })
            .collect();
        curves.push(Series::new(m, pts));
    }
    let y_label = if extra.is_empty() {
        "max switch error (time or position)"
    } else {
        "switch error; max |x − x_ref| where the legend says so"
    };
    curves.extend(extra);
    line_plot(
        &config.out_dir.join(file),
        title,
        "run time [ms]",
        y_label,
        &curves,
        Scale::Log,
        Scale::Log,
    );
}

/// A headline row: event-driven's best time `a` against time-stepping's `b` (seconds),
/// the ratio's range pairing the slowest repetition of one with the fastest of the other.
fn race_headline(claim: &str, a: Timing, b: Timing, basis: &str) {
    super::markdown::headline(
        claim,
        format!("{} ms", a.scaled(1e3).show(3)),
        format!("{} ms (Moreau time-stepping)", b.scaled(1e3).show(3)),
        b.ratio_to(&a, 0),
        basis,
    );
}

fn summarize(name: &str, rows: &[Row], summary: &mut Vec<String>) {
    let best = |m: &str| {
        rows.iter()
            .filter(|r| r.method.starts_with(m))
            .filter_map(|r| r.outcome.as_ref().ok())
            .filter(|(dt, dx, ..)| dt.max(*dx) <= 1e-3)
            .map(|o| o.3)
            .min_by(|a, b| a.median.total_cmp(&b.median))
    };
    let (edt, tst) = (best("event"), best("time"));
    let (ed, ts) = (
        edt.map_or(f64::INFINITY, |t| t.median),
        tst.map_or(f64::INFINITY, |t| t.median),
    );
    if let (Some(a), Some(b)) = (edt, tst) {
        summary.push(format!("{name}: to switch errors ≤ 1e-3, event-driven takes {:.3} ms, time-stepping {:.3} ms ({:.1}×)", ed * 1e3, ts * 1e3, ts / ed));
        if name.starts_with("S6") {
            race_headline(
                "Event-driven integration beats time-stepping on Coulomb friction (S6, to switch errors ≤ 1e-3 against the closed form)",
                a,
                b,
                "fastest run of each sweep reaching the accuracy (time-stepping: the faster of θ = 1 and θ = ½); medians (min–max) of its repetitions",
            );
        }
    } else if ed.is_finite() {
        summary.push(format!("{name}: event-driven reaches switch errors ≤ 1e-3 in {:.3} ms; time-stepping does not within the swept steps", ed * 1e3));
    }
    let failures = rows.iter().filter(|r| r.outcome.is_err()).count();
    if failures > 0 {
        summary.push(format!("{name}: {failures} run(s) failed (see the table)"));
    }
}

/// Max |x(t) − x_ref(t)| over a grid of 300 times and |x(tf) − x_ref(tf)|.
fn grid_errors(traj: &Solution, reference: &Solution, tf: f64) -> (f64, f64) {
    let mut worst = 0.0f64;
    for i in 0..=300 {
        let t = tf * i as f64 / 300.0;
        match (traj.at(t), reference.at(t)) {
            (Some(a), Some(b)) => worst = worst.max((a[0] - b[0]).abs()),
            _ => return (f64::INFINITY, f64::INFINITY),
        }
    }
    let fin = (traj.last().map_or(f64::NAN, |r| r.1[0])
        - reference.last().map_or(f64::NAN, |r| r.1[0]))
    .abs();
    (worst, fin)
}

/// Tolerance of the reference runs of [`sweep_vs_reference`].
const REFERENCE_RTOL: f64 = 1e-13;

/// A reference for switch times without the event-driven integrator
/// (`filippov_scenes::references`: closed forms, smooth runs with their own root
/// finding): reference runs of the event-driven integrator share its event location
/// with the runs they check, so a bias there cancels against them but not against
/// this.
struct Exact<'a> {
    /// What it is and which switches it covers, for the page.
    what: &'a str,
    /// The switches, time and mode entered.
    switches: &'a [(f64, Mode)],
    /// Whether they are the whole log, or only its first switches.
    whole: bool,
}

/// A sweep against reference runs of a *different* method: event-driven DOPRI5 rows
/// against event-driven SDIRK4 at rtol [`REFERENCE_RTOL`], the other rows against
/// event-driven DOPRI5 at that tolerance, and, where the scene has one, against a
/// reference without the event-driven integrator ([`Exact`]). The event-driven rows go down to rtol
/// 1e-12 where the configuration reaches 1e-10.
#[allow(clippy::too_many_arguments)]
fn sweep_vs_reference<S: filippov::runtime::NonSmooth<1>>(
    config: &Config,
    page: &mut Page,
    summary: &mut Vec<String>,
    name: &str,
    sys: &S,
    problem: &NonSmoothProblem<1>,
    input: &dyn Fn(f64, &V1, &V1) -> V1,
    exact: Option<Exact<'_>>,
) {
    let tight = |m: fn(Options) -> Method| {
        NonSmoothMethod::EventDriven(m(Options::tolerances(
            REFERENCE_RTOL,
            1e-2 * REFERENCE_RTOL,
        )))
    };
    let (ref_sdirk, ref_dopri) = (
        solve_nonsmooth(sys, &input, problem, &tight(Method::Sdirk4)),
        solve_nonsmooth(sys, &input, problem, &tight(Method::Dopri5)),
    );
    let (Ok(ref_sdirk), Ok(ref_dopri)) = (ref_sdirk, ref_dopri) else {
        page.para("**The reference runs failed**; no work-precision data for this scene.");
        summary.push(format!("{name}: reference runs failed"));
        return;
    };
    let tf = problem.tf;
    let agree = grid_errors(&ref_dopri, &ref_sdirk, tf).0;
    page.para(&format!(
        "References: event-driven SDIRK4 and DOPRI5 at rtol {REFERENCE_RTOL:.0e}; they agree to {} in x over the run.",
        sci(agree)
    ));
    // How well the switch times are determined: the references' own disagreement per
    // switch, against their disagreement in x. A switch reached tangentially (at the fold
    // of a branch, say) moves far more than the state does.
    let reference_switches = switch_spread(&ref_sdirk, &ref_dopri);
    if let Some((dt, i)) = reference_switches {
        let sw = &ref_sdirk.switches[i];
        page.para(&format!(
            "Their switch times agree to {} (largest at switch {i}, t = {:.4}, `{}` from {} to {}): {:.2} times their agreement in x. A run's switch-time error is its state error times such a factor, so at that switch a bound of 100·rtol needs a state error near {:.2}·rtol or below.",
            sci(dt),
            sw.t,
            sw.element.as_deref().unwrap_or("—"),
            sw.from.map_or("—".into(), |m| format!("{m:?}")),
            sw.to.map_or("—".into(), |m| format!("{m:?}")),
            dt / agree.max(f64::MIN_POSITIVE),
            100.0 * agree / dt,
        ));
    }
    let mut rows = Vec::new();
    let mut curves: Vec<Series> = METHODS
        .iter()
        .map(|m| Series::new(*m, Vec::new()))
        .collect();
    let mut best: [Option<Timing>; METHODS.len()] = [None; METHODS.len()];
    let mut tolerances: Vec<f64> = config
        .tolerances
        .iter()
        .copied()
        .filter(|t| *t >= 1e-12)
        .collect();
    if tolerances.iter().any(|t| *t <= 1e-10) {
        for t in [1e-11, 1e-12] {
            if !tolerances.contains(&t) {
                tolerances.push(t);
            }
        }
    }
    let runs = sweep_runs_to(config, &tolerances);
    let (mut worst, mut mismatches) = ([None::<(WorstSwitch, f64)>; METHODS.len()], 0);
    // The largest switch-time error against `exact`, in units of rtol, and its rtol.
    let mut worst_exact = [None::<(f64, f64)>; METHODS.len()];
    for (kind, setting, m) in runs {
        let reference = if kind == 0 { &ref_sdirk } else { &ref_dopri };
        let (time, result) = timed(config.repeats, || solve_nonsmooth(sys, &input, problem, &m));
        let label = curves[kind].label.clone();
        match result {
            Ok(traj) => {
                let (grid, fin) = grid_errors(&traj, reference, tf);
                let s = &traj.stats;
                let switches = match m {
                    NonSmoothMethod::EventDriven(method) => {
                        let options = method.options();
                        let c = compare_switches(&traj, reference, options.rtol, 2);
                        match c {
                            Some(w) => {
                                if worst[kind].is_none_or(|(v, _)| w.ratio > v.ratio) {
                                    worst[kind] = Some((w, options.rtol));
                                }
                            }
                            None => mismatches += 1,
                        }
                        let against_exact = match &exact {
                            Some(x) => match references::switch_time_error(
                                &traj.switches,
                                x.switches,
                                x.whole,
                            ) {
                                Some(dt) => {
                                    let r = dt / options.rtol;
                                    if worst_exact[kind].is_none_or(|(v, _)| r > v) {
                                        worst_exact[kind] = Some((r, options.rtol));
                                    }
                                    format!("; {}: {:.0}·rtol", x.what, r)
                                }
                                None => format!("; {}: **not in the log**", x.what),
                            },
                            None => String::new(),
                        };
                        match c {
                            Some(w) => format!(
                                "{} as the reference; max Δt = {:.0}·rtol{against_exact}",
                                traj.switches.len(),
                                w.ratio
                            ),
                            None => format!(
                                "**{} against the reference's {}**{against_exact}",
                                traj.switches.len(),
                                reference.switches.len()
                            ),
                        }
                    }
                    _ => "—".into(),
                };
                rows.push(vec![
                    label,
                    setting,
                    sci(grid),
                    sci(fin),
                    time.scaled(1e3).show(3),
                    format!(
                        "{} steps, {} evals, {} events",
                        s.steps, s.rhs_evaluations, s.events
                    ),
                    switches,
                ]);
                curves[kind].points.push((time.median * 1e3, grid));
                if grid <= 1e-3 && best[kind].is_none_or(|b| time.median < b.median) {
                    best[kind] = Some(time);
                }
            }
            Err(e) => rows.push(vec![
                label,
                setting,
                format!("**failed**: {e}"),
                String::new(),
                String::new(),
                String::new(),
                String::new(),
            ]),
        }
    }
    page.para("Switches: the run's switch log against its reference's — the same elements entering the same modes in the same order, and the largest difference of their times in units of the run's rtol (the references themselves agree to the time given above).");
    page.table(
        &[
            "method",
            "setting",
            "max error in x (grid)",
            "final error",
            "time [ms], median (min–max)",
            "work",
            "switches",
        ],
        &rows,
    );
    let spread = reference_switches.map_or(String::new(), |(dt, _)| {
        format!(
            " (the two references' switch times differ by up to {}, {:.2}× their difference in x)",
            sci(dt),
            dt / agree.max(f64::MIN_POSITIVE)
        )
    });
    let worst = SMOOTH
        .iter()
        .zip(&worst)
        .map(|(m, w)| match w {
            Some((w, rtol)) => format!(
                "{} {:.0} (switch {} at rtol {rtol:.0e}, state off by {:.1}·rtol just before it)",
                family(*m),
                w.ratio,
                w.index,
                w.state_before
            ),
            None => format!("{} —", family(*m)),
        })
        .collect::<Vec<_>>()
        .join(", ");
    let exact_summary = match &exact {
        Some(x) => {
            let per_method = SMOOTH
                .iter()
                .zip(&worst_exact)
                .map(|(m, w)| match w {
                    Some((r, rtol)) => format!("{} {r:.0} (at rtol {rtol:.0e})", family(*m)),
                    None => format!("{} —", family(*m)),
                })
                .collect::<Vec<_>>()
                .join(", ");
            format!(
                "; against {} (no event-driven integration): {per_method}",
                x.what
            )
        }
        None => String::new(),
    };
    summary.push(format!(
        "{name}: event-driven switch logs equal to the reference's in {} of {} runs (rtol {:.0e}…{:.0e}); largest switch-time error in units of rtol: {worst}{spread}{exact_summary}",
        rows.iter().filter(|r| !r[6].is_empty() && r[6] != "—").count() - mismatches,
        rows.iter().filter(|r| !r[6].is_empty() && r[6] != "—").count(),
        tolerances.iter().copied().fold(0.0, f64::max),
        tolerances.iter().copied().fold(f64::INFINITY, f64::min),
    ));
    if name == "S5" {
        // diffsol on the regularised law (peers/diffsol), same metric.
        curves.extend(super::peers::diffsol_series(config, "S5", false));
    }
    let file = format!("ns_{}.svg", name.to_lowercase().replace(' ', "_"));
    line_plot(
        &config.out_dir.join(&file),
        &format!("{name}: error against run time"),
        "run time [ms]",
        "max |x − x_ref| over the run",
        &curves,
        Scale::Log,
        Scale::Log,
    );
    page.image(name, &file);
    let event_best = best[..TIME_STEPPING]
        .iter()
        .flatten()
        .min_by(|a, b| a.median.total_cmp(&b.median))
        .copied();
    let ts_best = best[TIME_STEPPING..]
        .iter()
        .flatten()
        .min_by(|a, b| a.median.total_cmp(&b.median))
        .copied();
    if let (Some(a), Some(b)) = (event_best, ts_best) {
        let (event_best, ts_best) = (a.median, b.median);
        summary.push(format!("{name}: to an error ≤ 1e-3, event-driven takes {:.3} ms, time-stepping {:.3} ms ({:.1}×)", event_best * 1e3, ts_best * 1e3, ts_best / event_best));
        if name == "S5" {
            race_headline(
                "Event-driven integration beats time-stepping on forced stick–slip (S5, max error in x ≤ 1e-3 against a reference run)",
                a,
                b,
                &format!(
                    "fastest run of each sweep reaching the accuracy (time-stepping: the faster of θ = 1 and θ = ½); reference: event-driven SDIRK4 and DOPRI5 at rtol {REFERENCE_RTOL:.0e}"
                ),
            );
        }
    }
    let failures = rows.iter().filter(|r| r[2].starts_with("**failed")).count();
    if failures > 0 {
        summary.push(format!("{name}: {failures} run(s) failed (see the table)"));
    }
}

pub fn nonsmooth(config: &Config, progress: &indicatif::ProgressBar) -> Section {
    let mut page = Page::empty();
    let mut summary = Vec::new();
    page.h2("Work-precision: non-smooth scenes");
    page.para("Event-driven (DOPRI5, SDIRK4 or BDF between switches, tolerance sweep) against Moreau time-stepping (θ = 1 and θ = ½, step sweep; a race takes the faster of the two). Switch errors compare the velocity zeros (turning points, stick onsets) with the closed forms of theory §5; the final error is x(tf). Times are medians.");
    let tf = 30.0 * config.horizon.max(0.34);
    let p = NonSmoothProblem::new(0.0, tf, V1::new(1.0), V1::new(0.0));
    let keep = |r: Vec<(f64, f64)>| r.into_iter().filter(|(t, _)| *t <= tf).collect::<Vec<_>>();

    page.h3("S6: Coulomb free decay (closed form)");
    let reference = keep(s6_reference());
    let x_final = if tf >= 5.0 * PI { 0.0 } else { f64::NAN };
    let rows = sweep(
        config,
        &CoulombOscillator {
            m: 1.0,
            k: 1.0,
            f_crit: 0.1,
        },
        &p,
        &unforced,
        &reference,
        x_final,
    );
    table(&mut page, &rows);
    plot_with(
        config,
        "ns_s6.svg",
        "S6 Coulomb free decay: error against run time",
        &rows,
        super::peers::diffsol_series(config, "S6", true),
    );
    page.image("S6", "ns_s6.svg");
    summarize("S6", &rows, &mut summary);

    page.h3("S1: linear Bingham free decay (closed form)");
    let reference = keep(s1_reference());
    let x_final = reference.last().map_or(f64::NAN, |r| r.1);
    let rows = sweep(
        config,
        &BinghamOscillator {
            m: 1.0,
            k: 1.0,
            f_crit: 0.1,
            eta: 0.2,
        },
        &p,
        &unforced,
        &reference,
        if tf >= 25.0 { x_final } else { f64::NAN },
    );
    table(&mut page, &rows);
    plot(
        config,
        "ns_s1.svg",
        "S1 Bingham free decay: switch error against run time",
        &rows,
    );
    page.image("S1", "ns_s1.svg");
    summarize("S1", &rows, &mut summary);

    page.h3("Static/kinetic friction: block on a belt (closed-form stick–slip cycle)");
    page.para("m = k = 1, f_static = 1, f_kinetic = 0.5, belt speed 0.2, starting at rest on the belt at x = 0 (theory.md §5): stick 5, slip π + 2 atan 0.4 = 3.9026, re-stick at x = 2 x_k − x_s = 0. The switch points are the re-sticks (the relative velocity returning to 0), in the belt's frame y = x − v_b t.");
    let belt = BeltFriction {
        m: 1.0,
        k: 1.0,
        f_static: 1.0,
        f_kinetic: 0.5,
    };
    let v_b = 0.2;
    let (stick, slip) = (5.0, PI + 2.0 * 0.4f64.atan());
    let reference: Vec<(f64, f64)> = (0..)
        .map(|n| 5.0 + n as f64 * (stick + slip) + slip)
        .take_while(|t| *t <= tf)
        .map(|t| (t, -v_b * t))
        .collect();
    let belt_input = move |t: f64, _q: &V1, _v: &V1| V1::new(-v_b * t);
    let rows = sweep(
        config,
        &belt,
        &NonSmoothProblem::new(0.0, tf, V1::new(0.0), V1::new(0.0)),
        &belt_input,
        &reference,
        f64::NAN,
    );
    table(&mut page, &rows);
    plot(
        config,
        "ns_belt.svg",
        "Static/kinetic friction on a belt: switch error against run time",
        &rows,
    );
    page.image("belt", "ns_belt.svg");
    summarize("Belt (static/kinetic)", &rows, &mut summary);

    page.h3("S7 elastic: bilinear oscillator (closed-form period 5.8620872)");
    let bil = BilinearOscillator {
        m: 1.0,
        k: 1.0,
        l: 0.5,
        k_support: 1.0,
    };
    let p7 = NonSmoothProblem::new(
        0.0,
        2.0 * 5.8620872 * config.horizon.max(0.5) + 0.5,
        V1::new(0.0),
        V1::new(1.0),
    );
    // Velocity zeros of the bilinear oscillator: the turning points, alternately at
    // x = +A2 + x_e side and −A1, every half-period of each side.
    let (w1, w2) = (1.0f64, 2f64.sqrt());
    let xe = 0.25f64;
    let vl = (1.0f64 - 0.25).sqrt();
    let a2 = ((0.5 - xe).powi(2) + (vl / w2).powi(2)).sqrt();
    let t_l = (0.5f64).asin() / w1; // reach x = L
    let t_top = t_l + (((0.5 - xe) / a2).acos()) / w2;
    let half = 2.0 * (PI - 0.5f64.acos()) / w1 + 2.0 * ((0.5 - xe) / a2).acos() / w2;
    let mut reference = Vec::new();
    let mut k = 0;
    loop {
        let t_max = t_top + k as f64 * half;
        let t_min = t_top
            + (2.0 * ((0.5 - xe) / a2).acos() / w2) / 2.0
            + (PI - 0.5f64.acos()) / w1
            + k as f64 * half;
        if t_max > p7.tf {
            break;
        }
        reference.push((t_max, xe + a2));
        if t_min <= p7.tf {
            reference.push((t_min, -1.0));
        }
        k += 1;
    }
    let rows = sweep(config, &bil, &p7, &unforced, &reference, f64::NAN);
    table(&mut page, &rows);
    plot(
        config,
        "ns_s7.svg",
        "S7 elastic (bilinear): turning-point error against run time",
        &rows,
    );
    page.image("S7 elastic", "ns_s7.svg");
    summarize("S7 elastic", &rows, &mut summary);

    let horizon = 30.0 * config.horizon.max(0.34);
    page.h3("S2: cubic Bingham (thesis 4.7b), forced by 2 sin t (reference runs)");
    let cubic = filippov_scenes::CubicBingham {
        m: 1.0,
        k: 1.0,
        f_crit: 1.0,
        gamma: 1.0,
    };
    let p2 = NonSmoothProblem::new(0.0, horizon, V1::new(0.0), V1::new(0.0));
    sweep_vs_reference(
        config,
        &mut page,
        &mut summary,
        "S2",
        &cubic,
        &p2,
        &|t, _q, _v| V1::new(2.0 * t.sin()),
        None,
    );
    page.h3("S3: cubic Bingham, free from x0 = 2 (reference runs)");
    let p3 = NonSmoothProblem::new(0.0, horizon, V1::new(2.0), V1::new(0.0));
    sweep_vs_reference(
        config,
        &mut page,
        &mut summary,
        "S3",
        &cubic,
        &p3,
        &unforced,
        None,
    );
    page.h3("S5: Coulomb stick–slip forced by 1.2 sin(0.5 t), starting stuck with f = −f_crit/2 (reference runs)");
    let coulomb = CoulombOscillator {
        m: 1.0,
        k: 1.0,
        f_crit: 0.5,
    };
    let p5 = NonSmoothProblem::new(0.0, horizon, V1::new(0.25), V1::new(0.0))
        .with_forces(vec![Some(-0.25)]);
    let s5_exact = references::s5_switches(horizon);
    sweep_vs_reference(
        config,
        &mut page,
        &mut summary,
        "S5",
        &coulomb,
        &p5,
        &|t, _q, _v| V1::new(1.2 * (0.5 * t).sin()),
        Some(Exact {
            what: "the closed form (every switch)",
            switches: &s5_exact,
            whole: true,
        }),
    );

    page.h3("S4: non-monotone law (thesis 4.9b), approach 1 (no velocity jumps), forced by 3 sin(0.5 t) (reference runs)");
    let p4 = NonSmoothProblem::new(
        0.0,
        40.0 * config.horizon.max(0.25),
        V1::new(0.0),
        V1::new(0.0),
    );
    let f4 = |t: f64, _q: &V1, _v: &V1| V1::new(3.0 * (0.5 * t).sin());
    // Breakaway at 3 sin(t/2) = f_crit, then the fold.
    let s4_fold = [
        (2.0 * (1.0f64 / 3.0).asin(), Mode::SlipPos(0)),
        (references::s4_first_fold().t, Mode::SlipPos(1)),
    ];
    let s4_plateau = references::s4_approach2_first_switches();
    sweep_vs_reference(
        config,
        &mut page,
        &mut summary,
        "S4 approach 1",
        &filippov_scenes::NonMonotoneNoJumps {
            m: 1.0,
            k: 1.0,
            f_crit: 1.0,
        },
        &p4,
        &f4,
        Some(Exact {
            what: "the closed-form breakaway and the branch integrated through its fold in the force (first two switches)",
            switches: &s4_fold,
            whole: false,
        }),
    );
    page.h3("S4: approach 2 (maximal dissipation, with the plateau mode) (reference runs)");
    sweep_vs_reference(
        config,
        &mut page,
        &mut summary,
        "S4 approach 2",
        &filippov_scenes::NonMonotoneMaxDissipation {
            m: 1.0,
            k: 1.0,
            f_crit: 1.0,
        },
        &p4,
        &f4,
        Some(Exact {
            what: "the inner branch as a smooth run and the plateau in closed form (first four switches)",
            switches: &s4_plateau,
            whole: false,
        }),
    );

    stiff_support(config, &mut page, &mut summary);

    page.h2("Stiff and extreme cases");
    let mut rows = Vec::new();
    let ed = NonSmoothMethod::EventDriven(Method::Dopri5(Options::tolerances(1e-8, 1e-10)));
    let ts = NonSmoothMethod::TimeStepping {
        h: 1e-3,
        theta: 1.0,
    };
    let mut record = |case: String,
                      method: &str,
                      run: &dyn Fn() -> Result<Solution, filippov::runtime::SolveError>,
                      check: &dyn Fn(&Solution) -> String| {
        let (time, r) = timed(config.repeats.min(3), run);
        let (status, detail) = outcome(r, check);
        rows.push(vec![
            case,
            method.into(),
            status,
            detail,
            time.scaled(1e3).show(2),
        ]);
    };
    let short = 10.0 * config.horizon.max(0.2);
    for ks in [1e3, 1e6, 1e9, 1e12] {
        let s = SupportedStop {
            m: 1.0,
            k: 1.0,
            f_crit: 0.1,
            eta: 0.2,
            l: 0.5,
            k_support: ks,
        };
        let p = NonSmoothProblem::new(0.0, short, V1::new(0.0), V1::new(1.0));
        let check = |t: &Solution| {
            format!(
                "max x = {:.6} (stop at 0.5)",
                (0..t.len()).map(|i| t.state(i)[0]).fold(f64::MIN, f64::max)
            )
        };
        for (name, m) in [("event-driven", ed), ("time-stepping h = 1e-3", ts)] {
            record(
                format!("S7, k_support = {ks:.0e} (stiffness ratio {ks:.0e})"),
                name,
                &|| solve_nonsmooth(&s, &unforced, &p, &m),
                &check,
            );
        }
    }
    // A stiff spring inside the mechanism: two blocks with friction, the second on a
    // spring of stiffness k2 relative to the first (k1 = 1): stiffness ratio k2/k1.
    for k2 in [1e3, 1e6, 1e9, 1e12] {
        let s = filippov_scenes::FrictionChain::stiff(k2);
        type V2 = SVector<f64, 2>;
        let none = |_t: f64, _q: &V2, _v: &V2| V2::zeros();
        let p = NonSmoothProblem::new(0.0, short, V2::new(1.0, 1e-3 / k2.sqrt()), V2::zeros());
        let check = |t: &Solution| {
            let y = t.last().map_or(vec![f64::NAN; 4], |r| r.1.to_vec());
            format!("final x1 = {:.6}, x2 = {:.3e}", y[0], y[1])
        };
        let sdirk = NonSmoothMethod::EventDriven(Method::Sdirk4(Options::tolerances(1e-8, 1e-10)));
        for (name, m) in [
            ("event-driven DOPRI5", ed),
            ("event-driven SDIRK4", sdirk),
            ("time-stepping h = 1e-3", ts),
        ] {
            record(
                format!("two-block friction chain, k2/k1 = {k2:.0e}"),
                name,
                &|| solve_nonsmooth(&s, &none, &p, &m),
                &check,
            );
        }
    }
    for m in [1e-3, 1e-6, 1e-12] {
        let s = CoulombOscillator {
            m,
            k: 1.0,
            f_crit: 0.1,
        };
        let p = NonSmoothProblem::new(0.0, 30.0 * m.sqrt(), V1::new(1.0), V1::new(0.0));
        let check = |t: &Solution| {
            format!(
                "final x = {:.6} (closed form 0)",
                t.last().map_or(f64::NAN, |r| r.1[0])
            )
        };
        record(
            format!("S6 with mass {m:.0e} (horizon 30√m)"),
            "event-driven",
            &|| solve_nonsmooth(&s, &unforced, &p, &ed),
            &check,
        );
    }
    for fc in [1e-9, 1e3] {
        let s = CoulombOscillator {
            m: 1.0,
            k: 1.0,
            f_crit: fc,
        };
        let p = NonSmoothProblem::new(0.0, short, V1::new(1.0), V1::new(0.0));
        let check =
            |t: &Solution| format!("final x = {:.6}", t.last().map_or(f64::NAN, |r| r.1[0]));
        record(
            format!("S6 with f_crit = {fc:.0e}"),
            "event-driven",
            &|| solve_nonsmooth(&s, &unforced, &p, &ed),
            &check,
        );
    }
    for eps in [1e-12, -1e-12] {
        let s = CoulombOscillator {
            m: 1.0,
            k: 1.0,
            f_crit: 0.5,
        };
        let force = 0.5 * (1.0 + eps);
        let input = move |_t: f64, _q: &V1, _v: &V1| V1::new(force);
        let p = NonSmoothProblem::new(0.0, 5.0, V1::new(0.0), V1::new(0.0));
        let check = |t: &Solution| {
            format!(
                "final x = {:.3e}, v = {:.3e}",
                t.last().map_or(f64::NAN, |r| r.1[0]),
                t.last().map_or(f64::NAN, |r| r.1[1])
            )
        };
        record(
            format!(
                "applied force f_crit·(1 {} 1e-12), from rest",
                if eps > 0.0 { "+" } else { "−" }
            ),
            "event-driven",
            &|| solve_nonsmooth(&s, &input, &p, &ed),
            &check,
        );
    }
    for e in [0.5, 0.9, 0.99] {
        let s = BouncingBall { m: 1.0, g: 9.81, e };
        // Drop from 1 m: accumulation time √(2/g)·(1 + e)/(1 − e).
        let t_acc = (2.0f64 / 9.81).sqrt() * (1.0 + e) / (1.0 - e);
        let p = NonSmoothProblem::new(0.0, 1.5 * t_acc, V1::new(1.0), V1::new(0.0));
        let check = move |t: &Solution| {
            let y = t.last().map_or(vec![f64::NAN; 3], |r| r.1.to_vec());
            format!(
                "accumulation at {t_acc:.6} (closed form); {}; at tf: x = {:.2e}, v = {:.2e}",
                settled(t, t_acc),
                y[0],
                y[1]
            )
        };
        for (name, m) in [("event-driven", ed), ("time-stepping h = 1e-3", ts)] {
            record(
                format!("Zeno bouncing, e = {e}, run to 1.5× accumulation"),
                name,
                &|| solve_nonsmooth(&s, &unforced, &p, &m),
                &check,
            );
        }
    }
    rows.extend(resting_on_limits(config, short));
    let (cycles, horizon) = match config.name {
        "tiny" => (20, 20.0),
        "long" => (1_000_000, 10_000.0),
        _ => (10_000, 1_000.0),
    };
    rows.push(super::long_runs::stick_slip(cycles, progress));
    rows.extend(super::long_runs::chaotic_pendulum(horizon));
    page.para("Each case reports whether it completed or ended with a typed error, what it computed, and its run time (median; the two long runs at the end are timed once). `--long` runs 10⁶ stick–slip cycles and 10⁴ s of the pendulum.");
    page.table(
        &[
            "case",
            "method",
            "outcome",
            "result",
            "time [ms], median (min–max)",
        ],
        &rows,
    );
    let errors = rows
        .iter()
        .filter(|r| r[2].starts_with("typed error"))
        .count();
    summary.push(format!("Stiff and extreme suite: {} of {} cases completed, {errors} ended with a typed error (none panicked)", rows.len() - errors, rows.len()));
    Section { page, summary }
}

/// The bilinear oscillator (S7 elastic: m = k = 1, support at L = 0.5 of stiffness `ks`)
/// from x = 0, v = 1, in closed form: free arcs `sin`, and in contact a half-oscillation
/// of frequency √(k + k_s) about `x_e = k_s L / (k + k_s)`.
fn bilinear_exact(ks: f64, t: f64) -> f64 {
    let l: f64 = 0.5;
    let w2 = (1.0 + ks).sqrt();
    let x_e = ks * l / (1.0 + ks);
    let d = l - x_e;
    let v_l = (1.0 - l * l).sqrt();
    let b = (d * d + (v_l / w2).powi(2)).sqrt();
    let phi0 = (d / b).asin();
    let t_c = (PI - 2.0 * phi0) / w2;
    let t_in = l.asin();
    // Up to the support, the contact, then the free arc from phase π − asin L to 2π.
    let period = t_in + t_c + PI + t_in;
    let tau = t.rem_euclid(period);
    if tau < t_in {
        tau.sin()
    } else if tau < t_in + t_c {
        x_e + b * (w2 * (tau - t_in) + phi0).sin()
    } else {
        // The free arc resumes at phase π − asin L.
        (PI - t_in + (tau - t_in - t_c)).sin()
    }
}

/// Time-stepping through a stiff support at steps far above its contact time: θ = 1
/// (implicit Euler, the support at the step's end) against θ = ½ (implicit midpoint with
/// the support's discrete gradient), and the event-driven integrator; errors against the
/// closed form, and the energy each keeps.
fn stiff_support(config: &Config, page: &mut Page, summary: &mut Vec<String>) {
    let ks = 1e6;
    let s = BilinearOscillator {
        m: 1.0,
        k: 1.0,
        l: 0.5,
        k_support: ks,
    };
    let tf = (20.0 * config.horizon).max(2.0);
    let p = NonSmoothProblem::new(0.0, tf, V1::new(0.0), V1::new(1.0));
    let energy = |x: f64, v: f64| 0.5 * v * v + 0.5 * x * x + 0.5 * ks * (x - 0.5).max(0.0).powi(2);
    let steps: &[f64] = if config.name == "tiny" {
        &[1e-2, 1e-3]
    } else {
        &[1e-1, 3e-2, 1e-2, 3e-3, 1e-3, 3e-4, 1e-4]
    };
    let mut rows = Vec::new();
    let mut series: Vec<Series> = Vec::new();
    let mut runs: Vec<(String, String, NonSmoothMethod)> = Vec::new();
    for theta in [1.0, 0.5] {
        for &h in steps {
            runs.push((
                format!("time-stepping θ = {theta}"),
                format!("h = {}", sci(h)),
                NonSmoothMethod::TimeStepping { h, theta },
            ));
        }
    }
    for &t in config.tolerances.iter().filter(|t| **t >= 1e-10) {
        runs.push((
            "event-driven DOPRI5".into(),
            format!("rtol = {t:.0e}"),
            NonSmoothMethod::EventDriven(Method::Dopri5(Options::tolerances(t, t * 1e-2))),
        ));
    }
    let mut best: Vec<(String, f64, f64)> = Vec::new();
    for (method, setting, m) in runs {
        let (time, r) = timed(config.repeats.min(3), || {
            solve_nonsmooth(&s, &unforced, &p, &m)
        });
        let time = time.scaled(1e3);
        match r {
            Ok(sol) => {
                let err = sol
                    .rows()
                    .map(|(t, y)| (y[0] - bilinear_exact(ks, t)).abs())
                    .fold(0.0, f64::max);
                let (t_end, y) = sol.last().expect("rows");
                let kept = energy(y[0], y[1]) / 0.5;
                match series.iter_mut().find(|x| x.label == method) {
                    Some(x) => x.points.push((time.median, err)),
                    None => series.push(Series::new(method.clone(), vec![(time.median, err)])),
                }
                // The fastest run of each method that reaches the threshold.
                if err <= 1e-2 {
                    match best.iter_mut().find(|b| b.0 == method) {
                        Some(b) if time.median < b.1 => *b = (method.clone(), time.median, err),
                        Some(_) => {}
                        None => best.push((method.clone(), time.median, err)),
                    }
                }
                rows.push(vec![
                    method,
                    setting,
                    sci(err),
                    format!("{:.1} % at t = {t_end}", 100.0 * kept),
                    time.show(3),
                    sol.stats.steps.to_string(),
                ]);
            }
            Err(e) => rows.push(vec![
                method,
                setting,
                format!("**typed error: {}**", e.kind),
                String::new(),
                time.show(3),
                String::new(),
            ]),
        }
    }
    page.h3("Time-stepping through a stiff support: θ = 1 against θ = ½");
    page.para(&format!(
        "S7's elastic case (m = k = 1, support at L = 0.5 with k_s = {ks:.0e}: each contact lasts π/√(k + k_s) ≈ {:.1e} s) \
         from x = 0, v = 1 over t ∈ [0, {tf}], against its closed form (free arcs sin t, a half-oscillation of frequency \
         √(k + k_s) in contact). Time-stepping θ = 1 takes the support's force at the step's end (implicit Euler: stable for \
         every h, but a contact at h√(k_s/m) ≫ 1 loses much of its energy); θ = ½ is the implicit midpoint rule with the \
         support's discrete gradient (stable for every h, and exact in energy). Error: max |x − x_exact| over the run's rows; \
         energy kept: E(t_end)/E(0), the support's energy included; times median (min–max).",
        PI / (1.0 + ks).sqrt()
    ));
    page.table(
        &[
            "method",
            "setting",
            "max error in x",
            "energy kept",
            "time [ms], median (min–max)",
            "steps",
        ],
        &rows,
    );
    line_plot(
        &config.out_dir.join("stiff_support.svg"),
        &format!("Stiff support (k_s = {ks:.0e}): error against run time"),
        "time [ms]",
        "max |x − x_exact|",
        &series,
        Scale::Log,
        Scale::Log,
    );
    page.image("Stiff support work-precision", "stiff_support.svg");
    let list: Vec<String> = best
        .iter()
        .map(|(m, t, e)| format!("{m} {t:.2} ms ({})", sci(*e)))
        .collect();
    summary.push(format!(
        "Stiff support (k_s = {ks:.0e}), fastest to max |x − x_exact| ≤ 1e-2: {}",
        if list.is_empty() {
            "none of the runs".to_string()
        } else {
            list.join(", ")
        }
    ));
}

/// A case's outcome for the extreme suite's table: `(status, detail)` — completed with
/// what `describe` says and the work, or the typed error and the rows kept.
fn outcome(
    r: Result<Solution, filippov::runtime::SolveError>,
    describe: &dyn Fn(&Solution) -> String,
) -> (String, String) {
    match r {
        Ok(sol) => (
            "completed".to_string(),
            format!(
                "{}; {} steps, {} events, {} Zeno handovers",
                describe(&sol),
                sol.stats.steps,
                sol.stats.events,
                sol.stats.zeno_handovers
            ),
        ),
        Err(e) => (
            format!("typed error: {}", e.kind),
            format!("{} rows kept", e.solution.len()),
        ),
    }
}

/// Where a run's bounces settled: the time of its first `Settled` switch (event-driven),
/// against the closed-form accumulation time `t_acc` when there is one.
fn settled(sol: &Solution, t_acc: f64) -> String {
    match sol.switches.iter().find(|s| s.kind == SwitchKind::Settled) {
        Some(s) => {
            let located = match s.accumulation {
                Some(a) if t_acc.is_finite() => {
                    format!(
                        ", accumulation located at {a:.9} (error {:.1e})",
                        (a - t_acc).abs()
                    )
                }
                Some(a) => format!(", accumulation located at {a:.6}"),
                None => String::new(),
            };
            format!("settled at {:.6}{located}", s.t)
        }
        None => "no settle event".into(),
    }
}

/// Resting on joint limits, the state a robot arm is most often in: the two-link arm
/// falling onto its shoulder limit with friction on the elbow (restitution 0.3, 0.9,
/// 0.99), the three-link arm on a spring-backed limit (support stiffness 1e3 to
/// 1e12, 1e4 where its vibration is still followed), and the Panda from its URDF with every limit a stop, folding onto several.
/// Event-driven (default method and tolerance) beside time-stepping at h = 1e-3, each
/// timed (median), with the ratio of their times on the event-driven row.
fn resting_on_limits(config: &Config, short: f64) -> Vec<Vec<String>> {
    use super::panda_limits::{PandaOnLimits, V7, release_pose};
    use super::resting_arm::{RestingArm, V2, zero};
    use super::supported_arm::{SupportedArm, V3, zero as supported_zero};
    use filippov::runtime::NonSmooth;
    use filippov::runtime::nonsmooth::{Element, ElementKind};
    let ed = NonSmoothMethod::default();
    let ts = NonSmoothMethod::TimeStepping {
        h: 1e-3,
        theta: 1.0,
    };
    let mut rows = Vec::new();
    let mut pair =
        |case: String,
         run: &dyn Fn(&NonSmoothMethod) -> Result<Solution, filippov::runtime::SolveError>,
         describe: &dyn Fn(&Solution) -> String| {
            let mut times = [Timing::default(); 2];
            let mut out = Vec::new();
            for (i, (name, m)) in [
                ("event-driven (default)", &ed),
                ("time-stepping h = 1e-3", &ts),
            ]
            .into_iter()
            .enumerate()
            {
                let (time, r) = timed(config.repeats.min(5), || run(m));
                times[i] = time;
                let (status, detail) = outcome(r, describe);
                out.push(vec![
                    case.clone(),
                    name.to_string(),
                    status,
                    detail,
                    time.scaled(1e3).show(2),
                ]);
            }
            out[0][3] += &format!("; time {} time-stepping's", times[0].ratio_to(&times[1], 2));
            rows.extend(out);
        };
    let horizon = short.min(5.0);
    for e in [0.3, 0.9, 0.99] {
        let arm = RestingArm {
            m1: 1.0,
            l1: 1.0,
            m2: 0.5,
            l2: 0.7,
            fc: 20.0,
            lim: -1.0,
            e,
        };
        let p = NonSmoothProblem::new(0.0, horizon, V2::new(0.2, -0.5), V2::zeros());
        pair(
            format!("2-link arm onto its shoulder limit, e = {e}, elbow friction, {horizon} s"),
            &|m| solve_nonsmooth(&arm, &zero, &p, m),
            &|sol| {
                let y = sol.last().map_or(vec![f64::NAN; 4], |r| r.1.to_vec());
                format!(
                    "{}; at tf: q = ({:.6}, {:.6}) (limit −1), v = ({:.1e}, {:.1e})",
                    settled(sol, f64::NAN),
                    y[0],
                    y[1],
                    y[2],
                    y[3]
                )
            },
        );
    }
    // Resting on a spring-backed limit: the support's vibration, nanoradians at
    // k = 1e9, is followed only where it matters (see theory.md, "Resting on a stiff
    // support").
    for ks in [1e3, 1e4, 1e6, 1e9, 1e12] {
        let arm = SupportedArm::new(2.0, ks);
        let p = NonSmoothProblem::new(0.0, 2.0, arm.static_start(0.5), V3::zeros());
        pair(
            format!(
                "3-link arm on a spring-backed shoulder limit, k_support = {ks:.0e}, elbow friction, hand swinging, 2 s"
            ),
            &|m| solve_nonsmooth(&arm, &supported_zero, &p, m),
            &|sol| {
                let resting = sol
                    .switches
                    .iter()
                    .filter(|s| s.element.as_deref() == Some("stop_shoulder"))
                    .next_back()
                    .is_some_and(|s| s.to == Some(filippov::runtime::Mode::Contact));
                format!(
                    "{} steps, {} switches; at tf the support {}",
                    sol.stats.steps,
                    sol.switches.len(),
                    if resting {
                        "rests (held at its static compression)"
                    } else {
                        "is followed"
                    }
                )
            },
        );
    }
    let panda = PandaOnLimits { e: 0.5, fc: 5.0 };
    let p = NonSmoothProblem::new(0.0, horizon.min(3.0), release_pose(), V7::zeros());
    let input = |_t: f64, _q: &V7, _v: &V7| V7::zeros();
    pair(
        format!(
            "Panda (URDF), stops at all 14 limits, e = 0.5, released under gravity, {} s",
            horizon.min(3.0)
        ),
        &|m| solve_nonsmooth(&panda, &input, &p, m),
        &|sol| {
            let y = sol.last().map_or(vec![f64::NAN; 14], |r| r.1.to_vec());
            let impacts = sol
                .switches
                .iter()
                .filter(|s| s.kind == SwitchKind::Impact)
                .count();
            // The stops as the derive read them from the URDF file.
            let on: Vec<String> = (0..PandaOnLimits::ELEMENTS)
                .filter_map(|e| match NonSmooth::element(&panda, e) {
                    Element {
                        coordinate,
                        kind: ElementKind::Stop { position, .. },
                        name,
                    } if (y[coordinate] - position).abs() < 1e-3 => Some(name),
                    _ => None,
                })
                .map(|name| name.trim_start_matches("stop_").to_string())
                .collect();
            let vmax = y[7..14].iter().fold(0.0f64, |a, v| a.max(v.abs()));
            format!(
                "{impacts} impacts; {}; at tf within 1e-3 rad of a limit: {}; max |v| = {vmax:.1e}",
                settled(sol, f64::NAN),
                if on.is_empty() {
                    "none".to_string()
                } else {
                    on.join(", ")
                }
            )
        },
    );
    rows
}

/// The largest switch-time difference between two runs whose switch logs match, and at
/// which switch.
fn switch_spread(a: &Solution, b: &Solution) -> Option<(f64, usize)> {
    if a.switches.is_empty() {
        return None;
    }
    compare_switches(a, b, 1.0, 2).map(|w| (w.ratio, w.index))
}

/// The largest switch-time difference between a run and its reference.
#[derive(Clone, Copy, Debug)]
struct WorstSwitch {
    /// The difference in units of the run's rtol.
    ratio: f64,
    /// Which switch of the log.
    index: usize,
    /// The largest difference in the state (positions and velocities) just before
    /// the earlier of the two switch times, in units of the run's rtol: what the run
    /// carried into that switch. The ratio of the two is how much that switch
    /// magnifies a state error.
    state_before: f64,
}

/// The largest switch-time difference to `reference` (see [`WorstSwitch`]), if the two
/// switch logs name the same elements entering the same modes in the same order. The
/// rows' first `states` columns are the state `[q, v]`.
fn compare_switches(
    sol: &Solution,
    reference: &Solution,
    rtol: f64,
    states: usize,
) -> Option<WorstSwitch> {
    let same = sol.switches.len() == reference.switches.len()
        && sol
            .switches
            .iter()
            .zip(&reference.switches)
            .all(|(a, b)| a.element == b.element && a.to == b.to && a.kind == b.kind);
    if !same {
        return None;
    }
    let Some((index, dt)) = sol
        .switches
        .iter()
        .zip(&reference.switches)
        .map(|(a, b)| (a.t - b.t).abs())
        .enumerate()
        .max_by(|p, q| p.1.total_cmp(&q.1))
    else {
        return Some(WorstSwitch {
            ratio: 0.0,
            index: 0,
            state_before: 0.0,
        });
    };
    // Before both switches by as much as they differ (at least a little): both runs
    // are still on the arc that leads to this switch there (velocities may jump at the
    // switch itself).
    let t0 = sol.switches[index].t.min(reference.switches[index].t);
    let t = t0 - dt.max(1e-9 * t0.abs().max(1.0));
    let state_before = match (sol.at(t), reference.at(t)) {
        // The forces after the state are left out: at a fold the slip force has a
        // square-root singularity in the speed.
        (Some(a), Some(b)) => {
            a.iter()
                .take(states)
                .zip(&b)
                .map(|(x, y)| (x - y).abs())
                .fold(0.0, f64::max)
                / rtol
        }
        _ => f64::NAN,
    };
    Some(WorstSwitch {
        ratio: dt / rtol,
        index,
        state_before,
    })
}
