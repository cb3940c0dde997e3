//! The README's example, verbatim, so that it keeps compiling.

use filippov::prelude::*;
use filippov::runtime::{MechanicalSystem, Method, Options, Problem, solve};

#[derive(Mechanism)]
#[mechanism(gravity = [0.0, -9.81, 0.0])]
#[body(upper, mass = m1, com = [l1 / 2.0, 0.0, 0.0], inertia = rod(m1, l1))]
#[joint(shoulder: revolute(z), parent = world, child = upper)]
#[body(lower, mass = m2, com = [l2 / 2.0, 0.0, 0.0], inertia = rod(m2, l2))]
#[joint(elbow: revolute(z), parent = upper, child = lower, origin = [l1, 0.0, 0.0])]
#[damper(elbow, c = 0.05)]
struct DoublePendulum {
    m1: f64,
    l1: f64,
    m2: f64,
    l2: f64,
}

fn main() {
    let p = DoublePendulum {
        m1: 1.0,
        l1: 1.0,
        m2: 0.5,
        l2: 0.7,
    };
    let q = SVector::<f64, 2>::new(0.3, -0.2);
    let m = p.mass_matrix(&q); // 2×2, straight-line code
    let sys = MechanicalSystem::unforced(&p); // y = [q; v]
    let traj = solve(
        &sys,
        &Problem::new(0.0, 10.0, [1.2, -0.6, 0.0, 0.0]),
        &Method::Dopri5(Options::tolerances(1e-9, 1e-11)),
    )
    .unwrap();
    println!(
        "{m}\n{} steps, q(10) = {:?}",
        traj.stats.steps,
        &traj.last().unwrap().1[..2]
    );
}
