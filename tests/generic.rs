//! Forward dynamics on any scalar (`emit = [generic]`): on `f64` the same numbers as the
//! `f64` kernel bit for bit; on dual numbers the derivatives with respect to the state
//! equal the symbolic Jacobian the derive writes separately, and those with respect to
//! the parameters equal central differences; on `f32` close to `f64`.

mod common;

use common::Rng;

use filippov::prelude::*;
use filippov::runtime::Dual;
use filippov::runtime::kernels::GenericDynamics;
use filippov::runtime::liegroup::LieMechanism;
use filippov::scenes::{BallChain, Panda};

/// An oblique spatial tree whose masses, lengths, spring and damper are parameters.
#[derive(Mechanism, Clone, Copy)]
#[mechanism(emit = [generic], gravity = [0.0, 0.0, -g])]
#[body(base, mass = m1, com = [0.1, 0.0, 0.05], inertia = sphere(m1, 0.2))]
#[joint(slide: prismatic([0.6, 0.0, 0.8]), parent = world, child = base, origin = [0.0, 0.0, 1.0], rpy = [0.1, 0.2, 0.3])]
#[spring(slide, k = k)]
#[damper(slide, c = c)]
#[body(arm, mass = m2, com = [l / 2.0, 0.05, 0.0], inertia = rod(m2, l))]
#[joint(shoulder: revolute([0.0, 0.6, 0.8]), parent = base, child = arm, origin = [0.1, 0.2, 0.0], rpy = [0.3, -0.2, 0.5])]
#[body(hand, mass = m3, com = [0.05, 0.0, 0.02], inertia = sphere(m3, 0.05))]
#[joint(wrist: revolute([1.0, 1.0, 0.0]), parent = arm, child = hand, origin = [l, 0.0, 0.1], rpy = [-0.2, 0.1, 0.0])]
struct Oblique {
    m1: f64,
    m2: f64,
    m3: f64,
    l: f64,
    k: f64,
    c: f64,
    g: f64,
}

const OBLIQUE: Oblique = Oblique {
    m1: 1.0,
    m2: 0.5,
    m3: 0.3,
    l: 0.4,
    k: 20.0,
    c: 0.7,
    g: 9.81,
};

/// Uniform random arrays from the tests' shared generator.
fn array<const N: usize>(rng: &mut Rng, scale: f64) -> [f64; N] {
    rng.vector::<N>(scale).into()
}

fn bits<const N: usize>(x: &[f64; N]) -> [u64; N] {
    x.map(f64::to_bits)
}

#[test]
fn on_f64_it_is_the_f64_kernel_bit_for_bit() {
    let mut rng = Rng::new(7);
    for _ in 0..50 {
        let (q, v, tau) = (
            array::<3>(&mut rng, 2.0),
            array::<3>(&mut rng, 3.0),
            array::<3>(&mut rng, 5.0),
        );
        let f = OBLIQUE.forward_dynamics(&q.into(), &v.into(), &tau.into());
        let g = OBLIQUE.forward_dynamics_as::<f64>(&q, &v, &tau);
        assert_eq!(bits(&g), bits(&f.into()), "{q:?} {v:?}");
        // The Panda (`emit = all`): seven joints, literal inertias, one parameter.
        let (q, v, tau) = (
            array::<7>(&mut rng, 2.0),
            array::<7>(&mut rng, 3.0),
            array::<7>(&mut rng, 5.0),
        );
        let f = Panda::default().forward_dynamics(&q.into(), &v.into(), &tau.into());
        let g = Panda::default().forward_dynamics_as::<f64>(&q, &v, &tau);
        assert_eq!(bits(&g), bits(&f.into()));
    }
    // A chain with a ball joint (a quaternion: six configuration slots, five
    // velocities), through the Lie-group trait.
    let chain = BallChain::default();
    let slot = <BallChain as LieMechanism<5, 6>>::ROTATIONS[0].0;
    for _ in 0..20 {
        let mut q: [f64; 6] = array(&mut rng, 1.0);
        let norm = q[slot..slot + 4].iter().map(|x| x * x).sum::<f64>().sqrt();
        q[slot..slot + 4].iter_mut().for_each(|x| *x /= norm);
        let (v, tau) = (array::<5>(&mut rng, 3.0), array::<5>(&mut rng, 5.0));
        let f = LieMechanism::forward_dynamics(&chain, &q.into(), &v.into(), &tau.into());
        let g = chain.forward_dynamics_as::<f64>(&q, &v, &tau);
        assert_eq!(bits(&g), bits(&f.into()));
    }
    assert_eq!(
        <Oblique as GenericDynamics<3, 3, 7>>::PARAMETERS,
        ["m1", "m2", "m3", "l", "k", "c", "g"]
    );
}

