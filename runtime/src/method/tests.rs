//! Reference problems against closed forms, convergence orders, stiffness, failures.

use super::*;
use crate::{ErrorKind, FnSystem, OdeSystem, Options, Problem, Solution, solve};

fn oscillator() -> FnSystem<impl Fn(f64, &[f64], &mut [f64])> {
    FnSystem::new(2, |_t, y: &[f64], dy: &mut [f64]| {
        dy[0] = y[1];
        dy[1] = -y[0];
    })
}

fn oscillator_error(traj: &Solution) -> f64 {
    let (t, y) = traj.last().unwrap();
    ((y[0] - t.cos()).powi(2) + (y[1] + t.sin()).powi(2)).sqrt()
}

#[test]
fn harmonic_oscillator_all_methods() {
    let problem = Problem::new(0.0, 10.0, [1.0, 0.0]);
    let tight = Options::tolerances(1e-10, 1e-12);
    for (method, tol) in [
        (Method::Rk4 { h: 0.01 }, 1e-8),
        (Method::Dopri5(tight), 1e-8),
        (Method::Sdirk4(tight), 1e-7),
    ] {
        let traj = solve(&oscillator(), &problem, &method).unwrap();
        assert_eq!(traj.last().unwrap().0, 10.0);
        let err = oscillator_error(&traj);
        assert!(err < tol, "{method:?}: error {err:e}, {}", traj.stats);
        // Dense output between the steps, for every method.
        for t in [0.123, 3.3, 7.77] {
            let y = traj.at(t).unwrap();
            assert!((y[0] - t.cos()).abs() < 1e2 * tol, "{method:?} at {t}");
        }
    }
}

#[test]
fn rk4_converges_with_order_four() {
    let problem = Problem::new(0.0, 2.0, [1.0, 0.0]);
    let err = |h: f64| {
        oscillator_error(
            &crate::solve(&oscillator(), &problem, &crate::Method::Rk4 { h: h }).unwrap(),
        )
    };
    let (e1, e2) = (err(0.1), err(0.05));
    let order = (e1 / e2).log2();
    assert!((order - 4.0).abs() < 0.15, "measured order {order}");
}

#[test]
fn dopri5_error_decreases_with_tolerance() {
    let problem = Problem::new(0.0, 10.0, [1.0, 0.0]);
    let mut previous = f64::INFINITY;
    let mut steps = 0;
    for tol in [1e-4, 1e-6, 1e-8, 1e-10] {
        let traj = crate::solve(
            &oscillator(),
            &problem,
            &crate::Method::Dopri5(Options::tolerances(tol, tol)),
        )
        .unwrap();
        let err = oscillator_error(&traj);
        assert!(
            err < previous / 5.0,
            "tol {tol:e}: error {err:e} vs {previous:e}"
        );
        assert!(err < 100.0 * tol);
        assert!(traj.stats.steps > steps);
        previous = err;
        steps = traj.stats.steps;
        // FSAL: 6 new evaluations per attempt, plus the first f and the initial-step probe.
        let s = traj.stats;
        assert_eq!(s.rhs_evaluations, 6 * (s.steps + s.rejected_steps) + 2);
    }
}

#[test]
fn dopri5_dense_output_is_accurate_between_steps() {
    let problem = Problem::new(0.0, 10.0, [1.0, 0.0]);
    let traj = crate::solve(
        &oscillator(),
        &problem,
        &crate::Method::Dopri5(Options::tolerances(1e-9, 1e-12)),
    )
    .unwrap();
    let worst = (0..1000)
        .map(|i| {
            let t = i as f64 * 0.01;
            (traj.at(t).unwrap()[0] - t.cos()).abs()
        })
        .fold(0.0, f64::max);
    assert!(worst < 1e-7, "worst dense error {worst:e}");
}

/// Van der Pol `x'' − μ(1 − x²)x' + x = 0` with μ = 1000 (Hairer & Wanner II, §IV.1):
/// from x = 2 it creeps along the slow manifold (period ≈ 1614), with a fast
/// eigenvalue ≈ −μ(x² − 1).
fn van_der_pol(mu: f64) -> FnSystem<impl Fn(f64, &[f64], &mut [f64])> {
    FnSystem::new(2, move |_t, y: &[f64], dy: &mut [f64]| {
        dy[0] = y[1];
        dy[1] = mu * (1.0 - y[0] * y[0]) * y[1] - y[0];
    })
}

