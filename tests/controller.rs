//! A controller driving a non-smooth run through the step-level `Integrator` (issue 28):
//! a cart on a rail with Coulomb friction and a stop at each end, a pendulum on it with
//! a Bingham dash-pot, the cart pushed by a digital PD controller at 1 kHz with a
//! zero-order hold.
//!
//! The references are independent runs of the same scene: one `solve_nonsmooth` call
//! with the recorded piecewise-constant force given as a function of time (steps ending
//! at the sample times, `tstops`), and, for a smooth input, one call with no stops at
//! all. Random gains, set-points and initial states.

use filippov::prelude::*;
use filippov::runtime::nonsmooth::Integrator;
use filippov::runtime::{
    Method, NonSmoothMethod, NonSmoothProblem, Options, Solution, solve_nonsmooth,
};

#[derive(Mechanism)]
#[mechanism(gravity = [0.0, -g, 0.0], inputs = [x])]
#[body(cart, mass = m_cart, com = [0.0, 0.0, 0.0], inertia = point)]
#[joint(x: prismatic(x), parent = world, child = cart)]
#[body(pole, mass = m_pole, com = [l / 2.0, 0.0, 0.0], inertia = rod(m_pole, l))]
#[joint(phi: revolute(z), parent = cart, child = pole)]
#[friction(x, f_crit = rail_friction)]
#[bingham(phi, f_crit = hinge_yield, eta = hinge_eta)]
#[stop(x, min = -0.4, max = 0.4, restitution = 0.3)]
struct CartPendulum {
    g: f64,
    m_cart: f64,
    m_pole: f64,
    l: f64,
    rail_friction: f64,
    hinge_yield: f64,
    hinge_eta: f64,
}

const SCENE: CartPendulum = CartPendulum {
    g: 9.81,
    m_cart: 1.0,
    m_pole: 0.3,
    l: 0.6,
    rail_friction: 0.8,
    hinge_yield: 0.02,
    hinge_eta: 0.01,
};

const RTOL: f64 = 1e-9;
const ATOL: f64 = 1e-11;
const SAMPLE: f64 = 1e-3;

type V2 = SVector<f64, 2>;

/// A small deterministic generator (xorshift), so that each case is reproducible.
struct Rng(u64);