/// Seeded on `(q, v)`, the duals' derivatives are the columns of `∂v̇/∂q` and `∂v̇/∂v`,
/// which the derive also writes symbolically (`forward_dynamics_jacobian`): two
/// independent differentiations of one expression graph, equal to rounding.
#[test]
fn dual_derivatives_equal_the_symbolic_jacobian() {
    let mut rng = Rng::new(11);
    let mut worst = 0.0f64;
    for _ in 0..50 {
        let (q, v, tau) = (
            array::<7>(&mut rng, 2.0),
            array::<7>(&mut rng, 3.0),
            array::<7>(&mut rng, 5.0),
        );
        let panda = Panda::default();
        let jac = panda.forward_dynamics_jacobian(&q.into(), &v.into(), &tau.into());
        let qd: [Dual<14>; 7] = std::array::from_fn(|i| Dual::variable(q[i], i));
        let vd: [Dual<14>; 7] = std::array::from_fn(|i| Dual::variable(v[i], 7 + i));
        let td = tau.map(Dual::constant);
        let a = panda.forward_dynamics_as(&qd, &vd, &td);
        let scale = jac.d_dq.amax().max(jac.d_dv.amax());
        for i in 0..7 {
            assert_eq!(a[i].re.to_bits(), jac.acceleration[i].to_bits());
            for j in 0..7 {
                worst = worst
                    .max((a[i].eps[j] - jac.d_dq[(i, j)]).abs() / scale)
                    .max((a[i].eps[7 + j] - jac.d_dv[(i, j)]).abs() / scale);
            }
        }
    }
    eprintln!(
        "Panda: duals against the symbolic Jacobian, largest difference {worst:.2e} of its scale"
    );
    assert!(worst <= 1e-12, "{worst:e}");
}

/// Seeded on the parameters, the duals give `∂v̇/∂p`: against central differences of
/// the `f64` kernel in each parameter (step ε^⅓ of it), to 1e-7 of the derivative's
/// scale (the larger of the column's and the accelerations' over the parameter's).
#[test]
fn parameter_sensitivities_equal_central_differences() {
    let mut rng = Rng::new(5);
    let p0 = OBLIQUE.parameters();
    let mut worst = 0.0f64;
    for _ in 0..30 {
        let (q, v, tau) = (
            array::<3>(&mut rng, 2.0),
            array::<3>(&mut rng, 3.0),
            array::<3>(&mut rng, 5.0),
        );
        let pd: [Dual<7>; 7] = std::array::from_fn(|i| Dual::variable(p0[i], i));
        let a = Oblique::forward_dynamics_generic(
            &pd,
            &q.map(Dual::constant),
            &v.map(Dual::constant),
            &tau.map(Dual::constant),
        );
        for (j, &pj) in p0.iter().enumerate() {
            // The step that balances truncation (h²) against rounding (ε/h).
            let h = f64::EPSILON.cbrt() * pj.abs().max(1e-3);
            let at = |x: f64| {
                let mut p = p0;
                p[j] = x;
                Oblique::forward_dynamics_generic(&p, &q, &v, &tau)
            };
            let (up, down) = (at(pj + h), at(pj - h));
            let column: Vec<f64> = (0..3).map(|i| (up[i] - down[i]) / (2.0 * h)).collect();
            // A derivative's natural size: the accelerations' over the parameter's (the
            // differences' rounding is relative to the accelerations, not to a small
            // derivative).
            let natural = a.iter().fold(0.0f64, |m, x| m.max(x.re.abs())) / pj.abs();
            let scale = column.iter().fold(natural, |m, x| m.max(x.abs()));
            for i in 0..3 {
                worst = worst.max((a[i].eps[j] - column[i]).abs() / scale);
            }
        }
    }
    eprintln!(
        "oblique tree: ∂v̇/∂p by duals against central differences, largest {worst:.2e} of its scale"
    );
    assert!(worst <= 1e-7, "{worst:e}");
}

