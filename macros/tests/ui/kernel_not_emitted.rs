use filippov::prelude::*;

#[derive(Mechanism)]
#[mechanism(gravity = [0.0, -9.81, 0.0])]
#[body(link, mass = m, com = [0.5, 0.0, 0.0], inertia = rod(m, 1.0))]
#[joint(hinge: revolute(z), parent = world, child = link)]
struct Pendulum { m: f64 }

fn total<S: Energy<1>>(s: &S, q: &SVector<f64, 1>, v: &SVector<f64, 1>) -> f64 {
    s.kinetic_energy(q, v) + s.potential_energy(q)
}

fn main() {
    let p = Pendulum { m: 1.0 };
    let q = SVector::<f64, 1>::new(0.1);
    // Without `emit = [energy]` there is no energy kernel: the bound names the option.
    let _ = total(&p, &q, &q);
    // Forward dynamics is always there.
    let _ = p.forward_dynamics(&q, &q, &q);
}