#[test]
fn sdirk4_solves_stiff_van_der_pol_in_far_fewer_steps_than_dopri5() {
    let problem = Problem::new(0.0, 20.0, [2.0, 0.0]);
    let options = Options {
        max_steps: 1_000_000,
        ..Options::tolerances(1e-6, 1e-6)
    };
    let stiff = crate::solve(
        &van_der_pol(1000.0),
        &problem,
        &crate::Method::Sdirk4(options),
    )
    .unwrap();
    let explicit = crate::solve(
        &van_der_pol(1000.0),
        &problem,
        &crate::Method::Dopri5(options),
    )
    .unwrap();
    let (ys, ye) = (stiff.last().unwrap().1, explicit.last().unwrap().1);
    assert!((ys[0] - ye[0]).abs() < 1e-3, "{ys:?} vs {ye:?}");
    let s = stiff.stats;
    assert!(s.steps < 200, "SDIRK4: {s}");
    assert!(
        50 * s.steps < explicit.stats.steps,
        "SDIRK4 {s}; DOPRI5 {}",
        explicit.stats
    );
    // No analytic Jacobian: every Jacobian came from finite differences, with reuse.
    assert_eq!(s.jacobian_evaluations, s.finite_difference_jacobians);
    assert!(s.jacobian_evaluations <= s.steps + s.rejected_steps);
    assert!(s.newton_iterations > 0 && s.lu_factorisations > 0);
}

/// A system with an analytic Jacobian: no finite differences are taken.
struct LinearStiff;

impl OdeSystem for LinearStiff {
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&self, _t: f64, y: &[f64], dy: &mut [f64]) {
        dy[0] = -1e4 * (y[0] - y[1].cos());
        dy[1] = 1.0;
    }
    fn jacobian(&self, _t: f64, y: &[f64], jac: &mut nalgebra::DMatrix<f64>) -> bool {
        jac[(0, 0)] = -1e4;
        jac[(0, 1)] = -1e4 * y[1].sin();
        jac[(1, 0)] = 0.0;
        jac[(1, 1)] = 0.0;
        true
    }
}

#[test]
fn sdirk4_uses_the_analytic_jacobian() {
    let traj = crate::solve(
        &LinearStiff,
        &Problem::new(0.0, 5.0, [0.0, 0.0]),
        &crate::Method::Sdirk4(Options::tolerances(1e-6, 1e-8)),
    )
    .unwrap();
    let (t, y) = traj.last().unwrap();
    // Slow manifold y0 ≈ cos(t) + 1e-4 sin(t).
    assert!((y[0] - (t.cos() + 1e-4 * t.sin())).abs() < 1e-6);
    assert_eq!(traj.stats.finite_difference_jacobians, 0);
    assert!(traj.stats.jacobian_evaluations > 0);
    // A Prothero–Robinson-type problem: the embedded estimate of an SDIRK (stage
    // order 1) is only O(h²) in the stiff limit, so steps are smaller than on Van der
    // Pol, yet far fewer than the ~15 000 an explicit method needs for stability.
    // This is a property of the method, not of the code: every order-3 embedded
    // formula on these stages gives the same estimate up to a factor
    // (`tableau::tests::sdirk4_error_estimate_is_unique_and_order_reduced_when_stiff`).
    // Measured: 651 steps (and 8 822 at rtol 1e-8); the global error, 5e-8, is well
    // inside the tolerance.
    assert!(traj.stats.steps < 1000, "{}", traj.stats);
}

#[test]
fn nan_rhs_is_reported_with_the_trajectory_kept() {
    let system = FnSystem::new(1, |t, y: &[f64], dy: &mut [f64]| {
        dy[0] = if t > 0.5 { f64::NAN } else { -y[0] };
    });
    let problem = Problem::new(0.0, 1.0, [1.0]);
    for method in [
        Method::Rk4 { h: 0.01 },
        Method::Dopri5(Options::default()),
        Method::Sdirk4(Options::default()),
    ] {
        let err = solve(&system, &problem, &method).unwrap_err();
        let ErrorKind::NonFinite { t, component } = err.kind else {
            panic!("{method:?}: {err}");
        };
        assert!(t > 0.5 && component == 0, "{method:?}: {err}");
        let (t_last, y_last) = err.solution.last().unwrap();
        assert!(t_last <= 0.5 && t_last > 0.3, "{method:?}: last t {t_last}");
        assert!(y_last[0].is_finite());
        assert!(err.to_string().contains("non-finite"));
    }
}