impl Rng {
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        lo + (hi - lo) * (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

fn method() -> NonSmoothMethod {
    NonSmoothMethod::EventDriven(Method::Dopri5(Options::tolerances(RTOL, ATOL)))
}

/// The largest difference of `[q; v]` at `times`, each component in units of the
/// tolerance at its size over the run, `ATOL + RTOL max |y_i|`.
fn distance(a: &Solution, b: &Solution, times: &[f64]) -> f64 {
    let (ya, yb) = (a.sample(times).unwrap(), b.sample(times).unwrap());
    let mut worst: f64 = 0.0;
    for i in 0..4 {
        let size = ya.iter().chain(&yb).map(|y| y[i].abs()).fold(0.0, f64::max);
        let scale = ATOL + RTOL * size;
        for (p, r) in ya.iter().zip(&yb) {
            worst = worst.max((p[i] - r[i]).abs() / scale);
        }
    }
    worst
}

/// The PD controller's run: the force it held on each sample interval, and the run.
fn pd_run(rng: &mut Rng, method: &NonSmoothMethod, tf: f64) -> (Vec<f64>, Solution, [f64; 4]) {
    let (kp, kd) = (rng.uniform(5.0, 40.0), rng.uniform(0.5, 6.0));
    let target = rng.uniform(-0.6, 0.6);
    let q0 = V2::new(rng.uniform(-0.3, 0.3), rng.uniform(-2.0, -1.0));
    let v0 = V2::new(rng.uniform(-0.5, 0.5), rng.uniform(-1.0, 1.0));
    let problem = NonSmoothProblem::new(0.0, tf, q0, v0);
    let mut run = Integrator::held(&SCENE, &problem, method).unwrap();
    let samples = (tf / SAMPLE).round() as usize;
    let mut held = Vec::with_capacity(samples);
    for k in 0..samples {
        // The controller reads the state at the sample and holds its force until the
        // next one.
        let u = kp * (target - run.q()[0]) - kd * run.v()[0];
        run.set_input(CartPendulum::input_forces(&SVector::from([u])))
            .unwrap();
        held.push(u);
        run.advance_to(((k + 1) as f64 * SAMPLE).min(tf)).unwrap();
    }
    let initial = [q0[0], q0[1], v0[0], v0[1]];
    (held, run.into_solution(), initial)
}

/// The recorded forces as a function of time: `held[k]` on `[k Δ, (k + 1) Δ)`.
fn zero_order_hold(held: &[f64]) -> impl Fn(f64, &V2, &V2) -> V2 + '_ {
    move |t: f64, _q: &V2, _v: &V2| {
        // The k with k Δ ≤ t < (k + 1) Δ, for the sample times as the driver computes
        // them (a quotient t / Δ may round across an integer).
        let mut k = (t / SAMPLE).floor().max(0.0) as usize;
        while k > 0 && k as f64 * SAMPLE > t {
            k -= 1;
        }
        while (k + 1) as f64 * SAMPLE <= t {
            k += 1;
        }
        let k = k.min(held.len() - 1);
        CartPendulum::input_forces(&SVector::from([held[k]]))
    }
}

fn sample_times(tf: f64) -> Vec<f64> {
    let n = (tf / SAMPLE).round() as usize;
    (1..=n).map(|k| (k as f64 * SAMPLE).min(tf)).collect()
}

#[test]
fn a_sampled_controller_equals_one_run_with_its_forces_as_a_function() {
    let tf = 1.5;
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let mut switches = 0;
    for case in 0..4 {
        let (held, driven, y0) = pd_run(&mut rng, &method(), tf);
        let times = sample_times(tf);
        let stops: Vec<f64> = times[..times.len() - 1].to_vec();
        let problem = NonSmoothProblem::new(0.0, tf, V2::new(y0[0], y0[1]), V2::new(y0[2], y0[3]))
            .with_tstops(stops);
        let batch = solve_nonsmooth(&SCENE, &zero_order_hold(&held), &problem, &method()).unwrap();
        let d = distance(&driven, &batch, &times);
        // Independent of the restarts: the same function without stops, its jumps
        // found by the step-size control alone, at a thousandth of the tolerance.
        let tight = NonSmoothMethod::EventDriven(Method::Dopri5(Options::tolerances(
            1e-3 * RTOL,
            1e-3 * ATOL,
        )));
        let unstopped = NonSmoothProblem {
            tstops: Vec::new(),
            ..problem.clone()
        };
        let reference =
            solve_nonsmooth(&SCENE, &zero_order_hold(&held), &unstopped, &tight).unwrap();
        let d_ref = distance(&driven, &reference, &times);
        eprintln!(
            "PD case {case}: {d:.3} tolerances from the batch run, {d_ref:.3} from the reference, {} switches",
            driven.switches.len()
        );
        assert!(
            d <= 10.0 && d_ref <= 10.0,
            "case {case}: the driven run differs from the batch run by {d:.2} tolerances and from the reference by {d_ref:.2}"
        );
        switches += driven.switches.len();
    }
    // The cases exercise the elements: stick–slip of the rail, the hinge, the stops.
    assert!(switches >= 8, "only {switches} switches in all cases");
}

/// A staircase force on a cart at rest: it breaks away at the sample where the held force
/// first passes what friction can hold, and sticks again when the force is taken back.
#[test]
fn a_held_force_breaks_away_and_sticks_at_its_samples() {
    let tf = 1.2;
    let mut rng = Rng(0x0123_4567_89ab_cdef);
    for case in 0..4 {
        let (slope, hold) = (rng.uniform(2.0, 8.0), rng.uniform(0.4, 0.7));
        let force = |t: f64| {
            if t < hold { slope * t } else { 0.3 }
        };
        let problem = NonSmoothProblem::new(
            0.0,
            tf,
            V2::new(0.0, -std::f64::consts::FRAC_PI_2),
            V2::zeros(),
        );
        let mut run = Integrator::held(&SCENE, &problem, &method()).unwrap();
        let times = sample_times(tf);
        let mut held = Vec::new();
        let mut t = 0.0;
        for &next in &times {
            held.push(force(t));
            run.set_input(V2::new(force(t), 0.0)).unwrap();
            run.advance_to(next).unwrap();
            t = next;
        }
        let driven = run.into_solution();
        let tight = NonSmoothMethod::EventDriven(Method::Dopri5(Options::tolerances(
            1e-3 * RTOL,
            1e-3 * ATOL,
        )));
        let reference = solve_nonsmooth(&SCENE, &zero_order_hold(&held), &problem, &tight).unwrap();
        let d = distance(&driven, &reference, &times);
        let kinds: Vec<_> = driven
            .switches
            .iter()
            .filter(|s| s.element.as_deref() == Some("friction_x"))
            .map(|s| s.to)
            .collect();
        eprintln!("staircase case {case}: {d:.3} tolerances, rail switches {kinds:?}");
        assert!(
            d <= 10.0,
            "case {case}: {d:.2} tolerances from the reference"
        );
        // It broke away at the sample where the force jumped, not a step after it.
        let first = driven
            .switches
            .iter()
            .find(|s| s.element.as_deref() == Some("friction_x"))
            .unwrap();
        assert!(
            first.t == 0.0 || times.contains(&first.t),
            "case {case}: broke away at {:e}, between samples",
            first.t
        );
    }
}

#[test]
fn advancing_sample_by_sample_equals_one_run() {
    let tf = 1.0;
    let mut rng = Rng(0x2545_f491_4f6c_dd1d);
    for case in 0..4 {
        let (a, w) = (rng.uniform(1.0, 4.0), rng.uniform(3.0, 12.0));
        let input = move |t: f64, _q: &V2, _v: &V2| V2::new(a * (w * t).sin(), 0.0);
        let q0 = V2::new(rng.uniform(-0.3, 0.3), rng.uniform(-2.0, -1.0));
        let v0 = V2::new(rng.uniform(-0.5, 0.5), 0.0);
        let problem = NonSmoothProblem::new(0.0, tf, q0, v0);
        let mut run = Integrator::new(&SCENE, input, &problem, &method()).unwrap();
        let times = sample_times(tf);
        for &t in &times {
            run.advance_to(t).unwrap();
            assert_eq!(run.t(), t);
        }
        let driven = run.into_solution();
        let batch = solve_nonsmooth(&SCENE, &input, &problem, &method()).unwrap();
        let d = distance(&driven, &batch, &times);
        eprintln!("sine case {case}: {d:.3} tolerances");
        assert!(d <= 10.0, "case {case}: {d:.2} tolerances apart");
        assert_eq!(
            driven
                .switches
                .iter()
                .map(|s| (s.element.clone(), s.kind))
                .collect::<Vec<_>>(),
            batch
                .switches
                .iter()
                .map(|s| (s.element.clone(), s.kind))
                .collect::<Vec<_>>(),
            "case {case}: the switch logs differ"
        );
    }
}

#[test]
fn time_stepping_driven_equals_its_batch_run() {
    let tf = 0.5;
    let mut rng = Rng(0xdead_beef_1234_5678);
    let ts = NonSmoothMethod::TimeStepping {
        h: 1e-4,
        theta: 0.5,
    };
    for case in 0..3 {
        let (held, driven, y0) = pd_run(&mut rng, &ts, tf);
        let times = sample_times(tf);
        let problem = NonSmoothProblem::new(0.0, tf, V2::new(y0[0], y0[1]), V2::new(y0[2], y0[3]))
            .with_tstops(times[..times.len() - 1].to_vec());
        let batch = solve_nonsmooth(&SCENE, &zero_order_hold(&held), &problem, &ts).unwrap();
        assert_eq!(
            driven.times(),
            batch.times(),
            "case {case}: the grids differ"
        );
        for i in 0..driven.len() {
            assert_eq!(driven.state(i), batch.state(i), "case {case}, row {i}");
        }
    }
}

#[test]
fn driving_errors_are_typed_and_keep_the_run() {
    let problem = NonSmoothProblem::new(0.0, 1.0, V2::new(0.0, -1.5), V2::zeros());
    let mut run = Integrator::held(&SCENE, &problem, &method()).unwrap();
    run.advance_to(0.5).unwrap();
    let rows = run.solution().len();
    // Backwards, past the end, not finite: refused, nothing lost.
    for t in [0.25, 1.5, f64::NAN] {
        let err = run.advance_to(t).unwrap_err();
        assert!(
            matches!(err, filippov::runtime::ErrorKind::InvalidInput(_)),
            "{err}"
        );
    }
    let err = run.set_input(V2::new(f64::INFINITY, 0.0)).unwrap_err();
    assert!(err.to_string().contains("`x`"), "{err}");
    assert_eq!(run.solution().len(), rows);
    // Bad tstops are refused before anything runs.
    let bad = problem.clone().with_tstops(vec![0.5, 0.2]);
    assert!(Integrator::held(&SCENE, &bad, &method()).is_err());
    run.advance_to(1.0).unwrap();
    assert_eq!(run.solution().last().unwrap().0, 1.0);
}

/// `step()` says what each step did, and `modes()` follows the switch log: summed over a
/// run, the steps' counts are the log's and the events' lengths; after every step each
/// element's mode is the `to` of its last log entry (for time-stepping, `None` before the
/// first step). Random initial states and a constant push, both kinds of run.
#[test]
fn steps_report_their_switches_and_modes_follow_the_log() {
    let mut rng = Rng(0x57e9_5e1f);
    let cart_turns = |_t: f64, y: &[f64]| y[2];
    let events = [filippov::runtime::Event::new(&cart_turns)];
    for case in 0..6 {
        let q0 = V2::new(rng.uniform(-0.3, 0.3), rng.uniform(-2.0, -1.0));
        let v0 = V2::new(rng.uniform(-1.5, 1.5), rng.uniform(-2.0, 2.0));
        let push = rng.uniform(-3.0, 3.0);
        let problem = NonSmoothProblem::new(0.0, 1.5, q0, v0);
        for method in [
            method(),
            NonSmoothMethod::TimeStepping {
                h: 2e-3,
                theta: 1.0,
            },
        ] {
            let time_stepping = matches!(method, NonSmoothMethod::TimeStepping { .. });
            let mut run = Integrator::held(&SCENE, &problem, &method)
                .unwrap()
                .with_events(&events)
                .unwrap();
            run.set_input(CartPendulum::input_forces(&SVector::from([push])))
                .unwrap();
            let modes0 = run.modes();
            assert_eq!(modes0.len(), 4);
            assert_eq!(
                modes0.iter().all(Option::is_none),
                time_stepping,
                "case {case}: {modes0:?}"
            );
            let (mut switches, mut hits) = (run.solution().switches.len(), 0);
            while run.t() < problem.tf {
                let before = run.t();
                let stepped = run.step().unwrap();
                assert!(stepped.t > before && stepped.t == run.t());
                switches += stepped.switches;
                hits += stepped.events;
                let sol = run.solution();
                assert_eq!(
                    (switches, hits),
                    (sol.switches.len(), sol.events.len()),
                    "case {case} {method:?}"
                );
                let modes = run.modes();
                for (e, mode) in modes.iter().enumerate() {
                    assert!(mode.is_some(), "case {case} {method:?}: element {e}");
                    if let Some(last) = sol.switches.iter().rfind(|s| s.index == Some(e)) {
                        assert_eq!(
                            last.to,
                            *mode,
                            "case {case} {method:?} t = {}: element {e}",
                            run.t()
                        );
                    }
                }
            }
            assert!(switches > 0, "case {case} {method:?}: nothing switched");
        }
    }
}
