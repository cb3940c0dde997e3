//! Shared by the non-smooth scene examples (S1–S7): running an integrator with its error
//! printed rather than hidden, the trajectory's columns, summaries, and the thesis-style
//! plots (x, v, f against t; the f–v plane with the constitutive graph and the path).
#![allow(dead_code)]

use filippov::runtime::{Solution, SolveError};

use super::support::{Scale, Series, line_plot, plot_path};

/// The columns of a one-coordinate scene: time, position, velocity, one element force.
pub struct Cols {
    pub t: Vec<f64>,
    pub x: Vec<f64>,
    pub v: Vec<f64>,
    pub f: Vec<f64>,
}

/// Columns of coordinate 0 and the force of the first element whose name contains `force`.
pub fn cols(traj: &Solution, force: &str) -> Cols {
    let fi = traj
        .names()
        .iter()
        .position(|n| n.starts_with("f_") && n.contains(force))
        .unwrap_or_else(|| panic!("no force matching {force} in {:?}", traj.names()));
    Cols {
        t: traj.times().to_vec(),
        x: traj.component(0),
        // The state is [q; v]: the first velocity follows the coordinates.
        v: traj.component(
            (traj.names().len() - traj.names().iter().filter(|n| n.starts_with("f_")).count()) / 2,
        ),
        f: traj.component(fi),
    }
}

/// Prints an integrator's result: the statistics, or the error (never hidden).
pub fn report(label: &str, result: Result<Solution, SolveError>) -> Option<Solution> {
    match result {
        Ok(traj) => {
            let s = &traj.stats;
            println!(
                "  {label:<34} rows {:>7}  steps {:>7}  rejected {:>4}  rhs {:>8}  events {:>4}  mode changes {:>4}  zeno {}/{}",
                traj.len(),
                s.steps,
                s.rejected_steps,
                s.rhs_evaluations,
                s.events,
                s.mode_changes,
                s.zeno_detected,
                s.zeno_handovers
            );
            Some(traj)
        }
        Err(e) => {
            println!("  {label:<34} INTEGRATOR ERROR: {e}");
            println!("  {:<34} error kind: {:?}", "", e.kind);
            None
        }
    }
}

/// Largest `|y_i − exact(t_i)|` over the rows.
pub fn max_err(t: &[f64], y: &[f64], exact: impl Fn(f64) -> f64) -> f64 {
    t.iter()
        .zip(y)
        .map(|(&t, &y)| (y - exact(t)).abs())
        .fold(0.0, f64::max)
}

/// Largest difference of component `j` of `a` from `reference` on a grid of spacing `dt`
/// (both interpolated), and the difference at the final time.
pub fn diff_to(a: &Solution, reference: &Solution, j: usize, dt: f64) -> (f64, f64) {
    let (t0, tf) = (a.times()[0], *a.times().last().unwrap());
    let n = ((tf - t0) / dt).round() as usize;
    let grid = (0..=n)
        .map(|i| (t0 + i as f64 * dt).min(tf))
        .map(|t| (a.at(t).unwrap()[j] - reference.at(t).unwrap()[j]).abs())
        .fold(0.0, f64::max);
    let end = (a.last().unwrap().1[j] - reference.last().unwrap().1[j]).abs();
    (grid, end)
}

/// Times where the velocity reaches or crosses zero from a non-zero value, with x there.
pub fn velocity_zeros(c: &Cols) -> Vec<(f64, f64)> {
    let mut out: Vec<(f64, f64)> = Vec::new();
    for i in 1..c.t.len() {
        let (a, b) = (c.v[i - 1], c.v[i]);
        if a != 0.0 && (b == 0.0 || a.signum() != b.signum()) {
            // Linear interpolation inside a crossing step (exact on an event row).
            let s = if b == 0.0 { 1.0 } else { a / (a - b) };
            let t = c.t[i - 1] + s * (c.t[i] - c.t[i - 1]);
            let x = c.x[i - 1] + s * (c.x[i] - c.x[i - 1]);
            if out.last().is_none_or(|(tl, _)| t - tl > 1e-6) {
                out.push((t, x));
            }
        }
    }
    out
}

/// Points for a plot, thinned to at most about 5000 (fine time-stepping runs).
fn zip(a: &[f64], b: &[f64]) -> Vec<(f64, f64)> {
    let stride = a.len().div_ceil(5000).max(1);
    let mut pts: Vec<(f64, f64)> = a
        .iter()
        .copied()
        .zip(b.iter().copied())
        .step_by(stride)
        .collect();
    if a.len() > 1 && !(a.len() - 1).is_multiple_of(stride) {
        pts.push((a[a.len() - 1], b[b.len() - 1]));
    }
    pts
}

