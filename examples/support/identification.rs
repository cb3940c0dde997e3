//! Identifying a URDF arm's link masses and joint friction from noisy joint torques, by
#![allow(dead_code)]
//! Gauss–Newton on the sensitivities dual numbers give (`emit = [generic]`).
//!
//! The arm is the Panda read from its URDF, with the masses of links 2–7 and the
//! Coulomb friction of every joint bound to struct fields (`#[urdf_param]`). Along an
//! exciting trajectory (a sum of sines per joint), the torque a joint needs is
//!
//! ```text
//! τ(p; q, v, a) = ID(p; q, v, a) + f ⊙ sign(v)
//! ```
//!
//! — inverse dynamics (the generated `inverse_dynamics_generic`) plus Coulomb friction
//! opposing the motion (the joints never stop along the trajectory, so `sign(v)` is the
//! sliding law). Measurements add white Gaussian noise of standard deviation `σ` to
//! every torque. Gauss–Newton minimises `Σ |τ_meas − τ(p)|²`; its Jacobian `∂τ/∂p` is
//! one evaluation of `τ` on `Dual<13>` parameters per sample. The same Jacobian gives the
//! Cramér–Rao bound: no unbiased estimator has a covariance below `σ² (JᵀJ)⁻¹`, and least
//! squares on a model linear in `p` (this one is: masses enter the Newton–Euler
//! equations linearly when the inertia tensors and centres of mass are held) attains
//! it.

use filippov::nalgebra::{DMatrix, DVector};
use filippov::prelude::*;
use filippov::runtime::{Dual, Real};

/// The parameters' count: six masses, seven friction coefficients.
pub const P: usize = 13;

/// The Panda with masses of links 2–7 and every joint's Coulomb friction as fields.
#[derive(Mechanism, Clone, Copy, Debug)]
#[mechanism(
    urdf = "robots/panda.urdf",
    lock = [panda_finger_joint1, panda_finger_joint2],
    gravity = [0.0, 0.0, -9.81],
    emit = [generic]
)]
#[urdf_param(
    panda_link2.mass = m2, panda_link3.mass = m3, panda_link4.mass = m4,
    panda_link5.mass = m5, panda_link6.mass = m6, panda_link7.mass = m7,
    panda_joint1.friction = f1, panda_joint2.friction = f2, panda_joint3.friction = f3,
    panda_joint4.friction = f4, panda_joint5.friction = f5, panda_joint6.friction = f6,
    panda_joint7.friction = f7
)]
pub struct Arm {
    pub m2: f64,
    pub m3: f64,
    pub m4: f64,
    pub m5: f64,
    pub m6: f64,
    pub m7: f64,
    pub f1: f64,
    pub f2: f64,
    pub f3: f64,
    pub f4: f64,
    pub f5: f64,
    pub f6: f64,
    pub f7: f64,
}

/// The true arm: the file's masses, and friction of a few newton-metres.
pub const TRUTH: Arm = Arm {
    m2: 0.646926,
    m3: 3.228604,
    m4: 3.587895,
    m5: 1.225946,
    m6: 1.666555,
    m7: 0.735522,
    f1: 1.2,
    f2: 1.5,
    f3: 0.9,
    f4: 1.1,
    f5: 0.5,
    f6: 0.4,
    f7: 0.3,
};

/// One sample: the state, the acceleration and the measured torques.
#[derive(Clone, Copy, Debug)]
pub struct Sample {
    pub t: f64,
    pub q: [f64; 7],
    pub v: [f64; 7],
    pub a: [f64; 7],
    pub tau: [f64; 7],
}

/// The exciting trajectory: per joint `q_i(t) = c_i + Σ_k A_ik sin(ω_k t + φ_ik)` and its
/// derivatives, with a velocity offset so that no joint's velocity crosses zero (Coulomb
/// friction then acts with one sign per joint).
pub fn trajectory(t: f64) -> ([f64; 7], [f64; 7], [f64; 7]) {
    const W: [f64; 3] = [0.7, 1.3, 2.9];
    let (mut q, mut v, mut a) = ([0.0; 7], [0.0; 7], [0.0; 7]);
    for i in 0..7 {
        let fi = i as f64;
        // A drift of 0.25 rad/s (alternating in sign) and three harmonics whose speeds
        // add to less than it.
        let drift = if i % 2 == 0 { 0.25 } else { -0.25 };
        q[i] = 0.3 * (fi - 3.0) / 3.0 + drift * t;
        v[i] = drift;
        for (k, w) in W.iter().enumerate() {
            let amp = 0.06 / w * (1.0 + 0.1 * k as f64);
            let phase = 0.9 * fi + 1.7 * k as f64;
            q[i] += amp * (w * t + phase).sin();
            v[i] += amp * w * (w * t + phase).cos();
            a[i] -= amp * w * w * (w * t + phase).sin();
        }
    }
    (q, v, a)
}

