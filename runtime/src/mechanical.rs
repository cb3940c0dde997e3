//! [`OdeSystem`] adapters for mechanisms: state `y = [q; v]`, `ẏ = [v; FD(q, v, τ)]`.

use nalgebra::{DMatrix, DVector, SVector};

use crate::OdeSystem;
use crate::numeric::{self, Model};
use crate::system::Mechanism;

/// An input-force law `τ(t, q, v)` for [`MechanicalSystem`].
pub type InputFn<const N: usize> = fn(f64, &SVector<f64, N>, &SVector<f64, N>) -> SVector<f64, N>;

fn zero_input<const N: usize>(_: f64, _: &SVector<f64, N>, _: &SVector<f64, N>) -> SVector<f64, N> {
    SVector::zeros()
}

/// A generated [`Mechanism`] driven by input forces `τ(t, q, v)`, as a first-order
/// system of dimension `2N` with `y = [q; v]`.
///
/// The right-hand side copies the slices into stack vectors (no allocation) and calls
/// [`Mechanism::forward_dynamics`]. The Jacobian comes from
/// [`Mechanism::forward_dynamics_jacobian`], which holds `τ` fixed: it is exact only
/// when the input does not depend on the state. For state feedback `τ(t, q, v)` it is
/// an approximation that still serves a simplified Newton iteration (convergence may be
/// slower); use a wrapper returning `false` from `jacobian` to get finite differences.
pub struct MechanicalSystem<'a, S, F, const N: usize> {
    pub mechanism: &'a S,
    pub input: F,
}

impl<'a, S, F, const N: usize> MechanicalSystem<'a, S, F, N>
where
    S: Mechanism<N>,
    F: Fn(f64, &SVector<f64, N>, &SVector<f64, N>) -> SVector<f64, N>,
{
    pub fn new(mechanism: &'a S, input: F) -> Self {
        MechanicalSystem { mechanism, input }
    }

    fn split(y: &[f64]) -> (SVector<f64, N>, SVector<f64, N>) {
        (
            SVector::from_column_slice(&y[..N]),
            SVector::from_column_slice(&y[N..2 * N]),
        )
    }
}

impl<'a, S: Mechanism<N>, const N: usize> MechanicalSystem<'a, S, InputFn<N>, N> {
    /// The mechanism with no input forces (only gravity, springs and dampers act).
    pub fn unforced(mechanism: &'a S) -> Self {
        MechanicalSystem {
            mechanism,
            input: zero_input::<N>,
        }
    }
}

impl<S, F, const N: usize> OdeSystem for MechanicalSystem<'_, S, F, N>
where
    S: Mechanism<N>,
    F: Fn(f64, &SVector<f64, N>, &SVector<f64, N>) -> SVector<f64, N>,
{
    fn dim(&self) -> usize {
        2 * N
    }

    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        let (q, v) = Self::split(y);
        let tau = (self.input)(t, &q, &v);
        let a = self.mechanism.forward_dynamics(&q, &v, &tau);
        dy[..N].copy_from_slice(v.as_slice());
        dy[N..2 * N].copy_from_slice(a.as_slice());
    }

    /// `[[0, I], [∂v̇/∂q, ∂v̇/∂v]]` with `τ` held at its current value.
    fn jacobian(&self, t: f64, y: &[f64], jac: &mut DMatrix<f64>) -> bool {
        let (q, v) = Self::split(y);
        let tau = (self.input)(t, &q, &v);
        let d = self.mechanism.forward_dynamics_jacobian(&q, &v, &tau);
        jac.fill(0.0);
        jac.view_mut((0, N), (N, N)).fill_with_identity();
        jac.view_mut((N, 0), (N, N)).copy_from(&d.d_dq);
        jac.view_mut((N, N), (N, N)).copy_from(&d.d_dv);
        true
    }

    fn names(&self) -> Vec<String> {
        let q = S::JOINTS.iter().map(|j| format!("q_{j}"));
        let v = S::JOINTS.iter().map(|j| format!("v_{j}"));
        q.chain(v).collect()
    }
}

/// The baseline: a [`Model`] integrated with the plain numeric dynamics of
/// [`crate::numeric`] (allocating), `y = [q; v]`. No analytic Jacobian: implicit methods
/// use finite differences.
pub struct NumericSystem<'a, F> {
    pub model: &'a Model,
    pub input: F,
    dof: usize,
}

impl<'a, F: Fn(f64, &DVector<f64>, &DVector<f64>) -> DVector<f64>> NumericSystem<'a, F> {
    pub fn new(model: &'a Model, input: F) -> Self {
        NumericSystem {
            model,
            input,
            dof: model.dof(),
        }
    }
}

/// Zero input for [`NumericSystem::unforced`].
pub type NumericInputFn = fn(f64, &DVector<f64>, &DVector<f64>) -> DVector<f64>;

impl<'a> NumericSystem<'a, NumericInputFn> {
    /// The model with no input forces.
    pub fn unforced(model: &'a Model) -> Self {
        NumericSystem::new(model, |_, q, _| DVector::zeros(q.len()))
    }
}

impl<F: Fn(f64, &DVector<f64>, &DVector<f64>) -> DVector<f64>> OdeSystem for NumericSystem<'_, F> {
    fn dim(&self) -> usize {
        2 * self.dof
    }

    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        let n = self.dof;
        let q = DVector::from_column_slice(&y[..n]);
        let v = DVector::from_column_slice(&y[n..2 * n]);
        let tau = (self.input)(t, &q, &v);
        let a = numeric::forward_dynamics(self.model, &q, &v, &tau);
        dy[..n].copy_from_slice(v.as_slice());
        dy[n..2 * n].copy_from_slice(a.as_slice());
    }

    fn names(&self) -> Vec<String> {
        let mut names = vec![String::new(); 2 * self.dof];
        for link in &self.model.links {
            if let Some(k) = link.coordinate {
                names[k] = format!("q_{}", link.name);
                names[self.dof + k] = format!("v_{}", link.name);
            }
        }
        names
    }
}
