//! Theory S5 and S6: the Coulomb oscillator (m = k = 1).
//! S5, forced stick–slip: f_crit = 0.5, F = 1.2 sin(0.5 t), x0 = 0.25, v0 = 0, stuck with
//! friction force −f_crit/2, t ∈ [0, 30]; reference a tight event-driven run.
//! S6, free decay: f_crit = 0.1, x0 = 1, v0 = 0, t ∈ [0, 30], against the closed form of
//! theory §5 (turning points −0.8, 0.6, −0.4, 0.2, 0.0 at t = π … 5π, then at rest).
//!
//! Run: `cargo run --release --example s5_s6_coulomb` (plots in `target/plots/`).

#[path = "support/nonsmooth.rs"]
mod ns;
#[path = "support/mod.rs"]
mod support;

use std::f64::consts::PI;

use filippov::nalgebra::SVector;
use filippov::runtime::{
    Method, NonSmoothMethod, NonSmoothProblem, Options, Solution, solve_nonsmooth,
};
use filippov::scenes::CoulombOscillator;

type V1 = SVector<f64, 1>;
const H: f64 = 1e-3;

/// Event-driven default, time-stepping at `H`, and (S5) a tight event-driven reference.
fn runs(
    s: &CoulombOscillator,
    p: &NonSmoothProblem<1>,
    force: impl Fn(f64) -> f64,
    tight: bool,
) -> [Option<Solution>; 3] {
    let input = |t: f64, _q: &V1, _v: &V1| SVector::from([force(t)]);
    let tight_m = NonSmoothMethod::EventDriven(Method::Dopri5(Options::tolerances(1e-12, 1e-14)));
    let ts = NonSmoothMethod::TimeStepping { h: H, theta: 1.0 };
    [
        ns::report(
            "event-driven DOPRI5 (1e-8, 1e-10)",
            solve_nonsmooth(s, &input, p, &NonSmoothMethod::default()),
        ),
        ns::report(
            &format!("time-stepping h = {H:e}, θ = 1"),
            solve_nonsmooth(s, &input, p, &ts),
        ),
        tight
            .then(|| {
                ns::report(
                    "reference: event-driven (1e-12)",
                    solve_nonsmooth(s, &input, p, &tight_m),
                )
            })
            .flatten(),
    ]
}

/// S6 closed form (theory §5), x at t.
fn s6_exact(x0: f64, xf: f64, t: f64) -> f64 {
    let mut n = 0usize;
    while (x0 - 2.0 * n as f64 * xf).abs() > xf {
        if t < (n + 1) as f64 * PI {
            let sign = (-1f64).powi(n as i32);
            return sign * (xf + (x0 - (2 * n + 1) as f64 * xf) * (t - n as f64 * PI).cos());
        }
        n += 1;
    }
    (-1f64).powi(n as i32) * (x0 - 2.0 * n as f64 * xf)
}

fn main() {
    println!(
        "S5 Coulomb, forced stick–slip: m = k = 1, f_crit = 0.5, F = 1.2 sin(0.5 t), x0 = 0.25, f(0) = −0.25"
    );
    let s5 = CoulombOscillator {
        m: 1.0,
        k: 1.0,
        f_crit: 0.5,
    };
    let p5 = NonSmoothProblem::new(0.0, 30.0, V1::new(0.25), V1::new(0.0))
        .with_forces(vec![Some(-0.25)]);
    let [ed, ts, reference] = runs(&s5, &p5, |t| 1.2 * (0.5 * t).sin(), true);
    if let Some(r) = &reference {
        let c = ns::cols(r, "");
        println!(
            "  reference: x(30) = {:.10}, v(30) = {:.3e}, f(30) = {:.6}, f(0) = {}",
            c.x.last().unwrap(),
            c.v.last().unwrap(),
            c.f.last().unwrap(),
            c.f[0]
        );
        for (label, traj) in [("event-driven", &ed), ("time-stepping", &ts)] {
            if let Some(traj) = traj {
                let (gx, ex) = ns::diff_to(traj, r, 0, 0.01);
                let (gv, _) = ns::diff_to(traj, r, 1, 0.01);
                println!(
                    "  {label:<14} vs reference: max |Δx| = {gx:.2e}, max |Δv| = {gv:.2e} (grid 0.01), |Δx(30)| = {ex:.2e}"
                );
            }
        }
        let f_bad = c.f.iter().fold(0.0f64, |m, f| m.max(f.abs() - 0.5));
        println!(
            "  reference: max(|f| − f_crit) = {f_bad:.1e} (≤ 0: friction force inside its bounds)"
        );
    }
    if let Some(ed) = &ed {
        ns::coulomb_plots(
            "s5_coulomb",
            "S5 Coulomb stick–slip",
            0.5,
            &ns::cols(ed, ""),
        );
    }

    println!("S6 Coulomb, free decay: m = k = 1, f_crit = 0.1, x0 = 1, t ∈ [0, 30]");
    let s6 = CoulombOscillator {
        m: 1.0,
        k: 1.0,
        f_crit: 0.1,
    };
    let p6 = NonSmoothProblem::new(0.0, 30.0, V1::new(1.0), V1::new(0.0));
    let [ed, ts, _] = runs(&s6, &p6, |_| 0.0, false);
    for (label, traj) in [("event-driven", &ed), ("time-stepping", &ts)] {
        let Some(traj) = traj else { continue };
        let c = ns::cols(traj, "");
        let err = ns::max_err(&c.t, &c.x, |t| s6_exact(1.0, 0.1, t));
        println!(
            "  {label:<14} max |x − x_exact| = {err:.2e}, x(30) = {:+.3e} (exact 0)",
            c.x.last().unwrap()
        );
        let zeros = ns::velocity_zeros(&c);
        for (n, (t, x)) in zeros.iter().enumerate() {
            let (te, xe) = ((n + 1) as f64 * PI, s6_exact(1.0, 0.1, (n + 1) as f64 * PI));
            println!(
                "    turning point {}: t = {t:.9} (exact {te:.9}, Δ {:.1e}), x = {x:+.9} (exact {xe:+.1}, Δ {:.1e})",
                n + 1,
                t - te,
                x - xe
            );
        }
        if zeros.len() != 5 {
            println!(
                "    SUSPICIOUS: {} turning points, closed form has 5",
                zeros.len()
            );
        }
        let moving =
            c.t.iter()
                .zip(&c.v)
                .filter(|(t, v)| **t > 5.0 * PI + 10.0 * H && **v != 0.0)
                .count();
        println!("    rows after 5π + 10 h with v ≠ 0: {moving} (closed form: at rest)");
    }
    if let Some(ed) = &ed {
        ns::coulomb_plots(
            "s6_coulomb",
            "S6 Coulomb free decay",
            0.1,
            &ns::cols(ed, ""),
        );
    }
}
