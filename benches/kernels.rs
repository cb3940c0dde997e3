//! ns per call of the generated kernels against the plain numeric implementation
//! (`runtime::numeric`, dynamically sized, allocating) on the same scenes and states.
//!
//! Run: `cargo bench --bench kernels`.

use divan::{Bencher, black_box};
use filippov::nalgebra::{DVector, SVector, Vector3};
use filippov::prelude::*;
use filippov::runtime::liegroup::LieMechanism;
use filippov::runtime::{UnitQuat, numeric};
use filippov_scenes::{BallChain, BranchedTree, DoublePendulum, Panda, PlanarArm3, Satellite};

fn main() {
    divan::main();
}

fn state<const N: usize>() -> (SVector<f64, N>, SVector<f64, N>, SVector<f64, N>) {
    let q = SVector::from_fn(|i, _| 0.3 + 0.7 * (i as f64).sin());
    let v = SVector::from_fn(|i, _| 0.5 - 0.4 * (i as f64).cos());
    let tau = SVector::from_fn(|i, _| 0.2 * i as f64);
    (q, v, tau)
}

macro_rules! scene_benches {
    ($module:ident, $ty:ty, $n:literal) => {
        mod $module {
            use super::*;

            #[divan::bench]
            fn forward_dynamics_generated(b: Bencher) {
                let s = <$ty>::default();
                let (q, v, tau) = state::<$n>();
                b.bench(|| s.forward_dynamics(black_box(&q), black_box(&v), black_box(&tau)));
            }

            #[divan::bench]
            fn forward_dynamics_numeric(b: Bencher) {
                let m = <$ty>::default().model();
                let (q, v, tau) = state::<$n>();
                let (q, v, tau) = (
                    DVector::from_column_slice(q.as_slice()),
                    DVector::from_column_slice(v.as_slice()),
                    DVector::from_column_slice(tau.as_slice()),
                );
                b.bench(|| {
                    numeric::forward_dynamics(&m, black_box(&q), black_box(&v), black_box(&tau))
                });
            }

            #[divan::bench]
            fn mass_matrix_generated(b: Bencher) {
                let s = <$ty>::default();
                let (q, _, _) = state::<$n>();
                b.bench(|| s.mass_matrix(black_box(&q)));
            }

            #[divan::bench]
            fn mass_matrix_numeric(b: Bencher) {
                let m = <$ty>::default().model();
                let (q, _, _) = state::<$n>();
                let q = DVector::from_column_slice(q.as_slice());
                b.bench(|| numeric::crba(&m, black_box(&q)));
            }

            #[divan::bench]
            fn coriolis_matrix_generated(b: Bencher) {
                let s = <$ty>::default();
                let (q, v, _) = state::<$n>();
                b.bench(|| s.coriolis_matrix(black_box(&q), black_box(&v)));
            }

            #[divan::bench]
            fn coriolis_matrix_numeric(b: Bencher) {
                let m = <$ty>::default().model();
                let (q, v, _) = state::<$n>();
                let (q, v) = (
                    DVector::from_column_slice(q.as_slice()),
                    DVector::from_column_slice(v.as_slice()),
                );
                b.bench(|| numeric::coriolis_matrix(&m, black_box(&q), black_box(&v)));
            }

            #[divan::bench]
            fn gravity_generated(b: Bencher) {
                let s = <$ty>::default();
                let (q, _, _) = state::<$n>();
                b.bench(|| s.gravity(black_box(&q)));
            }

            #[divan::bench]
            fn gravity_numeric(b: Bencher) {
                let m = <$ty>::default().model();
                let (q, _, _) = state::<$n>();
                let q = DVector::from_column_slice(q.as_slice());
                b.bench(|| numeric::gravity(&m, black_box(&q)));
            }

            #[divan::bench]
            fn forward_dynamics_jacobian_generated(b: Bencher) {
                let s = <$ty>::default();
                let (q, v, tau) = state::<$n>();
                b.bench(|| {
                    s.forward_dynamics_jacobian(black_box(&q), black_box(&v), black_box(&tau))
                });
            }
        }
    };
}

