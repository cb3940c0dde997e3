//! BDF against closed forms, the stiff references, typed failures and its own
//! Jacobian paths.

use nalgebra::DMatrix;

use super::*;
use crate::{ErrorKind, FnSystem, Method, OdeSystem, Options, Problem, solve};

fn oscillator() -> FnSystem<impl Fn(f64, &[f64], &mut [f64])> {
    FnSystem::new(2, |_t, y: &[f64], dy: &mut [f64]| {
        dy[0] = y[1];
        dy[1] = -y[0];
    })
}

/// `y' = −y + sin t`, `y(0) = 1`: `y = 1.5 e^{−t} + (sin t − cos t)/2`.
fn forced_decay() -> FnSystem<impl Fn(f64, &[f64], &mut [f64])> {
    FnSystem::new(1, |t, y: &[f64], dy: &mut [f64]| dy[0] = -y[0] + t.sin())
}

fn forced_decay_exact(t: f64) -> f64 {
    1.5 * (-t).exp() + 0.5 * (t.sin() - t.cos())
}

/// Robertson's chemical kinetics (Hairer & Wanner II, §IV.1, eq. 1.3), with an
/// optional analytic Jacobian.
struct Robertson {
    analytic: bool,
}

impl OdeSystem for Robertson {
    fn dim(&self) -> usize {
        3
    }
    fn rhs(&self, _t: f64, y: &[f64], dy: &mut [f64]) {
        dy[0] = -0.04 * y[0] + 1e4 * y[1] * y[2];
        dy[2] = 3e7 * y[1] * y[1];
        dy[1] = -dy[0] - dy[2];
    }
    fn jacobian(&self, _t: f64, y: &[f64], jac: &mut DMatrix<f64>) -> bool {
        if !self.analytic {
            return false;
        }
        jac[(0, 0)] = -0.04;
        jac[(0, 1)] = 1e4 * y[2];
        jac[(0, 2)] = 1e4 * y[1];
        jac[(2, 0)] = 0.0;
        jac[(2, 1)] = 6e7 * y[1];
        jac[(2, 2)] = 0.0;
        for j in 0..3 {
            jac[(1, j)] = -jac[(0, j)] - jac[(2, j)];
        }
        true
    }
}

fn robertson_problem() -> Problem {
    Problem::new(0.0, 1e5, [1.0, 0.0, 0.0])
}

