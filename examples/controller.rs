//! A digital controller driving a non-smooth run: a cart on a rail with Coulomb friction
//! and a stop at each end, a pendulum on it with a Bingham dash-pot at its hinge, and a
//! PD controller that samples the cart every millisecond and holds its force in between
//! (a zero-order hold). The loop is the step-level `Integrator`: `set_input` at each
//! sample, `advance_to` the next.
//!
//! Run: `cargo run --release --example controller`. Prints the switches and writes the
//! run, its switch log and a plot to `target/controller/`.

use std::fs::File;
use std::io::BufWriter;
use std::path::Path;

use filippov::prelude::*;
use filippov::runtime::nonsmooth::Integrator;
use filippov::runtime::{Method, NonSmoothMethod, NonSmoothProblem, Options};
use plotters::prelude::*;

#[derive(Mechanism)]
#[mechanism(gravity = [0.0, -g, 0.0], inputs = [x])]
#[body(cart, mass = m_cart, com = [0.0, 0.0, 0.0], inertia = point)]
#[joint(x: prismatic(x), parent = world, child = cart)]
#[body(pole, mass = m_pole, com = [l / 2.0, 0.0, 0.0], inertia = rod(m_pole, l))]
#[joint(phi: revolute(z), parent = cart, child = pole)]
#[friction(x, f_crit = rail_friction)]
#[bingham(phi, f_crit = hinge_yield, eta = hinge_eta)]
#[stop(x, min = -0.4, max = 0.4, restitution = 0.3)]
struct CartPendulum {
    g: f64,
    m_cart: f64,
    m_pole: f64,
    l: f64,
    rail_friction: f64,
    hinge_yield: f64,
    hinge_eta: f64,
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let scene = CartPendulum {
        g: 9.81,
        m_cart: 1.0,
        m_pole: 0.3,
        l: 0.6,
        rail_friction: 0.8,
        hinge_yield: 0.02,
        hinge_eta: 0.01,
    };
    // Hanging at rest (φ = −π/2), the cart at the middle of the rail.
    let q0 = SVector::<f64, 2>::new(0.0, -std::f64::consts::FRAC_PI_2);
    let problem = NonSmoothProblem::new(0.0, 4.0, q0, SVector::zeros());
    let method = NonSmoothMethod::EventDriven(Method::Dopri5(Options::tolerances(1e-9, 1e-11)));
    let mut run = Integrator::held(&scene, &problem, &method)?;

    // The controller: PD on the cart's position towards a set-point that steps from
    // 0.2 m to −0.45 m (beyond the stop at −0.4 m: the cart ends on it) at t = 2 s.
    let (kp, kd, sample) = (30.0, 4.0, 1e-3);
    let samples = (problem.tf / sample).round() as usize;
    for k in 0..samples {
        let t = k as f64 * sample;
        let target = if t < 2.0 { 0.2 } else { -0.45 };
        let u = kp * (target - run.q()[0]) - kd * run.v()[0];
        run.set_input(CartPendulum::input_forces(&SVector::from([u])))?;
        run.advance_to(((k + 1) as f64 * sample).min(problem.tf))?;
    }
    let solution = run.into_solution();

    println!(
        "{} rows, {} steps, {} switches:",
        solution.len(),
        solution.stats.steps,
        solution.switches.len()
    );
    for s in &solution.switches {
        println!(
            "  t = {:.6} s  {:<14} {:?}: {:?} → {:?}",
            s.t,
            s.element.as_deref().unwrap_or("-"),
            s.kind,
            s.from,
            s.to
        );
    }
    let (t, y) = solution.last().expect("a run keeps its first row");
    println!("at t = {t}: x = {:.6} m, φ = {:.6} rad", y[0], y[1]);

    let dir = Path::new("target/controller");
    std::fs::create_dir_all(dir)?;
    solution.write_csv(BufWriter::new(File::create(dir.join("run.csv"))?))?;
    solution.write_switches_csv(BufWriter::new(File::create(dir.join("switches.csv"))?))?;
    plot(&solution, &dir.join("run.svg"))?;
    println!("wrote {}/{{run.csv, switches.csv, run.svg}}", dir.display());
    Ok(())
}

/// The cart's position and the rail's friction force over time.
fn plot(
    solution: &filippov::runtime::Solution,
    path: &Path,
) -> Result<(), Box<dyn std::error::Error>> {
    let x = solution.column("q_x").expect("the cart's coordinate");
    let f = solution
        .column("f_friction_x")
        .expect("the rail's friction force");
    let times = solution.times();
    let root = SVGBackend::new(path, (900, 600)).into_drawing_area();
    root.fill(&WHITE)?;
    let (upper, lower) = root.split_vertically(300);
    let t_end = *times.last().unwrap_or(&1.0);
    for (area, values, label) in [
        (&upper, &x, "cart position x [m]"),
        (&lower, &f, "rail friction force [N]"),
    ] {
        let (lo, hi) = values
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                (a.min(v), b.max(v))
            });
        let pad = 0.05 * (hi - lo).max(1e-9);
        let mut chart = ChartBuilder::on(area)
            .margin(10)
            .x_label_area_size(30)
            .y_label_area_size(60)
            .build_cartesian_2d(0.0..t_end, (lo - pad)..(hi + pad))?;
        chart
            .configure_mesh()
            .x_desc("t [s]")
            .y_desc(label)
            .draw()?;
        chart.draw_series(LineSeries::new(
            times.iter().copied().zip(values.iter().copied()),
            &BLUE,
        ))?;
    }
    root.present()?;
    Ok(())
}
