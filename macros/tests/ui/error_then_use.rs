use filippov::prelude::*;
use filippov::runtime::{MechanicalSystem, NonSmoothMethod, NonSmoothProblem, solve_nonsmooth};

// One mistake in the scene (an unknown field), and a program that uses the scene the
// usual ways: the mistake is the only error (no "no method named `mass_matrix`", no
// unsatisfied trait bound at each use).
#[derive(Mechanism)]
#[body(block, mass = m, com = [0.0, 0.0, 0.0], inertia = point)]
#[joint(x: prismatic(x), parent = world, child = block)]
#[friction(x, f_crit = mu)]
struct Block {
    m: f64,
}

fn main() {
    let b = Block { m: 1.0 };
    let q = SVector::<f64, 1>::zeros();
    let m = b.mass_matrix(&q);
    let a = b.forward_dynamics(&q, &q, &q);
    let _ = MechanicalSystem::unforced(&b).ignoring_elements();
    let p = NonSmoothProblem::new(0.0, 1.0, q, q);
    let zero = |_t: f64, _q: &SVector<f64, 1>, _v: &SVector<f64, 1>| SVector::<f64, 1>::zeros();
    let _ = solve_nonsmooth(&b, &zero, &p, &NonSmoothMethod::default());
    println!("{m} {a}");
}
