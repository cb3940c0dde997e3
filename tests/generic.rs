//! The dynamics on any scalar (`emit = [generic]`): on `f64` the same numbers as the
//! `f64` kernels bit for bit (forward dynamics, its Jacobian, the mass matrix, inverse
//! dynamics); on dual numbers the derivatives with respect to the state equal the
//! symbolic Jacobian the derive writes separately, and those with respect to the
//! parameters equal central differences and the complex step; on `f32` close to `f64`;
//! on SIMD lanes each lane the scalar kernel bit for bit. The `f64` kernels are compared
//! bit for bit on their portable path (`runtime::numerics::fused` off); their fused
//! multiply–add twins are compared to rounding.

mod common;
#[path = "../examples/support/complex_step.rs"]
mod complex_step;

use common::Rng;

use filippov::prelude::*;
use filippov::runtime::Dual;
use filippov::runtime::kernels::{GenericDynamics, GenericJacobian};
use filippov::runtime::liegroup::LieMechanism;
use filippov::scenes::{BallChain, Panda};

#[path = "common/oblique.rs"]
mod oblique;
use oblique::{OBLIQUE, Oblique};

/// Uniform random arrays from the tests' shared generator.
fn array<const N: usize>(rng: &mut Rng, scale: f64) -> [f64; N] {
    rng.vector::<N>(scale).into()
}

/// A random state: coordinates within ±2, velocities ±3, torques ±5.
fn state<const N: usize>(rng: &mut Rng) -> ([f64; N], [f64; N], [f64; N]) {
    (array(rng, 2.0), array(rng, 3.0), array(rng, 5.0))
}

/// The kernels' portable path for the rest of the run: their fused multiply–add twins
/// round differently, and the generic kernels on `f64` and most lanes are always
/// portable. (The switch is global; no test here needs it on, `fused_…` call the twins
/// directly.)
fn portable() {
    filippov::runtime::numerics::fused::set_enabled(false);
}

fn bits<const N: usize>(x: &[f64; N]) -> [u64; N] {
    x.map(f64::to_bits)
}

/// A matrix's entries' bits, row by row.
fn matrix_bits<const N: usize>(m: &SMatrix<f64, N, N>) -> Vec<u64> {
    (0..N * N).map(|k| m[(k / N, k % N)].to_bits()).collect()
}

fn rows_bits<const N: usize>(m: &[[f64; N]; N]) -> Vec<u64> {
    m.iter().flatten().map(|x| x.to_bits()).collect()
}

/// The generic mass matrix, inverse dynamics and Jacobian on `f64` against the `f64`
/// kernels, bit for bit.
fn other_kernels_bit_for_bit<S, const N: usize, const P: usize>(
    s: &S,
    q: [f64; N],
    v: [f64; N],
    tau: [f64; N],
) where
    S: Mechanism<N> + InverseDynamics<N> + GenericDynamics<N, N, P>,
{
    let (qs, vs, ts) = (q.into(), v.into(), tau.into());
    assert_eq!(
        rows_bits(&s.mass_matrix_as::<f64>(&q)),
        matrix_bits(&s.mass_matrix(&qs))
    );
    assert_eq!(
        bits(&s.inverse_dynamics_as::<f64>(&q, &v, &tau)),
        bits(&s.inverse_dynamics(&qs, &vs, &ts).into())
    );
    let j: GenericJacobian<f64, N> = s.forward_dynamics_jacobian_as(&q, &v, &tau);
    let f = Mechanism::forward_dynamics_jacobian(s, &qs, &vs, &ts);
    assert_eq!(bits(&j.acceleration), bits(&f.acceleration.into()));
    assert_eq!(rows_bits(&j.d_dq), matrix_bits(&f.d_dq));
    assert_eq!(rows_bits(&j.d_dv), matrix_bits(&f.d_dv));
}

