//! Events on Lie states for both methods: crossing times against an independent
//! location (bisection on a tight fixed-step run's dense output), a terminal event
//! against the closed-form fall time, directions, and what events leave unchanged.

use nalgebra::Vector3;

use super::*;
use crate::liegroup::{FnLieSystem, LieSdirk, LieTrajectory, Rkmk5, UnitQuat};
use crate::{Options, SolveError};

const INERTIA: [f64; 3] = [1.0, 2.0, 3.0];

/// Euler's equations of the torque-free body, into `dv[..3]`.
fn euler(y: &LieState, dv: &mut [f64]) {
    let w = y.omega(0);
    let iw = Vector3::new(INERTIA[0] * w.x, INERTIA[1] * w.y, INERTIA[2] * w.z);
    let rhs = -w.cross(&iw);
    for k in 0..3 {
        dv[k] = rhs[k] / INERTIA[k];
    }
}

fn free_body() -> impl LieSystem {
    FnLieSystem::new(1, 0, |_t, y: &LieState, dv: &mut [f64]| euler(y, dv))
}

/// A tumble near the intermediate axis: `ω_y` changes sign periodically.
fn tumble(tf: f64) -> LieProblem {
    LieProblem::new(
        0.0,
        tf,
        LieState::new(
            vec![UnitQuat::exp(&Vector3::new(0.2, 0.1, -0.3))],
            vec![],
            vec![0.3, 1.0, 0.2],
        ),
    )
}

