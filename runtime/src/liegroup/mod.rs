//! Lie-group integration on products of SO(3) and ℝⁿ (theory §2, "Lie-group joints").
//!
//! A [`LieSystem`] is a second-order system whose configuration `g` lives in
//! `G = SO(3)^m × ℝⁿ` and whose velocity `v ∈ ℝ^(3m + n)` lives in the Lie algebra:
//!
//! ```text
//! y = (g, v),   g = (R_1, …, R_m, x),   v = (ω_1, …, ω_m, u)
//! Ṙ_k = R_k ω̂_k   (body angular velocity, right-trivialised)
//! ẋ   = u         (ℝⁿ: the ordinary derivative)
//! v̇   = f(t, g, v)  (LieSystem::rhs)
//! ```
//!
//! Rotations are stored as [`UnitQuat`]s. There is no chart: configurations advance by
//! `g ← g · exp(θ)` with `θ` small local exponential coordinates, so nothing is singular
//! (no gimbal lock). A free body is `m = 1, n = 3` (SO(3) × ℝ³; the translational
//! velocity is then `ẋ` in world axes), a spherical joint `m = 1`, revolute and
//! prismatic joints add to `n`.
//!
//! Two methods, both Runge–Kutta–Munthe-Kaas (a Runge–Kutta method applied in local
//! exponential coordinates around the step's start, see [`rkmk`]):
//!
//! | method | kind | use |
//! |---|---|---|
//! | [`Rkmk5`] | explicit, Dormand–Prince 5(4), dense output of order 4 | non-stiff problems |
//! | [`LieSdirk`] | L-stable SDIRK4 (order 4, embedded 3), simplified Newton, quartic dense output through the previous point | stiff problems: stiff springs, strong damping |
//!
//! Both are step-level steppers (`drive::LieStepper`: start, then one accepted step at a
//! time, each stored with its chart's extension) under one driver, which validates the
//! problem, checks [`LieEvent`]s after every step and locates them on the dense output
//! (`solve_with_events`), and keeps the accepted steps on failure. It is the group's
//! counterpart of [`Stepper`](crate::Stepper): a state here is a point of the group, not
//! a vector. [`so3`] has the group's functions.

mod chart;
mod drive;
pub mod events;
pub mod implicit;
pub mod mechanism;
pub mod rkmk;
mod trajectory;

pub use crate::geometry::so3;
pub use crate::geometry::so3::UnitQuat;
pub use events::{EventDirection, LieEvent, LieEventHit};
pub use implicit::LieSdirk;
pub use mechanism::{LieInputFn, LieMechanical, LieMechanism, mechanism_rows};
pub use rkmk::Rkmk5;
pub use trajectory::{LieProblem, LieTrajectory};

use nalgebra::{Matrix3, Vector3};

/// A point `y = (g, v)` of a [`LieSystem`]'s state space (see the module documentation).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LieState {
    /// `R_1 … R_m`.
    pub rotations: Vec<UnitQuat>,
    /// `x ∈ ℝⁿ`.
    pub euclid: Vec<f64>,
    /// `v = (ω_1, …, ω_m, u)`, length `3m + n`.
    pub velocity: Vec<f64>,
}

impl LieState {
    pub fn new(rotations: Vec<UnitQuat>, euclid: Vec<f64>, velocity: Vec<f64>) -> Self {
        LieState {
            rotations,
            euclid,
            velocity,
        }
    }

    /// `R_k` as a matrix.
    pub fn rotation_matrix(&self, k: usize) -> Matrix3<f64> {
        self.rotations[k].to_matrix()
    }

    /// `ω_k`, the body angular velocity of rotation `k`.
    pub fn omega(&self, k: usize) -> Vector3<f64> {
        Vector3::from_column_slice(&self.velocity[3 * k..3 * k + 3])
    }

    /// `u`, the velocity of the Euclidean part.
    pub fn euclid_velocity(&self) -> &[f64] {
        &self.velocity[3 * self.rotations.len()..]
    }
}

/// A system on `SO(3)^m × ℝⁿ` with velocities in the Lie algebra (see the module
/// documentation). Only the dynamics `v̇ = f(t, g, v)` are supplied; the kinematics
/// `Ṙ = R ω̂`, `ẋ = u` are fixed.
pub trait LieSystem {
    /// `m`, the number of SO(3) factors.
    fn n_rot(&self) -> usize;

    /// `n`, the number of Euclidean coordinates.
    fn n_euclid(&self) -> usize;

    /// Writes `v̇ = f(t, g, v)` into `dv` (length `3m + n`).
    fn rhs(&self, t: f64, state: &LieState, dv: &mut [f64]);

    /// The Jacobian of the dynamics in local coordinates, for implicit methods
    /// ([`LieSdirk`]): with `n = 3m + n_euclid`, writes the row-major `n × n` blocks
    ///
    /// * `dq[i·n + j] = ∂v̇_i/∂φ_j`, the derivative along `state · exp(s e_j)` at
    ///   `s = 0` (for `j < 3m` the rotation `j / 3` turns about its body axis `j % 3`,
    ///   `R ← R exp(s ê)`; for `j ≥ 3m` the Euclidean coordinate `j − 3m` moves by `s`),
    /// * `dv[i·n + j] = ∂v̇_i/∂v_j`,
    ///
    /// and returns `true`; or returns `false` (the default) when no Jacobian is
    /// available, and the method takes central differences of [`rhs`](Self::rhs).
    fn jacobian(&self, t: f64, state: &LieState, dq: &mut [f64], dv: &mut [f64]) -> bool {
        let _ = (t, state, dq, dv);
        false
    }

    /// Checks the system's own parameters; an error becomes
    /// [`ErrorKind::InvalidInput`](crate::ErrorKind::InvalidInput).
    fn validate(&self) -> Result<(), String> {
        Ok(())
    }

    /// `3m + n`.
    fn n_velocity(&self) -> usize {
        3 * self.n_rot() + self.n_euclid()
    }
}

/// A [`LieSystem`] from a closure `f(t, state, dv)`, for small problems and tests.
pub struct FnLieSystem<F> {
    n_rot: usize,
    n_euclid: usize,
    f: F,
}

impl<F: Fn(f64, &LieState, &mut [f64])> FnLieSystem<F> {
    pub fn new(n_rot: usize, n_euclid: usize, f: F) -> Self {
        FnLieSystem { n_rot, n_euclid, f }
    }
}

impl<F: Fn(f64, &LieState, &mut [f64])> LieSystem for FnLieSystem<F> {
    fn n_rot(&self) -> usize {
        self.n_rot
    }

    fn n_euclid(&self) -> usize {
        self.n_euclid
    }

    fn rhs(&self, t: f64, state: &LieState, dv: &mut [f64]) {
        (self.f)(t, state, dv)
    }
}

#[cfg(test)]
mod tests;