#[test]
fn blow_up_gives_step_size_underflow() {
    // y' = y², y(0) = 1 blows up at t = 1.
    let system = FnSystem::new(1, |_t, y: &[f64], dy: &mut [f64]| dy[0] = y[0] * y[0]);
    let problem = Problem::new(0.0, 2.0, [1.0]);
    let options = Options {
        h_min: 1e-6,
        ..Options::default()
    };
    for method in [Method::Dopri5(options), Method::Sdirk4(options)] {
        let err = solve(&system, &problem, &method).unwrap_err();
        match err.kind {
            ErrorKind::StepSizeUnderflow { t, h } => {
                assert!(t > 0.99 && t < 1.0 && h < 1e-6, "{method:?}: {err}")
            }
            ErrorKind::NewtonDivergence { t } => {
                assert!(matches!(method, Method::Sdirk4(_)) && t > 0.99 && t < 1.0)
            }
            _ => panic!("{method:?}: {err}"),
        }
        assert!(err.solution.len() > 10);
    }
}

#[test]
fn max_steps_is_reported() {
    let options = Options {
        max_steps: 5,
        ..Options::default()
    };
    let err = crate::solve(
        &oscillator(),
        &Problem::new(0.0, 100.0, [1.0, 0.0]),
        &crate::Method::Dopri5(options),
    )
    .unwrap_err();
    assert!(matches!(err.kind, ErrorKind::MaxSteps { .. }));
    assert!(!err.solution.is_empty());
}

#[test]
fn invalid_input_is_an_error_not_a_panic() {
    let good = Problem::new(0.0, 1.0, [1.0, 0.0]);
    let cases: Vec<(Problem, Method)> = vec![
        (
            good.clone(),
            Method::Dopri5(Options::tolerances(-1e-6, 1e-9)),
        ),
        (good.clone(), Method::Sdirk4(Options::tolerances(0.0, 0.0))),
        (
            good.clone(),
            Method::Dopri5(Options {
                h0: Some(-1.0),
                ..Options::default()
            }),
        ),
        (
            good.clone(),
            Method::Dopri5(Options {
                h_max: 0.0,
                ..Options::default()
            }),
        ),
        (good.clone(), Method::Rk4 { h: 0.0 }),
        (good.clone(), Method::Rk4 { h: f64::NAN }),
        (
            Problem::new(1.0, 0.0, [1.0, 0.0]),
            Method::Dopri5(Options::default()),
        ),
        (
            Problem::new(0.0, 1.0, [1.0]),
            Method::Sdirk4(Options::default()),
        ),
        (
            Problem::new(0.0, 1.0, [1.0, f64::NAN]),
            Method::Rk4 { h: 0.1 },
        ),
        (
            Problem::new(0.0, f64::INFINITY, [1.0, 0.0]),
            Method::Dopri5(Options::default()),
        ),
    ];
    for (problem, method) in cases {
        let err = solve(&oscillator(), &problem, &method).unwrap_err();
        assert!(
            matches!(err.kind, ErrorKind::InvalidInput(_)),
            "{problem:?} {method:?}: {err}"
        );
        assert!(err.solution.is_empty());
    }
}

#[test]
fn empty_interval_returns_the_initial_point() {
    let problem = Problem::new(1.0, 1.0, [1.0, 0.0]);
    for method in [
        Method::Rk4 { h: 0.1 },
        Method::Dopri5(Options::default()),
        Method::Sdirk4(Options::default()),
    ] {
        let traj = solve(&oscillator(), &problem, &method).unwrap();
        assert_eq!(traj.len(), 1);
        assert_eq!(traj.at(1.0).unwrap(), vec![1.0, 0.0]);
    }
}

/// Least-squares slope of `log y` against `log x`.
fn log_slope(points: &[(f64, f64)]) -> f64 {
    let n = points.len() as f64;
    let (lx, ly): (Vec<f64>, Vec<f64>) = points.iter().map(|(x, y)| (x.ln(), y.ln())).unzip();
    let (mx, my) = (lx.iter().sum::<f64>() / n, ly.iter().sum::<f64>() / n);
    let sxy: f64 = lx.iter().zip(&ly).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = lx.iter().map(|x| (x - mx).powi(2)).sum();
    sxy / sxx
}

