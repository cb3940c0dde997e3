//! A robot arm from its URDF file (`robots/three_link_arm.urdf`), with the file's joint
//! limits as stops and its joint friction and damping as elements, released under
//! gravity: it falls onto the shoulder's limit, the elbow and wrist stick under their
//! friction, and it comes to rest. Prints the switch log and the end state; plots the
//! joint angles.
//!
//! Run: `cargo run --release --example urdf_arm` (event-driven, the default method), or
//! `… -- 1e-10` for event-driven DOPRI5 at that rtol, `… -- ts [h]` for
//! time-stepping (h = 1e-3 unless given); plot and switch log in `target/plots/`.

#[path = "support/mod.rs"]
mod support;

#[path = "support/urdf_arm.rs"]
mod urdf_arm;
use filippov::nalgebra::SVector;
use filippov::prelude::*;
use filippov::runtime::{NonSmoothMethod, NonSmoothProblem, solve_nonsmooth};
use urdf_arm::Arm;

type V3 = SVector<f64, 3>;

fn main() {
    println!("joints {:?}", Arm::JOINTS);
    println!("non-smooth elements {:?}", Arm::NON_SMOOTH_ELEMENTS);
    // Released horizontal, at rest.
    let p = NonSmoothProblem::new(0.0, 4.0, V3::new(0.0, 0.2, -0.3), V3::zeros());
    let zero = |_t: f64, _q: &V3, _v: &V3| V3::zeros();
    let method = match std::env::args().nth(1).as_deref() {
        Some("ts") => NonSmoothMethod::TimeStepping {
            h: std::env::args()
                .nth(2)
                .and_then(|h| h.parse().ok())
                .unwrap_or(1e-3),
            theta: 1.0,
        },
        Some(arg) => match arg.parse::<f64>() {
            Ok(rtol) => NonSmoothMethod::EventDriven(filippov::runtime::Method::Dopri5(
                filippov::runtime::Options::tolerances(rtol, 1e-3 * rtol),
            )),
            Err(_) => NonSmoothMethod::default(),
        },
        _ => NonSmoothMethod::default(),
    };
    let sol = match solve_nonsmooth(&Arm, &zero, &p, &method) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("failed: {e}");
            std::process::exit(1);
        }
    };
    println!("{}", sol.stats);
    println!("{} switches:", sol.switches.len());
    for s in sol.switches.iter().take(40) {
        println!(
            "  t = {:.6}  {:<22} {:?} → {:?}  jump {:+.4}",
            s.t,
            s.element.as_deref().unwrap_or(&format!("{:?}", s.kind)),
            s.from,
            s.to,
            s.jump
        );
    }
    if sol.switches.len() > 40 {
        println!("  … ({} more)", sol.switches.len() - 40);
    }
    let (t, y) = sol.last().expect("a row");
    println!("end t = {t}: q = {:?}, v = {:?}", &y[..3], &y[3..6]);
    println!(
        "shoulder on its upper limit (0.6): {}; at rest: {}",
        y[0] == 0.6,
        y[3..6].iter().all(|v| *v == 0.0)
    );
    let series = support::time_series(&sol, &["shoulder", "elbow", "wrist"]);
    support::plot_over_time(
        "urdf_arm_angles",
        "three_link_arm.urdf released under gravity: joint angles",
        "q [rad]",
        &series,
    );
    let csv = support::plot_path("urdf_arm_switches").with_extension("csv");
    let written = std::fs::File::create(&csv).and_then(|f| sol.write_switches_csv(f));
    if written.is_ok() {
        println!("wrote {}", csv.display());
    }
}
