//! Bearing friction (`#[friction(joint, mu = …, radius = …)]`, theory §8): Coulomb
//! friction whose limit is `f_crit + μ r |F_⊥|`, `F_⊥` the reaction force the joint
//! transmits.
//!
//! - The generated loads against Newton's law for the joint's subtree, `F = Σ m (a − g)`,
//!   written here from the numeric model's link poses and central differences of the
//!   centres of mass (no generated code), on an oblique spatial tree at random motions.
//! - The time-stepper's friction on the limit of the load it makes, by a closed form of
//!   the loaded slider's rail force, in every sliding step.
//! - The loaded slider converging, as the step shrinks, to the cart that rests on its
//!   rail through two contacts, integrated event-driven (an independent model and
//!   method: the rail's friction there is μ times the contacts' normal forces).
//! - A slider held exactly still by its load; passivity on random scenes; the same
//!   slider beside a contact, by `contact_time_stepping`; the event driver's refusal.

mod common;

use filippov::nalgebra::{DVector, Isometry3, Point3, Vector3};
use filippov::prelude::*;
use filippov::runtime::nonsmooth::NonSmooth;
use filippov::runtime::{
    Method, NonSmoothMethod, NonSmoothProblem, Options, Unforced, contact_event_driven,
    contact_time_stepping, numeric, solve_nonsmooth,
};
use filippov::scenes::{CartOnRail, JournalPendulum, LoadedSlider};

type V2 = SVector<f64, 2>;

/// Time-stepping at step `h` and weight `theta`, without input.
fn time_stepping<S: NonSmooth<N>, const N: usize>(
    s: &S,
    p: &NonSmoothProblem<N>,
    h: f64,
    theta: f64,
) -> Result<filippov::runtime::Solution, filippov::runtime::SolveError> {
    let free = |_: f64, _: &SVector<f64, N>, _: &SVector<f64, N>| SVector::<f64, N>::zeros();
    solve_nonsmooth(s, &free, p, &NonSmoothMethod::TimeStepping { h, theta })
}

/// An oblique tree (nothing axis-aligned to fold, gravity oblique too): a bearing on a
/// prismatic joint carrying two revolute links, and a journal on the middle joint.
#[derive(Mechanism, Clone, Copy)]
#[mechanism(gravity = [0.3, -9.81, 0.5])]
#[body(base, mass = 1.5, com = [0.1, 0.0, 0.05], inertia = sphere(1.5, 0.2))]
#[joint(slide: prismatic([0.6, 0.0, 0.8]), parent = world, child = base, origin = [0.0, 0.0, 1.0], rpy = [0.1, 0.2, 0.3])]
#[body(arm, mass = 0.5, com = [0.2, 0.05, 0.0], inertia = sphere(0.5, 0.1))]
#[joint(shoulder: revolute([0.0, 0.6, 0.8]), parent = base, child = arm, origin = [0.1, 0.2, 0.0], rpy = [0.3, -0.2, 0.5])]
#[body(hand, mass = 0.3, com = [0.05, 0.0, 0.02], inertia = sphere(0.3, 0.05))]
#[joint(wrist: revolute([1.0, 1.0, 0.0]), parent = arm, child = hand, origin = [0.4, 0.0, 0.1], rpy = [-0.2, 0.1, 0.0])]
#[friction(slide, mu = mu, f_crit = 0.5)]
#[friction(shoulder, mu = 0.2, radius = r)]
#[stop(wrist, min = -1.0, max = 1.0, restitution = 0.5)]
struct Oblique {
    mu: f64,
    r: f64,
}