/// The torques the model predicts at parameters `p`, on any scalar.
pub fn torques<T: Real>(p: &[T; P], q: &[f64; 7], v: &[f64; 7], a: &[f64; 7]) -> [T; 7] {
    let c = |x: &[f64; 7]| x.map(T::cst);
    let mut tau = Arm::inverse_dynamics_generic(p, &c(q), &c(v), &c(a));
    for i in 0..7 {
        let sign = if v[i] > 0.0 { 1.0 } else { -1.0 };
        tau[i] = tau[i] + p[6 + i] * T::cst(sign);
    }
    tau
}

/// A small deterministic generator of standard normal numbers (64-bit LCG, Box–Muller).
pub struct Normal(u64);

impl Normal {
    pub fn new(seed: u64) -> Normal {
        Normal(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }

    fn uniform(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }

    pub fn sample(&mut self) -> f64 {
        let (u, w) = (self.uniform(), self.uniform());
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * w).cos()
    }
}

/// `count` samples over `[0, duration]` of the true arm's torques plus noise `σ`.
pub fn measure(count: usize, duration: f64, sigma: f64, seed: u64) -> Vec<Sample> {
    let truth = TRUTH.parameters();
    let mut noise = Normal::new(seed);
    (0..count)
        .map(|k| {
            let t = duration * k as f64 / (count - 1).max(1) as f64;
            let (q, v, a) = trajectory(t);
            let tau = torques::<f64>(&truth, &q, &v, &a).map(|x| x + sigma * noise.sample());
            Sample { t, q, v, a, tau }
        })
        .collect()
}

/// The residuals `τ_meas − τ(p)` and the Jacobian `∂τ/∂p` (rows: samples × joints), the
/// latter from one evaluation on dual numbers per sample.
pub fn linearise(samples: &[Sample], p: &[f64; P]) -> (DVector<f64>, DMatrix<f64>) {
    let rows = 7 * samples.len();
    let mut r = DVector::zeros(rows);
    let mut j = DMatrix::zeros(rows, P);
    let pd: [Dual<P>; P] = std::array::from_fn(|k| Dual::variable(p[k], k));
    for (s, x) in samples.iter().enumerate() {
        let tau = torques(&pd, &x.q, &x.v, &x.a);
        for i in 0..7 {
            r[7 * s + i] = x.tau[i] - tau[i].re;
            for k in 0..P {
                j[(7 * s + i, k)] = tau[i].eps[k];
            }
        }
    }
    (r, j)
}

/// What Gauss–Newton found.
#[derive(Clone, Debug)]
pub struct Estimate {
    pub parameters: [f64; P],
    /// Iterations until the step was below 1e-10 of the parameters.
    pub iterations: usize,
    /// The Cramér–Rao bound at the estimate, `σ² (JᵀJ)⁻¹`.
    pub covariance: DMatrix<f64>,
    /// The residuals' RMS at the estimate (an estimate of `σ`).
    pub rms: f64,
}

/// Why Gauss–Newton stopped without an estimate.
#[derive(Clone, Debug)]
pub enum IdentificationError {
    /// `JᵀJ` is not positive definite: the trajectory does not excite every parameter.
    NotIdentifiable,
    /// No convergence within the iteration budget.
    NoConvergence { iterations: usize },
}

impl std::fmt::Display for IdentificationError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            IdentificationError::NotIdentifiable => write!(
                f,
                "the trajectory does not excite every parameter (JᵀJ is singular): lengthen it or add harmonics"
            ),
            IdentificationError::NoConvergence { iterations } => {
                write!(
                    f,
                    "Gauss–Newton did not converge in {iterations} iterations"
                )
            }
        }
    }
}

/// Gauss–Newton from `start`: `p ← p + (JᵀJ)⁻¹ Jᵀ r` until the step is below 1e-10 of
/// the parameters; the bound with the noise's `σ`.
pub fn gauss_newton(
    samples: &[Sample],
    start: [f64; P],
    sigma: f64,
) -> Result<Estimate, IdentificationError> {
    let mut p = start;
    for iteration in 1..=20 {
        let (r, j) = linearise(samples, &p);
        let normal = j.transpose() * &j;
        let chol = normal
            .clone()
            .cholesky()
            .ok_or(IdentificationError::NotIdentifiable)?;
        let step = chol.solve(&(j.transpose() * &r));
        let size = p.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        for k in 0..P {
            p[k] += step[k];
        }
        if step.amax() <= 1e-10 * size {
            let (r, _) = linearise(samples, &p);
            return Ok(Estimate {
                parameters: p,
                iterations: iteration,
                covariance: chol.inverse() * (sigma * sigma),
                rms: (r.norm_squared() / r.len() as f64).sqrt(),
            });
        }
    }
    Err(IdentificationError::NoConvergence { iterations: 20 })
}

/// The parameters' names as declared.
pub fn names() -> [&'static str; P] {
    <Arm as GenericDynamics<7, 7, P>>::PARAMETERS
}