/// Robertson's tolerances: `y₂` lives around 10⁻⁵ … 10⁻⁶, so `atol` must be far below.
fn robertson_options(rtol: f64) -> Options {
    Options {
        max_steps: 200_000,
        ..Options::tolerances(rtol, rtol * 1e-6)
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

/// The global error against closed forms follows the tolerance. BDF controls the
/// error per step (as `ode15s`, SciPy and CVODE), so the global error is at most the
/// sum of the `N` local errors, each below the weight `atol + rtol |y| ≤ 2 tol` per
/// component (`2√2 tol` in the 2-norm of the oscillator), when the flow does not
/// amplify errors (a rotation, a contraction). With `N ∝ tol^{−1/(k+1)}` at order `k`,
/// the log–log slope is `1 − 1/(k+1)`, about 0.83 at order 5.
#[test]
fn bdf_global_error_follows_the_tolerance() {
    for (name, tf) in [("oscillator", 10.0), ("forced decay", 10.0)] {
        let mut previous = f64::INFINITY;
        let mut by_tol = Vec::new();
        for tol in [1e-4, 1e-6, 1e-8, 1e-10] {
            let options = Options::tolerances(tol, tol);
            let (traj, err) = if name == "oscillator" {
                let traj = crate::solve(
                    &oscillator(),
                    &Problem::new(0.0, tf, [1.0, 0.0]),
                    &crate::Method::Bdf(options),
                )
                .unwrap();
                let (t, y) = traj.last().unwrap();
                let err = ((y[0] - t.cos()).powi(2) + (y[1] + t.sin()).powi(2)).sqrt();
                (traj, err)
            } else {
                let traj = crate::solve(
                    &forced_decay(),
                    &Problem::new(0.0, tf, [1.0]),
                    &crate::Method::Bdf(options),
                )
                .unwrap();
                let (t, y) = traj.last().unwrap();
                let err = (y[0] - forced_decay_exact(t)).abs();
                (traj, err)
            };
            eprintln!("{name} tol {tol:e}: error {err:e}, {}", traj.stats);
            assert_eq!(traj.last().unwrap().0, tf);
            let steps = traj.stats.steps as f64;
            assert!(
                err <= 2.0 * 2f64.sqrt() * steps * tol,
                "{name} tol {tol:e}: error {err:e}, {steps} steps"
            );
            if name == "forced decay" {
                // Dissipative: local errors are damped, not summed.
                assert!(err < 50.0 * tol, "{name} tol {tol:e}: error {err:e}");
            }
            assert!(
                err < previous / 10.0,
                "{name} tol {tol:e}: error {err:e} vs {previous:e}"
            );
            previous = err;
            by_tol.push((tol, err));
        }
        let slope = log_slope(&by_tol);
        eprintln!("{name}: error ∝ tol^{slope:.3}");
        assert!((0.75..=1.1).contains(&slope), "{name}: error ∝ tol^{slope}");
    }
}

#[test]
fn bdf_reaches_order_five_and_dense_output_is_accurate() {
    let problem = Problem::new(0.0, 10.0, [1.0]);
    let traj = crate::solve(
        &forced_decay(),
        &problem,
        &crate::Method::Bdf(Options::tolerances(1e-9, 1e-9)),
    )
    .unwrap();
    let worst = (0..=1000)
        .map(|i| {
            let t = i as f64 * 0.01;
            (traj.at(t).unwrap()[0] - forced_decay_exact(t)).abs()
        })
        .fold(0.0, f64::max);
    // A high order shows in few steps: order 1 would need ~1/√tol ≈ 3·10⁴ steps.
    eprintln!("worst dense error {worst:e}, {}", traj.stats);
    assert!(worst < 1e-6, "worst dense error {worst:e}");
    assert!(traj.stats.steps < 1000, "{}", traj.stats);
}

#[test]
fn bdf_solves_robertson_in_far_fewer_steps_than_dopri5() {
    let rtol = 1e-6;
    let problem = robertson_problem();
    let reference = crate::solve(
        &Robertson { analytic: true },
        &problem,
        &crate::Method::Sdirk4(Options::tolerances(1e-10, 1e-16)),
    )
    .unwrap();
    let r = reference.last().unwrap().1.to_vec();
    let bdf = crate::solve(
        &Robertson { analytic: false },
        &problem,
        &crate::Method::Bdf(robertson_options(rtol)),
    )
    .unwrap();
    let sdirk = crate::solve(
        &Robertson { analytic: false },
        &problem,
        &crate::Method::Sdirk4(robertson_options(rtol)),
    )
    .unwrap();
    let y = bdf.last().unwrap().1;
    eprintln!("reference {r:?} ({})", reference.stats);
    eprintln!("BDF {y:?} ({})", bdf.stats);
    eprintln!("SDIRK4 {:?} ({})", sdirk.last().unwrap().1, sdirk.stats);
    for i in 0..3 {
        let rel = (y[i] - r[i]).abs() / r[i].abs();
        assert!(rel < 20.0 * rtol, "component {i}: {} vs {}", y[i], r[i]);
    }
    // Mass conservation y₁ + y₂ + y₃ = 1 (linear invariant, kept by any linear
    // multistep method up to the Newton tolerance).
    assert!((y.iter().sum::<f64>() - 1.0).abs() < 1e-9);
    // DOPRI5 is limited by stability to h ≲ 3.3/|λ| ≈ 10⁻⁴ at late times: it cannot
    // get far with a hundred times the steps BDF takes.
    let budget = 100 * (bdf.stats.steps + bdf.stats.rejected_steps);
    let explicit = crate::solve(
        &Robertson { analytic: false },
        &problem,
        &crate::Method::Dopri5(Options {
            max_steps: budget,
            ..robertson_options(rtol)
        }),
    )
    .unwrap_err();
    let ErrorKind::MaxSteps { t } = explicit.kind else {
        panic!("DOPRI5: {explicit}");
    };
    eprintln!("DOPRI5 stopped at t = {t} after {budget} attempts");
    assert!(t < 1e3, "DOPRI5 reached t = {t}");
    assert!(bdf.stats.steps < 1000, "{}", bdf.stats);
    assert!(bdf.stats.newton_iterations < sdirk.stats.newton_iterations);
}

/// Van der Pol `x'' − μ(1 − x²)x' + x = 0`, μ = 1000.
fn van_der_pol(mu: f64) -> FnSystem<impl Fn(f64, &[f64], &mut [f64])> {
    FnSystem::new(2, move |_t, y: &[f64], dy: &mut [f64]| {
        dy[0] = y[1];
        dy[1] = mu * (1.0 - y[0] * y[0]) * y[1] - y[0];
    })
}

#[test]
fn bdf_solves_stiff_van_der_pol() {
    let problem = Problem::new(0.0, 3000.0, [2.0, 0.0]);
    let rtol = 1e-6;
    let reference = crate::solve(
        &van_der_pol(1000.0),
        &problem,
        &crate::Method::Sdirk4(Options {
            max_steps: 1_000_000,
            ..Options::tolerances(1e-10, 1e-10)
        }),
    )
    .unwrap();
    let bdf = crate::solve(
        &van_der_pol(1000.0),
        &problem,
        &crate::Method::Bdf(Options::tolerances(rtol, rtol)),
    )
    .unwrap();
    let sdirk = crate::solve(
        &van_der_pol(1000.0),
        &problem,
        &crate::Method::Sdirk4(Options::tolerances(rtol, rtol)),
    )
    .unwrap();
    let (y, r) = (bdf.last().unwrap().1, reference.last().unwrap().1);
    eprintln!(
        "BDF {y:?} ({}); SDIRK4 ({}); reference {r:?}",
        bdf.stats, sdirk.stats
    );
    // Past one relaxation oscillation (period ≈ 1614) the phase error of the jump
    // is amplified; the slow coordinate still has to agree to a few 1e-4.
    assert!((y[0] - r[0]).abs() < 1e3 * rtol, "{y:?} vs {r:?}");
    assert!(bdf.stats.steps < 3000, "{}", bdf.stats);
}

#[test]
fn analytic_and_finite_difference_jacobians_agree() {
    let rtol = 1e-7;
    let problem = robertson_problem();
    let a = crate::solve(
        &Robertson { analytic: true },
        &problem,
        &crate::Method::Bdf(robertson_options(rtol)),
    )
    .unwrap();
    let fd = crate::solve(
        &Robertson { analytic: false },
        &problem,
        &crate::Method::Bdf(robertson_options(rtol)),
    )
    .unwrap();
    assert_eq!(a.stats.finite_difference_jacobians, 0);
    assert!(a.stats.jacobian_evaluations > 0);
    assert_eq!(
        fd.stats.finite_difference_jacobians,
        fd.stats.jacobian_evaluations
    );
    assert!(fd.stats.jacobian_evaluations > 0);
    let (ya, yf) = (a.last().unwrap().1, fd.last().unwrap().1);
    eprintln!("analytic {ya:?} ({}); fd {yf:?} ({})", a.stats, fd.stats);
    // Both against a different method at a far tighter tolerance, with the bound of
    // `bdf_solves_robertson_in_far_fewer_steps_than_dopri5` (each run's global error is
    // a few times rtol either way, so they may differ by more than either misses).
    let reference = crate::solve(
        &Robertson { analytic: true },
        &problem,
        &crate::Method::Sdirk4(Options::tolerances(1e-10, 1e-16)),
    )
    .unwrap();
    let r = reference.last().unwrap().1;
    for (name, y) in [("analytic", ya), ("finite differences", yf)] {
        for i in 0..3 {
            let rel = (y[i] - r[i]).abs() / r[i].abs();
            assert!(
                rel < 20.0 * rtol,
                "{name}, component {i}: {} vs {}",
                y[i],
                r[i]
            );
        }
    }
    // And along the way, at points of the two different meshes.
    for t in [1e-3, 0.4, 40.0, 4e3] {
        let (pa, pf) = (a.at(t).unwrap(), fd.at(t).unwrap());
        for i in 0..3 {
            let scale = pa[i].abs().max(1e-7);
            assert!(
                (pa[i] - pf[i]).abs() <= 1e-4 * scale,
                "t = {t}: {pa:?} vs {pf:?}"
            );
        }
    }
}

#[test]
fn blow_up_gives_a_typed_error_with_the_steps_kept() {
    // y' = y², y(0) = 1 blows up at t = 1.
    let system = FnSystem::new(1, |_t, y: &[f64], dy: &mut [f64]| dy[0] = y[0] * y[0]);
    let err = crate::solve(
        &system,
        &Problem::new(0.0, 2.0, [1.0]),
        &crate::Method::Bdf(Options::default()),
    )
    .unwrap_err();
    eprintln!("{err:?}");
    match err.kind {
        ErrorKind::StepSizeUnderflow { t, .. } | ErrorKind::NonFinite { t, .. } => {
            assert!(t > 0.99 && t < 1.0, "{err}")
        }
        _ => panic!("{err}"),
    }
    assert!(err.solution.len() > 10);
    assert_eq!(err.solution.len(), err.solution.stats.steps + 1);
    // Before the blow-up the kept trajectory is accurate. The flow amplifies errors
    // in y like y², but not in u = 1/y (u' = −1): check u = 1 − t.
    for t in [0.5, 0.9, 0.99] {
        let y = err.solution.at(t).unwrap()[0];
        let du = (1.0 / y - (1.0 - t)).abs();
        assert!(du < 100.0 * Options::default().rtol, "y({t}) = {y}");
    }
}

#[test]
fn nan_rhs_and_max_steps_are_reported() {
    let system = FnSystem::new(1, |t, y: &[f64], dy: &mut [f64]| {
        dy[0] = if t > 0.5 { f64::NAN } else { -y[0] };
    });
    let err = solve(
        &system,
        &Problem::new(0.0, 1.0, [1.0]),
        &Method::Bdf(Options::default()),
    )
    .unwrap_err();
    assert!(
        matches!(err.kind, ErrorKind::NonFinite { t, component: 0 } if t > 0.5),
        "{err}"
    );
    assert!(err.solution.last().unwrap().0 <= 0.5);
    let err = crate::solve(
        &oscillator(),
        &Problem::new(0.0, 100.0, [1.0, 0.0]),
        &crate::Method::Bdf(Options {
            max_steps: 5,
            ..Options::default()
        }),
    )
    .unwrap_err();
    assert!(matches!(err.kind, ErrorKind::MaxSteps { .. }), "{err}");
    assert!(!err.solution.is_empty());
}

#[test]
fn invalid_input_is_an_error_not_a_panic() {
    let good = Problem::new(0.0, 1.0, [1.0, 0.0]);
    let cases = [
        (good.clone(), Options::tolerances(0.0, 0.0)),
        (good.clone(), Options::tolerances(f64::NAN, 1e-9)),
        (
            good.clone(),
            Options {
                h0: Some(0.0),
                ..Options::default()
            },
        ),
        (
            good.clone(),
            Options {
                max_steps: 0,
                ..Options::default()
            },
        ),
        (Problem::new(0.0, 1.0, [1.0]), Options::default()),
        (Problem::new(1.0, 0.0, [1.0, 0.0]), Options::default()),
    ];
    for (problem, options) in cases {
        let err = solve(&oscillator(), &problem, &Method::Bdf(options)).unwrap_err();
        assert!(matches!(err.kind, ErrorKind::InvalidInput(_)), "{err}");
        assert!(err.solution.is_empty());
    }
    let traj = solve(
        &oscillator(),
        &Problem::new(1.0, 1.0, [1.0, 0.0]),
        &Method::Bdf(Options::default()),
    )
    .unwrap();
    assert_eq!(traj.len(), 1);
}

#[test]
fn rescaling_the_differences_is_exact_for_polynomials() {
    // Differences of a quadratic p on the grid t = 0, −h, −2h, … are re-interpolated
    // to spacing 0.3h: they must equal the differences of p on the new grid.
    let p = |t: f64| 2.0 - 3.0 * t + 0.7 * t * t;
    let differences = |h: f64, k: usize| {
        let mut col: Vec<f64> = (0..=k).map(|i| p(-(i as f64) * h)).collect();
        let mut out = vec![col[0]];
        for _ in 0..k {
            col = col.windows(2).map(|w| w[0] - w[1]).collect();
            out.push(col[0]);
        }
        out
    };
    let order = 3;
    let mut diff: Vec<Vec<f64>> = differences(0.5, order)
        .into_iter()
        .map(|x| vec![x])
        .collect();
    diff.resize(MAX_ORDER + 3, vec![0.0]);
    rescale(&mut diff, order, 0.3);
    let expected = differences(0.15, order);
    for j in 0..=order {
        assert!(
            (diff[j][0] - expected[j]).abs() < 1e-13,
            "D_{j}: {} vs {}",
            diff[j][0],
            expected[j]
        );
    }
}
