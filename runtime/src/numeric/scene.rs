//! A scene built at run time: a numeric [`Model`] with non-smooth elements, implementing
//! [`Mechanism`] and [`NonSmooth`] through the numeric algorithms of this module (CRBA,
//! RNEA, exact `∂M/∂q`). What the derive generates at compile time, without compiling:
//! for scenes that are only known at run time (random scenes in the agreement suite, a
//! model read from a file) and as an independent reference.
//!
//! Every call allocates (it is the numeric reference, not the hot path); the forward
//! dynamics Jacobian is by central differences of the numeric forward dynamics.

use nalgebra::{DVector, SMatrix, SVector};

use super::{Model, crba, dynamics};
use crate::element::{Element, NonSmooth};
use crate::system::{ForwardJacobian, Mechanism};

/// A slip law `v = φ(f)` with its slope, for the scene's user-law elements.
pub type SlipLaw = fn(f64) -> (f64, f64);

/// A numeric model with `N` coordinates and `E` non-smooth elements (see the module
/// documentation). Its columns are named `q0 … v0 …` (joints have no names here).
#[derive(Clone, Debug)]
pub struct Scene<const N: usize, const E: usize> {
    pub model: Model,
    pub elements: [Element; E],
    /// The slip law of each element with a user law (`None` for the others).
    pub laws: [Option<SlipLaw>; E],
}

impl<const N: usize, const E: usize> Scene<N, E> {
    /// The scene of `model` (which must have `N` coordinates, of revolute or prismatic
    /// joints) with `elements`; `None` if the model has another number of coordinates.
    pub fn new(model: Model, elements: [Element; E]) -> Option<Self> {
        (model.dof() == N).then_some(Scene {
            model,
            elements,
            laws: [None; E],
        })
    }

    fn d(x: &SVector<f64, N>) -> DVector<f64> {
        DVector::from_column_slice(x.as_slice())
    }

    fn s(x: &DVector<f64>) -> SVector<f64, N> {
        SVector::from_column_slice(x.as_slice())
    }
}

