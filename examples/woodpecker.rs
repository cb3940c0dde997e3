//! The woodpecker toy (Glocker's benchmark, theory §8): a sleeve with play on a pole, a
//! bird on a torsion spring, the beak pecking the pole; the sleeve jams on the pole by
//! friction and slips down a little at each peck.
//!
//! The published linearised model (`examples/support/woodpecker.rs`, written against
//! the runtime's traits) from the published state, integrated event-driven and by
//! time-stepping, beside Siconos's reference run of the same model. Prints the beak's
//! impacts and the largest differences; plots the bird's angle and the descent.
//! Run: `cargo run --release --example woodpecker`.

#[path = "support/mod.rs"]
mod support;
#[path = "support/woodpecker.rs"]
mod woodpecker;

use filippov::nalgebra::SVector;
use filippov::runtime::{
    Method, NonSmoothProblem, Options, Solution, SwitchKind, Unforced, contact_event_driven,
    contact_time_stepping,
};
use support::{Scale, Series, line_plot, plot_path};
use woodpecker::{GLOCKER, PUBLISHED_START, largest_difference, siconos_reference};

type V3 = SVector<f64, 3>;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let (q0, v0) = PUBLISHED_START;
    let p = NonSmoothProblem::new(0.0, 0.3, V3::from(q0), V3::from(v0));
    let method = Method::Dopri5(Options {
        max_steps: 1_000_000,
        ..Options::tolerances(1e-10, 1e-13)
    });
    let start = std::time::Instant::now();
    let ed = contact_event_driven(&GLOCKER, &Unforced, &p, &method)?;
    let ed_time = start.elapsed();
    let h = 1e-5;
    let start = std::time::Instant::now();
    let ts = contact_time_stepping(&GLOCKER, &Unforced, &p, h)?;
    let ts_time = start.elapsed();
    let reference = siconos_reference();

    println!(
        "event-driven (rtol 1e-10): {} switches in {ed_time:.2?}",
        ed.switches.len()
    );
    for s in &ed.switches {
        let kind = match s.kind {
            SwitchKind::Impact => "impact",
            SwitchKind::Settled => "settles",
            _ => "mode",
        };
        println!(
            "  t = {:.6} s  {:>8}  {kind:<8} {:?} → {:?}",
            s.t,
            s.element.as_deref().unwrap_or("-"),
            s.from,
            s.to
        );
    }
    println!("time-stepping (h = {h:e}): {ts_time:.2?}");
    for (name, sol) in [("event-driven", &ed), ("time-stepping", &ts)] {
        let d = largest_difference(sol, None);
        println!(
            "{name} against Siconos (Moreau–Jean, h = 2e-5): |Δy| ≤ {:.2e} m, |Δφ_M| ≤ {:.2e} rad, |Δφ_S| ≤ {:.2e} rad",
            d[0], d[1], d[2]
        );
    }
    let (t_end, q_end, _) = *reference.last().expect("rows");
    println!(
        "descent by t = {t_end}: {:.6} m event-driven, {:.6} m Siconos",
        -ed.at(t_end).expect("inside")[0],
        -q_end[0]
    );

    let curve = |sol: &Solution, i: usize| -> Vec<(f64, f64)> {
        (0..=600)
            .map(|j| {
                let t = 0.3 * j as f64 / 600.0;
                (t, sol.at(t).expect("inside the run")[i])
            })
            .collect()
    };
    let theirs =
        |i: usize| -> Vec<(f64, f64)> { reference.iter().map(|r| (r.0, r.1[i])).collect() };
    for (i, name, label, title) in [
        (
            2,
            "woodpecker_bird",
            "φ_S [rad]",
            "Woodpecker: the bird's angle",
        ),
        (
            0,
            "woodpecker_descent",
            "y [m]",
            "Woodpecker: the sleeve's height",
        ),
    ] {
        let path = plot_path(name);
        line_plot(
            &path,
            title,
            "t [s]",
            label,
            &[
                Series::new("event-driven", curve(&ed, i)),
                Series::new(format!("time-stepping, h = {h:e}"), curve(&ts, i)),
                Series::new("Siconos, Moreau–Jean h = 2e-5", theirs(i)),
            ],
            Scale::Linear,
            Scale::Linear,
        );
        println!("  plot: {}", path.display());
    }
    Ok(())
}
