//! Resting contact: an arm under gravity that falls onto its joint limit and comes to rest
//! there — the most common state of a robot arm — and a ball settling on a floor.

#[path = "../examples/support/resting_arm.rs"]
mod resting_arm;

use filippov::runtime::{NonSmoothMethod, NonSmoothProblem, solve_nonsmooth};
use resting_arm::{RestingArm, V2, zero};

/// The arm released above its limit settles on it: event-driven (default method and
/// options) completes — the last bounces, too small to see, settle into contact instead
/// of re-impacting at ~1e-10 rad/s until the step budget runs out — ends at rest exactly
/// on the limit, and time-stepping converges to its end state.
#[test]
fn arm_comes_to_rest_on_its_joint_limit() {
    for (e, fc) in [(0.3, 20.0), (0.9, 20.0), (0.99, 20.0), (0.5, 2.0)] {
        let arm = RestingArm {
            m1: 1.0,
            l1: 1.0,
            m2: 0.5,
            l2: 0.7,
            fc,
            lim: -1.0,
            e,
        };
        let p = NonSmoothProblem::new(0.0, 5.0, V2::new(0.2, -0.5), V2::zeros());
        let sol = solve_nonsmooth(&arm, &zero, &p, &NonSmoothMethod::default())
            .unwrap_or_else(|err| panic!("e = {e}: {err}"));
        let (_, y) = sol.last().unwrap();
        eprintln!(
            "e = {e}, fc = {fc}: {} ({} switches), end {y:?}",
            sol.stats,
            sol.switches.len()
        );
        assert_eq!(y[0], -1.0, "e = {e}: on the limit");
        assert_eq!(y[2], 0.0, "e = {e}: at rest");
        // Time-stepping converges to the event-driven end state (first order).
        let dist = |h: f64| {
            let ts = solve_nonsmooth(
                &arm,
                &zero,
                &p,
                &NonSmoothMethod::TimeStepping { h, theta: 1.0 },
            )
            .unwrap();
            let z = ts.last().unwrap().1.to_vec();
            (z[0] - y[0]).abs().max((z[1] - y[1]).abs())
        };
        let (d3, d4) = (dist(1e-3), dist(1e-4));
        eprintln!("  time-stepping end-state distance: h = 1e-3 {d3:.2e}, 1e-4 {d4:.2e}");
        assert!(d4 < 1e-2 && d4 < 0.2 * d3, "e = {e}: {d3:e} → {d4:e}");
    }
}