/// `c |F_⊥|` of the bearing on the joint of link `top` (axis `axis` in its frame),
/// from Newton's law for its subtree along the path `q + v t + a t²/2`.
fn reference_load(
    model: &numeric::Model,
    top: usize,
    axis: Vector3<f64>,
    c: f64,
    (q, v, a): (&DVector<f64>, &DVector<f64>, &DVector<f64>),
) -> f64 {
    let inside = |mut i: usize| loop {
        if i == top {
            return true;
        }
        match model.links[i].parent {
            Some(p) => i = p,
            None => return false,
        }
    };
    let com = |t: f64| -> Vec<Point3<f64>> {
        let qt = q + v * t + a * (0.5 * t * t);
        numeric::link_poses(model, &qt)
            .into_iter()
            .zip(&model.links)
            .map(|(pose, link)| Isometry3::<f64>::from(pose) * Point3::from(link.com))
            .collect()
    };
    let d = 1e-4;
    let (before, now, after) = (com(-d), com(0.0), com(d));
    let mut force = Vector3::zeros();
    for (i, link) in model.links.iter().enumerate().filter(|&(i, _)| inside(i)) {
        let acc = (after[i].coords - 2.0 * now[i].coords + before[i].coords) / (d * d);
        force += link.mass * (acc - model.gravity);
    }
    let pose: Isometry3<f64> = numeric::link_poses(model, q)[top].into();
    let s = (pose.rotation * axis).normalize();
    c * (force - s * s.dot(&force)).norm()
}

#[test]
fn generated_loads_are_newtons_law_for_the_subtree() {
    let s = Oblique { mu: 0.35, r: 0.02 };
    assert_eq!(<Oblique as NonSmooth<3>>::BEARINGS, &[0, 1]);
    let model = s.model();
    let mut rng = common::Rng::new(5);
    let mut worst: f64 = 0.0;
    for _ in 0..30 {
        let (q, v, a): (SVector<f64, 3>, SVector<f64, 3>, SVector<f64, 3>) =
            (rng.vector(1.0), rng.vector(2.0), rng.vector(5.0));
        let mut loads = [0.0; 2];
        s.bearing_limits(&q, &v, &a, &mut loads);
        let motion = (&common::dvec(&q), &common::dvec(&v), &common::dvec(&a));
        let expected = [
            reference_load(&model, 0, Vector3::new(0.6, 0.0, 0.8), s.mu, motion),
            reference_load(&model, 1, Vector3::new(0.0, 0.6, 0.8), 0.2 * s.r, motion),
        ];
        for (got, want) in loads.iter().zip(expected) {
            let err = (got - want).abs() / want.abs().max(1e-3);
            worst = worst.max(err);
        }
    }
    // Second differences at d = 1e-4: truncation ~1e-8, rounding ~1e-16/d² ~ 1e-8.
    assert!(
        worst < 1e-6,
        "generated loads off Newton's law by {worst:e}"
    );
}

/// The rail's force on the loaded slider, `F_y = m_c g + m_p (g + ÿ_bob)`, with the bob
/// at `(x + l sin θ, −l cos θ)`: `ÿ_bob = l (θ̈ sin θ + θ̇² cos θ)`.
fn rail_force(s: &LoadedSlider, theta: f64, dtheta: f64, ddtheta: f64) -> f64 {
    let ddy = s.l * (ddtheta * theta.sin() + dtheta * dtheta * theta.cos());
    s.mc * s.g + s.mp * (s.g + ddy)
}