#[test]
fn on_f64_it_is_the_f64_kernel_bit_for_bit() {
    portable();
    let mut rng = Rng::new(7);
    for _ in 0..50 {
        let (q, v, tau) = state::<3>(&mut rng);
        let f = OBLIQUE.forward_dynamics(&q.into(), &v.into(), &tau.into());
        let g = OBLIQUE.forward_dynamics_as::<f64>(&q, &v, &tau);
        assert_eq!(bits(&g), bits(&f.into()), "{q:?} {v:?}");
        other_kernels_bit_for_bit(&OBLIQUE, q, v, tau);
        // The Panda (`emit = all`): seven joints, literal inertias, one parameter.
        let (q, v, tau) = state::<7>(&mut rng);
        let f = Panda::default().forward_dynamics(&q.into(), &v.into(), &tau.into());
        let g = Panda::default().forward_dynamics_as::<f64>(&q, &v, &tau);
        assert_eq!(bits(&g), bits(&f.into()));
        other_kernels_bit_for_bit(&Panda::default(), q, v, tau);
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
        let m = LieMechanism::mass_matrix(&chain, &q.into());
        assert_eq!(rows_bits(&chain.mass_matrix_as::<f64>(&q)), matrix_bits(&m));
        let j = chain.forward_dynamics_jacobian_as::<f64>(&q, &v, &tau);
        let f = LieMechanism::forward_dynamics_jacobian(&chain, &q.into(), &v.into(), &tau.into());
        assert_eq!(rows_bits(&j.d_dq), matrix_bits(&f.d_dq));
        assert_eq!(rows_bits(&j.d_dv), matrix_bits(&f.d_dv));
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
        let (q, v, tau) = state::<7>(&mut rng);
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
        let (q, v, tau) = state::<3>(&mut rng);
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

/// A second differentiation beside the duals: the complex step, `Im f(p + i h e_j) / h`
/// with `h = 1e-100` — no subtraction, so exact to rounding too, but through complex
/// arithmetic and complex elementary functions instead of the chain rule. `∂v̇/∂p` and
/// `∂τ/∂p` (inverse dynamics) of the oblique tree, and `∂v̇/∂q` of the Panda, agree to
/// 1e-12 of their scale.
#[test]
fn dual_sensitivities_equal_the_complex_step() {
    use complex_step::{Complex, H};
    use filippov::runtime::Real;
    let mut rng = Rng::new(29);
    let p0 = OBLIQUE.parameters();
    let mut worst = 0.0f64;
    let mut compare = |dual: &[f64], step: &[f64]| {
        let scale = dual
            .iter()
            .chain(step)
            .fold(1e-300f64, |m, x| m.max(x.abs()));
        for (a, b) in dual.iter().zip(step) {
            worst = worst.max((a - b).abs() / scale);
        }
    };
    for _ in 0..30 {
        let (q, v, tau) = state::<3>(&mut rng);
        let pd: [Dual<7>; 7] = std::array::from_fn(|i| Dual::variable(p0[i], i));
        let (qd, vd, td) = (
            q.map(Dual::constant),
            v.map(Dual::constant),
            tau.map(Dual::constant),
        );
        let a = Oblique::forward_dynamics_generic(&pd, &qd, &vd, &td);
        let id = Oblique::inverse_dynamics_generic(&pd, &qd, &vd, &td);
        let c = |x: [f64; 3]| x.map(Complex::cst);
        for j in 0..7 {
            let pc: [Complex; 7] =
                std::array::from_fn(|i| Complex::new(p0[i], if i == j { H } else { 0.0 }));
            let ac = Oblique::forward_dynamics_generic(&pc, &c(q), &c(v), &c(tau));
            let idc = Oblique::inverse_dynamics_generic(&pc, &c(q), &c(v), &c(tau));
            compare(&a.map(|x| x.eps[j]), &ac.map(|x| x.im / H));
            compare(&id.map(|x| x.eps[j]), &idc.map(|x| x.im / H));
        }
        let (q, v, tau) = state::<7>(&mut rng);
        let panda = Panda::default();
        let qd: [Dual<7>; 7] = std::array::from_fn(|i| Dual::variable(q[i], i));
        let a = panda.forward_dynamics_as(&qd, &v.map(Dual::constant), &tau.map(Dual::constant));
        let c = |x: [f64; 7]| x.map(Complex::cst);
        for j in 0..7 {
            let qc: [Complex; 7] =
                std::array::from_fn(|i| Complex::new(q[i], if i == j { H } else { 0.0 }));
            let ac = panda.forward_dynamics_as(&qc, &c(v), &c(tau));
            compare(&a.map(|x| x.eps[j]), &ac.map(|x| x.im / H));
        }
    }
    eprintln!("duals against the complex step, largest difference {worst:.2e} of the scale");
    assert!(worst <= 1e-12, "{worst:e}");
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

/// A batch through [`pack`](filippov::runtime::real::pack) and `unpack`: the mass matrix,
/// inverse dynamics and the Jacobian of three states in the four lanes of `f64x4` (the
/// fourth lane repeating the third), each the scalar kernel's result bit for bit.
#[test]
fn batches_of_every_kernel_are_the_scalar_kernels_bit_for_bit() {
    portable();
    use filippov::runtime::real::{f64x4, pack, unpack};
    let mut rng = Rng::new(31);
    let panda = Panda::default();
    for _ in 0..20 {
        let q: Vec<[f64; 7]> = (0..3).map(|_| array(&mut rng, 2.0)).collect();
        let v: Vec<[f64; 7]> = (0..3).map(|_| array(&mut rng, 3.0)).collect();
        let a: Vec<[f64; 7]> = (0..3).map(|_| array(&mut rng, 5.0)).collect();
        let (qb, vb, ab): ([f64x4; 7], [f64x4; 7], [f64x4; 7]) = (pack(&q), pack(&v), pack(&a));
        let m = panda.mass_matrix_as(&qb);
        let tau = unpack(&panda.inverse_dynamics_as(&qb, &vb, &ab), 3);
        let j = panda.forward_dynamics_jacobian_as(&qb, &vb, &ab);
        let acc = unpack(&j.acceleration, 3);
        let dq: [Vec<[f64; 7]>; 7] = j.d_dq.map(|r| unpack(&r, 3));
        for s in 0..3 {
            let (qs, vs, as_) = (q[s].into(), v[s].into(), a[s].into());
            let ms = panda.mass_matrix(&qs);
            let rows: [[f64; 7]; 7] = m.map(|r| unpack(&r, 3)[s]);
            assert_eq!(rows_bits(&rows), matrix_bits(&ms), "state {s}");
            assert_eq!(
                bits(&tau[s]),
                bits(&panda.inverse_dynamics(&qs, &vs, &as_).into())
            );
            let f = panda.forward_dynamics_jacobian(&qs, &vs, &as_);
            assert_eq!(bits(&acc[s]), bits(&f.acceleration.into()));
            let rows: [[f64; 7]; 7] = std::array::from_fn(|i| dq[i][s]);
            assert_eq!(rows_bits(&rows), matrix_bits(&f.d_dq));
        }
    }
}

/// States in the lanes of one call, on every batch (`f64x2`, `f64x4`, `f32x4`,
/// `f32x8`): each lane is the scalar kernel's result bit for bit (the `f64` kernel for
/// `f64` lanes, the generic kernel on `f32` for `f32` lanes).
#[test]
fn simd_lanes_are_the_scalar_kernel_bit_for_bit() {
    portable();
    use filippov::runtime::real::{Lanes, f32x4, f32x8, f64x2, f64x4, pack, unpack};
    type State = ([f64; 7], [f64; 7], [f64; 7]);
    /// The accelerations of the first `L::LANES` states, from one call.
    fn lanes<L: Lanes>(panda: &Panda, states: &[State]) -> Vec<[f64; 7]> {
        let take = |k: fn(&State) -> [f64; 7]| -> [L; 7] {
            pack(&states[..L::LANES].iter().map(k).collect::<Vec<_>>())
        };
        let a = panda.forward_dynamics_as(&take(|s| s.0), &take(|s| s.1), &take(|s| s.2));
        unpack(&a, L::LANES)
    }
    let mut rng = Rng::new(23);
    let panda = Panda::default();
    for _ in 0..20 {
        let states: [State; 8] = std::array::from_fn(|_| {
            (
                array(&mut rng, 2.0),
                array(&mut rng, 3.0),
                array(&mut rng, 5.0),
            )
        });
        let f64_kernel: Vec<[f64; 7]> = states
            .iter()
            .map(|(q, v, tau)| {
                panda
                    .forward_dynamics(&(*q).into(), &(*v).into(), &(*tau).into())
                    .into()
            })
            .collect();
        let f32_kernel: Vec<[f64; 7]> = states
            .iter()
            .map(|(q, v, tau)| {
                let f = |x: &[f64; 7]| x.map(|x| x as f32);
                panda
                    .forward_dynamics_as::<f32>(&f(q), &f(v), &f(tau))
                    .map(f64::from)
            })
            .collect();
        for (name, batch, scalar) in [
            ("f64x2", lanes::<f64x2>(&panda, &states), &f64_kernel),
            ("f64x4", lanes::<f64x4>(&panda, &states), &f64_kernel),
            ("f32x4", lanes::<f32x4>(&panda, &states), &f32_kernel),
            ("f32x8", lanes::<f32x8>(&panda, &states), &f32_kernel),
        ] {
            for (l, a) in batch.iter().enumerate() {
                assert_eq!(bits(a), bits(&scalar[l]), "{name}, lane {l}");
            }
        }
    }
}

/// The `f64` forward dynamics and mass matrix run a twin compiled for AVX2 and FMA where
/// the processor has them (`runtime::numerics::fused`): the same algorithm with products
/// fused into sums, so the same numbers to rounding. Called directly here (where the
/// processor has the features), against the generic kernel on `f64`, which is the
/// portable path: the mass matrices within eight units in the last place of their
/// largest entry, the accelerations within the rounding that `M`'s condition number
/// `κ` amplifies, `|Δv̇| ≤ 4 ε κ max(1, |v̇|)` (both measured far below).
#[test]
#[cfg(target_arch = "x86_64")]
fn fused_twins_agree_with_the_portable_kernels() {
    if !filippov::runtime::numerics::fused::available() {
        eprintln!("this processor has no AVX2 and FMA: no fused twins to compare");
        return;
    }
    fn check<S, const N: usize, const P: usize>(
        s: &S,
        q: [f64; N],
        v: [f64; N],
        tau: [f64; N],
        fused: (SVector<f64, N>, SMatrix<f64, N, N>),
        worst: &mut (f64, f64),
    ) where
        S: GenericDynamics<N, N, P>,
    {
        let a = s.forward_dynamics_as::<f64>(&q, &v, &tau);
        let m = s.mass_matrix_as::<f64>(&q);
        let m = SMatrix::<f64, N, N>::from_fn(|i, j| m[i][j]);
        let eig =
            filippov::nalgebra::DMatrix::from_fn(N, N, |i, j| m[(i, j)]).symmetric_eigenvalues();
        let kappa = eig.amax() / eig.amin();
        let scale = a.iter().fold(1.0f64, |x, y| x.max(y.abs()));
        let da = (0..N).fold(0.0f64, |x, i| x.max((fused.0[i] - a[i]).abs()));
        let dm = (fused.1 - m).amax() / m.amax();
        worst.0 = worst.0.max(da / (f64::EPSILON * kappa * scale));
        worst.1 = worst.1.max(dm / f64::EPSILON);
    }
    let mut rng = Rng::new(41);
    let panda = Panda::default();
    let mut worst = (0.0, 0.0);
    for _ in 0..200 {
        let (q, v, tau) = state::<7>(&mut rng);
        let (qs, vs, ts) = (q.into(), v.into(), tau.into());
        // SAFETY: `available` says the processor has AVX2 and FMA.
        let fused = unsafe {
            (
                panda.__forward_dynamics_fused(&qs, &vs, &ts),
                panda.__mass_matrix_fused(&qs),
            )
        };
        check(&panda, q, v, tau, fused, &mut worst);
        let (q, v, tau) = state::<3>(&mut rng);
        let (qs, vs, ts) = (q.into(), v.into(), tau.into());
        // SAFETY: as above.
        let fused = unsafe {
            (
                OBLIQUE.__forward_dynamics_fused(&qs, &vs, &ts),
                OBLIQUE.__mass_matrix_fused(&qs),
            )
        };
        check(&OBLIQUE, q, v, tau, fused, &mut worst);
    }
    eprintln!(
        "fused against portable: accelerations {:.2} ε κ, mass matrices {:.2} ε",
        worst.0, worst.1
    );
    assert!(worst.0 <= 4.0, "accelerations differ by {} ε κ", worst.0);
    assert!(worst.1 <= 8.0, "mass matrices differ by {} ε", worst.1);
}

/// The generic kernels' twins, which the forward dynamics and mass matrix call on `f64x4`
/// lanes where the processor has AVX2 and FMA (`runtime::numerics::fused_lanes`): each
/// lane is the `f64` kernel's fused twin bit for bit, as the portable lanes are the
/// portable kernel's. Called directly (the switch is off in this test binary).
#[test]
#[cfg(target_arch = "x86_64")]
fn fused_lanes_are_the_fused_scalar_kernel_bit_for_bit() {
    use filippov::runtime::Real;
    use filippov::runtime::numerics::fused_lanes::F64x4;
    use filippov::runtime::real::{Lanes, pack, unpack};
    if !filippov::runtime::numerics::fused::available() {
        eprintln!("this processor has no AVX2 and FMA: no fused twins to compare");
        return;
    }
    fn lanes<S, const N: usize, const P: usize>(
        s: &S,
        rng: &mut Rng,
        twins: impl Fn(
            &[F64x4; P],
            &[F64x4; N],
            &[F64x4; N],
            &[F64x4; N],
        ) -> ([F64x4; N], [[F64x4; N]; N]),
        scalar: impl Fn(&[f64; N], &[f64; N], &[f64; N]) -> (SVector<f64, N>, SMatrix<f64, N, N>),
    ) where
        S: GenericDynamics<N, N, P>,
    {
        let states: Vec<([f64; N], [f64; N], [f64; N])> = (0..4).map(|_| state::<N>(rng)).collect();
        let take = |k: fn(&([f64; N], [f64; N], [f64; N])) -> [f64; N]| -> [F64x4; N] {
            pack(&states.iter().map(k).collect::<Vec<_>>())
        };
        let p: [F64x4; P] = s.parameters().map(F64x4::cst);
        let (a, m) = twins(&p, &take(|s| s.0), &take(|s| s.1), &take(|s| s.2));
        for (l, (q, v, tau)) in states.iter().enumerate() {
            let (sa, sm) = scalar(q, v, tau);
            assert_eq!(
                bits(&unpack(&a, 4)[l]),
                bits(&sa.into()),
                "accelerations, lane {l}"
            );
            let ml = SMatrix::<f64, N, N>::from_fn(|i, j| m[i][j].lane(l));
            assert_eq!(matrix_bits(&ml), matrix_bits(&sm), "mass matrix, lane {l}");
        }
    }
    let mut rng = Rng::new(43);
    let panda = Panda::default();
    for _ in 0..50 {
        // SAFETY (all four calls): `available` says the processor has AVX2 and FMA.
        lanes(
            &panda,
            &mut rng,
            |p, q, v, t| unsafe {
                (
                    Panda::__forward_dynamics_generic_fused(p, q, v, t),
                    Panda::__mass_matrix_generic_fused(p, q),
                )
            },
            |q, v, t| unsafe {
                let q = (*q).into();
                (
                    panda.__forward_dynamics_fused(&q, &(*v).into(), &(*t).into()),
                    panda.__mass_matrix_fused(&q),
                )
            },
        );
        lanes(
            &OBLIQUE,
            &mut rng,
            |p, q, v, t| unsafe {
                (
                    Oblique::__forward_dynamics_generic_fused(p, q, v, t),
                    Oblique::__mass_matrix_generic_fused(p, q),
                )
            },
            |q, v, t| unsafe {
                let q = (*q).into();
                (
                    OBLIQUE.__forward_dynamics_fused(&q, &(*v).into(), &(*t).into()),
                    OBLIQUE.__mass_matrix_fused(&q),
                )
            },
        );
    }
}
