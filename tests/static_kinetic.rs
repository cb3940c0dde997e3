//! Static and kinetic friction (`#[friction(joint, f_static = …, f_kinetic = …)]`)
//! against the closed form of theory.md §5: a block on a spring, lying on a belt moving
//! at constant speed, sticks and slips on a limit cycle whose stick time, slip time and
//! amplitude are known exactly. Random masses, stiffnesses, friction forces and belt
//! speeds, with kinetic friction well below a third of the static one among them (where,
//! at the end of each slip, slipping on would also be consistent and rest must persist).
//!
//! The belt is modelled in its own frame: the coordinate is `y = x − v_b t`, the spring
//! pulls with `−k y`, and the input adds the rest of the spring force, `−k v_b t`.

mod common;

use common::Rng;
use filippov::prelude::*;
use filippov::runtime::nonsmooth::Mode;
use filippov::runtime::{
    ErrorKind, Method, NonSmoothMethod, NonSmoothProblem, Options, Solution, SwitchKind,
    solve_nonsmooth,
};

#[derive(Mechanism)]
#[body(block, mass = m, com = [0.0, 0.0, 0.0], inertia = point)]
#[joint(y: prismatic(x), parent = world, child = block)]
#[spring(y, k = k)]
#[friction(y, f_static = f_static, f_kinetic = f_kinetic)]
struct Belt {
    m: f64,
    k: f64,
    f_static: f64,
    f_kinetic: f64,
}

/// The same block with Coulomb friction.
#[derive(Mechanism)]
#[body(block, mass = m, com = [0.0, 0.0, 0.0], inertia = point)]
#[joint(y: prismatic(x), parent = world, child = block)]
#[spring(y, k = k)]
#[friction(y, f_crit = f_crit)]
struct CoulombBelt {
    m: f64,
    k: f64,
    f_crit: f64,
}

type V1 = SVector<f64, 1>;

/// The limit cycle of theory.md §5.
struct Cycle {
    /// Time of the first breakaway, starting stuck at `x = 0`.
    first: f64,
    stick: f64,
    slip: f64,
    /// `x` where the block sticks again, `2 x_k − x_s`.
    x_restick: f64,
}

fn cycle(belt: &Belt, v_b: f64) -> Cycle {
    let (x_s, x_k) = (belt.f_static / belt.k, belt.f_kinetic / belt.k);
    let omega = (belt.k / belt.m).sqrt();
    let phi = f64::atan2(v_b / omega, x_s - x_k);
    Cycle {
        first: x_s / v_b,
        stick: 2.0 * (x_s - x_k) / v_b,
        slip: (std::f64::consts::PI + 2.0 * phi) / omega,
        x_restick: 2.0 * x_k - x_s,
    }
}

/// `(breakaways, re-sticks)` of the switch log, with `x = y + v_b t` at each re-stick.
fn switches(sol: &Solution, v_b: f64) -> (Vec<f64>, Vec<(f64, f64)>) {
    let mut away = Vec::new();
    let mut back = Vec::new();
    for s in &sol.switches {
        match (s.kind, s.from, s.to) {
            (SwitchKind::Mode, Some(Mode::Stick), Some(Mode::SlipNeg(_))) => away.push(s.t),
            (SwitchKind::Mode, Some(Mode::SlipNeg(_)), Some(Mode::Stick)) => {
                back.push((s.t, s.after[0] + v_b * s.t))
            }
            other => panic!("unexpected switch {other:?} at t = {}", s.t),
        }
    }
    (away, back)
}

fn run(belt: &Belt, v_b: f64, tf: f64, method: &NonSmoothMethod) -> Solution {
    let k = belt.k;
    let input = move |t: f64, _q: &V1, _v: &V1| V1::new(-k * v_b * t);
    // Riding with the belt at x = 0: at rest in the belt's frame.
    let problem = NonSmoothProblem::new(0.0, tf, V1::new(0.0), V1::new(0.0));
    solve_nonsmooth(belt, &input, &problem, method).expect("the belt run")
}