#[test]
fn sliding_friction_is_mu_times_the_rail_force_of_its_step() {
    let s = LoadedSlider::default();
    let (h, theta) = (1e-3, 0.5);
    let q0 = V2::new(0.0, 1.2);
    let p = NonSmoothProblem::new(0.0, 3.0, q0, V2::new(1.5, 0.0));
    let sol = time_stepping(&s, &p, h, theta).unwrap_or_else(|e| panic!("{e}"));
    let f = sol
        .column_index("f_friction_x")
        .expect("the friction's column");
    let (mut sliding, mut stuck, mut worst) = (0, 0, 0.0f64);
    for i in 1..sol.len() {
        let (y0, y1) = (sol.state(i - 1), sol.state(i));
        let dt = sol.times()[i] - sol.times()[i - 1];
        // The step's motion: θ-weighted velocity, mean acceleration.
        let dtheta = y0[3] + theta * (y1[3] - y0[3]);
        let ddtheta = (y1[3] - y0[3]) / dt;
        let angle = y0[1] + theta * dt * y0[3];
        let limit = s.mu * rail_force(&s, angle, dtheta, ddtheta).abs();
        if y1[2] != 0.0 {
            sliding += 1;
            // Resisting the motion, at the limit.
            assert!(
                y1[f] * y1[2] > 0.0,
                "friction along the slide at t = {}",
                sol.times()[i]
            );
            worst = worst.max((y1[f].abs() - limit).abs() / limit);
        } else {
            stuck += 1;
            assert!(
                y1[f].abs() <= limit * (1.0 + 1e-9),
                "stuck beyond the limit"
            );
        }
    }
    assert!(
        sliding > 100 && stuck > 100,
        "{sliding} sliding, {stuck} stuck steps"
    );
    // The limits settle to 1e-12; the passivity guard may scale a step's velocities.
    assert!(worst < 1e-8, "sliding friction off μ |F_⊥| by {worst:e}");
}

/// The loaded slider's distance from the cart on its skids (event-driven at rtol 1e-12)
/// at 1.5 s, by time-stepping at each step of `steps`; `None` where a skid left the
/// rail (the two are the same mechanism only while both skids slide on it).
fn distances(
    rail: &LoadedSlider,
    cart: &CartOnRail,
    swing: f64,
    v0: f64,
    steps: &[f64],
) -> Option<Vec<f64>> {
    assert_eq!(
        (rail.mc, rail.mp, rail.l, rail.mu, rail.g),
        (cart.mc, cart.mp, cart.l, cart.mu, cart.g)
    );
    let tf = 1.5;
    let q0 = SVector::<f64, 4>::from([0.0, cart.b, 0.0, swing]);
    let v0c = SVector::<f64, 4>::from([v0, 0.0, 0.0, 0.0]);
    let p = NonSmoothProblem::new(0.0, tf, q0, v0c);
    let method = Method::Dopri5(Options {
        max_steps: 1_000_000,
        ..Options::tolerances(1e-12, 1e-14)
    });
    let exact =
        contact_event_driven(cart, &Unforced, &p, &method).unwrap_or_else(|e| panic!("{e}"));
    if exact
        .switches
        .iter()
        .any(|w| w.to == Some(filippov::runtime::Mode::Free))
    {
        return None;
    }
    let (_, y) = exact.last().unwrap();
    assert!(
        y[1] == cart.b && y[2].abs() < 1e-12,
        "the cart lifted: {y:?}"
    );
    let reference = [y[0], y[3], y[4], y[7]];
    let p = NonSmoothProblem::new(0.0, tf, V2::new(0.0, swing), V2::new(v0, 0.0));
    Some(
        steps
            .iter()
            .map(|&h| {
                let sol = time_stepping(rail, &p, h, 0.5).unwrap_or_else(|e| panic!("{e}"));
                let (_, y) = sol.last().unwrap();
                (0..4)
                    .map(|j| (y[j] - reference[j]).abs())
                    .fold(0.0, f64::max)
            })
            .collect(),
    )
}

#[test]
fn loaded_slider_converges_to_the_cart_on_contacts() {
    let d = distances(
        &LoadedSlider::default(),
        &CartOnRail::default(),
        1.2,
        0.8,
        &[2e-3, 2e-4],
    )
    .expect("both skids stay on the rail");
    let (coarse, fine) = (d[0], d[1]);
    assert!(
        fine < 1e-4,
        "h = 2e-4: off the contacts' solution by {fine:e}"
    );
    assert!(
        coarse / fine > 4.0,
        "not first order: {coarse:e} → {fine:e}"
    );
}

