//! Theory S9: the 7-dof arm with joint Coulomb friction and joint stops, event-driven.
//! Reference: the energy balance `ΔE = work in − friction dissipation − impact losses`
//! (each term computed independently of the integrator: `E` from the generated energies,
//! the work from the applied torques, the dissipation from `f_crit |v|`, impact losses
//! from the switch log's impulses and the mass matrix, never from the rows' energy
//! jumps), with every element's power `f·v ≥ 0`; and time-stepping converging to the
//! event-driven run.

#[path = "../examples/support/s9.rs"]
mod s9;

use filippov::runtime::{NonSmoothMethod, Options, SmoothMethod};
use filippov_scenes::PandaS9;
use s9::{s9_balance, s9_run};

#[test]
fn s9_energy_balance_event_driven() {
    let arm = PandaS9::default();
    let method = NonSmoothMethod::EventDriven {
        method: SmoothMethod::Dopri5,
        options: Options::tolerances(1e-10, 1e-12),
    };
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

/// Moreau time-stepping converges to the event-driven run (final joint angles at t = 1).
#[test]
fn s9_time_stepping_approaches_event_driven() {
    const T: f64 = 0.5;
    let arm = PandaS9::default();
    let tight = NonSmoothMethod::EventDriven {
        method: SmoothMethod::Dopri5,
        options: Options::tolerances(1e-10, 1e-12),
    };
    let reference = s9_run(&arm, T, &tight).expect("event-driven");
    let q_ref = reference.last().expect("rows").1[..7].to_vec();
    let err = |h: f64| {
        let traj = s9_run(&arm, T, &NonSmoothMethod::TimeStepping { h, theta: 1.0 })
            .expect("time-stepping");
        let q = &traj.last().expect("rows").1[..7];
        q.iter()
            .zip(&q_ref)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max)
    };
    // Moreau is first order. Coarse steps decide stick/slip differently where the
    // torques hover near the friction levels (at h = 2.5e-4 the error is still O(0.1)),
    // so compare in the asymptotic range: a 4× finer step must cut the error by 4^p,
    // p ∈ [0.66, 1.5].
    let (coarse, fine) = (err(6.25e-5), err(1.5625e-5));
    let ratio = coarse / fine;
    assert!(
        (2.5..=8.0).contains(&ratio),
        "not first-order convergence: {coarse:.3e} → {fine:.3e} (ratio {ratio:.2})"
    );
}