fn random_belt(rng: &mut Rng) -> (Belt, f64) {
    let f_static = rng.uniform(0.5, 2.0);
    let belt = Belt {
        m: rng.uniform(0.5, 2.0),
        k: rng.uniform(0.5, 3.0),
        f_static,
        f_kinetic: f_static * rng.uniform(0.05, 0.95),
    };
    (belt, rng.uniform(0.1, 0.5))
}

#[test]
fn event_driven_stick_slip_meets_the_closed_form() {
    let tol = 1e-9;
    let mut rng = Rng::new(0x5eed_be17);
    let mut below_a_third = 0;
    for case in 0..12 {
        let (belt, v_b) = random_belt(&mut rng);
        below_a_third += usize::from(belt.f_kinetic < belt.f_static / 3.0);
        let c = cycle(&belt, v_b);
        let period = c.stick + c.slip;
        let tf = c.first + 3.0 * period + 0.5 * c.slip;
        for method in [
            Method::Dopri5(Options::tolerances(1e-12, 1e-14)),
            Method::Sdirk4(Options::tolerances(1e-12, 1e-14)),
        ] {
            let name = method.name();
            let sol = run(&belt, v_b, tf, &NonSmoothMethod::EventDriven(method));
            let (away, back) = switches(&sol, v_b);
            assert_eq!(
                (away.len(), back.len()),
                (4, 3),
                "case {case} {name}: {away:?} {back:?}"
            );
            let mut worst: f64 = 0.0;
            for (n, t) in away.iter().enumerate() {
                let exact = c.first + n as f64 * period;
                worst = worst.max((t - exact).abs());
                assert!(
                    (t - exact).abs() <= tol,
                    "case {case} {name}: breakaway {n} at {t}, exact {exact}"
                );
            }
            for (n, (t, x)) in back.iter().enumerate() {
                let exact = c.first + n as f64 * period + c.slip;
                worst = worst.max((t - exact).abs()).max((x - c.x_restick).abs());
                assert!(
                    (t - exact).abs() <= tol,
                    "case {case} {name}: re-stick {n} at {t}, exact {exact}"
                );
                assert!(
                    (x - c.x_restick).abs() <= tol,
                    "case {case} {name}: re-stick {n} at x = {x}, exact {}",
                    c.x_restick
                );
            }
            eprintln!(
                "case {case} {name}: f_k/f_s = {:.2}, worst {worst:.1e}",
                belt.f_kinetic / belt.f_static
            );
        }
    }
    assert!(below_a_third >= 2, "the sample must reach f_k < f_s/3");
}

/// How far a time-stepping run is from the cycle: `[first breakaway, slip durations,
/// stick durations, re-stick positions]`, worst over two cycles. A stick lasts
/// `(x_s − x)/v_b` for the position `x` it stuck at, so each phase is measured on its own
/// and errors do not add up from cycle to cycle.
fn time_stepping_errors(belt: &Belt, v_b: f64, h: f64) -> [f64; 4] {
    let c = cycle(belt, v_b);
    let tf = c.first + 2.0 * (c.stick + c.slip) + 0.5 * c.slip;
    let sol = run(
        belt,
        v_b,
        tf,
        &NonSmoothMethod::TimeStepping { h, theta: 1.0 },
    );
    let (away, back) = switches(&sol, v_b);
    assert_eq!((away.len(), back.len()), (3, 2), "h = {h}");
    let x_s = belt.f_static / belt.k;
    let mut worst = [(away[0] - c.first).abs(), 0.0, 0.0, 0.0];
    for n in 0..back.len() {
        let (t_back, x) = back[n];
        worst[1] = worst[1].max((t_back - away[n] - c.slip).abs());
        worst[2] = worst[2].max((away[n + 1] - t_back - (x_s - x) / v_b).abs());
        worst[3] = worst[3].max((x - c.x_restick).abs());
    }
    worst
}

