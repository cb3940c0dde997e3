//! Theory S9: the 7-dof arm with joint Coulomb friction and joint stops, event-driven.
//! Reference: the energy balance `ΔE = work in − friction dissipation − impact losses`
//! (each term computed independently of the integrator: `E` from the generated energies,
//! the work from the applied torques, the dissipation from `f_crit |v|`, impact losses
//! from the switch log's impulses and the mass matrix, never from the rows' energy
//! jumps), with every element's power `f·v ≥ 0`; and time-stepping converging to the
//! event-driven run.

#[path = "../examples/support/s9.rs"]
mod s9;

use filippov::runtime::{Method, NonSmoothMethod, Options};
use filippov_scenes::PandaS9;
use s9::{s9_balance, s9_run};

#[test]
fn s9_energy_balance_event_driven() {
    let arm = PandaS9::default();
    let method = NonSmoothMethod::EventDriven(Method::Dopri5(Options::tolerances(1e-10, 1e-12)));
    let traj = s9_run(&arm, 2.0, &method).expect("S9 integrates");
    let b = s9_balance(&arm, &traj, 16);
    assert!(
        b.impacts >= 1,
        "the run must rebound from a joint stop ({} impacts)",
        b.impacts
    );
    assert_eq!(
        b.handovers, 0,
        "a hand-over's impacts are not logged: the balance needs a run without"
    );
    assert!(
        traj.stats.events >= 3,
        "stick–slip or contact events: {}",
        traj.stats
    );
    assert!(b.friction_dissipation > 0.0 && b.work_in.abs() > 0.0);
    assert!(
        b.impact_loss > 0.0,
        "restitution 0.5 loses energy at impacts: {}",
        b.impact_loss
    );
    assert!(
        b.min_element_power >= -1e-9,
        "friction must dissipate: f·v = {}",
        b.min_element_power
    );
    assert!(
        b.relative_residual < 1e-6,
        "energy balance residual {:.3e} (work {:.4}, friction {:.4}, impacts {:.4})",
        b.relative_residual,
        b.work_in,
        b.friction_dissipation,
        b.impact_loss
    );
}

/// Moreau time-stepping converges to the event-driven run (joint angles at t = 0.5).
/// Bound derived as in the agreement suite: the scheme is first order, so the finer
/// run's own error is estimated as `D / (4 − 1)` from the distance `D` between runs at
/// `h` and `h/4`; event-driven must lie within twice that estimate, plus one step times
/// the velocity jumps of its impacts (time-stepping places an impact only at a step's
/// end), plus event-driven's own accuracy (100·rtol). The steps are in the asymptotic
/// range: at h = 2.5e-4 the arm still decides stick and slip differently where the
/// torques hover near the friction levels.
#[test]
fn s9_time_stepping_approaches_event_driven() {
    const T: f64 = 0.5;
    let arm = PandaS9::default();
    let rtol = 1e-10;
    let tight =
        NonSmoothMethod::EventDriven(Method::Dopri5(Options::tolerances(rtol, 1e-2 * rtol)));
    let reference = s9_run(&arm, T, &tight).expect("event-driven");
    let q_ref = reference.last().expect("rows").1[..7].to_vec();
    let q_at = |h: f64| {
        let traj = s9_run(&arm, T, &NonSmoothMethod::TimeStepping { h, theta: 1.0 })
            .expect("time-stepping");
        traj.last().expect("rows").1[..7].to_vec()
    };
    let dist = |a: &[f64], b: &[f64]| {
        a.iter()
            .zip(b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max)
    };
    let h = 1.5625e-5;
    let (coarse, fine) = (q_at(4.0 * h), q_at(h));
    let estimate = dist(&coarse, &fine) / 3.0;
    let times = reference.times();
    let jumps = (0..7)
        .map(|c| {
            (1..times.len())
                .filter(|&i| times[i] == times[i - 1])
                .map(|i| (reference.state(i)[7 + c] - reference.state(i - 1)[7 + c]).abs())
                .sum::<f64>()
        })
        .fold(0.0, f64::max);
    let distance = dist(&fine, &q_ref);
    let allowed = 2.0 * estimate + h * jumps + 100.0 * rtol;
    println!(
        "S9: event-driven {distance:.3e} from time-stepping at h = {h:e}, whose error is estimated at {estimate:.3e}; allowed {allowed:.3e} (impacts' velocity jumps {jumps:.3})"
    );
    assert!(
        distance <= allowed,
        "event-driven is {distance:.3e} from time-stepping at h = {h:e}; allowed {allowed:.3e}"
    );
}
