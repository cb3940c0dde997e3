//! Time-stepping's passivity and its rigid stops: on arms that swing, are driven hard,
//! bounce on a rigid limit (restitution 0 to 1) or press a stiff spring-backed one, with
//! friction, at θ = ½ and θ = 1, random states and forcing. No step ends with more
//! energy than it began with plus the input's work over it, `τ(t_n + θh) · (q_{n+1} −
//! q_n)` (so the energy never rises above the initial energy plus the input's work), and
//! no rigid stop is ever passed.

mod common;
/// Two links in a vertical plane, a rigid lower limit on the shoulder (restitution `e`),
/// friction on the elbow.
#[path = "../examples/support/resting_arm.rs"]
#[allow(dead_code)]
mod resting_arm;

use common::Rng;
use filippov::Mechanism;
use filippov::prelude::*;
use filippov::runtime::{NonSmoothMethod, NonSmoothProblem, Solution, solve_nonsmooth};
use resting_arm::{RestingArm as LimitedArm, V2};

type V3 = SVector<f64, 3>;

/// Three links, a spring-backed lower limit on the shoulder, static/kinetic friction on
/// the elbow, a spring on the wrist, both limits rigid on the wrist.
#[derive(Mechanism, Clone, Copy)]
#[mechanism(gravity = [0.0, -9.81, 0.0])]
#[body(upper, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[joint(shoulder: revolute(z), parent = world, child = upper)]
#[body(fore, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[joint(elbow: revolute(z), parent = upper, child = fore, origin = [l, 0.0, 0.0])]
#[body(hand, mass = m / 2.0, com = [l / 4.0, 0.0, 0.0], inertia = rod(m / 2.0, l / 2.0))]
#[joint(wrist: revolute(z), parent = fore, child = hand, origin = [l, 0.0, 0.0])]
#[stop(shoulder, min = -0.5, k_support = ks)]
#[friction(elbow, f_static = 2.0 * fk, f_kinetic = fk)]
#[spring(wrist, k = 3.0, rest = 0.2)]
#[stop(wrist, min = -1.0, max = 1.0, restitution = e)]
struct SupportedArm {
    m: f64,
    l: f64,
    ks: f64,
    fk: f64,
    e: f64,
}

/// Checks the run `sol` of `scene` under `input` with step `h` and `theta`: each step's
/// energy gain beyond the input's work, relative to the run's energy scale, at most
/// 1e-12; the gaps of the rigid stops `(coordinate, position, +1 upper / −1 lower)`
/// never negative. Returns the largest relative gain.
fn check<S, const N: usize>(
    scene: &S,
    sol: &Solution,
    input: &dyn Fn(f64) -> SVector<f64, N>,
    theta: f64,
    stops: &[(usize, f64, f64)],
    stored: &dyn Fn(&[f64]) -> f64,
    case: &str,
) -> f64
where
    S: Energy<N>,
{
    let energy = |y: &[f64]| {
        let q = SVector::<f64, N>::from_column_slice(&y[..N]);
        let v = SVector::<f64, N>::from_column_slice(&y[N..2 * N]);
        scene.total_energy(&q, &v) + stored(y)
    };
    let t = sol.times();
    let e0 = energy(sol.state(0));
    let (mut work, mut worst, mut scale) = (0.0, f64::NEG_INFINITY, e0.abs().max(1.0));
    for i in 1..t.len() {
        let (a, b) = (sol.state(i - 1), sol.state(i));
        let tau = input(t[i - 1] + theta * (t[i] - t[i - 1]));
        let w: f64 = (0..N).map(|c| tau[c] * (b[c] - a[c])).sum();
        work += w;
        scale = scale.max(energy(b).abs()).max(work.abs());
        let gain = (energy(b) - energy(a) - w) / scale;
        worst = worst.max(gain);
        assert!(
            gain <= 1e-12,
            "{case}: step to t = {} gains {gain:.3e} of the energy scale beyond the work ({a:?} → {b:?})",
            t[i]
        );
        let total = (energy(b) - e0 - work) / scale;
        assert!(
            total <= 1e-12,
            "{case}: at t = {} the energy is {total:.3e} above the initial plus the work",
            t[i]
        );
        for &(c, position, s) in stops {
            assert!(
                s * (position - b[c]) >= 0.0,
                "{case}: at t = {} coordinate {c} = {} passes its rigid stop at {position}",
                t[i],
                b[c]
            );
        }
    }
    worst
}

