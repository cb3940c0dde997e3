//! An oblique spatial tree whose masses, length, spring, damper and gravity are
//! parameters, shared by the tests of the generic kernels and of lockstep ensembles
//! (`#[path]`-included, so that only the tests that use it compile it).

use filippov::prelude::*;

/// An oblique spatial tree whose masses, lengths, spring and damper are parameters.
#[derive(Mechanism, Clone, Copy)]
#[mechanism(emit = [generic, inverse_dynamics], gravity = [0.0, 0.0, -g])]
#[body(base, mass = m1, com = [0.1, 0.0, 0.05], inertia = sphere(m1, 0.2))]
#[joint(slide: prismatic([0.6, 0.0, 0.8]), parent = world, child = base, origin = [0.0, 0.0, 1.0], rpy = [0.1, 0.2, 0.3])]
#[spring(slide, k = k)]
#[damper(slide, c = c)]
#[body(arm, mass = m2, com = [l / 2.0, 0.05, 0.0], inertia = rod(m2, l))]
#[joint(shoulder: revolute([0.0, 0.6, 0.8]), parent = base, child = arm, origin = [0.1, 0.2, 0.0], rpy = [0.3, -0.2, 0.5])]
#[body(hand, mass = m3, com = [0.05, 0.0, 0.02], inertia = sphere(m3, 0.05))]
#[joint(wrist: revolute([1.0, 1.0, 0.0]), parent = arm, child = hand, origin = [l, 0.0, 0.1], rpy = [-0.2, 0.1, 0.0])]
pub struct Oblique {
    pub m1: f64,
    pub m2: f64,
    pub m3: f64,
    pub l: f64,
    pub k: f64,
    pub c: f64,
    pub g: f64,
}

/// The tree's reference parameters.
pub const OBLIQUE: Oblique = Oblique {
    m1: 1.0,
    m2: 0.5,
    m3: 0.3,
    l: 0.4,
    k: 20.0,
    c: 0.7,
    g: 9.81,
};
