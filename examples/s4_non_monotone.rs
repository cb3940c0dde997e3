//! Theory S4: the non-monotone Bingham law of thesis eq. 4.9b,
//! `v = (1 + 0.1 (f² − 4)(f² − 9)) (f − sgn(f) f_crit)` (m = k = 1, f_crit = 1,
//! F = 3 sin(0.5 t), x0 = v0 = 0, t ∈ [0, 40]), solved both ways of the thesis:
//! approach 1 (no velocity jumps: force jumps at folds, hysteresis) and approach 2
//! (maximal dissipation: outer branch, plateau at v_min). The event-driven integrator
//! rejects non-monotone laws, so both run with implicit time-stepping; the reference per
//! approach is a run at a ten times smaller step.
//!
//! Run: `cargo run --release --example s4_non_monotone` (plots in `target/plots/`).

#[path = "support/nonsmooth.rs"]
mod ns;
#[path = "support/mod.rs"]
mod support;

use filippov::nalgebra::SVector;
use filippov::runtime::{NonSmooth, NonSmoothMethod, NonSmoothProblem, Solution, solve_nonsmooth};
use filippov::scenes::{NonMonotoneMaxDissipation, NonMonotoneNoJumps};
use support::{Scale, Series, line_plot, plot_path};

type V1 = SVector<f64, 1>;

fn input(t: f64, _q: &V1, _v: &V1) -> V1 {
    SVector::from([3.0 * (0.5 * t).sin()])
}

/// Event-driven (fold jumps for approach 1, the plateau mode for approach 2), then
/// time-stepping at h and h/10, which must converge to the event-driven result.
fn approach<S: NonSmooth<1>>(label: &str, s: &S, p: &NonSmoothProblem<1>) -> Option<Solution> {
    println!("{label}");
    let ed = ns::report(
        "event-driven DOPRI5 (default)",
        solve_nonsmooth(s, &input, p, &NonSmoothMethod::default()),
    );
    if let Some(tr) = &ed {
        let c = ns::cols(tr, "");
        println!(
            "  event-driven: x(40) = {:+.6}, v(40) = {:+.6}",
            c.x.last().unwrap(),
            c.v.last().unwrap()
        );
    } else {
        println!("  → event-driven failed (printed above): time-stepping only");
    }
    let run = |h: f64| {
        let m = NonSmoothMethod::TimeStepping { h, theta: 1.0 };
        ns::report(
            &format!("time-stepping h = {h:e}, θ = 1"),
            solve_nonsmooth(s, &input, p, &m),
        )
    };
    let (coarse, fine) = (run(1e-3), run(1e-4));
    for (h, traj) in [(1e-3, &coarse), (1e-4, &fine)] {
        if let Some(tr) = traj {
            let c = ns::cols(tr, "");
            println!(
                "  h = {h:e}: x(40) = {:+.6}, v(40) = {:+.6}, f_d(40) = {:+.6}, max |v| = {:.4}",
                c.x.last().unwrap(),
                c.v.last().unwrap(),
                c.f.last().unwrap(),
                c.v.iter().fold(0.0f64, |m, v| m.max(v.abs()))
            );
        }
    }
    if let (Some(c), Some(f)) = (&coarse, &fine) {
        let (gx, ex) = ns::diff_to(c, f, 0, 0.01);
        println!("  h = 1e-3 vs h = 1e-4: max |Δx| = {gx:.2e}, |Δx(40)| = {ex:.2e}");
    }
    if let Some(e) = &ed {
        for (h, traj) in [(1e-3, &coarse), (1e-4, &fine)] {
            if let Some(tr) = traj {
                let (gx, ex) = ns::diff_to(tr, e, 0, 0.01);
                println!(
                    "  time-stepping h = {h:e} vs event-driven: max |Δx| = {gx:.2e}, |Δx(40)| = {ex:.2e}"
                );
            }
        }
    }
    fine.or(coarse)
}

fn main() {
    let (m, k, f_crit) = (1.0, 1.0, 1.0);
    let a1 = NonMonotoneNoJumps { m, k, f_crit };
    let a2 = NonMonotoneMaxDissipation { m, k, f_crit };
    let p = NonSmoothProblem::new(0.0, 40.0, V1::new(0.0), V1::new(0.0));
    println!(
        "S4 non-monotone Bingham (4.9b): m = k = 1, f_crit = 1, F = 3 sin(0.5 t), t ∈ [0, 40]"
    );
    println!(
        "law: φ(1.69072) = {:.5} (local max 1.17493), φ(2.49909) = {:.5} (local min 0.57187)",
        a1.law(0, 1.69072).0,
        a1.law(0, 2.49909).0
    );
    let r1 = approach("approach 1 (no velocity jumps)", &a1, &p);
    let r2 = approach("approach 2 (maximal dissipation)", &a2, &p);
    let labels = ["approach 1", "approach 2"];
    let cols: Vec<(&str, ns::Cols)> = labels
        .iter()
        .zip([&r1, &r2])
        .filter_map(|(l, r)| r.as_ref().map(|r| (*l, ns::cols(r, ""))))
        .collect();
    if let [(_, c1), (_, c2)] = cols.as_slice() {
        let (x1, x2) = (c1.x.last().unwrap(), c2.x.last().unwrap());
        println!(
            "x(40): approach 1 {x1:+.6}, approach 2 {x2:+.6} — {} (theory: differ in sign)",
            if x1.signum() != x2.signum() {
                "opposite signs"
            } else {
                "SAME SIGN"
            }
        );
    }
    let views: Vec<(&str, &ns::Cols)> = cols.iter().map(|(l, c)| (*l, c)).collect();
    for (l, c) in &views {
        let id = format!("s4_{}", l.replace(' ', ""));
        ns::plot_time(
            &id,
            &format!("S4 non-monotone law, {l} (time-stepping h = 1e-4)"),
            &[("", c)],
        );
    }
    let xs: Vec<Series> = views
        .iter()
        .map(|(l, c)| {
            Series::new(
                *l,
                c.t.iter()
                    .copied()
                    .zip(c.x.iter().copied())
                    .step_by(10)
                    .collect(),
            )
        })
        .collect();
    let path = plot_path("s4_non_monotone_x");
    line_plot(
        &path,
        "S4: x(t), approach 1 vs approach 2",
        "t",
        "x",
        &xs,
        Scale::Linear,
        Scale::Linear,
    );
    println!("  wrote {}", path.display());
    let fmax = 1.02 * ns::f_range(&views.iter().map(|r| r.1).collect::<Vec<_>>(), 3.0);
    let graph = ns::bingham_graph(f_crit, fmax, |f| a1.law(0, f).0);
    ns::plot_fv(
        "s4_non_monotone",
        "S4: f–v plane, non-monotone law (4.9b), paths of both approaches",
        graph,
        &views,
    );
}
