use filippov::prelude::*;

#[derive(Mechanism)]
#[body(link, mass = m, com = [0.5, 0.0, 0.0], inertia = rod(m, 1.0))]
#[joint(hinge: revolute(z), parent = world, child = link)]
struct Pendulum { m: f64 }

fn tip<S: Kinematics<1>>(s: &S, q: &SVector<f64, 1>) -> f64 {
    let link = S::frame("link").expect("a body");
    s.frame_pose(link, q).translation.x
}

fn main() {
    // Without `emit = [kinematics]` or a `#[frame]` there is no forward kinematics:
    // the bound names the option.
    let _ = tip(&Pendulum { m: 1.0 }, &SVector::<f64, 1>::new(0.1));
}