/// Time-stepping (implicit Euler, the rest segment taken whenever the step's line
/// crosses `v = 0` inside it) converges to the cycle at first order: the switches sit at
/// step ends, so breakaways and sticks are within a step or two; the slip, damped by
/// implicit Euler, and the position where it ends improve with the step as `O(h)`.
#[test]
fn time_stepping_converges_to_the_cycle_at_first_order() {
    let mut rng = Rng::new(0x7153_0001);
    for case in 0..4 {
        let (belt, v_b) = random_belt(&mut rng);
        let coarse = time_stepping_errors(&belt, v_b, 8e-4);
        let fine = time_stepping_errors(&belt, v_b, 1e-4);
        eprintln!("case {case}: h = 8e-4 {coarse:?}\n        h = 1e-4 {fine:?}");
        for (k, what) in ["first breakaway", "stick"].into_iter().enumerate() {
            let k = [0, 2][k];
            assert!(
                fine[k] <= 2.0 * 1e-4 && coarse[k] <= 2.0 * 8e-4,
                "case {case}: {what} off by {} (h = 1e-4), {} (h = 8e-4)",
                fine[k],
                coarse[k]
            );
        }
        for (k, what) in [(1, "slip"), (3, "re-stick position")] {
            assert!(
                fine[k] <= coarse[k] / 4.0,
                "case {case}: {what} error {} at h = 1e-4 against {} at 8e-4: not first order",
                fine[k],
                coarse[k]
            );
        }
    }
}

/// With `f_static = f_kinetic` the law is Coulomb's: the same run, to round-off.
#[test]
fn equal_forces_are_coulomb_friction() {
    let mut rng = Rng::new(0xc0_1001);
    for _ in 0..4 {
        let (mut belt, v_b) = random_belt(&mut rng);
        belt.f_kinetic = belt.f_static;
        let coulomb = CoulombBelt {
            m: belt.m,
            k: belt.k,
            f_crit: belt.f_static,
        };
        let k = belt.k;
        let input = move |t: f64, _q: &V1, _v: &V1| V1::new(-k * v_b * t);
        let problem = NonSmoothProblem::new(0.0, 20.0, V1::new(0.0), V1::new(0.0));
        for method in [
            NonSmoothMethod::EventDriven(Method::Dopri5(Options::tolerances(1e-10, 1e-12))),
            NonSmoothMethod::TimeStepping {
                h: 1e-3,
                theta: 1.0,
            },
        ] {
            let a = solve_nonsmooth(&belt, &input, &problem, &method).unwrap();
            let b = solve_nonsmooth(&coulomb, &input, &problem, &method).unwrap();
            assert_eq!(a.times(), b.times());
            let diff = a
                .rows()
                .zip(b.rows())
                .flat_map(|((_, x), (_, y))| x.iter().zip(y).map(|(x, y)| (x - y).abs()))
                .fold(0.0, f64::max);
            assert!(diff == 0.0, "{method:?}: rows differ by {diff:e}");
            assert_eq!(a.switches.len(), b.switches.len());
        }
    }
}

/// Kinetic friction above the static one is refused, naming the element.
#[test]
fn kinetic_above_static_is_refused_by_name() {
    let belt = Belt {
        m: 1.0,
        k: 1.0,
        f_static: 0.5,
        f_kinetic: 0.8,
    };
    let err = belt.validate().expect_err("f_kinetic > f_static");
    assert!(
        err.to_string().contains("f_kinetic of `friction_y`"),
        "{err}"
    );
    let input = |_t: f64, _q: &V1, _v: &V1| V1::zeros();
    let problem = NonSmoothProblem::new(0.0, 1.0, V1::new(0.0), V1::new(0.0));
    for method in [
        NonSmoothMethod::default(),
        NonSmoothMethod::TimeStepping {
            h: 1e-3,
            theta: 1.0,
        },
    ] {
        let err = solve_nonsmooth(&belt, &input, &problem, &method).expect_err("refused");
        assert!(
            matches!(err.kind, ErrorKind::InvalidInput(_))
                && err.to_string().contains("friction_y"),
            "{method:?}: {err}"
        );
        assert!(err.to_string().contains("f_kinetic"), "{err}");
    }
}