scene_benches!(double_pendulum, DoublePendulum, 2);
scene_benches!(planar_arm3, PlanarArm3, 3);
scene_benches!(branched_tree, BranchedTree, 4);
scene_benches!(panda, Panda, 7);

/// A configuration of a Lie-group scene: every rotation `exp((0.3, −0.5, 0.8))`, the
/// Euclidean slots as in [`state`].
fn lie_state<S: LieMechanism<N, NQ>, const N: usize, const NQ: usize>()
-> (SVector<f64, NQ>, SVector<f64, N>, SVector<f64, N>) {
    let mut q = S::identity_configuration();
    for &(slot, _) in S::ROTATIONS {
        let r = UnitQuat::exp(&Vector3::new(0.3, -0.5, 0.8)).coords();
        q.fixed_rows_mut::<4>(slot).copy_from_slice(&r);
    }
    for &(slot, c) in S::EUCLID {
        q[slot] = 0.3 + 0.7 * (c as f64).sin();
    }
    let (_, v, tau) = state::<N>();
    (q, v, tau)
}

macro_rules! lie_benches {
    ($module:ident, $ty:ty, $n:literal, $nq:literal) => {
        mod $module {
            use super::*;

            #[divan::bench]
            fn forward_dynamics_generated(b: Bencher) {
                let s = <$ty>::default();
                let (q, v, tau) = lie_state::<$ty, $n, $nq>();
                b.bench(|| s.forward_dynamics(black_box(&q), black_box(&v), black_box(&tau)));
            }

            #[divan::bench]
            fn forward_dynamics_numeric(b: Bencher) {
                let m = <$ty>::default().model();
                let (q, v, tau) = lie_state::<$ty, $n, $nq>();
                let (q, v, tau) = (
                    DVector::from_column_slice(q.as_slice()),
                    DVector::from_column_slice(v.as_slice()),
                    DVector::from_column_slice(tau.as_slice()),
                );
                b.bench(|| {
                    numeric::forward_dynamics(&m, black_box(&q), black_box(&v), black_box(&tau))
                });
            }

            #[divan::bench]
            fn mass_matrix_generated(b: Bencher) {
                let s = <$ty>::default();
                let (q, _, _) = lie_state::<$ty, $n, $nq>();
                b.bench(|| s.mass_matrix(black_box(&q)));
            }

            #[divan::bench]
            fn mass_matrix_numeric(b: Bencher) {
                let m = <$ty>::default().model();
                let (q, _, _) = lie_state::<$ty, $n, $nq>();
                let q = DVector::from_column_slice(q.as_slice());
                b.bench(|| numeric::crba(&m, black_box(&q)));
            }

            #[divan::bench]
            fn coriolis_matrix_generated(b: Bencher) {
                let s = <$ty>::default();
                let (q, v, _) = lie_state::<$ty, $n, $nq>();
                b.bench(|| s.coriolis_matrix(black_box(&q), black_box(&v)));
            }

            #[divan::bench]
            fn coriolis_matrix_numeric(b: Bencher) {
                let m = <$ty>::default().model();
                let (q, v, _) = lie_state::<$ty, $n, $nq>();
                let (q, v) = (
                    DVector::from_column_slice(q.as_slice()),
                    DVector::from_column_slice(v.as_slice()),
                );
                b.bench(|| numeric::lie_coriolis_matrix(&m, black_box(&q), black_box(&v)));
            }
        }
    };
}

lie_benches!(satellite, Satellite, 8, 9);
lie_benches!(ball_chain, BallChain, 5, 6);

