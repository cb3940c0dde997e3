//! Springs between two points (`#[spring(name: between(a, b), …)]`): on an oblique
//! spatial tree under gravity, one spring from a fixed point to a body and one between
//! two bodies on different branches, every generated kernel against the numeric
//! implementation (its point-spring forces computed from link poses and joint axes, not
//! by differentiation) and against finite differences, at random states
//! (`common::check`); and a planar pendulum on a spring against its closed-form force.

mod common;

use filippov::prelude::*;

#[derive(Mechanism)]
#[mechanism(emit = all, gravity = [0.0, 0.0, -9.81])]
#[body(b1, mass = 1.0, com = [0.1, 0.2, 0.0], inertia = cuboid(1.0, 0.3, 0.1, 0.1))]
#[joint(j1: revolute([0.3, 0.5, 0.8]), parent = world, child = b1, origin = [0.1, -0.2, 0.3], rpy = [0.2, 0.1, -0.3])]
#[body(b2, mass = 0.7, com = [0.2, 0.0, 0.1], inertia = cuboid(0.7, 0.2, 0.1, 0.1))]
#[joint(j2: revolute(x), parent = b1, child = b2, origin = [0.4, 0.1, -0.2], rpy = [0.1, 0.2, 0.3])]
#[body(b3, mass = 0.5, com = [0.0, 0.1, 0.1], inertia = sphere(0.5, 0.1))]
#[joint(j3: prismatic([0.0, 0.6, 0.8]), parent = world, child = b3, origin = [1.0, 0.2, 0.0], rpy = [0.0, 0.4, 0.0])]
#[spring(anchor: between(world, b2), k = ka, rest = 0.3, from = [0.5, 0.5, 1.0], to = [0.1, 0.0, 0.2])]
#[spring(link: between(b1, b3), k = kb, rest = 0.8, from = [0.2, 0.1, 0.0], to = [0.0, 0.1, 0.05])]
struct Sprung {
    ka: f64,
    kb: f64,
}

#[test]
fn point_springs_match_the_numeric_model() {
    common::check(&Sprung { ka: 40.0, kb: 25.0 }, 40);
}

/// A rod hanging from a pivot, pulled by a spring from the fixed point `(0, h)` to its
/// tip: the generalised force is `−k (ℓ − L) ∂ℓ/∂θ` with `ℓ` the distance from the
/// fixed point to the tip `(l cos θ, l sin θ)`.
#[derive(Mechanism)]
#[mechanism(emit = [passive_forces, energy])]
#[body(rod, mass = 1.0, com = [l / 2.0, 0.0, 0.0], inertia = rod(1.0, l))]
#[joint(pivot: revolute(z), parent = world, child = rod)]
#[spring(pull: between(world, rod), k = k, rest = rest, from = [0.0, h, 0.0], to = [l, 0.0, 0.0])]
struct Pulled {
    l: f64,
    h: f64,
    k: f64,
    rest: f64,
}

#[test]
fn a_pulled_rod_has_its_closed_form_force() {
    use filippov::runtime::kernels::{Energy, PassiveForces};
    let s = Pulled {
        l: 0.7,
        h: 0.4,
        k: 30.0,
        rest: 0.2,
    };
    let mut rng = common::Rng::new(41);
    for _ in 0..20 {
        let theta = rng.uniform(-3.0, 3.0);
        let (dx, dy) = (s.l * theta.cos(), s.l * theta.sin() - s.h);
        let length = (dx * dx + dy * dy).sqrt();
        // ∂ℓ/∂θ = (dx · (−l sin θ) + dy · l cos θ) / ℓ.
        let dl = (dx * (-s.l * theta.sin()) + dy * s.l * theta.cos()) / length;
        let force = -s.k * (length - s.rest) * dl;
        let q = SVector::from([theta]);
        let got = s.passive_forces(&q, &SVector::zeros())[0];
        assert!(
            (got - force).abs() < 1e-12 * (1.0 + force.abs()),
            "{got} against {force}"
        );
        let u = 0.5 * s.k * (length - s.rest).powi(2);
        assert!((s.potential_energy(&q) - u).abs() < 1e-13);
    }
}
