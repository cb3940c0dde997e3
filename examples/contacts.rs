//! Contacts (theory §8), three scenes a user asks for:
//!
//! - a box on an incline below its friction angle, for 10⁴ s: it does not creep;
//! - a cart on a rail with a pendulum swinging below it: the rail's friction is μ times
//!   the skids' load, which carries the pendulum's swing (plot: load and friction);
//! - a three-legged table launched sliding and spinning (spatial contacts, the exact
//!   friction cone): it comes to rest exactly.
//!
//! Run: `cargo run --release --example contacts` (plots in `target/plots/`).

#[path = "support/mod.rs"]
mod support;

use filippov::nalgebra::SVector;
use filippov::runtime::{
    Method, NonSmoothProblem, Options, SwitchKind, Unforced, contact_event_driven,
    contact_time_stepping,
};
use filippov::scenes::{CartOnRail, SlidingBox, Table};
use support::{Scale, Series, line_plot, plot_path};

type V3 = SVector<f64, 3>;
type V4 = SVector<f64, 4>;
type V6 = SVector<f64, 6>;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let method = Method::Dopri5(Options {
        max_steps: 1_000_000,
        ..Options::tolerances(1e-10, 1e-12)
    });

    // A box resting on a 0.3 rad incline with μ = 0.5 (friction angle 0.464 rad).
    let incline = SlidingBox {
        phi: 0.3,
        ..SlidingBox::default()
    };
    let q0 = V3::from([
        -incline.b * incline.phi.sin(),
        incline.b * incline.phi.cos(),
        incline.phi,
    ]);
    let p = NonSmoothProblem::new(0.0, 1e4, q0, V3::zeros());
    let sol = contact_event_driven(&incline, &Unforced, &p, &method)?;
    let moved = sol
        .rows()
        .map(|(_, y)| (0..3).map(|j| (y[j] - q0[j]).abs()).fold(0.0, f64::max))
        .fold(0.0, f64::max);
    println!("box on a 0.3 rad incline, μ = 0.5, 10⁴ s: largest displacement {moved:e} m");

    // A cart on a rail, its pendulum released at 1.2 rad.
    let cart = CartOnRail::default();
    let p = NonSmoothProblem::new(0.0, 3.0, V4::from([0.0, cart.b, 0.0, 1.2]), V4::zeros());
    let sol = contact_event_driven(&cart, &Unforced, &p, &method)?;
    let col = |name: &str| sol.column(name).expect("a force column");
    let (rear, front) = (col("λ_rear.n"), col("λ_front.n"));
    let (rear_t, front_t) = (col("λ_rear.x"), col("λ_front.x"));
    let times = sol.times();
    let load: Vec<(f64, f64)> = times
        .iter()
        .zip(rear.iter().zip(&front))
        .map(|(&t, (r, f))| (t, r + f))
        .collect();
    let friction: Vec<(f64, f64)> = times
        .iter()
        .zip(rear_t.iter().zip(&front_t))
        .map(|(&t, (r, f))| (t, (r + f).abs()))
        .collect();
    let limit: Vec<(f64, f64)> = load.iter().map(|&(t, n)| (t, cart.mu * n)).collect();
    let weight = (cart.mc + cart.mp) * cart.g;
    let switches = sol
        .switches
        .iter()
        .filter(|s| s.kind == SwitchKind::Mode)
        .count();
    let (lo, hi) = load
        .iter()
        .skip(1)
        .fold((f64::MAX, f64::MIN), |(lo, hi), &(_, n)| {
            (lo.min(n), hi.max(n))
        });
    println!(
        "cart on a rail with a pendulum: the skids' load swings between {lo:.2} and {hi:.2} N \
         (weight {weight:.2} N); {switches} stick/slip switches; cart ends at x = {:.4} m",
        sol.last().expect("rows").1[0]
    );
    let path = plot_path("contacts_cart_on_rail");
    line_plot(
        &path,
        "Cart on a rail: the skids' load and the rail's friction",
        "t [s]",
        "force [N]",
        &[
            Series::new("load λ_N (both skids)", load),
            Series::new("friction |λ_T|", friction),
            Series::new("limit μ λ_N", limit),
        ],
        Scale::Linear,
        Scale::Linear,
    );
    println!("  plot: {}", path.display());

    // A table sliding and spinning on three legs: spatial contacts, time-stepping.
    let table = Table::default();
    let p = NonSmoothProblem::new(
        0.0,
        1.0,
        V6::from([0.0, 0.0, table.d, 0.0, 0.0, 0.0]),
        V6::from([1.2, -0.7, 0.0, 4.0, 0.0, 0.0]),
    );
    let sol = contact_time_stepping(&table, &Unforced, &p, 1e-4)?;
    let stopped = sol
        .rows()
        .find(|(_, y)| y[6..12].iter().all(|&v| v == 0.0))
        .map(|(t, _)| t);
    let (_, last) = sol.last().expect("rows");
    println!(
        "table launched sliding and spinning (h = 1e-4): at rest from t = {:.4} s at x = {:.4}, y = {:.4}, \
         turned {:.4} rad; the cone problems solved to a residual of {:.1e} ({:.1} sweeps per step)",
        stopped.unwrap_or(f64::NAN),
        last[0],
        last[1],
        last[3],
        sol.stats.contact_residual,
        sol.stats.contact_sweeps as f64 / sol.stats.steps as f64
    );
    Ok(())
}
