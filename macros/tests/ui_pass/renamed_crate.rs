//! The crate under another name, as after `fil = { package = "filippov", … }` in
//! Cargo.toml: `#[mechanism(crate = fil)]` makes the generated code use that path.
extern crate filippov as fil;

use fil::nalgebra::SVector;

#[derive(fil::Mechanism)]
#[mechanism(gravity = [0.0, -9.81, 0.0], crate = fil)]
#[body(link, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[joint(hinge: revolute(z), parent = world, child = link)]
struct Pendulum {
    m: f64,
    l: f64,
}

fn main() {
    use fil::Mechanism;
    let p = Pendulum { m: 1.0, l: 1.0 };
    let m = p.mass_matrix(&SVector::<f64, 1>::new(0.3));
    assert!((m[(0, 0)] - 1.0 / 3.0).abs() < 1e-12);
}