/// The Panda's forward dynamics on each scalar (`emit = [generic]`): one state per call
/// on `f64`, `f32` and duals (14 directions: `∂v̇/∂(q, v)` with the value), four states
/// per `f64x4` call and eight per `f32x8` call. Divide a batch's time by its lanes for
/// the cost per state.
mod panda_scalars {
    use super::*;
    use filippov::runtime::Dual;
    use filippov::runtime::real::{f32x4, f32x8, f64x2, f64x4};

    fn arrays() -> ([f64; 7], [f64; 7], [f64; 7]) {
        let (q, v, tau) = state::<7>();
        (q.into(), v.into(), tau.into())
    }

    #[divan::bench]
    fn f64_kernel(b: Bencher) {
        let (s, (q, v, tau)) = (Panda::default(), state::<7>());
        b.bench(|| s.forward_dynamics(black_box(&q), black_box(&v), black_box(&tau)));
    }

    #[divan::bench]
    fn f64_generic(b: Bencher) {
        let (s, (q, v, tau)) = (Panda::default(), arrays());
        b.bench(|| s.forward_dynamics_as::<f64>(black_box(&q), black_box(&v), black_box(&tau)));
    }

    #[divan::bench]
    fn f32_generic(b: Bencher) {
        let (s, (q, v, tau)) = (Panda::default(), arrays());
        let f = |x: [f64; 7]| x.map(|x| x as f32);
        let (q, v, tau) = (f(q), f(v), f(tau));
        b.bench(|| s.forward_dynamics_as::<f32>(black_box(&q), black_box(&v), black_box(&tau)));
    }

    #[divan::bench]
    fn f64x4_four_states(b: Bencher) {
        let (s, (q, v, tau)) = (Panda::default(), arrays());
        let f = |x: [f64; 7]| x.map(f64x4::splat);
        let (q, v, tau) = (f(q), f(v), f(tau));
        b.bench(|| s.forward_dynamics_as(black_box(&q), black_box(&v), black_box(&tau)));
    }

    #[divan::bench]
    fn f64x2_two_states(b: Bencher) {
        let (s, (q, v, tau)) = (Panda::default(), arrays());
        let f = |x: [f64; 7]| x.map(f64x2::splat);
        let (q, v, tau) = (f(q), f(v), f(tau));
        b.bench(|| s.forward_dynamics_as(black_box(&q), black_box(&v), black_box(&tau)));
    }

    #[divan::bench]
    fn f32x4_four_states(b: Bencher) {
        let (s, (q, v, tau)) = (Panda::default(), arrays());
        let f = |x: [f64; 7]| x.map(|x| f32x4::splat(x as f32));
        let (q, v, tau) = (f(q), f(v), f(tau));
        b.bench(|| s.forward_dynamics_as(black_box(&q), black_box(&v), black_box(&tau)));
    }

    #[divan::bench]
    fn f32x8_eight_states(b: Bencher) {
        let (s, (q, v, tau)) = (Panda::default(), arrays());
        let f = |x: [f64; 7]| x.map(|x| f32x8::splat(x as f32));
        let (q, v, tau) = (f(q), f(v), f(tau));
        b.bench(|| s.forward_dynamics_as(black_box(&q), black_box(&v), black_box(&tau)));
    }

    #[divan::bench]
    fn dual14_state_derivatives(b: Bencher) {
        let (s, (q, v, tau)) = (Panda::default(), arrays());
        let qd: [Dual<14>; 7] = std::array::from_fn(|i| Dual::variable(q[i], i));
        let vd: [Dual<14>; 7] = std::array::from_fn(|i| Dual::variable(v[i], 7 + i));
        let td = tau.map(Dual::constant);
        b.bench(|| s.forward_dynamics_as(black_box(&qd), black_box(&vd), black_box(&td)));
    }

    #[divan::bench]
    fn symbolic_jacobian(b: Bencher) {
        let (s, (q, v, tau)) = (Panda::default(), state::<7>());
        b.bench(|| s.forward_dynamics_jacobian(black_box(&q), black_box(&v), black_box(&tau)));
    }
}