/// Both methods behind one signature.
type Solver = dyn Fn(
    &dyn LieSystem,
    &LieProblem,
    &[LieEvent<'_>],
) -> Result<(LieTrajectory, Vec<LieEventHit>), SolveError>;

fn solvers(rtol: f64) -> [(&'static str, Box<Solver>); 2] {
    let options = Options::tolerances(rtol, rtol * 1e-3);
    [
        (
            "Rkmk5",
            Box::new(move |s, p, e| Rkmk5::new(options).solve_with_events(s, p, e)),
        ),
        (
            "LieSdirk",
            Box::new(move |s, p, e| LieSdirk::new(options).solve_with_events(s, p, e)),
        ),
    ]
}

/// The reference crossings of `ω_y = 0`: a fixed-step Rkmk5 run (h = 0.005, error
/// ~1e-12), its sign changes between stored points, each refined by plain bisection
/// on its dense output to 1e-14.
fn reference_crossings(tf: f64) -> Vec<f64> {
    let traj = Rkmk5::fixed(0.005)
        .solve(&free_body(), &tumble(tf))
        .unwrap();
    let wy = |t: f64| traj.at(t).unwrap().velocity[1];
    let mut out = Vec::new();
    for i in 1..traj.len() {
        let (mut a, mut b) = (traj.times()[i - 1], traj.times()[i]);
        let ga = wy(a);
        if ga * wy(b) > 0.0 || ga == 0.0 {
            continue;
        }
        while b - a > 1e-14 {
            let m = 0.5 * (a + b);
            if wy(m) * ga > 0.0 {
                a = m;
            } else {
                b = m;
            }
        }
        out.push(0.5 * (a + b));
    }
    out
}

/// "ω_y crosses zero" on the free body: the located times match the reference to
/// about the tolerance for both methods, the states there have `ω_y ≈ 0`, the
/// direction filter keeps the falling crossings, and non-terminal events leave the
/// trajectory as `solve` computes it.
#[test]
fn free_body_omega_y_crossings_match_a_bisection_reference() {
    let tf = 40.0;
    let reference = reference_crossings(tf);
    assert!(reference.len() >= 4, "{reference:?}");
    let wy = |_t: f64, y: &LieState| y.velocity[1];
    for (rtol, tol) in [(1e-10, 1e-8), (1e-7, 1e-5)] {
        for (name, solve) in solvers(rtol) {
            let events = [
                LieEvent::new(&wy),
                LieEvent::new(&wy).direction(EventDirection::Falling),
            ];
            let (traj, hits) = solve(&free_body(), &tumble(tf), &events).unwrap();
            let all: Vec<&LieEventHit> = hits.iter().filter(|h| h.event == 0).collect();
            let falling: Vec<&LieEventHit> = hits.iter().filter(|h| h.event == 1).collect();
            assert_eq!(
                all.len(),
                reference.len(),
                "{name}: {all:?} vs {reference:?}"
            );
            let worst = all
                .iter()
                .zip(&reference)
                .map(|(h, r)| (h.t - r).abs())
                .fold(0.0, f64::max);
            eprintln!(
                "{name} rtol {rtol:e}: {} crossings of ω_y, worst time error {worst:.2e}, {}",
                all.len(),
                traj.stats
            );
            assert!(worst < tol, "{name} rtol {rtol:e}: {worst:e}");
            for h in &all {
                assert!(h.state.velocity[1].abs() < 1e-9, "{h:?}");
                assert_eq!(h.state, traj.at(h.t).unwrap());
            }
            // Falling crossings are every other one, starting with the first.
            let expected: Vec<f64> = all.iter().step_by(2).map(|h| h.t).collect();
            let got: Vec<f64> = falling.iter().map(|h| h.t).collect();
            assert_eq!(got, expected, "{name}");
            assert!(hits.windows(2).all(|w| w[0].t <= w[1].t));
            assert_eq!(traj.stats.events, hits.len());
            assert_eq!(traj.last().unwrap().0, tf);
        }
    }
    // Non-terminal events change nothing in the integration itself.
    let options = Options::tolerances(1e-8, 1e-11);
    let events = [LieEvent::new(&wy)];
    let plain = Rkmk5::new(options)
        .solve(&free_body(), &tumble(tf))
        .unwrap();
    let (with, _) = Rkmk5::new(options)
        .solve_with_events(&free_body(), &tumble(tf), &events)
        .unwrap();
    assert_eq!(plain.times(), with.times());
    assert_eq!(plain.last(), with.last());
    let plain = LieSdirk::new(options)
        .solve(&free_body(), &tumble(tf))
        .unwrap();
    let (with, _) = LieSdirk::new(options)
        .solve_with_events(&free_body(), &tumble(tf), &events)
        .unwrap();
    assert_eq!(plain.times(), with.times());
}

const G: f64 = 9.81;
const HEIGHT: f64 = 10.0;

/// A tumbling free body falling from `HEIGHT` at rest vertically (horizontal drift
/// `u_x = 0.7`): `u̇ = (0, 0, −g)`.
fn falling_body() -> impl LieSystem {
    FnLieSystem::new(1, 3, |_t, y: &LieState, dv: &mut [f64]| {
        euler(y, &mut dv[..3]);
        dv[3..].copy_from_slice(&[0.0, 0.0, -G]);
    })
}

fn drop_problem() -> LieProblem {
    LieProblem::new(
        0.0,
        10.0,
        LieState::new(
            vec![UnitQuat::exp(&Vector3::new(0.2, 0.1, -0.3))],
            vec![0.0, 1.0, HEIGHT],
            vec![0.3, 1.0, 0.2, 0.7, 0.0, 0.0],
        ),
    )
}

/// A terminal event at height 0 stops both methods at `t* = √(2 h₀ / g)` to 1e-10,
/// with the event state as the last point; a non-terminal event at half height is
/// reported at `√(h₀ / g)`, one below the ground never, and a rising event at half
/// height not at all.
#[test]
fn falling_body_stops_at_the_ground() {
    let t_ground = (2.0 * HEIGHT / G).sqrt();
    let t_half = (HEIGHT / G).sqrt();
    let height = |_t: f64, y: &LieState| y.euclid[2];
    let half = |_t: f64, y: &LieState| y.euclid[2] - 0.5 * HEIGHT;
    let below = |_t: f64, y: &LieState| y.euclid[2] + 1.0;
    for (name, solve) in solvers(1e-8) {
        let events = [
            LieEvent::new(&below),
            LieEvent::new(&height)
                .terminal()
                .direction(EventDirection::Falling),
            LieEvent::new(&half).direction(EventDirection::Rising),
            LieEvent::new(&half),
        ];
        let (traj, hits) = solve(&falling_body(), &drop_problem(), &events).unwrap();
        let (t_end, y_end) = traj.last().unwrap();
        eprintln!(
            "{name}: stopped at t = {t_end:.15} (exact {t_ground:.15}), {} points, {}",
            traj.len(),
            traj.stats
        );
        assert!(
            (t_end - t_ground).abs() < 1e-10,
            "{name}: {t_end} vs {t_ground}"
        );
        assert_eq!(hits.len(), 2, "{name}: {hits:?}");
        assert_eq!(hits[0].event, 3);
        assert!((hits[0].t - t_half).abs() < 1e-10, "{name}: {hits:?}");
        assert_eq!((hits[1].event, hits[1].t), (1, t_end));
        assert_eq!(hits[1].state, y_end);
        assert!(y_end.euclid[2].abs() < 1e-9, "{y_end:?}");
        assert!((y_end.velocity[5] + G * t_ground).abs() < 1e-9);
        assert!((y_end.euclid[0] - 0.7 * t_ground).abs() < 1e-9);
        // The cut step keeps its interpolant: the dense output up to t* is the exact
        // parabola (the methods are exact on it), and nothing lies beyond.
        let n = traj.len();
        let t_mid = 0.5 * (traj.times()[n - 2] + t_end);
        let y_mid = traj.at(t_mid).unwrap();
        assert!((y_mid.euclid[2] - (HEIGHT - 0.5 * G * t_mid * t_mid)).abs() < 1e-9);
        assert_eq!(traj.at(t_end + 1e-9), None);
        // The flat trajectory ends at the same point, with f(t*, y*) as derivative.
        let flat = traj.flat();
        assert_eq!(flat.len(), n);
        assert_eq!(flat.times()[n - 1], t_end);
        assert_eq!(flat.derivative(n - 1)[4 + 3 + 5], -G);
        assert!(traj.times().windows(2).all(|w| w[0] < w[1]));
    }
}

/// An event function that is NaN at the start is invalid input.
#[test]
fn nan_event_at_start_is_invalid_input() {
    let nan = |_t: f64, _y: &LieState| f64::NAN;
    let err = Rkmk5::new(Options::default())
        .solve_with_events(&free_body(), &tumble(1.0), &[LieEvent::new(&nan)])
        .unwrap_err();
    assert!(
        matches!(err.kind, crate::ErrorKind::InvalidInput(_)),
        "{err}"
    );
}

/// A reset bounces the falling body off the ground (`u_z → −e u_z`): both methods land
/// at the closed-form bounce times (`√(2 h₀/g)`, then flights of `2w/g` at speeds `w`
/// shrinking by `e`), each bounce a point before and after at its time, the attitude
/// continuous across it.
#[test]
fn falling_body_bounces_by_a_reset() {
    let e = 0.7;
    let height = |_t: f64, y: &LieState| y.euclid[2];
    let bounce = move |_t: f64, y: &mut LieState| y.velocity[5] *= -e;
    let mut expected = vec![(2.0 * HEIGHT / G).sqrt()];
    let mut w = e * (2.0 * G * HEIGHT).sqrt();
    while expected.len() < 4 {
        let last = expected[expected.len() - 1];
        expected.push(last + 2.0 * w / G);
        w *= e;
    }
    let tf = expected[3] + 0.5 * w / G;
    let problem = LieProblem::new(0.0, tf, drop_problem().y0);
    for (name, solve) in solvers(1e-10) {
        let events = [LieEvent::new(&height)
            .direction(EventDirection::Falling)
            .reset(&bounce)];
        let (traj, hits) = solve(&falling_body(), &problem, &events).unwrap();
        assert_eq!(hits.len(), 4, "{name}: {hits:?}");
        for (n, (hit, t)) in hits.iter().zip(&expected).enumerate() {
            assert!(
                (hit.t - t).abs() < 1e-9,
                "{name}: bounce {n} at {} vs {t}",
                hit.t
            );
            let at: Vec<usize> = (0..traj.len())
                .filter(|&i| traj.times()[i] == hit.t)
                .collect();
            assert_eq!(at.len(), 2, "{name}: bounce {n}");
            let (before, after) = (traj.state(at[0]), traj.state(at[1]));
            let landing = (2.0 * G * HEIGHT).sqrt() * e.powi(n as i32);
            assert!(
                (before.velocity[5] + landing).abs() < 1e-8,
                "{name}: {before:?}"
            );
            assert!(
                (after.velocity[5] - e * landing).abs() < 1e-8,
                "{name}: {after:?}"
            );
            assert_eq!(before.rotations, after.rotations);
            // Just after the bounce the body rises.
            let later = traj.at(hit.t + 1e-3).unwrap();
            assert!(later.euclid[2] > 0.0, "{name}: {later:?}");
        }
        let (t_end, _) = traj.last().unwrap();
        assert_eq!(t_end, tf);
    }
}
