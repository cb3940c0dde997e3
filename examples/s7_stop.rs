//! Theory S7: a mass on a spring with a linear Bingham dash-pot (m = k = 1, η = 0.2,
//! f_crit = 0.1) hitting a stop at L = 0.5 backed by a massless support on a spring
//! k_support ∈ {1, 10, 100, 1000, 1e6} (x0 = 0, v0 = 1, t ∈ [0, 20]): towards a rigid
//! stop. Plus the elastic case without dash-pot (bilinear oscillator, k_support = 1)
//! against its closed-form period T = 5.8620872 (theory §5).
//!
//! Run: `cargo run --release --example s7_stop` (plots in `target/plots/`).

#[path = "support/nonsmooth.rs"]
mod ns;
#[path = "support/mod.rs"]
mod support;

use std::f64::consts::PI;

use filippov::nalgebra::SVector;
use filippov::runtime::{Method, NonSmoothMethod, NonSmoothProblem, Options, solve_nonsmooth};
use filippov::scenes::{BilinearOscillator, SupportedStop};
use support::{Scale, Series, line_plot, plot_path};

type V1 = SVector<f64, 1>;

fn input(_t: f64, _q: &V1, _v: &V1) -> V1 {
    SVector::from([0.0])
}

/// Closed-form period of the bilinear oscillator (theory §5), m = 1, started at x = 0.
fn bilinear_period(k: f64, ks: f64, l: f64, v0: f64) -> f64 {
    let (w1, w2) = (k.sqrt(), (k + ks).sqrt());
    let a1 = v0 / w1; // √(2E/k), E = v0²/2
    let xe = ks * l / (k + ks);
    let vl = w1 * (a1 * a1 - l * l).sqrt();
    let a2 = ((l - xe).powi(2) + (vl / w2).powi(2)).sqrt();
    2.0 * (PI - (l / a1).acos()) / w1 + 2.0 * ((l - xe) / a2).acos() / w2
}

fn main() {
    let p = NonSmoothProblem::new(0.0, 20.0, V1::new(0.0), V1::new(1.0));
    println!(
        "S7 Bingham oscillator with spring-backed stop: m = k = 1, η = 0.2, f_crit = 0.1, L = 0.5, x0 = 0, v0 = 1, t ∈ [0, 20]"
    );
    let mut runs: Vec<(String, ns::Cols, f64)> = Vec::new();
    for ks in [1.0, 10.0, 100.0, 1000.0, 1e6] {
        let s = SupportedStop {
            m: 1.0,
            k: 1.0,
            f_crit: 0.1,
            eta: 0.2,
            l: 0.5,
            k_support: ks,
        };
        let label = format!("k_support = {ks:e}");
        let Some(traj) = ns::report(
            &label,
            solve_nonsmooth(&s, &input, &p, &NonSmoothMethod::default()),
        ) else {
            continue;
        };
        let c = ns::cols(&traj, "bingham");
        let stop = ns::cols(&traj, "stop");
        let x_max = c.x.iter().fold(f64::MIN, |m, x| m.max(*x));
        let lambda = stop.f.iter().fold(0.0f64, |m, f| m.max(f.abs()));
        let rest =
            c.t.iter()
                .zip(&c.v)
                .rev()
                .take_while(|(_, v)| **v == 0.0)
                .last()
                .map(|(t, _)| *t);
        println!(
            "    max x = {x_max:.6} (penetration {:.2e}), max contact force {lambda:.4}, x(20) = {:+.6}, at rest from t = {}",
            x_max - 0.5,
            c.x.last().unwrap(),
            rest.map_or("—".into(), |t| format!("{t:.4}"))
        );
        runs.push((label, c, ks));
    }
    println!("  components: q0, v0, then one force per element (dash-pot, stop)");
    let xs: Vec<Series> = runs
        .iter()
        .map(|(l, c, _)| {
            Series::new(
                l.clone(),
                c.t.iter().copied().zip(c.x.iter().copied()).collect(),
            )
        })
        .collect();
    let path = plot_path("s7_stop_x");
    line_plot(
        &path,
        "S7: x(t) against the stop at L = 0.5, k_support sweep",
        "t",
        "x",
        &xs,
        Scale::Linear,
        Scale::Linear,
    );
    println!("  wrote {}", path.display());
    if let Some((_, c, _)) = runs.iter().find(|r| r.2 == 1e6) {
        ns::plot_time(
            "s7_stop_k1e6",
            "S7 with k_support = 1e6 (event-driven)",
            &[("", c)],
        );
    }
    let views: Vec<(&str, &ns::Cols)> = runs.iter().map(|(l, c, _)| (l.as_str(), c)).collect();
    let fmax = 1.1 * ns::f_range(&views.iter().map(|r| r.1).collect::<Vec<_>>(), 0.2);
    let graph = ns::bingham_graph(0.1, fmax, |f| (f - f.signum() * 0.1) / 0.2);
    ns::plot_fv(
        "s7_stop",
        "S7: dash-pot f–v plane, linear Bingham law",
        graph,
        &views,
    );

    println!(
        "S7 elastic case (bilinear oscillator, no dash-pot): m = k = k_support = 1, L = 0.5, v0 = 1"
    );
    let b = BilinearOscillator {
        m: 1.0,
        k: 1.0,
        l: 0.5,
        k_support: 1.0,
    };
    let t_exact = bilinear_period(1.0, 1.0, 0.5, 1.0);
    println!("  closed-form period T = {t_exact:.9} (theory: 5.8620872)");
    let methods = [
        (
            "event-driven DOPRI5 (1e-8, 1e-10)",
            NonSmoothMethod::default(),
        ),
        (
            "event-driven DOPRI5 (1e-12)",
            NonSmoothMethod::EventDriven(Method::Dopri5(Options::tolerances(1e-12, 1e-14))),
        ),
        (
            "time-stepping h = 1e-3, θ = 1",
            NonSmoothMethod::TimeStepping {
                h: 1e-3,
                theta: 1.0,
            },
        ),
    ];
    for (label, m) in methods {
        let Some(traj) = ns::report(label, solve_nonsmooth(&b, &input, &p, &m)) else {
            continue;
        };
        // Upward zero crossings of x, by bisection on the interpolant.
        let ups = ns::upward_crossings(&traj, 0);
        let periods: Vec<f64> = ups.windows(2).map(|w| w[1] - w[0]).collect();
        let err = periods
            .iter()
            .fold(0.0f64, |m, p| m.max((p - t_exact).abs()));
        println!("    periods {periods:.9?}, max |T − T_exact| = {err:.2e}");
    }
}