/// Tolerance proportionality on a smooth non-linear problem (Van der Pol, μ = 1): the
/// global error of SDIRK4 must follow the tolerance (slope ≈ 1 in log–log) and, against
/// the number of steps, fall like `N⁻⁴` (observed order 4). The harmonic oscillator is
/// linear, so Newton converges in one iteration there and it cannot show this: with
/// the old Newton stopping tolerance the slope here was ≈ 0.7, the order ≈ 2.9, and the
/// error at `tol = 1e-9` was 80 × the tolerance.
#[test]
fn sdirk4_global_error_is_proportional_to_the_tolerance() {
    let problem = Problem::new(0.0, 2.0, [2.0, 0.0]);
    let reference = crate::solve(
        &van_der_pol(1.0),
        &problem,
        &crate::Method::Dopri5(Options::tolerances(1e-13, 1e-15)),
    )
    .unwrap();
    let r = reference.last().unwrap().1.to_vec();
    let mut by_tol = Vec::new();
    let mut by_steps = Vec::new();
    for tol in [1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9] {
        let traj = crate::solve(
            &van_der_pol(1.0),
            &problem,
            &crate::Method::Sdirk4(Options::tolerances(tol, tol)),
        )
        .unwrap();
        let y = traj.last().unwrap().1;
        let err = ((y[0] - r[0]).powi(2) + (y[1] - r[1]).powi(2)).sqrt();
        eprintln!("tol {tol:e}: error {err:e}, {}", traj.stats);
        assert!(err < 5.0 * tol, "tol {tol:e}: error {err:e}");
        by_tol.push((tol, err));
        by_steps.push((traj.stats.steps as f64, err));
    }
    let slope = log_slope(&by_tol);
    let order = -log_slope(&by_steps);
    eprintln!("error ∝ tol^{slope:.3}, error ∝ steps^-{order:.3}");
    assert!((0.9..=1.1).contains(&slope), "error ∝ tol^{slope}");
    assert!((3.6..=4.6).contains(&order), "observed order {order}");
}

/// Observed orders of an error `f(h)` at h = 0.2, 0.1, 0.05 (two halvings).
fn observed_orders(f: &dyn Fn(f64) -> f64) -> [f64; 2] {
    let e: Vec<f64> = [0.2, 0.1, 0.05].iter().map(|&h| f(h)).collect();
    [(e[0] / e[1]).log2(), (e[1] / e[2]).log2()]
}

fn assert_order(name: &str, expected: f64, measured: [f64; 2], tol: f64) {
    for m in measured {
        assert!(
            (m - expected).abs() < tol,
            "{name}: local dense error order {m:.2}, expected {expected}"
        );
    }
}

/// The dense output of one step from the exact state of `y'' = −y`, evaluated mid-step:
/// its error is the local error of the continuous extension, `O(h^{p+1})` for an
/// extension of order `p` — 4 for DOPRI5's (degree 4), 3 for cubic Hermite (RK4,
/// SDIRK4). Halving `h` must divide it by `2^{p+1}`.
#[test]
fn dense_output_has_the_order_of_its_method() {
    fn midstep_error<St: Stepper>(mut stepper: St, h: f64) -> f64 {
        let sys = oscillator();
        let mut stats = crate::Stats::default();
        let mut ev = Eval::new(&sys, &mut stats);
        let t0: f64 = 0.3;
        let y0 = [t0.cos(), -t0.sin()];
        let at = Begin {
            t: t0,
            y: &y0,
            span: h,
            fresh: true,
        };
        stepper.begin(&mut ev, at).unwrap();
        stepper.step(&mut ev, t0 + h).unwrap();
        assert_eq!(
            stepper.t(),
            t0 + h,
            "{}: one step to the end",
            std::any::type_name::<St>()
        );
        let mut y = [0.0; 2];
        let tm = t0 + 0.5 * h;
        stepper.prepare_dense();
        stepper.dense().eval(tm, &mut y);
        (y[0] - tm.cos()).abs().max((y[1] + tm.sin()).abs())
    }
    // Huge tolerances: the first step is accepted as it is.
    let loose = Options {
        h0: Some(1.0),
        ..Options::tolerances(1e3, 1e3)
    };
    for (name, expected, measured) in [
        (
            "RK4",
            4.0,
            observed_orders(&|h| midstep_error(Rk4::new(h).stepper(2), h)),
        ),
        (
            "DOPRI5",
            5.0,
            observed_orders(&|h| {
                midstep_error(
                    Dopri5::new(Options {
                        h0: Some(h),
                        ..loose
                    })
                    .stepper(2),
                    h,
                )
            }),
        ),
        (
            "SDIRK4",
            4.0,
            observed_orders(&|h| {
                midstep_error(
                    Sdirk4::new(Options {
                        h0: Some(h),
                        ..loose
                    })
                    .stepper(2),
                    h,
                )
            }),
        ),
    ] {
        assert_order(name, expected, measured, 0.3);
    }
}

