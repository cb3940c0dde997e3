//! User events (issue 28) on every kind of run, against closed-form crossing times:
//! smooth runs (`solve_with_events`, each method), event-driven runs (a block sliding
//! to rest under friction, a block bouncing on a rigid stop: crossings between the
//! switches and across the impacts' velocity jumps) and time-stepping (a block sliding
//! under a constant net force, which θ = ½ integrates exactly). Lie-group runs use the
//! same `Event` (their closed-form tests are in the runtime: a falling body). Resets:
//! a bouncing ball written as an ODE (smooth runs), kicks on a block under friction and a
//! reset into a rigid stop (event-driven runs); time-stepping refuses them.

use filippov::prelude::*;
use filippov::runtime::nonsmooth::Integrator;
use filippov::runtime::{
    Event, EventDirection, FnSystem, Method, Mode, NonSmoothMethod, NonSmoothProblem, Options,
    Problem, SwitchKind, solve_with_events,
};

const RTOL: f64 = 1e-10;
const ATOL: f64 = 1e-12;
/// The crossing times must match the closed forms to this.
const TIME_TOL: f64 = 1e-9;

type V1 = SVector<f64, 1>;
type EventFn = Box<dyn Fn(f64, &[f64]) -> f64 + Sync>;

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

/// A reset on a smooth run: a ball written as an ODE, its bounce a user event that
/// reverses the velocity with restitution `e`. From rest at height `h` it lands at
/// `√(2h/g)` at speed `√(2gh)`; each flight after a bounce at speed `w` lasts `2w/g`.
#[test]
fn a_reset_event_bounces_a_smooth_ball_at_the_closed_form_times() {
    let g = 9.81;
    let ball = FnSystem::new(2, move |_t, y: &[f64], dy: &mut [f64]| {
        dy[0] = y[1];
        dy[1] = -g;
    });
    let ground = |_t: f64, y: &[f64]| y[0];
    for (h, e) in [(1.0, 0.8), (0.3, 0.5), (2.0, 0.9)] {
        let bounce = move |_t: f64, y: &mut [f64]| y[1] *= -e;
        let events = [Event::new(&ground)
            .direction(EventDirection::Falling)
            .reset(&bounce)];
        let mut expected = vec![f64::sqrt(2.0 * h / g)];
        let mut w = e * f64::sqrt(2.0 * g * h);
        while expected.len() < 5 {
            let last = expected[expected.len() - 1];
            expected.push(last + 2.0 * w / g);
            w *= e;
        }
        let tf = expected[4] + 0.5 * w / g;
        for method in [
            Method::Dopri5(Options::tolerances(RTOL, ATOL)),
            Method::Sdirk4(Options::tolerances(RTOL, ATOL)),
            Method::Bdf(Options::tolerances(RTOL, ATOL)),
        ] {
            let what = format!("{} h = {h}, e = {e}", method.name());
            let sol = solve_with_events(&ball, &Problem::new(0.0, tf, [h, 0.0]), &method, &events)
                .unwrap();
            let got: Vec<f64> = sol.events.iter().map(|hit| hit.t).collect();
            assert_times(&what, &got, &expected);
            // Both sides of each bounce are rows at its time: falling at the landing
            // speed, rising at e times it.
            for (n, &t) in got.iter().enumerate() {
                let rows: Vec<&[f64]> = (0..sol.len())
                    .filter(|&i| sol.times()[i] == t)
                    .map(|i| sol.state(i))
                    .collect();
                assert_eq!(rows.len(), 2, "{what}: bounce {n}");
                let landing = f64::sqrt(2.0 * g * h) * e.powi(n as i32);
                assert!((rows[0][1] + landing).abs() < 1e-8, "{what}: {rows:?}");
                assert!((rows[1][1] - e * landing).abs() < 1e-8, "{what}: {rows:?}");
            }
            assert!(sol.stats.events == 5, "{what}: {}", sol.stats.events);
        }
    }
}

type Clock = Box<dyn Fn(f64, &[f64]) -> f64 + Sync>;
type Push = Box<dyn Fn(f64, &mut [f64]) + Sync>;