/// The same on random sliders, pendulums, frictions and launches: time-stepping with the
/// bearing converges at first order (over one of two 4× refinements: two first-order
/// errors of opposite sign can cancel at one step) to the cart on its skids.
#[test]
fn random_loaded_sliders_converge_to_their_carts() {
    let mut rng = common::Rng::new(23);
    let mut compared = 0;
    for k in 0..8 {
        let (mc, mp, l, mu) = (
            rng.uniform(0.5, 3.0),
            rng.uniform(0.2, 2.0),
            rng.uniform(0.2, 0.8),
            rng.uniform(0.05, 0.4),
        );
        let (swing, v0) = (rng.uniform(-1.5, 1.5), rng.uniform(-1.5, 1.5));
        let rail = LoadedSlider {
            mc,
            mp,
            l,
            mu,
            g: 9.81,
        };
        // Skids wide and low, so that the friction's moment seldom lifts one.
        let cart = CartOnRail {
            mc,
            mp,
            l,
            mu,
            a: 0.4,
            b: 0.05,
            g: 9.81,
        };
        let Some(d) = distances(&rail, &cart, swing, v0, &[2e-3, 5e-4, 1.25e-4]) else {
            continue;
        };
        compared += 1;
        eprintln!("draw {k}: {d:?}");
        let scale = 1.0 + swing.abs() + v0.abs();
        assert!(
            d[2] < 1e-3 * scale,
            "draw {k}: off the contacts' solution by {:e}",
            d[2]
        );
        assert!(
            d[1] < d[0] / 2.5 || d[2] < d[1] / 2.5,
            "draw {k}: not first order: {d:?}"
        );
    }
    assert!(
        compared >= 6,
        "only {compared} draws kept both skids on the rail"
    );
}

#[test]
fn a_slider_its_load_holds_stays_exactly_still() {
    // Swinging 0.3 rad: the horizontal pull stays far below μ times the rail's force.
    let s = LoadedSlider {
        mu: 0.5,
        ..LoadedSlider::default()
    };
    let p = NonSmoothProblem::new(0.0, 5.0, V2::new(0.25, 0.3), V2::zeros());
    let sol = time_stepping(&s, &p, 1e-3, 0.5).unwrap_or_else(|e| panic!("{e}"));
    assert!(sol.rows().all(|(_, y)| y[0] == 0.25 && y[2] == 0.0));
    // And the pendulum still swings.
    let swing = sol.component(1);
    assert!(
        swing.iter().any(|&a| a < -0.25),
        "the pendulum did not swing"
    );
}

#[test]
fn random_bearing_scenes_are_passive() {
    let mut rng = common::Rng::new(11);
    for k in 0..12 {
        let s = LoadedSlider {
            mc: rng.uniform(0.2, 3.0),
            mp: rng.uniform(0.2, 3.0),
            l: rng.uniform(0.2, 1.5),
            mu: rng.uniform(0.05, 0.8),
            g: 9.81,
        };
        let q0 = V2::new(0.0, rng.uniform(-2.5, 2.5));
        let v0 = V2::new(rng.uniform(-3.0, 3.0), rng.uniform(-4.0, 4.0));
        let p = NonSmoothProblem::new(0.0, 2.0, q0, v0);
        let theta = if k % 2 == 0 { 0.5 } else { 1.0 };
        let sol =
            time_stepping(&s, &p, 2e-3, theta).unwrap_or_else(|e| panic!("scene {k} ({s:?}): {e}"));
        let energy: Vec<f64> = sol
            .rows()
            .map(|(_, y)| {
                let (q, v) = (V2::new(y[0], y[1]), V2::new(y[2], y[3]));
                s.total_energy(&q, &v)
            })
            .collect();
        let scale = energy.iter().fold(1.0f64, |m, e| m.max(e.abs()));
        for w in energy.windows(2) {
            assert!(
                w[1] <= w[0] + 1e-12 * scale,
                "scene {k}: energy rose {}",
                w[1] - w[0]
            );
        }
    }
}

