//! User events (issue 28) on every kind of run, against closed-form crossing times:
//! smooth runs (`solve_with_events`, each method), event-driven runs (a block sliding
//! to rest under friction, a block bouncing on a rigid stop: crossings between the
//! switches and across the impacts' velocity jumps) and time-stepping (a block sliding
//! under a constant net force, which θ = ½ integrates exactly). Lie-group runs use the
//! same `Event` (their closed-form tests are in the runtime: a falling body).

use filippov::prelude::*;
use filippov::runtime::nonsmooth::Integrator;
use filippov::runtime::{
    Event, EventDirection, FnSystem, Method, Mode, NonSmoothMethod, NonSmoothProblem, Options,
    Problem, solve_with_events,
};

const RTOL: f64 = 1e-10;
const ATOL: f64 = 1e-12;
/// The crossing times must match the closed forms to this.
const TIME_TOL: f64 = 1e-9;

type V1 = SVector<f64, 1>;
type EventFn = Box<dyn Fn(f64, &[f64]) -> f64>;

#[derive(Mechanism)]
#[body(block, mass = m, com = [0.0, 0.0, 0.0], inertia = point)]
#[joint(x: prismatic(x), parent = world, child = block)]
#[friction(x, f_crit = mu)]
struct SlidingBlock {
    m: f64,
    mu: f64,
}

#[derive(Mechanism)]
#[body(block, mass = m, com = [0.0, 0.0, 0.0], inertia = point)]
#[joint(x: prismatic(x), parent = world, child = block)]
#[stop(x, max = 1.0, restitution = e)]
struct Bouncer {
    m: f64,
    e: f64,
}

fn event_driven() -> NonSmoothMethod {
    NonSmoothMethod::EventDriven(Method::Dopri5(Options::tolerances(RTOL, ATOL)))
}

fn assert_times(what: &str, got: &[f64], expected: &[f64]) {
    assert_eq!(
        got.len(),
        expected.len(),
        "{what}: got {got:?}, expected {expected:?}"
    );
    let worst = got
        .iter()
        .zip(expected)
        .map(|(g, e)| (g - e).abs())
        .fold(0.0, f64::max);
    eprintln!("{what}: {} crossings, worst {worst:.1e}", got.len());
    for (g, e) in got.iter().zip(expected) {
        assert!(
            (g - e).abs() <= TIME_TOL,
            "{what}: crossing at {g} instead of {e} ({:.1e} off)",
            (g - e).abs()
        );
    }
}

#[test]
fn smooth_runs_locate_an_oscillators_zeros() {
    for (amplitude, omega, phase) in [(1.0, 1.0, 0.0), (0.3, 2.7, 0.4), (2.0, 0.8, -1.1)] {
        let oscillator = FnSystem::new(2, move |_t, y: &[f64], dy: &mut [f64]| {
            dy[0] = y[1];
            dy[1] = -omega * omega * y[0];
        });
        let y0 = [
            amplitude * f64::cos(phase),
            -amplitude * omega * f64::sin(phase),
        ];
        let tf = 10.0;
        let zero = |_t: f64, y: &[f64]| y[0];
        let falling = |_t: f64, y: &[f64]| y[0];
        let events = [
            Event::new(&zero),
            Event::new(&falling).direction(EventDirection::Falling),
        ];
        // x = A cos(ω t + φ) is zero at ω t + φ = π/2 + k π, falling for even k.
        let crossings: Vec<(f64, bool)> = (-5..20)
            .map(|k| {
                let t =
                    (std::f64::consts::FRAC_PI_2 + k as f64 * std::f64::consts::PI - phase) / omega;
                (t, k % 2 == 0)
            })
            .filter(|&(t, _)| t > 0.0 && t < tf)
            .collect();
        let all: Vec<f64> = crossings.iter().map(|c| c.0).collect();
        let falls: Vec<f64> = crossings.iter().filter(|c| c.1).map(|c| c.0).collect();
        for method in [
            Method::Dopri5(Options::tolerances(RTOL, ATOL)),
            Method::Sdirk4(Options::tolerances(RTOL, ATOL)),
            Method::Bdf(Options::tolerances(RTOL, ATOL)),
        ] {
            let sol = solve_with_events(&oscillator, &Problem::new(0.0, tf, y0), &method, &events)
                .unwrap();
            let times = |k: usize| -> Vec<f64> {
                sol.events
                    .iter()
                    .filter(|h| h.event == k)
                    .map(|h| h.t)
                    .collect()
            };
            let what = format!("{} ω = {omega}", method.name());
            assert_times(&what, &times(0), &all);
            assert_times(&what, &times(1), &falls);
            assert_eq!(sol.stats.events, sol.events.len());
            assert!(sol.events.windows(2).all(|w| w[0].t <= w[1].t));
            assert_eq!(sol.last().unwrap().0, tf);
        }
    }
}