#[test]
fn time_stepping_is_passive_and_never_passes_a_rigid_stop() {
    let mut rng = Rng::new(29);
    let mut worst: f64 = f64::NEG_INFINITY;
    let mut runs = 0;
    for case in 0..12 {
        let arm = LimitedArm {
            m1: rng.uniform(0.5, 2.0),
            l1: rng.uniform(0.5, 1.2),
            m2: rng.uniform(0.2, 1.0),
            l2: rng.uniform(0.3, 1.0),
            fc: rng.uniform(0.0, 5.0),
            lim: -1.0,
            e: [0.0, 0.5, 1.0][case % 3],
        };
        // Swinging (case < 4), or driven hard by torques of up to 40 N·m.
        let amp = if case < 4 {
            0.0
        } else {
            rng.uniform(5.0, 40.0)
        };
        let (w1, w2) = (rng.uniform(1.0, 20.0), rng.uniform(1.0, 20.0));
        let input = move |t: f64| V2::new(amp * (w1 * t).sin(), 0.5 * amp * (w2 * t).cos());
        let q0 = V2::new(rng.uniform(-0.9, 1.0), rng.uniform(-2.0, 2.0));
        let v0 = rng.vector::<2>(10.0);
        let p = NonSmoothProblem::new(0.0, 3.0, q0, v0);
        for theta in [0.5, 1.0] {
            for h in [1e-3, 1e-4] {
                let label = format!(
                    "arm {case} (e = {}, amp {amp:.1}), θ = {theta}, h = {h:e}",
                    arm.e
                );
                let sol = solve_nonsmooth(
                    &arm,
                    &|t: f64, _q: &V2, _v: &V2| input(t),
                    &p,
                    &NonSmoothMethod::TimeStepping { h, theta },
                )
                .unwrap_or_else(|err| panic!("{label}: {err}"));
                let stops = [(0, arm.lim, -1.0)];
                worst = worst.max(check(&arm, &sol, &input, theta, &stops, &|_| 0.0, &label));
                runs += 1;
            }
        }
    }
    for case in 0..6 {
        let arm = SupportedArm {
            m: rng.uniform(0.5, 2.0),
            l: rng.uniform(0.3, 0.8),
            ks: [1e3, 1e6, 1e9][case % 3],
            fk: rng.uniform(0.5, 3.0),
            e: rng.uniform(0.0, 1.0),
        };
        let amp = if case < 3 {
            0.0
        } else {
            rng.uniform(5.0, 30.0)
        };
        let w = rng.uniform(1.0, 15.0);
        let input = move |t: f64| V3::new(amp * (w * t).sin(), 0.0, 0.2 * amp * (w * t).cos());
        let q0 = V3::new(
            rng.uniform(-0.4, 1.0),
            rng.uniform(-2.0, 2.0),
            rng.uniform(-0.9, 0.9),
        );
        let v0 = rng.vector::<3>(5.0);
        let p = NonSmoothProblem::new(0.0, 2.0, q0, v0);
        let ks = arm.ks;
        let stored = move |y: &[f64]| 0.5 * ks * (-0.5 - y[0]).max(0.0).powi(2);
        for theta in [0.5, 1.0] {
            let h = 1e-3;
            let label = format!("supported arm {case} (k_s = {ks:e}), θ = {theta}");
            let sol = solve_nonsmooth(
                &arm,
                &|t: f64, _q: &V3, _v: &V3| input(t),
                &p,
                &NonSmoothMethod::TimeStepping { h, theta },
            )
            .unwrap_or_else(|err| panic!("{label}: {err}"));
            let stops = [(2, -1.0, -1.0), (2, 1.0, 1.0)];
            worst = worst.max(check(&arm, &sol, &input, theta, &stops, &stored, &label));
            runs += 1;
        }
    }
    eprintln!("{runs} runs: largest step gain beyond the work {worst:.2e} of the energy scale");
}