/// `NAME_t.svg`: x, v and the element force against t (one curve set per labelled run).
pub fn plot_time(name: &str, title: &str, runs: &[(&str, &Cols)]) {
    let mut series = Vec::new();
    for (label, c) in runs {
        let tag = |s: &str| {
            if label.is_empty() {
                s.to_string()
            } else {
                format!("{s} ({label})")
            }
        };
        series.push(Series::new(tag("x"), zip(&c.t, &c.x)));
        series.push(Series::new(tag("v"), zip(&c.t, &c.v)));
        series.push(Series::new(tag("f_d"), zip(&c.t, &c.f)));
    }
    let path = plot_path(&format!("{name}_t"));
    line_plot(
        &path,
        title,
        "t",
        "x, v, f_d",
        &series,
        Scale::Linear,
        Scale::Linear,
    );
    println!("  wrote {}", path.display());
}

/// `NAME_fv.svg`: the constitutive graph (f horizontal, v vertical) and solution paths
/// (drawn over the graph; draw the graph beyond the paths' force range so it shows).
pub fn plot_fv(name: &str, title: &str, graph: Vec<(f64, f64)>, runs: &[(&str, &Cols)]) {
    let mut series = vec![Series::new("constitutive law", graph)];
    for (label, c) in runs {
        series.push(Series::new(format!("path {label}"), zip(&c.f, &c.v)));
    }
    let path = plot_path(&format!("{name}_fv"));
    line_plot(
        &path,
        title,
        "dash-pot force f",
        "velocity v",
        &series,
        Scale::Linear,
        Scale::Linear,
    );
    println!("  wrote {}", path.display());
}

/// The Bingham graph as one polyline: slip branch `v = φ(f)` for `f ∈ [−f_max, −f_crit]`,
/// the dead zone `v = 0` on `[−f_crit, f_crit]`, the slip branch on `[f_crit, f_max]`.
pub fn bingham_graph(f_crit: f64, f_max: f64, phi: impl Fn(f64) -> f64) -> Vec<(f64, f64)> {
    let n = 400;
    let branch: Vec<f64> = (0..=n)
        .map(|i| f_crit + (f_max - f_crit) * i as f64 / n as f64)
        .collect();
    let mut g: Vec<(f64, f64)> = branch.iter().rev().map(|&f| (-f, phi(-f))).collect();
    g.push((-f_crit, 0.0));
    g.push((f_crit, 0.0));
    g.extend(branch.iter().map(|&f| (f, phi(f))));
    g
}

/// The Coulomb graph: `f = −f_crit` for `v < 0`, the dead zone at `v = 0`, `f = f_crit`
/// for `v > 0` (vertical lines up to `±v_max`).
pub fn coulomb_graph(f_crit: f64, v_max: f64) -> Vec<(f64, f64)> {
    vec![
        (-f_crit, -v_max),
        (-f_crit, 0.0),
        (f_crit, 0.0),
        (f_crit, v_max),
    ]
}

/// Largest `|f|` of the runs (to size the drawn graph), at least `floor`.
pub fn f_range(runs: &[&Cols], floor: f64) -> f64 {
    runs.iter()
        .flat_map(|c| c.f.iter())
        .fold(floor, |m, f| m.max(f.abs()))
}

/// Upward zero crossings of component `j`, located by bisection on the interpolant.
pub fn upward_crossings(traj: &Solution, j: usize) -> Vec<f64> {
    let (t, x) = (traj.times(), traj.component(j));
    (1..t.len())
        .filter(|&i| x[i - 1] < 0.0 && x[i] >= 0.0)
        .map(|i| {
            let (mut a, mut b) = (t[i - 1], t[i]);
            for _ in 0..80 {
                let mid = 0.5 * (a + b);
                if traj.at(mid).unwrap()[j] < 0.0 {
                    a = mid
                } else {
                    b = mid
                }
            }
            0.5 * (a + b)
        })
        .collect()
}

/// Both plots of a Coulomb scene: x, v, f against t, and the f–v plane.
pub fn coulomb_plots(id: &str, title: &str, f_crit: f64, c: &Cols) {
    plot_time(id, &format!("{title} (event-driven)"), &[("", c)]);
    let v_max = 1.2 * c.v.iter().fold(0.1f64, |m, v| m.max(v.abs()));
    let graph = coulomb_graph(f_crit, v_max);
    plot_fv(
        id,
        &format!("{title}: f–v plane, Coulomb graph"),
        graph,
        &[("event-driven", c)],
    );
}
