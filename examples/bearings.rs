//! Bearing friction (theory §8): a slider on a rail with a pendulum hanging from it, the
//! rail's friction μ times the load it carries (`#[friction(x, mu = mu)]`), beside
//!
//! - the same mechanism resting on the rail through two skids (`CartOnRail`, contacts,
//!   event-driven): the same friction, from the skids' normal forces;
//! - the slider with a constant friction limit, μ times the weight at rest: what the
//!   rail does if it ignores the pendulum's swing.
//!
//! Plot: the slider's position under the three. Then a pendulum on a journal bearing
//! (`JournalPendulum`) comes to rest. Run: `cargo run --release --example bearings`.

#[path = "support/mod.rs"]
mod support;

use filippov::nalgebra::SVector;
use filippov::runtime::{
    Method, NonSmoothMethod, NonSmoothProblem, Options, Unforced, contact_event_driven,
    solve_nonsmooth,
};
use filippov::scenes::{CartOnRail, FixedLimitSlider, JournalPendulum, LoadedSlider};
use support::{Scale, Series, line_plot, plot_path};

type V1 = SVector<f64, 1>;
type V2 = SVector<f64, 2>;
type V4 = SVector<f64, 4>;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let (tf, swing, v0, h) = (3.0, 1.2, 0.8, 1e-4);
    let slider = LoadedSlider::default();
    let stepping = NonSmoothMethod::TimeStepping { h, theta: 0.5 };
    let p = NonSmoothProblem::new(0.0, tf, V2::new(0.0, swing), V2::new(v0, 0.0));
    let free = |_: f64, _: &V2, _: &V2| V2::zeros();
    let loaded = solve_nonsmooth(&slider, &free, &p, &stepping)?;
    let fixed = FixedLimitSlider::resting_load_of(&slider);
    let constant = solve_nonsmooth(&fixed, &free, &p, &stepping)?;

    let cart = CartOnRail::default();
    let method = Method::Dopri5(Options {
        max_steps: 1_000_000,
        ..Options::tolerances(1e-10, 1e-12)
    });
    let pc = NonSmoothProblem::new(
        0.0,
        tf,
        V4::from([0.0, cart.b, 0.0, swing]),
        V4::from([v0, 0.0, 0.0, 0.0]),
    );
    let skids = contact_event_driven(&cart, &Unforced, &pc, &method)?;

    let x_of = |sol: &filippov::runtime::Solution| -> Vec<(f64, f64)> {
        sol.rows().map(|(t, y)| (t, y[0])).collect()
    };
    let end = |sol: &filippov::runtime::Solution| sol.last().expect("rows").1[0];
    println!(
        "slider released at {swing} rad, moving at {v0} m/s, after {tf} s: x = {:.6} m on a \
         bearing (time-stepping, h = {h:e}), {:.6} m on two skids (contacts, event-driven), \
         {:.6} m with the limit fixed at μ (m_c + m_p) g",
        end(&loaded),
        end(&skids),
        end(&constant)
    );
    let path = plot_path("bearings_loaded_slider");
    line_plot(
        &path,
        "Slider under a swinging pendulum: the rail's friction",
        "t [s]",
        "x [m]",
        &[
            Series::new("bearing, μ |F_⊥|", x_of(&loaded)),
            Series::new("two skids, μ λ_N (contacts)", x_of(&skids)),
            Series::new("fixed limit μ (m_c + m_p) g", x_of(&constant)),
        ],
        Scale::Linear,
        Scale::Linear,
    );
    println!("  plot: {}", path.display());

    // A pendulum on a journal bearing, released at 1 rad.
    let journal = JournalPendulum {
        r: 0.05,
        ..JournalPendulum::default()
    };
    let p = NonSmoothProblem::new(0.0, 20.0, V1::new(1.0), V1::zeros());
    let free = |_: f64, _: &V1, _: &V1| V1::zeros();
    let sol = solve_nonsmooth(&journal, &free, &p, &stepping)?;
    let rows: Vec<(f64, &[f64])> = sol.rows().collect();
    let rest = rows
        .iter()
        .rev()
        .take_while(|(_, y)| y[1] == 0.0)
        .last()
        .map(|&(t, y)| (t, y[0]));
    match rest {
        Some((t, angle)) => println!(
            "pendulum on a journal (μ = {}, r = {} m): at rest from t = {t:.4} s at {angle:.5} rad",
            journal.mu, journal.r
        ),
        None => println!("pendulum on a journal: still swinging at 20 s"),
    }
    Ok(())
}
