//! ns per call of the generated kernels against the plain numeric implementation
//! (`runtime::numeric`, dynamically sized, allocating) on the same scenes and states.
//!
//! Run: `cargo bench --bench kernels`.

use divan::{Bencher, black_box};
use filippov::Mechanism;
use filippov::nalgebra::{DVector, SVector};
use filippov::runtime::numeric;
use filippov::scenes::{BranchedTree, DoublePendulum, Panda, PlanarArm3};

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