#[test]
fn a_terminal_event_ends_a_smooth_run_at_the_crossing() {
    let ball = FnSystem::new(2, |_t, y: &[f64], dy: &mut [f64]| {
        dy[0] = y[1];
        dy[1] = -9.81;
    });
    let ground = |_t: f64, y: &[f64]| y[0] + 1.0;
    let events = [Event::new(&ground).terminal()];
    let method = Method::Dopri5(Options::tolerances(RTOL, ATOL));
    let sol = solve_with_events(
        &ball,
        &Problem::new(0.0, 10.0, [0.0, 3.0]),
        &method,
        &events,
    )
    .unwrap();
    // y = 3 t − g t²/2 = −1.
    let t_hit = (3.0 + f64::sqrt(9.0 + 2.0 * 9.81)) / 9.81;
    assert_times("terminal", &[sol.events[0].t], &[t_hit]);
    let (t_end, y_end) = sol.last().unwrap();
    assert_eq!(t_end, sol.events[0].t);
    assert!((y_end[0] + 1.0).abs() < 1e-9);
    // The dense output ends there too.
    assert!(sol.at(t_end + 1e-6).is_none());
}

#[test]
fn event_driven_crossings_on_a_block_sliding_to_rest() {
    for (m, mu, v0) in [(1.0, 2.0, 3.0), (0.5, 0.7, 1.2), (3.0, 9.0, 0.4)] {
        let block = SlidingBlock { m, mu };
        let decel = mu / m;
        let t_rest = v0 / decel;
        let x_rest = 0.5 * v0 * t_rest;
        let d = 0.6 * x_rest;
        let position = |_t: f64, y: &[f64]| y[0] - d;
        let half_speed = |_t: f64, y: &[f64]| y[1] - 0.5 * v0;
        // Past the rest point: never reached, the block sticks.
        let beyond = |_t: f64, y: &[f64]| y[0] - 1.01 * x_rest;
        let events = [
            Event::new(&position),
            Event::new(&half_speed),
            Event::new(&beyond),
        ];
        let problem = NonSmoothProblem::new(0.0, 2.0 * t_rest, V1::zeros(), V1::new(v0));
        let mut run = Integrator::held(&block, &problem, &event_driven())
            .unwrap()
            .with_events(&events)
            .unwrap();
        run.advance_to(problem.tf).unwrap();
        let sol = run.into_solution();
        let t_d = (v0 - f64::sqrt(v0 * v0 - 2.0 * decel * d)) / decel;
        let got: Vec<(usize, f64)> = sol.events.iter().map(|h| (h.event, h.t)).collect();
        assert_eq!(got.len(), 2, "{got:?}");
        assert_eq!((got[0].0, got[1].0), (0, 1), "{got:?}");
        assert_times(
            "position, half speed",
            &[got[0].1, got[1].1],
            &[t_d, t_rest / 2.0],
        );
        // The block stuck exactly at its closed-form rest point.
        let stick = sol
            .switches
            .iter()
            .find(|s| s.to == Some(Mode::Stick))
            .unwrap();
        assert_times("stick", &[stick.t], &[t_rest]);
    }
}