/// One time event per kick `(t_k, Δv)`: `t_k − t`, falling through zero at `t_k`, and the
/// reset adding `Δv` to the velocity.
fn kicks_of(kicks: &[(f64, f64)]) -> (Vec<Clock>, Vec<Push>) {
    let clocks = kicks
        .iter()
        .map(|&(tk, _)| Box::new(move |t: f64, _y: &[f64]| tk - t) as Clock)
        .collect();
    let pushes = kicks
        .iter()
        .map(|&(_, dv)| Box::new(move |_t: f64, y: &mut [f64]| y[1] += dv) as Push)
        .collect();
    (clocks, pushes)
}

/// The times of the switch log's entries into a stick.
fn stick_times(sol: &filippov::runtime::Solution) -> Vec<f64> {
    sol.switches
        .iter()
        .filter(|s| s.to == Some(Mode::Stick))
        .map(|s| s.t)
        .collect()
}

fn kick_events<'a>(clocks: &'a [Clock], pushes: &'a [Push]) -> Vec<Event<'a>> {
    clocks
        .iter()
        .zip(pushes)
        .map(|(g, r)| {
            Event::new(g.as_ref())
                .direction(EventDirection::Falling)
                .reset(r.as_ref())
        })
        .collect()
}

/// A reset on an event-driven run: a block at rest under Coulomb friction, kicked at
/// given times (a time event whose reset adds to the velocity). Each kick `Δv` sets it
/// sliding; it decelerates at `f_c/m` and sticks after `m Δv / f_c`, having moved
/// `m Δv² / (2 f_c)`. The log shows the reset, then the friction's stick→slip, then the
/// slip→stick; each kick's time is a row before and after it.
#[test]
fn reset_kicks_on_an_event_driven_block_match_the_closed_form() {
    let (m, mu) = (1.5, 0.6);
    let block = SlidingBlock { m, mu };
    let kicks = [(1.0, 0.6), (3.0, -1.1), (6.5, 0.4)];
    let (clocks, pushes) = kicks_of(&kicks);
    let events = kick_events(&clocks, &pushes);
    let tf = 8.5;
    let problem = NonSmoothProblem::new(0.0, tf, V1::zeros(), V1::zeros());
    let mut run = Integrator::held(&block, &problem, &event_driven())
        .unwrap()
        .with_events(&events)
        .unwrap();
    run.advance_to(tf).unwrap();
    let sol = run.into_solution();
    let decel = mu / m;
    let mut x = 0.0;
    let mut expected_stops = Vec::new();
    for &(tk, dv) in &kicks {
        expected_stops.push(tk + dv.abs() / decel);
        x += dv * dv.abs() / (2.0 * decel);
    }
    let kick_times: Vec<f64> = sol.events.iter().map(|h| h.t).collect();
    assert_times("kicks", &kick_times, &kicks.map(|k| k.0));
    let resets: Vec<f64> = sol
        .switches
        .iter()
        .filter(|s| s.kind == SwitchKind::Reset)
        .map(|s| s.t)
        .collect();
    assert_eq!(resets, kick_times);
    let sticks = stick_times(&sol);
    assert_times("sticks", &sticks, &expected_stops);
    for (tk, dv) in kicks {
        let k = sol
            .switches
            .iter()
            .position(|s| s.kind == SwitchKind::Reset && (s.t - tk).abs() < 1e-9)
            .unwrap();
        let next = &sol.switches[k + 1];
        let slip = if dv > 0.0 {
            Mode::SlipPos(0)
        } else {
            Mode::SlipNeg(0)
        };
        assert_eq!(
            (next.kind, next.from, next.to),
            (SwitchKind::Mode, Some(Mode::Stick), Some(slip))
        );
        assert_eq!(sol.switches[k].after[1] - sol.switches[k].before[1], dv);
    }
    let (_, last) = sol.last().unwrap();
    assert!((last[0] - x).abs() < 1e-9, "x = {}, exact {x}", last[0]);
}

