//! Scenes read from URDF files of real robots (`robots/`): the derive's expansion
//! against the numeric model `Model::from_urdf` reads from the same file — two readers
//! written apart — at random states, and every identity of `common::check`.

mod common;

use filippov::nalgebra::{DVector, SVector, Vector3};
use filippov::prelude::*;
use filippov::runtime::numeric::{self, Model};

#[derive(Mechanism)]
#[mechanism(
    urdf = "robots/panda.urdf",
    lock = [panda_finger_joint1, panda_finger_joint2],
    gravity = [0.0, 0.0, -9.81],
    emit = all
)]
struct PandaUrdf;

#[derive(Mechanism)]
#[mechanism(urdf = "robots/ur5.urdf", gravity = [0.0, 0.0, -9.81], emit = all)]
struct Ur5;

/// M, C v + g and forward dynamics of `sys` against the numeric model, relative to the
/// size of each quantity, at 20 random states.
fn against_numeric<S: common::AllKernels<N>, const N: usize>(sys: &S, model: &Model, seed: u64) {
    assert_eq!(model.dof(), N, "the two readers find the same coordinates");
    let mut rng = common::Rng::new(seed);
    let d = |x: &SVector<f64, N>| DVector::from_column_slice(x.as_slice());
    let rel = |a: &[f64], b: &[f64]| {
        let scale = b.iter().fold(1.0f64, |m, x| m.max(x.abs()));
        a.iter()
            .zip(b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max)
            / scale
    };
    for _ in 0..20 {
        let q = SVector::<f64, N>::from_fn(|_, _| rng.uniform(-3.0, 3.0));
        let v = SVector::<f64, N>::from_fn(|_, _| rng.uniform(-2.0, 2.0));
        let tau = SVector::<f64, N>::from_fn(|_, _| rng.uniform(-10.0, 10.0));
        let m = sys.mass_matrix(&q);
        let m_ref = numeric::crba(model, &d(&q));
        assert!(rel(m.as_slice(), m_ref.as_slice()) < 1e-12, "M");
        let bias = sys.bias(&q, &v);
        let bias_ref = numeric::bias(model, &d(&q), &d(&v));
        assert!(rel(bias.as_slice(), bias_ref.as_slice()) < 1e-12, "C v + g");
        let fd = sys.forward_dynamics(&q, &v, &tau);
        let fd_ref = numeric::forward_dynamics(model, &d(&q), &d(&v), &d(&tau));
        assert!(
            rel(fd.as_slice(), fd_ref.as_slice()) < 1e-10,
            "forward dynamics"
        );
    }
}

#[test]
fn panda_from_urdf_matches_the_numeric_reader() {
    let text = include_str!("../robots/panda.urdf");
    let g = Vector3::new(0.0, 0.0, -9.81);
    let model = Model::from_urdf(
        text,
        g,
        false,
        &["panda_finger_joint1", "panda_finger_joint2"],
    )
    .expect("the file reads");
    assert_eq!(
        PandaUrdf::JOINTS,
        [
            "panda_joint1",
            "panda_joint2",
            "panda_joint3",
            "panda_joint4",
            "panda_joint5",
            "panda_joint6",
            "panda_joint7"
        ]
    );
    against_numeric(&PandaUrdf, &model, 11);
    common::check(&PandaUrdf, 12);
}

#[test]
fn ur5_from_urdf_matches_the_numeric_reader() {
    let text = include_str!("../robots/ur5.urdf");
    let model = Model::from_urdf(text, Vector3::new(0.0, 0.0, -9.81), false, &[]).expect("reads");
    assert_eq!(Ur5::DOF, 6);
    against_numeric(&Ur5, &model, 21);
    common::check(&Ur5, 22);
}
