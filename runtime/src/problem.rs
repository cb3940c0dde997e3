//! What is integrated: a first-order system `ẏ = f(t, y)` and its initial-value problem.
//!
//! States are plain slices: the state of an `N`-dof mechanism has `2N` components, and
//! `SVector<f64, {2 * N}>` is not expressible on stable Rust.

use nalgebra::DMatrix;

use crate::Output;

/// A first-order ODE system `ẏ = f(t, y)` of fixed dimension.
pub trait OdeSystem {
    /// Number of state components.
    fn dim(&self) -> usize;

    /// Writes `f(t, y)` into `dy` (both of length [`dim`](Self::dim)).
    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]);

    /// Writes `∂f/∂y (t, y)` into `jac` (`dim × dim`) and returns `true`, or returns
    /// `false` when no analytic Jacobian is available; implicit methods then use forward
    /// finite differences (counted in [`Stats`](crate::Stats)).
    fn jacobian(&self, t: f64, y: &[f64], jac: &mut DMatrix<f64>) -> bool {
        let _ = (t, y, jac);
        false
    }

    /// Names of the state components, used as CSV column headers.
    fn names(&self) -> Vec<String> {
        (0..self.dim()).map(|i| format!("y{i}")).collect()
    }

    /// `Some(n)` when the state is `y = [q; v]` with `q, v` of `n` components each and
    /// `q̇ = v` exactly (the first `n` components of `f(t, y)` are `y[n..2n]`): the form of
    /// a mechanical system. The implicit methods then solve their Newton systems through
    /// an `n × n` Schur complement. `None` (the default) promises nothing.
    fn second_order(&self) -> Option<usize> {
        None
    }

    /// With [`second_order`](Self::second_order): whether DOPRI5, RK4 and SDIRK4 write
    /// the positions' dense output as the quintic Hermite in `q, q̇, q̈ = f[n..2n]` on each
    /// step's two ends ([`DenseStep`](crate::method::DenseStep)) instead of the two-step
    /// quintic: a ninth of its interpolation error, and no earlier point needed. Off by
    /// default: it cost DOPRI5 7 % of its time on the 3- and 4-joint scenes (smooth runs,
    /// where reading back was already within 1.1× of the steps' error). The event-driven
    /// integrator turns it on, where the two-step quintic had missed by 2.18× on S4.
    fn dense_positions(&self) -> bool {
        false
    }

    /// Checks the system's own parameters before anything is integrated; an error
    /// message becomes [`ErrorKind::InvalidInput`](crate::ErrorKind::InvalidInput).
    fn validate(&self) -> Result<(), String> {
        Ok(())
    }

    /// Moves `y` at time `t` back onto an invariant manifold the equations keep only
    /// up to the integration error (a closed mechanism's loop constraints); the drivers
    /// call it after every accepted step and at the start. Returns whether `y` moved;
    /// the default has no manifold.
    fn project(&self, _t: f64, _y: &mut [f64]) -> Result<bool, crate::ErrorKind> {
        Ok(false)
    }

    /// Columns a solution carries after the state, computed from it at each row (a
    /// closed mechanism's constraint forces, `λ_<row>`): their names. None by default.
    /// Between rows they are interpolated linearly.
    fn output_names(&self) -> Vec<String> {
        Vec::new()
    }

    /// The values of [`output_names`](Self::output_names)' columns at `(t, y)`, into
    /// `out` (of their number).
    fn outputs(&self, _t: f64, _y: &[f64], _out: &mut [f64]) {}

    /// How far the manifold of [`project`](Self::project) is from becoming singular at
    /// `y` (`1` far, `0` singular; a closed mechanism's [`loops::conditioning`](crate::loops::conditioning)
    /// (crate::loops::conditioning)); `None` without one. The smooth driver follows it
    /// over each step and stops at a singular point it would step over.
    fn conditioning(&self, _y: &[f64]) -> Option<f64> {
        None
    }
}

/// The number of leading components whose dense output is the positions quintic: the
/// system's [`second_order`](OdeSystem::second_order) `n` when its
/// [`dense_positions`](OdeSystem::dense_positions) is on and `[q; v]` fits the state.
pub(crate) fn dense_positions<S: OdeSystem + ?Sized>(system: &S) -> Option<usize> {
    system
        .second_order()
        .filter(|&n| n > 0 && 2 * n <= system.dim() && system.dense_positions())
}

/// An [`OdeSystem`] from a closure `f(t, y, dy)`, for small problems and tests.
pub struct FnSystem<F> {
    dim: usize,
    f: F,
}

impl<F: Fn(f64, &[f64], &mut [f64])> FnSystem<F> {
    pub fn new(dim: usize, f: F) -> Self {
        FnSystem { dim, f }
    }
}

impl<F: Fn(f64, &[f64], &mut [f64])> OdeSystem for FnSystem<F> {
    fn dim(&self) -> usize {
        self.dim
    }

    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        (self.f)(t, y, dy)
    }
}

/// An initial-value problem: integrate from `(t0, y0)` to `tf ≥ t0`, keeping the rows
/// `output` says (every accepted step by default).
#[derive(Clone, Debug, PartialEq)]
pub struct Problem {
    pub t0: f64,
    pub tf: f64,
    pub y0: Vec<f64>,
    pub output: Output,
}

impl Problem {
    pub fn new(t0: f64, tf: f64, y0: impl Into<Vec<f64>>) -> Self {
        Problem {
            t0,
            tf,
            y0: y0.into(),
            output: Output::Steps,
        }
    }

    /// The same problem keeping the rows `output` says.
    pub fn with_output(mut self, output: Output) -> Self {
        self.output = output;
        self
    }

    /// Checks the problem against the system: `t0`, `tf` finite, `tf ≥ t0`, `y0` of
    /// the system's dimension and finite.
    pub(crate) fn validate(&self, dim: usize) -> Result<(), String> {
        if !self.t0.is_finite() || !self.tf.is_finite() {
            return Err(format!(
                "t0 = {} and tf = {} must be finite",
                self.t0, self.tf
            ));
        }
        if self.tf < self.t0 {
            return Err(format!("tf = {} is before t0 = {}", self.tf, self.t0));
        }
        if self.y0.len() != dim {
            return Err(format!(
                "y0 has {} components but the system has dimension {dim}",
                self.y0.len()
            ));
        }
        if let Some(i) = self.y0.iter().position(|x| !x.is_finite()) {
            return Err(format!("y0[{i}] = {} is not finite", self.y0[i]));
        }
        self.output.validate(self.t0, self.tf)
    }
}