#[test]
fn event_driven_crossings_through_impacts_and_a_terminal_event() {
    for (e, force) in [(0.5, 2.0), (0.8, 0.7), (0.3, 5.0)] {
        let bouncer = Bouncer { m: 1.0, e };
        let a = force;
        let input = move |_t: f64, _q: &V1, _v: &V1| V1::new(force);
        // From rest at x = 0 towards the stop at L = 1: hit at t1, rebound at −e v1.
        let length = 1.0;
        let t1 = f64::sqrt(2.0 * length / a);
        let v1 = a * t1;
        let d = 1.0 - 0.2 * (e * v1).powi(2) / a;
        let disc = (e * v1).powi(2) - 2.0 * a * (length - d);
        let (s_out, s_back) = ((e * v1 - disc.sqrt()) / a, (e * v1 + disc.sqrt()) / a);
        let position = |_t: f64, y: &[f64]| y[0] - d;
        let velocity = |_t: f64, y: &[f64]| y[1];
        let events = [Event::new(&position), Event::new(&velocity)];
        // Before the second impact at t1 + 2 e v1 / a.
        let tf = t1 + 1.9 * e * v1 / a;
        let problem = NonSmoothProblem::new(0.0, tf, V1::zeros(), V1::zeros());
        let mut run = Integrator::new(&bouncer, input, &problem, &event_driven())
            .unwrap()
            .with_events(&events)
            .unwrap();
        run.advance_to(tf).unwrap();
        let sol = run.into_solution();
        let times = |k: usize| -> Vec<f64> {
            sol.events
                .iter()
                .filter(|h| h.event == k)
                .map(|h| h.t)
                .collect()
        };
        let what = format!("e = {e}");
        assert_times(
            &what,
            &times(0),
            &[f64::sqrt(2.0 * d / a), t1 + s_out, t1 + s_back],
        );
        // v jumps from +v1 to −e v1 at the impact (a crossing at its time), then rises
        // through zero at the apex of the rebound.
        assert_times(&what, &times(1), &[t1, t1 + e * v1 / a]);

        // Terminal: the run ends where the block comes back out through d.
        let terminal = [Event::new(&position)
            .direction(EventDirection::Falling)
            .terminal()];
        let mut run = Integrator::new(&bouncer, input, &problem, &event_driven())
            .unwrap()
            .with_events(&terminal)
            .unwrap();
        run.advance_to(tf).unwrap();
        assert_times(&what, &[run.ended().unwrap()], &[t1 + s_out]);
        assert_eq!(run.t(), run.ended().unwrap());
        assert!((run.q()[0] - d).abs() < 1e-9);
        assert!(run.advance_to(tf).is_err(), "the run ended");
        let sol = run.into_solution();
        assert_eq!(sol.last().unwrap().0, sol.events.last().unwrap().t);
    }
}

#[test]
fn time_stepping_crossings_under_a_constant_net_force() {
    for (m, mu, force, h) in [(1.0, 0.5, 2.0, 1e-2), (2.0, 1.0, 7.0, 3e-3)] {
        let block = SlidingBlock { m, mu };
        let input = move |_t: f64, _q: &V1, _v: &V1| V1::new(force);
        let a = (force - mu) / m;
        let v0 = 0.3;
        let marks = [0.05, 0.4, 1.3];
        let fns: Vec<EventFn> = marks
            .iter()
            .map(|&d| Box::new(move |_t: f64, y: &[f64]| y[0] - d) as EventFn)
            .collect();
        let events: Vec<Event> = fns.iter().map(|f| Event::new(f.as_ref())).collect();
        let problem = NonSmoothProblem::new(0.0, 1.5, V1::zeros(), V1::new(v0));
        let method = NonSmoothMethod::TimeStepping { h, theta: 0.5 };
        let mut run = Integrator::new(&block, input, &problem, &method)
            .unwrap()
            .with_events(&events)
            .unwrap();
        run.advance_to(problem.tf).unwrap();
        let sol = run.into_solution();
        let got: Vec<f64> = sol.events.iter().map(|h| h.t).collect();
        // x = v0 t + a t²/2 = d.
        let expected: Vec<f64> = marks
            .iter()
            .map(|d| (-v0 + f64::sqrt(v0 * v0 + 2.0 * a * d)) / a)
            .filter(|&t| t < problem.tf)
            .collect();
        assert_times(&format!("h = {h}"), &got, &expected);
    }
}