/// `f32` holds about seven digits: its accelerations within 1e-4 of the `f64` ones'
/// scale (measured in the report per robot).
#[test]
fn on_f32_it_is_close_to_f64() {
    let mut rng = Rng::new(3);
    let mut worst = 0.0f64;
    for _ in 0..50 {
        let (q, v, tau) = (
            array::<7>(&mut rng, 2.0),
            array::<7>(&mut rng, 1.0),
            array::<7>(&mut rng, 5.0),
        );
        let f = Panda::default().forward_dynamics_as::<f64>(&q, &v, &tau);
        let g = Panda::default().forward_dynamics_as::<f32>(
            &q.map(|x| x as f32),
            &v.map(|x| x as f32),
            &tau.map(|x| x as f32),
        );
        let scale = f.iter().fold(1.0f64, |m, x| m.max(x.abs()));
        for i in 0..7 {
            worst = worst.max((f64::from(g[i]) - f[i]).abs() / scale);
        }
    }
    eprintln!("Panda: f32 against f64, largest difference {worst:.2e} of the accelerations' scale");
    assert!(worst <= 1e-4, "{worst:e}");
}

/// Four states in the lanes of one `f64x4` call (eight in `f32x8`): each lane is the
/// scalar kernel's result bit for bit.
#[test]
fn simd_lanes_are_the_scalar_kernel_bit_for_bit() {
    use filippov::runtime::real::{f32x8, f64x4};
    let mut rng = Rng::new(23);
    let panda = Panda::default();
    for _ in 0..20 {
        let states: [([f64; 7], [f64; 7], [f64; 7]); 8] = std::array::from_fn(|_| {
            (
                array(&mut rng, 2.0),
                array(&mut rng, 3.0),
                array(&mut rng, 5.0),
            )
        });
        let pack4 = |f: &dyn Fn(usize) -> [f64; 7]| -> [f64x4; 7] {
            std::array::from_fn(|i| f64x4::new(std::array::from_fn(|l| f(l)[i])))
        };
        let a = panda.forward_dynamics_as(
            &pack4(&|l| states[l].0),
            &pack4(&|l| states[l].1),
            &pack4(&|l| states[l].2),
        );
        for l in 0..4 {
            let (q, v, tau) = states[l];
            let scalar = panda.forward_dynamics(&q.into(), &v.into(), &tau.into());
            for i in 0..7 {
                assert_eq!(
                    a[i].to_array()[l].to_bits(),
                    scalar[i].to_bits(),
                    "lane {l}"
                );
            }
        }
        let pack8 = |f: &dyn Fn(usize) -> [f64; 7]| -> [f32x8; 7] {
            std::array::from_fn(|i| f32x8::new(std::array::from_fn(|l| f(l)[i] as f32)))
        };
        let a = panda.forward_dynamics_as(
            &pack8(&|l| states[l].0),
            &pack8(&|l| states[l].1),
            &pack8(&|l| states[l].2),
        );
        for l in 0..8 {
            let (q, v, tau) = states[l];
            let scalar = panda.forward_dynamics_as::<f32>(
                &q.map(|x| x as f32),
                &v.map(|x| x as f32),
                &tau.map(|x| x as f32),
            );
            for i in 0..7 {
                assert_eq!(
                    a[i].to_array()[l].to_bits(),
                    scalar[i].to_bits(),
                    "lane {l}"
                );
            }
        }
    }
}
