//! Helpers shared by the integration tests.
#![allow(dead_code)]

pub mod random_trees;

use filippov::nalgebra::{DMatrix, DVector, SMatrix, SVector};
use filippov::prelude::*;
use filippov::runtime::numeric;

/// A small deterministic generator (SplitMix64), so tests need no RNG dependency and
/// every failure reproduces.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(seed)
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[lo, hi)`.
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * ((self.next_u64() >> 11) as f64 / (1u64 << 53) as f64)
    }

    pub fn vector<const N: usize>(&mut self, scale: f64) -> SVector<f64, N> {
        SVector::from_fn(|_, _| self.uniform(-scale, scale))
    }
}

pub fn dvec<const N: usize>(v: &SVector<f64, N>) -> DVector<f64> {
    DVector::from_column_slice(v.as_slice())
}

pub fn dmat<const N: usize>(m: &SMatrix<f64, N, N>) -> DMatrix<f64> {
    DMatrix::from_column_slice(N, N, m.as_slice())
}

/// `‖a − b‖ ≤ tol · max(‖b‖, floor)`, with a message naming `what`.
#[track_caller]
pub fn assert_close(a: &[f64], b: &[f64], tol: f64, floor: f64, what: &str) {
    assert_eq!(a.len(), b.len(), "{what}: lengths differ");
    let diff: f64 = a
        .iter()
        .zip(b)
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f64>()
        .sqrt();
    let norm: f64 = b.iter().map(|y| y * y).sum::<f64>().sqrt();
    assert!(
        diff <= tol * norm.max(floor),
        "{what}: relative difference {:.3e} (‖b‖ = {norm:.3e})\n a = {a:?}\n b = {b:?}",
        diff / norm.max(floor)
    );
}

/// Every identity a generated mechanism must satisfy, on random states (see
/// `tests/identities.rs`).
pub const STATES: usize = 25;

/// A scene with every kernel (`emit = all`).
pub trait AllKernels<const N: usize>:
    Mechanism<N>
    + Christoffel<N>
    + Coriolis<N>
    + Gravity<N>
    + Bias<N>
    + PassiveForces<N>
    + InverseDynamics<N>
    + Energy<N>
    + Kinematics<N>
{
}
impl<S, const N: usize> AllKernels<N> for S where
    S: Mechanism<N>
        + Christoffel<N>
        + Coriolis<N>
        + Gravity<N>
        + Bias<N>
        + PassiveForces<N>
        + InverseDynamics<N>
        + Energy<N>
        + Kinematics<N>
{
}

pub fn check<S: AllKernels<N>, const N: usize>(sys: &S, seed: u64) {
    let model = sys.model();
    let mut rng = Rng::new(seed);
    for _ in 0..STATES {
        let q: SVector<f64, N> = rng.vector(3.0);
        let v: SVector<f64, N> = rng.vector(2.0);
        let a: SVector<f64, N> = rng.vector(2.0);
        let tau: SVector<f64, N> = rng.vector(5.0);
        let (qd, vd) = (dvec(&q), dvec(&v));

        // Against the numeric implementation (≤ 1e-12 relative).
        let m = sys.mass_matrix(&q);
        assert_close(
            m.as_slice(),
            numeric::crba(&model, &qd).as_slice(),
            1e-12,
            1e-12,
            "M vs CRBA",
        );
        let c = sys.coriolis_matrix(&q, &v);
        let cn = numeric::coriolis_matrix(&model, &qd, &vd);
        assert_close(
            c.as_slice(),
            cn.as_slice(),
            1e-12,
            1e-9,
            "C vs numeric Christoffel",
        );
        let g = sys.gravity(&q);
        assert_close(
            g.as_slice(),
            numeric::gravity(&model, &qd).as_slice(),
            1e-12,
            1e-12,
            "g",
        );
        let b = sys.bias(&q, &v);
        assert_close(
            b.as_slice(),
            numeric::bias(&model, &qd, &vd).as_slice(),
            1e-12,
            1e-12,
            "bias",
        );
        let id = sys.inverse_dynamics(&q, &v, &a);
        let idn = numeric::inverse_dynamics(&model, &qd, &vd, &dvec(&a));
        assert_close(
            id.as_slice(),
            idn.as_slice(),
            1e-12,
            1e-12,
            "inverse dynamics",
        );
        let fd = sys.forward_dynamics(&q, &v, &tau);
        let fdn = numeric::forward_dynamics(&model, &qd, &vd, &dvec(&tau));
        assert_close(
            fd.as_slice(),
            fdn.as_slice(),
            1e-11,
            1e-12,
            "forward dynamics",
        );
        let p = sys.passive_forces(&q, &v);
        assert_close(
            p.as_slice(),
            numeric::passive_forces(&model, &qd, &vd).as_slice(),
            1e-14,
            1e-14,
            "passive",
        );
        let ke = sys.kinetic_energy(&q, &v);
        assert_close(
            &[ke],
            &[numeric::kinetic_energy(&model, &qd, &vd)],
            1e-12,
            1e-12,
            "kinetic energy",
        );
        let pe = sys.potential_energy(&q);
        assert_close(
            &[pe],
            &[numeric::potential_energy(&model, &qd)],
            1e-12,
            1e-9,
            "potential energy",
        );

        // Christoffel symbols assemble the Coriolis matrix.
        let gam = sys.christoffel_symbols(&q);
        for i in 0..N {
            let row: Vec<f64> = (0..N)
                .map(|j| (0..N).map(|k| gam[i][(j, k)] * v[k]).sum())
                .collect();
            let crow: Vec<f64> = (0..N).map(|j| c[(i, j)]).collect();
            assert_close(&row, &crow, 1e-13, 1e-12, "Σ c_ijk v_k = C_ij");
        }

        // M symmetric positive definite.
        assert_eq!(m, m.transpose(), "M must be exactly symmetric");
        assert!(m.cholesky().is_some(), "M must be positive definite");

        // C v + g = bias.
        assert_close(
            (c * v + g).as_slice(),
            b.as_slice(),
            1e-12,
            1e-12,
            "C v + g vs RNEA bias",
        );

        // Ṁ − 2C skew-symmetric, Ṁ by central differences along v.
        let h = 1e-6;
        let mdot = (sys.mass_matrix(&(q + v * h)) - sys.mass_matrix(&(q - v * h))) / (2.0 * h);
        let s = mdot - c * 2.0;
        let skew = s + s.transpose();
        assert!(
            skew.norm() <= 1e-6 * (1.0 + mdot.norm()),
            "Ṁ − 2C not skew: ‖S + Sᵀ‖ = {:.3e}",
            skew.norm()
        );

        // inverse ∘ forward = identity.
        let back = sys.inverse_dynamics(&q, &v, &fd);
        assert_close(
            back.as_slice(),
            tau.as_slice(),
            1e-10,
            1e-10,
            "ID(FD(τ)) = τ",
        );

        // Symbolic Jacobian against central finite differences.
        let jac = sys.forward_dynamics_jacobian(&q, &v, &tau);
        assert_close(
            jac.acceleration.as_slice(),
            fd.as_slice(),
            1e-13,
            1e-13,
            "Jacobian's acceleration",
        );
        let eps = 1e-6;
        let mut dq = dmat(&jac.d_dq) * 0.0;
        let mut dv = dq.clone();
        for k in 0..N {
            let mut e = SVector::<f64, N>::zeros();
            e[k] = eps;
            let col_q = (sys.forward_dynamics(&(q + e), &v, &tau)
                - sys.forward_dynamics(&(q - e), &v, &tau))
                / (2.0 * eps);
            let col_v = (sys.forward_dynamics(&q, &(v + e), &tau)
                - sys.forward_dynamics(&q, &(v - e), &tau))
                / (2.0 * eps);
            dq.set_column(k, &dvec(&col_q));
            dv.set_column(k, &dvec(&col_v));
        }
        assert_close(
            jac.d_dq.as_slice(),
            dq.as_slice(),
            1e-6,
            1.0,
            "∂v̇/∂q vs finite differences",
        );
        assert_close(
            jac.d_dv.as_slice(),
            dv.as_slice(),
            1e-6,
            1.0,
            "∂v̇/∂v vs finite differences",
        );

        check_kinematics(sys, &model, &q, &v, |s| q + v * s);

        // Power balance: d(T + U)/dt = vᵀ (τ + τ_damping), by central differences along
        // the flow (q̇ = v, v̇ = FD).
        let energy = |q: &SVector<f64, N>, v: &SVector<f64, N>| {
            sys.kinetic_energy(q, v) + sys.potential_energy(q)
        };
        let dt = 1e-6;
        let de = (energy(&(q + v * dt), &(v + fd * dt)) - energy(&(q - v * dt), &(v - fd * dt)))
            / (2.0 * dt);
        let damping: f64 = model
            .dampers
            .iter()
            .map(|d| -d.damping * v[d.coordinate] * v[d.coordinate])
            .sum();
        let power = v.dot(&tau) + damping;
        assert!(
            (de - power).abs() <= 1e-5 * (1.0 + power.abs()),
            "dE/dt = {de}, power = {power}"
        );
    }
}

/// Forward kinematics of every frame at `q`: the bodies' poses against the numeric
/// model's `link_poses`, and every frame's Jacobian against central differences of its
/// generated pose along the flow of `v` (ṗ from the origins, ω from
/// `R(q + h v) R(q − h v)ᵀ`); `flow(s)` is the configuration reached from `q` moving
/// with velocity `v` for time `s`.
pub fn check_kinematics<S: Kinematics<N, NQ>, const N: usize, const NQ: usize>(
    sys: &S,
    model: &numeric::Model,
    q: &SVector<f64, NQ>,
    v: &SVector<f64, N>,
    flow: impl Fn(f64) -> SVector<f64, NQ>,
) {
    let poses = numeric::link_poses(model, &DVector::from_column_slice(q.as_slice()));
    let mut bodies = 0;
    for (i, name) in S::FRAMES.iter().enumerate() {
        let f = S::frame_at(i).expect("in range");
        assert_eq!(S::frame(name), Some(f), "frame `{name}` by name");
        let pose = sys.frame_pose(f, q);
        if let Some(li) = model.links.iter().position(|l| l.name == *name) {
            bodies += 1;
            let r = pose.rotation.to_rotation_matrix().into_inner();
            assert_close(
                r.as_slice(),
                poses[li].rotation.as_slice(),
                1e-13,
                1.0,
                &format!("rotation of `{name}` vs numeric"),
            );
            assert_close(
                pose.translation.vector.as_slice(),
                poses[li].translation.as_slice(),
                1e-13,
                1.0,
                &format!("origin of `{name}` vs numeric"),
            );
        }
        let h = 1e-6;
        let (pp, pm) = (sys.frame_pose(f, &flow(h)), sys.frame_pose(f, &flow(-h)));
        let pdot = (pp.translation.vector - pm.translation.vector) / (2.0 * h);
        let omega = (pp.rotation * pm.rotation.inverse()).scaled_axis() / (2.0 * h);
        let j = sys.frame_jacobian(f, q);
        let twist = j * v;
        let fd: Vec<f64> = pdot.iter().chain(omega.iter()).copied().collect();
        assert_close(
            twist.as_slice(),
            &fd,
            1e-7,
            1.0,
            &format!("J v of `{name}` vs central differences of its pose"),
        );
        let (lin, ang) = sys.frame_velocity(f, q, v);
        assert_eq!(lin.as_slice(), &twist.as_slice()[..3]);
        assert_eq!(ang.as_slice(), &twist.as_slice()[3..]);
    }
    assert_eq!(S::frame("no such frame"), None);
    assert_eq!(S::frame_at(S::FRAMES.len()), None);
    // The translation half of a free joint is a massless link of its own, internal.
    let numeric_bodies = model
        .links
        .iter()
        .filter(|l| !matches!(l.joint, numeric::JointKind::Translation))
        .count();
    assert_eq!(
        bodies, numeric_bodies,
        "every body of the numeric model is a frame"
    );
}

/// [`check_kinematics`] for a scene with spherical or free joints: the flow turns each
/// quaternion by its body angular velocity (`q ⊗ exp(s ω)`) and moves every other slot
/// by its velocity.
pub fn check_kinematics_lie<S, const N: usize, const NQ: usize>(
    sys: &S,
    model: &numeric::Model,
    q: &SVector<f64, NQ>,
    v: &SVector<f64, N>,
) where
    S: Kinematics<N, NQ> + LieMechanism<N, NQ>,
{
    use filippov::nalgebra::Vector3;
    use filippov::runtime::UnitQuat;
    let flow = |s: f64| {
        let mut x = *q;
        for &(slot, c) in S::ROTATIONS {
            let r =
                UnitQuat::try_new(q[slot], q[slot + 1], q[slot + 2], q[slot + 3]).expect("unit");
            let w = Vector3::new(v[c], v[c + 1], v[c + 2]) * s;
            let turned = (r * UnitQuat::exp(&w)).coords();
            x.fixed_rows_mut::<4>(slot).copy_from_slice(&turned);
        }
        for &(slot, c) in S::EUCLID {
            x[slot] = q[slot] + s * v[c];
        }
        x
    };
    check_kinematics(sys, model, q, v, flow);
}

/// `∫ integrand(t, y(t)) dt` over a solution, five-point Gauss–Legendre on each interval
/// between its rows, on its dense output (exact for the interpolant up to degree 9).
pub fn integral(sol: &filippov::runtime::Solution, integrand: &dyn Fn(f64, &[f64]) -> f64) -> f64 {
    const NODES: [(f64, f64); 5] = [
        (-0.906_179_845_938_664, 0.236_926_885_056_189),
        (-0.538_469_310_105_683, 0.478_628_670_499_366),
        (0.0, 0.568_888_888_888_889),
        (0.538_469_310_105_683, 0.478_628_670_499_366),
        (0.906_179_845_938_664, 0.236_926_885_056_189),
    ];
    sol.times()
        .windows(2)
        .filter(|w| w[1] > w[0])
        .map(|w| {
            let (a, b) = (w[0], w[1]);
            NODES
                .iter()
                .map(|&(x, wt)| {
                    let t = 0.5 * (a + b) + 0.5 * (b - a) * x;
                    0.5 * (b - a) * wt * integrand(t, &sol.at(t).expect("inside the run"))
                })
                .sum::<f64>()
        })
        .sum()
}