#[test]
fn a_journal_slows_a_pendulum_and_holds_it() {
    // A journal's friction torque μ r |F| stops the pendulum near the bottom: from then
    // on it is held exactly, within the limit of its (static) load m g.
    let s = JournalPendulum {
        r: 0.05,
        ..JournalPendulum::default()
    };
    type V1 = SVector<f64, 1>;
    let p = NonSmoothProblem::new(0.0, 20.0, V1::new(1.0), V1::zeros());
    let sol = time_stepping(&s, &p, 1e-3, 0.5).unwrap_or_else(|e| panic!("{e}"));
    let (_, y) = sol.last().unwrap();
    assert_eq!(y[1], 0.0, "still moving at the end");
    // Held at rest, the pin carries the weight: |f| ≤ μ r m g, the angle where gravity's
    // torque m g l sin φ equals it is the widest it can rest at.
    let limit = s.mu * s.r * s.m * s.g;
    assert!(y[2].abs() <= limit * (1.0 + 1e-12));
    assert!((s.m * s.g * s.l * y[0].sin()).abs() <= limit * (1.0 + 1e-9));
}

/// The loaded slider beside a ball bouncing on the ground, apart: by
/// `contact_time_stepping` (the bearing in the contact problem) the slider moves as by
/// `time_stepping` alone at the same step, to the methods' first order.
#[derive(Mechanism, Clone, Copy)]
#[mechanism(gravity = [0.0, -9.81, 0.0])]
#[body(slider, mass = 2.0)]
#[joint(x: prismatic(x), parent = world, child = slider)]
#[body(bob, mass = 1.0, com = [0.0, -0.5, 0.0])]
#[joint(swing: revolute(z), parent = slider, child = bob)]
#[friction(x, mu = 0.2)]
#[body(ball, mass = 0.5, inertia = sphere(0.5, 0.1))]
#[joint(height: prismatic(y), parent = world, child = ball, origin = [5.0, 0.0, 0.0])]
#[contact(ground: sphere(0.1), body = ball, plane = world, normal = y, restitution = 0.5)]
struct SliderBesideBall;

#[test]
fn contact_time_stepping_takes_bearings() {
    type V3 = SVector<f64, 3>;
    let (tf, swing, v0) = (1.5, 1.2, 0.8);
    let gap = |h: f64| {
        let p = NonSmoothProblem::new(0.0, tf, V3::new(0.0, swing, 0.5), V3::new(v0, 0.0, 0.0));
        let both = contact_time_stepping(&SliderBesideBall, &Unforced, &p, h)
            .unwrap_or_else(|e| panic!("{e}"));
        let p = NonSmoothProblem::new(0.0, tf, V2::new(0.0, swing), V2::new(v0, 0.0));
        let alone =
            time_stepping(&LoadedSlider::default(), &p, h, 1.0).unwrap_or_else(|e| panic!("{e}"));
        let (b, a) = (both.last().unwrap().1, alone.last().unwrap().1);
        // The ball bounced on the ground, not into it.
        assert!(b[2] > 0.1 - 1e-9, "the ball is at {}", b[2]);
        [(b[0] - a[0]).abs(), (b[1] - a[1]).abs()]
            .into_iter()
            .fold(0.0, f64::max)
    };
    let (coarse, fine) = (gap(2e-3), gap(2e-4));
    assert!(fine < 1e-2 && coarse / fine > 4.0, "{coarse:e} → {fine:e}");
}

#[test]
fn the_event_driver_refuses_bearings_by_name() {
    let s = LoadedSlider::default();
    let p = NonSmoothProblem::new(0.0, 1.0, V2::new(0.0, 0.5), V2::zeros());
    let free = |_: f64, _: &V2, _: &V2| V2::zeros();
    let err = solve_nonsmooth(&s, &free, &p, &NonSmoothMethod::default())
        .expect_err("the event driver does not take bearings");
    let msg = err.to_string();
    assert!(
        msg.contains("`friction_x`") && msg.contains("time_stepping"),
        "{msg}"
    );
}