impl<const N: usize, const E: usize> Mechanism<N> for Scene<N, E> {
    const JOINTS: [&'static str; N] = [""; N];

    fn mass_matrix(&self, q: &SVector<f64, N>) -> SMatrix<f64, N, N> {
        SMatrix::from_column_slice(crba::crba(&self.model, &Self::d(q)).as_slice())
    }

    fn forward_dynamics(
        &self,
        q: &SVector<f64, N>,
        v: &SVector<f64, N>,
        tau: &SVector<f64, N>,
    ) -> SVector<f64, N> {
        let (q, v, tau) = (Self::d(q), Self::d(v), Self::d(tau));
        Self::s(&dynamics::forward_dynamics(&self.model, &q, &v, &tau))
    }

    /// Central differences of [`forward_dynamics`](Self::forward_dynamics).
    fn forward_dynamics_jacobian(
        &self,
        q: &SVector<f64, N>,
        v: &SVector<f64, N>,
        tau: &SVector<f64, N>,
    ) -> ForwardJacobian<N> {
        // The velocity columns share `q`: its tree and the factor of `M(q)` once.
        let (qd, taud) = (Self::d(q), Self::d(tau));
        let at_q = dynamics::AtConfiguration::new(&self.model, &qd);
        let at_v = |v: &SVector<f64, N>| Self::s(&at_q.forward_dynamics(&Self::d(v), &taud));
        let acceleration = at_v(v);
        let column =
            |x: &SVector<f64, N>, j: usize, f: &dyn Fn(&SVector<f64, N>) -> SVector<f64, N>| {
                let h = f64::EPSILON.cbrt() * x[j].abs().max(1.0);
                let (mut p, mut m) = (*x, *x);
                p[j] += h;
                m[j] -= h;
                (f(&p) - f(&m)) / (2.0 * h)
            };
        let mut d_dq = SMatrix::<f64, N, N>::zeros();
        let mut d_dv = SMatrix::<f64, N, N>::zeros();
        for j in 0..N {
            d_dq.set_column(j, &column(q, j, &|q| self.forward_dynamics(q, v, tau)));
            d_dv.set_column(j, &column(v, j, &at_v));
        }
        ForwardJacobian {
            acceleration,
            d_dq,
            d_dv,
        }
    }

    fn model(&self) -> Model {
        self.model.clone()
    }
}

impl<const N: usize, const E: usize> crate::kernels::Christoffel<N> for Scene<N, E> {
    fn christoffel_symbols(&self, q: &SVector<f64, N>) -> [SMatrix<f64, N, N>; N] {
        let c = super::christoffel_symbols(&self.model, &Self::d(q));
        std::array::from_fn(|i| SMatrix::from_column_slice(c[i].as_slice()))
    }
}

impl<const N: usize, const E: usize> crate::kernels::Coriolis<N> for Scene<N, E> {
    fn coriolis_matrix(&self, q: &SVector<f64, N>, v: &SVector<f64, N>) -> SMatrix<f64, N, N> {
        let c = super::coriolis_matrix(&self.model, &Self::d(q), &Self::d(v));
        SMatrix::from_column_slice(c.as_slice())
    }
}

impl<const N: usize, const E: usize> crate::kernels::Gravity<N> for Scene<N, E> {
    fn gravity(&self, q: &SVector<f64, N>) -> SVector<f64, N> {
        Self::s(&dynamics::gravity(&self.model, &Self::d(q)))
    }
}

impl<const N: usize, const E: usize> crate::kernels::Bias<N> for Scene<N, E> {
    fn bias(&self, q: &SVector<f64, N>, v: &SVector<f64, N>) -> SVector<f64, N> {
        Self::s(&dynamics::bias(&self.model, &Self::d(q), &Self::d(v)))
    }
}

impl<const N: usize, const E: usize> crate::kernels::PassiveForces<N> for Scene<N, E> {
    fn passive_forces(&self, q: &SVector<f64, N>, v: &SVector<f64, N>) -> SVector<f64, N> {
        Self::s(&dynamics::passive_forces(
            &self.model,
            &Self::d(q),
            &Self::d(v),
        ))
    }
}

impl<const N: usize, const E: usize> crate::kernels::InverseDynamics<N> for Scene<N, E> {
    fn inverse_dynamics(
        &self,
        q: &SVector<f64, N>,
        v: &SVector<f64, N>,
        a: &SVector<f64, N>,
    ) -> SVector<f64, N> {
        let (q, v, a) = (Self::d(q), Self::d(v), Self::d(a));
        Self::s(&dynamics::inverse_dynamics(&self.model, &q, &v, &a))
    }
}

impl<const N: usize, const E: usize> crate::kernels::Energy<N> for Scene<N, E> {
    fn kinetic_energy(&self, q: &SVector<f64, N>, v: &SVector<f64, N>) -> f64 {
        dynamics::kinetic_energy(&self.model, &Self::d(q), &Self::d(v))
    }
    fn potential_energy(&self, q: &SVector<f64, N>) -> f64 {
        dynamics::potential_energy(&self.model, &Self::d(q))
    }
}

impl<const N: usize, const E: usize> NonSmooth<N> for Scene<N, E> {
    const ELEMENTS: usize = E;

    fn element(&self, e: usize) -> Element {
        self.elements[e]
    }

    fn law(&self, e: usize, f: f64) -> (f64, f64) {
        match self.laws[e] {
            // The odd extension, as the derive emits it.
            Some(phi) if f < 0.0 => {
                let (v, d) = phi(-f);
                (-v, d)
            }
            Some(phi) => phi(f),
            None => (0.0, 0.0),
        }
    }

    fn inverse_mass_matrix(&self, q: &SVector<f64, N>) -> SMatrix<f64, N, N> {
        self.mass_matrix(q)
            .try_inverse()
            .expect("a valid model has a positive definite mass matrix")
    }
}