/// From the second step on, the one-step methods interpolate through the last three
/// points (quintic Hermite, interpolation error `O(h⁶)`): the dense output's error on a
/// step is then that of the points it joins, the method's local error `O(h^{p+1})`.
/// Two equal steps from the exact state of `y'' = −y`, evaluated in the middle of the
/// second: halving `h` must divide the error by `2^{p+1}` (`p` = 4 for RK4 and SDIRK4, 5
/// for DOPRI5, whose own extension on a first step has only local order 5).
#[test]
fn dense_output_after_a_first_step_has_the_local_order_of_its_method() {
    fn midstep_error<St: Stepper>(mut stepper: St, h: f64) -> f64 {
        let sys = oscillator();
        let mut stats = crate::Stats::default();
        let mut ev = Eval::new(&sys, &mut stats);
        let t0: f64 = 0.3;
        let y0 = [t0.cos(), -t0.sin()];
        let at = Begin {
            t: t0,
            y: &y0,
            span: 2.0 * h,
            fresh: true,
        };
        stepper.begin(&mut ev, at).unwrap();
        stepper.step(&mut ev, t0 + 2.0 * h).unwrap();
        stepper.step(&mut ev, t0 + 2.0 * h).unwrap();
        assert!(
            (stepper.t() - (t0 + 2.0 * h)).abs() < 1e-14,
            "{}: two steps to the end",
            std::any::type_name::<St>()
        );
        stepper.prepare_dense();
        assert_eq!(
            stepper.dense().degree(),
            5,
            "{}",
            std::any::type_name::<St>()
        );
        let mut y = [0.0; 2];
        let tm = t0 + 1.5 * h;
        stepper.dense().eval(tm, &mut y);
        (y[0] - tm.cos()).abs().max((y[1] + tm.sin()).abs())
    }
    // Huge tolerances and h_max = h: every step is accepted with the same h.
    let fixed = |h: f64| Options {
        h0: Some(h),
        h_max: h,
        ..Options::tolerances(1e3, 1e3)
    };
    for (name, expected, measured) in [
        (
            "RK4",
            5.0,
            observed_orders(&|h| midstep_error(Rk4::new(h).stepper(2), h)),
        ),
        (
            "DOPRI5",
            6.0,
            observed_orders(&|h| midstep_error(Dopri5::new(fixed(h)).stepper(2), h)),
        ),
        (
            "SDIRK4",
            5.0,
            observed_orders(&|h| midstep_error(Sdirk4::new(fixed(h)).stepper(2), h)),
        ),
    ] {
        assert_order(name, expected, measured, 0.35);
    }
}

/// Between the steps the dense output is as accurate as the steps themselves: on the
/// oscillator, the largest error on a fine grid is within 2× of the largest error at
/// the accepted points, for every method and tolerance.
#[test]
fn grid_error_is_within_twice_the_step_error() {
    let problem = Problem::new(0.0, 10.0, [1.0, 0.0]);
    for rtol in [1e-6, 1e-9] {
        let o = Options::tolerances(rtol, rtol * 1e-2);
        for method in [
            Method::Dopri5(o),
            Method::Sdirk4(o),
            Method::Bdf(o),
            Method::Rk4 { h: 0.05 },
        ] {
            let sol = solve(&oscillator(), &problem, &method).unwrap();
            let err = |t: f64, y: &[f64]| (y[0] - t.cos()).abs().max((y[1] + t.sin()).abs());
            let at_steps = sol.rows().map(|(t, y)| err(t, y)).fold(0.0, f64::max);
            let mut y = [0.0; 2];
            let on_grid = (0..=1000)
                .map(|i| {
                    let t = i as f64 * 0.01;
                    assert!(sol.at_into(t, &mut y));
                    err(t, &y)
                })
                .fold(0.0, f64::max);
            assert!(
                on_grid <= 2.0 * at_steps,
                "{} at rtol {rtol}: grid {on_grid:.2e} vs steps {at_steps:.2e}",
                method.name()
            );
        }
    }
}

