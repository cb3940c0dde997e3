//! Resting contact: an arm under gravity that falls onto its joint limit and comes to rest
//! there — the most common state of a robot arm — and a ball settling on a floor.

mod common;

#[path = "../examples/support/resting_arm.rs"]
mod resting_arm;
#[path = "../examples/support/supported_arm.rs"]
mod supported_arm;

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

mod energy_balance {
    use filippov::Energy;
    use filippov::runtime::Solution;

    use super::supported_arm::{SupportedArm, V3};

    /// Kinetic, gravitational and support energy of state `y = [q; v; …]`.
    pub fn energy(arm: &SupportedArm, y: &[f64]) -> f64 {
        let q = V3::from_column_slice(&y[..3]);
        let v = V3::from_column_slice(&y[3..6]);
        let pen = (arm.lim - q[0]).max(0.0);
        arm.kinetic_energy(&q, &v) + arm.potential_energy(&q) + 0.5 * arm.ks * pen * pen
    }

    /// The work the elbow's friction has dissipated, `∫ f v dt` over the solution.
    pub fn dissipated(sol: &Solution) -> f64 {
        let f = sol.column_index("f_friction_elbow").unwrap();
        let v = sol.column_index("v_elbow").unwrap();
        super::common::integral(sol, &|_, y| y[f] * y[v])
    }
}

/// The arm resting on a spring-backed limit with a stiff support (`k_support` from 1e3
/// to 1e12), started at the support's static compression under gravity, or on the limit
/// with the support uncompressed, with the wrist off its hanging pose (it swings, the
/// load on the support varies, the elbow sticks or slips): the default method
/// completes — for `k ≥ 1e5` in fewer steps than time-stepping at h = 1e-3, as the
/// support's vibration is not followed for more than a hundred periods — and at
/// rtol 1e-10 the energy balance closes (kinetic + gravity + support energy + the
/// friction's dissipated work) to 1e-8 of the energy scale. Where the stop rests at the
/// end, the coordinate sits at the static compression of the force it carries.
#[test]
fn arm_rests_on_a_stiff_spring_backed_limit() {
    use filippov::runtime::nonsmooth::RESTING_DRIFT;
    use filippov::runtime::{Method, Mode, NonSmoothMethod, Options};
    use supported_arm::{SupportedArm, V3, zero};
    for ks in [1e3, 1e4, 1e5, 1e6, 1e7, 1e9, 1e12] {
        for (fc, wrist, on_limit) in [
            (10.0, 0.5, false),
            (2.0, 0.0, false),
            (2.0, 0.5, false),
            (2.0, 0.5, true),
        ] {
            let arm = SupportedArm::new(fc, ks);
            let mut q0 = arm.static_start(wrist);
            if on_limit {
                // Where a user would start it: on the limit, the support uncompressed.
                q0[0] = arm.lim;
            }
            let p = NonSmoothProblem::new(0.0, 2.0, q0, V3::zeros());
            let case =
                format!("k_support = {ks:e}, fc = {fc}, wrist {wrist}, on the limit {on_limit}");
            let sol = solve_nonsmooth(&arm, &zero, &p, &NonSmoothMethod::default())
                .unwrap_or_else(|err| panic!("{case}: {err}"));
            let ts = solve_nonsmooth(
                &arm,
                &zero,
                &p,
                &NonSmoothMethod::TimeStepping {
                    h: 1e-3,
                    theta: 1.0,
                },
            )
            .unwrap();
            eprintln!(
                "{case}: default {} steps, {} switches; time-stepping {} steps",
                sol.stats.steps,
                sol.switches.len(),
                ts.stats.steps
            );
            if ks >= 1e5 {
                assert!(sol.stats.steps < ts.stats.steps, "{case}: {}", sol.stats);
            }
            let tight =
                NonSmoothMethod::EventDriven(Method::Dopri5(Options::tolerances(1e-10, 1e-12)));
            let sol = solve_nonsmooth(&arm, &zero, &p, &tight)
                .unwrap_or_else(|err| panic!("{case}, rtol 1e-10: {err}"));
            let e0 = energy_balance::energy(&arm, sol.state(0));
            let scale = e0.abs().max(arm.m * 9.81 * arm.l);
            let (t1, y1) = sol.last().unwrap();
            // Resting drops the support's vibration (at most λ²/2k each time a stop
            // comes to rest) and reports what it dropped.
            let dropped = sol.stats.resting_energy_dropped;
            let balance =
                energy_balance::energy(&arm, y1) + energy_balance::dissipated(&sol) + dropped - e0;
            eprintln!(
                "  rtol 1e-10: balance {:.2e} of {scale:.2}, resting dropped {:.2e}",
                balance / scale,
                dropped / scale
            );
            let entries = sol
                .switches
                .iter()
                .filter(|s| s.to == Some(Mode::Contact))
                .count() as f64;
            let lambda_max = 3.0 * arm.m * 9.81 * 2.0 * arm.l;
            assert!(
                dropped >= -1e-8 * scale
                    && dropped <= entries * lambda_max.powi(2) / (2.0 * ks) + 1e-8 * scale,
                "{case}: dropped {dropped:e} in {entries} rests"
            );
            assert!(balance.abs() <= 1e-8 * scale, "{case}: balance {balance:e}");
            assert_eq!(t1, 2.0);
            // Resting at the end: held at the static compression of its force.
            let stop = sol.column_index("f_stop_shoulder").unwrap();
            let resting = sol
                .switches
                .iter()
                .rev()
                .find(|s| s.element.as_deref() == Some("stop_shoulder"))
                .is_some_and(|s| s.to == Some(Mode::Contact));
            if resting {
                // Within the documented lag: RESTING_DRIFT of the compression, or the
                // position tolerance.
                let lambda = (-y1[stop]).max(0.0);
                let static_q = arm.lim - lambda / ks;
                let lag = (1e-12 + 1e-10 * y1[0].abs()).max(RESTING_DRIFT * lambda / ks);
                assert!(
                    (y1[0] - static_q).abs() <= lag * (1.0 + 1e-9),
                    "{case}: q = {} against {static_q}",
                    y1[0]
                );
            }
        }
    }
}
