//! Theory S1: the linear Bingham oscillator in free decay (m = k = 1, f_crit = 0.1,
//! η = 0.2, x0 = 1, v0 = 0, t ∈ [0, 30]) against the piecewise closed form of theory §5:
//! event-driven (DOPRI5) and implicit time-stepping.
//!
//! Run: `cargo run --release --example s1_bingham` (plots in `target/plots/`).

#[path = "support/nonsmooth.rs"]
mod ns;
#[path = "support/mod.rs"]
mod support;

use std::f64::consts::PI;

use filippov::nalgebra::SVector;
use filippov::runtime::{NonSmoothMethod, NonSmoothProblem, solve_nonsmooth};
use filippov::scenes::BinghamOscillator;

type V1 = SVector<f64, 1>;

/// Piecewise closed form: slides between velocity zeros nπ/ω_d about the offset
/// sgn(x_n) f_crit/k, sticks for good at the first zero with |k x| ≤ f_crit.
/// Returns (x, v, f_d) at `t`, and the list of velocity zeros.
fn exact(s: &BinghamOscillator, x0: f64, t: f64) -> ((f64, f64, f64), Vec<(f64, f64)>) {
    let zeta = s.eta / (2.0 * s.m);
    let wd = (s.k / s.m - zeta * zeta).sqrt();
    let (mut xn, mut tn, mut zeros) = (x0, 0.0, Vec::new());
    let mut at = None;
    loop {
        if (s.k * xn).abs() <= s.f_crit {
            // Stuck: the dash-pot holds the spring, f_d = −k x.
            return (at.unwrap_or((xn, 0.0, -s.k * xn)), zeros);
        }
        let c = xn.signum() * s.f_crit / s.k;
        let seg = |tau: f64| {
            let e = (-zeta * tau).exp();
            let x = c + (xn - c) * e * ((wd * tau).cos() + zeta / wd * (wd * tau).sin());
            let v = -(xn - c) * e * (wd + zeta * zeta / wd) * (wd * tau).sin();
            (x, v, v.signum() * (s.f_crit + s.eta * v.abs()))
        };
        let tnext = tn + PI / wd;
        if at.is_none() && t < tnext {
            at = Some(seg(t - tn));
        }
        xn = seg(PI / wd).0;
        tn = tnext;
        zeros.push((tn, xn));
    }
}

fn main() {
    let s = BinghamOscillator {
        m: 1.0,
        k: 1.0,
        f_crit: 0.1,
        eta: 0.2,
    };
    let x0 = 1.0;
    let p = NonSmoothProblem::new(0.0, 30.0, V1::new(x0), V1::new(0.0));
    let input = |_t: f64, _q: &V1, _v: &V1| SVector::from([0.0]);
    let h = 1e-3;
    println!(
        "S1 linear Bingham, free decay: m = k = 1, f_crit = 0.1, η = 0.2, x0 = 1, t ∈ [0, 30]"
    );
    let ed = ns::report(
        "event-driven DOPRI5 (1e-8, 1e-10)",
        solve_nonsmooth(&s, &input, &p, &NonSmoothMethod::default()),
    );
    let ts = ns::report(
        &format!("time-stepping h = {h:e}, θ = 1"),
        solve_nonsmooth(
            &s,
            &input,
            &p,
            &NonSmoothMethod::TimeStepping { h, theta: 1.0 },
        ),
    );
    let (_, zeros_exact) = exact(&s, x0, 0.0);
    let mut plotted = Vec::new();
    for (label, traj) in [("event-driven", &ed), ("time-stepping", &ts)] {
        let Some(traj) = traj else { continue };
        let c = ns::cols(traj, "");
        let ex = ns::max_err(&c.t, &c.x, |t| exact(&s, x0, t).0.0);
        let ev = ns::max_err(&c.t, &c.v, |t| exact(&s, x0, t).0.1);
        let zeros = ns::velocity_zeros(&c);
        println!(
            "  {label:<14} max |x − x_exact| = {ex:.2e}, max |v − v_exact| = {ev:.2e}, x(30) = {:.12} (exact {:.12})",
            c.x.last().unwrap(),
            exact(&s, x0, 30.0).0.0
        );
        println!("    velocity zeros (t, x) vs closed form:");
        for (i, (t, x)) in zeros.iter().enumerate() {
            match zeros_exact.get(i) {
                Some((te, xe)) => println!(
                    "      {t:>10.6} {x:>10.6}   exact {te:>10.6} {xe:>10.6}   Δt {:.1e}  Δx {:.1e}",
                    t - te,
                    x - xe
                ),
                None => println!("      {t:>10.6} {x:>10.6}   (no closed-form counterpart)"),
            }
        }
        if zeros.len() < zeros_exact.len() {
            println!(
                "    MISSING velocity zeros: {:?}",
                &zeros_exact[zeros.len()..]
            );
        }
        plotted.push((label, c));
    }
    let runs: Vec<(&str, &ns::Cols)> = plotted.iter().map(|(l, c)| (*l, c)).collect();
    if let Some((_, c)) = runs.first() {
        ns::plot_time(
            "s1_bingham",
            "S1 linear Bingham, free decay (event-driven)",
            &[("", c)],
        );
    }
    // The time-stepping path lies on the same graph: plot the event-driven one.
    let Some(first) = runs.first() else { return };
    let fmax = 1.3 * ns::f_range(&[first.1], 0.2);
    let graph = ns::bingham_graph(s.f_crit, fmax, |f| (f - f.signum() * s.f_crit) / s.eta);
    ns::plot_fv(
        "s1_bingham",
        "S1 linear Bingham: f–v plane, law v = (f − sgn f · f_crit)/η",
        graph,
        &runs[..1],
    );
}