/// The torque-free body as a flat ODE in ℝ⁷ (`q̇ = ½ q ⊗ (0, ω)`, `I ω̇ = −ω × I ω`,
/// I = diag(1, 2, 3)) from a tumbling state.
fn quaternion_free_body() -> FnSystem<impl Fn(f64, &[f64], &mut [f64])> {
    FnSystem::new(7, |_t, y: &[f64], dy: &mut [f64]| {
        let (w, x, yy, z) = (y[0], y[1], y[2], y[3]);
        let (o, i) = ([y[4], y[5], y[6]], [1.0, 2.0, 3.0]);
        dy[0] = -0.5 * (x * o[0] + yy * o[1] + z * o[2]);
        dy[1] = 0.5 * (w * o[0] + yy * o[2] - z * o[1]);
        dy[2] = 0.5 * (w * o[1] + z * o[0] - x * o[2]);
        dy[3] = 0.5 * (w * o[2] + x * o[1] - yy * o[0]);
        dy[4] = (i[1] - i[2]) * o[1] * o[2] / i[0];
        dy[5] = (i[2] - i[0]) * o[2] * o[0] / i[1];
        dy[6] = (i[0] - i[1]) * o[0] * o[1] / i[2];
    })
}

/// SDIRK4's global error keeps following the tolerance down to rtol 1e-12 over
/// thousands of steps (against DOPRI5 at 1e-14): its Newton solves for the stage
/// increments, whose round-off is that of an O(h) quantity. Solving for the stage
/// values, the Newton floor of ten round-offs of the state, amplified up to 68 times
/// into each step, left 4.7e-11 at rtol 1e-12 here (2.9e-10 at 1e-10; now 1.0e-12 and
/// 6.2e-11).
#[test]
fn sdirk4_follows_the_tolerance_to_1e_12_over_thousands_of_steps() {
    let problem = Problem::new(0.0, 40.0, [1.0, 0.0, 0.0, 0.0, 0.5, 0.8, -0.6]);
    let reference = crate::solve(
        &quaternion_free_body(),
        &problem,
        &crate::Method::Dopri5(Options::tolerances(1e-14, 1e-16)),
    )
    .unwrap();
    let r = reference.last().unwrap().1.to_vec();
    for tol in [1e-10, 1e-12] {
        let traj = crate::solve(
            &quaternion_free_body(),
            &problem,
            &crate::Method::Sdirk4(Options::tolerances(tol, tol * 1e-2)),
        )
        .unwrap();
        let y = traj.last().unwrap().1;
        let err = y
            .iter()
            .zip(&r)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        eprintln!("tol {tol:e}: error {err:e}, {}", traj.stats);
        assert!(err <= 10.0 * tol, "tol {tol:e}: error {err:e}");
    }
}

/// The first step of a run (and of every stretch after a restart) has only the method's
/// own extension, a cubic Hermite for SDIRK4; once the next step arrives the solution
/// rewrites it as the two-step quintic Hermite, so reading the first step back is as
/// accurate as the steps (y'' = −y: within twice the error at the first three rows).
/// Before, SDIRK4's first step read back 1.4, 26 and 470 times worse than its rows at
/// rtol 1e-4, 1e-6 and 1e-8.
#[test]
fn the_first_step_reads_back_as_accurately_as_the_steps() {
    let problem = Problem::new(0.0, 10.0, [1.0, 0.0]);
    for tol in [1e-4, 1e-6, 1e-8] {
        for m in [
            Method::Sdirk4(Options::tolerances(tol, tol)),
            Method::Dopri5(Options::tolerances(tol, tol)),
            Method::Rk4 { h: 0.05 },
        ] {
            let traj = solve(&oscillator(), &problem, &m).unwrap();
            let (t0, t1) = (traj.times()[0], traj.times()[1]);
            let first = (1..100)
                .map(|k| {
                    let t = t0 + (t1 - t0) * k as f64 / 100.0;
                    (traj.at(t).unwrap()[0] - t.cos()).abs()
                })
                .fold(0.0, f64::max);
            let rows = (0..3)
                .map(|i| (traj.state(i)[0] - traj.times()[i].cos()).abs())
                .fold(0.0, f64::max);
            eprintln!("{m:?}: first step read back {first:e}, rows {rows:e}");
            assert!(
                first <= 2.0 * rows.max(1e-15),
                "{m:?}: {first:e} vs {rows:e}"
            );
        }
    }
}