/// A reset that puts a block into its rigid stop is an impact at that instant, applied
/// and logged after the reset.
#[test]
fn a_reset_into_a_rigid_stop_is_an_impact() {
    for e in [0.0, 0.4, 1.0] {
        let bouncer = Bouncer { m: 2.0, e };
        let at_one = |t: f64, _y: &[f64]| 1.0 - t;
        let onto_the_stop = |_t: f64, y: &mut [f64]| {
            y[0] = 1.0;
            y[1] = 3.0;
        };
        let events = [Event::new(&at_one)
            .direction(EventDirection::Falling)
            .reset(&onto_the_stop)];
        let problem = NonSmoothProblem::new(0.0, 2.0, V1::new(0.2), V1::zeros());
        let input = |_t: f64, _q: &V1, _v: &V1| V1::zeros();
        let mut run = Integrator::new(&bouncer, input, &problem, &event_driven())
            .unwrap()
            .with_events(&events)
            .unwrap();
        run.advance_to(2.0).unwrap();
        let sol = run.into_solution();
        let kinds: Vec<SwitchKind> = sol.switches.iter().map(|s| s.kind).collect();
        let impact = if e == 0.0 {
            SwitchKind::Settled
        } else {
            SwitchKind::Impact
        };
        assert_eq!(kinds, [SwitchKind::Reset, impact], "e = {e}");
        assert!((sol.switches[1].before[1] - 3.0).abs() < 1e-12);
        // After the impact at t = 1 the block leaves the stop at e · 3.
        let (t, y) = sol.last().unwrap();
        assert_eq!(t, 2.0);
        assert!(
            (y[0] - (1.0 - 3.0 * e)).abs() < 1e-9,
            "e = {e}: x = {}",
            y[0]
        );
        assert!((y[1] + 3.0 * e).abs() < 1e-9, "e = {e}: v = {}", y[1]);
    }
}

/// Resets on time-stepping: the kicked block of the event-driven test, integrated by
/// implicit Euler. The kicks land at their times exactly (time events), each logged as a
/// reset with the state before and after; the stick times and the final position
/// converge to the closed form at first order (errors at h = 1e-4 at most a quarter of
/// those at 8e-4).
#[test]
fn time_stepping_resets_converge_to_the_kicked_block() {
    let (m, mu) = (1.5, 0.6);
    let block = SlidingBlock { m, mu };
    let kicks: [(f64, f64); 3] = [(1.0, 0.6), (3.0, -1.1), (6.5, 0.4)];
    let decel = mu / m;
    let x_exact: f64 = kicks
        .iter()
        .map(|&(_, dv)| dv * dv.abs() / (2.0 * decel))
        .sum();
    let stops: Vec<f64> = kicks
        .iter()
        .map(|&(tk, dv)| tk + dv.abs() / decel)
        .collect();
    let (clocks, pushes) = kicks_of(&kicks);
    let events = kick_events(&clocks, &pushes);
    let errors = |h: f64| -> (f64, f64) {
        let problem = NonSmoothProblem::new(0.0, 8.5, V1::zeros(), V1::zeros());
        let method = NonSmoothMethod::TimeStepping { h, theta: 1.0 };
        let mut run = Integrator::held(&block, &problem, &method)
            .unwrap()
            .with_events(&events)
            .unwrap();
        run.advance_to(8.5).unwrap();
        let sol = run.into_solution();
        let resets: Vec<&filippov::runtime::Switch> = sol
            .switches
            .iter()
            .filter(|s| s.kind == SwitchKind::Reset)
            .collect();
        assert_eq!(resets.len(), 3, "h = {h}");
        for (s, (tk, dv)) in resets.iter().zip(kicks) {
            assert!((s.t - tk).abs() < 1e-12, "h = {h}: reset at {}", s.t);
            assert!((s.after[1] - s.before[1] - dv).abs() < 1e-12);
        }
        let sticks = stick_times(&sol);
        assert_eq!(sticks.len(), 3, "h = {h}: {sticks:?}");
        let dt = sticks
            .iter()
            .zip(&stops)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        let (_, last) = sol.last().unwrap();
        (dt, (last[0] - x_exact).abs())
    };
    let (coarse, fine) = (errors(8e-4), errors(1e-4));
    eprintln!("time-stepping resets: h = 8e-4 {coarse:?}, h = 1e-4 {fine:?}");
    assert!(fine.0 <= 2e-4 && coarse.0 <= 1.6e-3, "{coarse:?} {fine:?}");
    assert!(fine.1 <= coarse.1 / 4.0, "{coarse:?} {fine:?}");
}
