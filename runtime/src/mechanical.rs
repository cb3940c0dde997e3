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
///
/// A scene with non-smooth elements (friction, Bingham dash-pots, stops) is refused
/// with [`ErrorKind::InvalidInput`](crate::ErrorKind) naming them: the smooth equations
/// have no element forces, and integrating them would silently misread the scene. Use
/// [`solve_nonsmooth`](crate::solve_nonsmooth), or say
/// [`ignoring_elements`](Self::ignoring_elements) to integrate the smooth part alone.
pub struct MechanicalSystem<'a, S, F, const N: usize> {
    pub mechanism: &'a S,
    pub input: F,
    /// Integrate a scene with non-smooth elements as if it had none.
    pub ignore_elements: bool,
}

impl<'a, S, F, const N: usize> MechanicalSystem<'a, S, F, N>
where
    S: Mechanism<N>,
    F: Fn(f64, &SVector<f64, N>, &SVector<f64, N>) -> SVector<f64, N>,
{
    pub fn new(mechanism: &'a S, input: F) -> Self {
        MechanicalSystem {
            mechanism,
            input,
            ignore_elements: false,
        }
    }

    /// The smooth part of a scene with non-smooth elements: the elements are left out
    /// of the equations (see the type's documentation).
    pub fn ignoring_elements(mut self) -> Self {
        self.ignore_elements = true;
        self
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
            ignore_elements: false,
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
        crate::system::state_names(&S::JOINTS)
    }

    /// `y = [q; v]`, `q̇ = v`.
    fn second_order(&self) -> Option<usize> {
        Some(N)
    }

    /// Onto the loop constraints of a closed mechanism ([`Mechanism::project_onto_loops`]).
    fn project(&self, t: f64, y: &mut [f64]) -> Result<bool, crate::ErrorKind> {
        if S::LOOP_CONSTRAINTS.is_empty() {
            return Ok(false);
        }
        let (mut q, mut v) = Self::split(y);
        let moved = self
            .mechanism
            .project_onto_loops(&mut q, &mut v, &[])
            .map_err(|error| crate::ErrorKind::Loops { t, error })?;
        if moved {
            y[..N].copy_from_slice(q.as_slice());
            y[N..2 * N].copy_from_slice(v.as_slice());
        }
        Ok(moved)
    }

    /// A closed mechanism's constraint forces, `λ_<row>`.
    fn output_names(&self) -> Vec<String> {
        crate::system::loop_force_names(S::LOOP_CONSTRAINTS)
    }

    fn outputs(&self, t: f64, y: &[f64], out: &mut [f64]) {
        if S::LOOP_CONSTRAINTS.is_empty() {
            return;
        }
        let (q, v) = Self::split(y);
        let tau = (self.input)(t, &q, &v);
        self.mechanism.loop_forces(&q, &v, &tau, out);
    }

    fn conditioning(&self, y: &[f64]) -> Option<f64> {
        if S::LOOP_CONSTRAINTS.is_empty() {
            return None;
        }
        Some(self.mechanism.loop_conditioning(&Self::split(y).0))
    }

    /// The mechanism's parameters ([`Mechanism::validate`]), and no non-smooth elements
    /// unless they are to be ignored.
    fn validate(&self) -> Result<(), String> {
        if !self.ignore_elements && !S::NON_SMOOTH_ELEMENTS.is_empty() {
            let names: Vec<String> = S::NON_SMOOTH_ELEMENTS
                .iter()
                .map(|e| format!("`{e}`"))
                .collect();
            return Err(format!(
                "the scene has non-smooth elements ({}) that the smooth integrators cannot \
                 represent: integrate it with `solve_nonsmooth`, or use \
                 `MechanicalSystem::ignoring_elements()` to integrate it without them",
                names.join(", ")
            ));
        }
        self.mechanism.validate().map_err(|e| e.to_string())
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

    /// `y = [q; v]`, `q̇ = v`.
    fn second_order(&self) -> Option<usize> {
        Some(self.dof)
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernels::Energy;
    use crate::numeric::test_models::double_pendulum;
    use crate::system::ForwardJacobian;
    use crate::{Options, Problem};
    use nalgebra::SMatrix;

    /// A [`Mechanism`] implemented with the numeric reference, standing in for
    /// generated code (S8 double pendulum: m1 = 1, l1 = 1, m2 = 0.5, l2 = 0.7).
    struct Pendulum(Model);

    fn d(x: &SVector<f64, 2>) -> DVector<f64> {
        DVector::from_column_slice(x.as_slice())
    }
    fn s(x: &DVector<f64>) -> SVector<f64, 2> {
        SVector::from_column_slice(x.as_slice())
    }

    impl Mechanism<2> for Pendulum {
        const JOINTS: [&'static str; 2] = ["shoulder", "elbow"];
        fn mass_matrix(&self, q: &SVector<f64, 2>) -> SMatrix<f64, 2, 2> {
            SMatrix::from_column_slice(numeric::crba(&self.0, &d(q)).as_slice())
        }
        fn forward_dynamics(
            &self,
            q: &SVector<f64, 2>,
            v: &SVector<f64, 2>,
            tau: &SVector<f64, 2>,
        ) -> SVector<f64, 2> {
            s(&numeric::forward_dynamics(&self.0, &d(q), &d(v), &d(tau)))
        }
        /// Central differences (a stand-in for the symbolic Jacobian).
        fn forward_dynamics_jacobian(
            &self,
            q: &SVector<f64, 2>,
            v: &SVector<f64, 2>,
            tau: &SVector<f64, 2>,
        ) -> ForwardJacobian<2> {
            let h = 1e-6;
            let fd = |q: SVector<f64, 2>, v: SVector<f64, 2>| self.forward_dynamics(&q, &v, tau);
            let e = |j: usize| SVector::<f64, 2>::from_fn(|i, _| if i == j { h } else { 0.0 });
            ForwardJacobian {
                acceleration: self.forward_dynamics(q, v, tau),
                d_dq: SMatrix::from_columns(
                    &[0, 1].map(|j| (fd(q + e(j), *v) - fd(q - e(j), *v)) / (2.0 * h)),
                ),
                d_dv: SMatrix::from_columns(
                    &[0, 1].map(|j| (fd(*q, v + e(j)) - fd(*q, v - e(j))) / (2.0 * h)),
                ),
            }
        }
        fn model(&self) -> Model {
            self.0.clone()
        }
    }

    impl crate::kernels::Christoffel<2> for Pendulum {
        fn christoffel_symbols(&self, q: &SVector<f64, 2>) -> [SMatrix<f64, 2, 2>; 2] {
            let c = numeric::christoffel_symbols(&self.0, &d(q));
            [0, 1].map(|i| SMatrix::from_column_slice(c[i].as_slice()))
        }
    }

    impl crate::kernels::Coriolis<2> for Pendulum {
        fn coriolis_matrix(&self, q: &SVector<f64, 2>, v: &SVector<f64, 2>) -> SMatrix<f64, 2, 2> {
            SMatrix::from_column_slice(numeric::coriolis_matrix(&self.0, &d(q), &d(v)).as_slice())
        }
    }

    impl crate::kernels::Gravity<2> for Pendulum {
        fn gravity(&self, q: &SVector<f64, 2>) -> SVector<f64, 2> {
            s(&numeric::gravity(&self.0, &d(q)))
        }
    }

    impl crate::kernels::Bias<2> for Pendulum {
        fn bias(&self, q: &SVector<f64, 2>, v: &SVector<f64, 2>) -> SVector<f64, 2> {
            s(&numeric::bias(&self.0, &d(q), &d(v)))
        }
    }

    impl crate::kernels::PassiveForces<2> for Pendulum {
        fn passive_forces(&self, q: &SVector<f64, 2>, v: &SVector<f64, 2>) -> SVector<f64, 2> {
            s(&numeric::passive_forces(&self.0, &d(q), &d(v)))
        }
    }

    impl crate::kernels::InverseDynamics<2> for Pendulum {
        fn inverse_dynamics(
            &self,
            q: &SVector<f64, 2>,
            v: &SVector<f64, 2>,
            a: &SVector<f64, 2>,
        ) -> SVector<f64, 2> {
            s(&numeric::inverse_dynamics(&self.0, &d(q), &d(v), &d(a)))
        }
    }

    impl crate::kernels::Energy<2> for Pendulum {
        fn kinetic_energy(&self, q: &SVector<f64, 2>, v: &SVector<f64, 2>) -> f64 {
            numeric::kinetic_energy(&self.0, &d(q), &d(v))
        }
        fn potential_energy(&self, q: &SVector<f64, 2>) -> f64 {
            numeric::potential_energy(&self.0, &d(q))
        }
    }

    fn energy(p: &Pendulum, y: &[f64]) -> f64 {
        let q = SVector::from_column_slice(&y[..2]);
        let v = SVector::from_column_slice(&y[2..]);
        p.kinetic_energy(&q, &v) + p.potential_energy(&q)
    }

    #[test]
    fn unforced_pendulum_conserves_energy_and_matches_numeric_system() {
        let pendulum = Pendulum(double_pendulum(1.0, 1.0, 0.5, 0.7));
        let system = MechanicalSystem::unforced(&pendulum);
        assert_eq!(
            system.names(),
            ["q_shoulder", "q_elbow", "v_shoulder", "v_elbow"]
        );
        let problem = Problem::new(0.0, 5.0, [1.0, -0.5, 0.0, 0.3]);
        let opts = Options::tolerances(1e-10, 1e-12);
        let traj = crate::solve(&system, &problem, &crate::Method::Dopri5(opts)).unwrap();
        let e0 = energy(&pendulum, &problem.y0);
        for i in 0..traj.len() {
            assert!((energy(&pendulum, traj.state(i)) - e0).abs() < 1e-7);
        }
        let model = pendulum.model();
        let baseline = crate::solve(
            &NumericSystem::unforced(&model),
            &problem,
            &crate::Method::Dopri5(opts),
        )
        .unwrap();
        assert_eq!(baseline.names()[1], "q_lower");
        let (a, b) = (traj.last().unwrap().1, baseline.last().unwrap().1);
        assert!(a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-12));
    }

    #[test]
    fn forced_jacobian_layout_and_stiff_solve_use_it() {
        let pendulum = Pendulum(double_pendulum(1.0, 1.0, 0.5, 0.7));
        let system = MechanicalSystem::new(
            &pendulum,
            |t, _q: &SVector<f64, 2>, _v: &SVector<f64, 2>| SVector::<f64, 2>::new(t.sin(), 0.0),
        );
        let y = [0.4, 0.2, -0.3, 0.8];
        let mut jac = DMatrix::zeros(4, 4);
        assert!(system.jacobian(0.3, &y, &mut jac));
        // Against central differences of the rhs.
        let h = 1e-6;
        for j in 0..4 {
            let (mut yp, mut ym) = (y, y);
            yp[j] += h;
            ym[j] -= h;
            let (mut fp, mut fm) = ([0.0; 4], [0.0; 4]);
            system.rhs(0.3, &yp, &mut fp);
            system.rhs(0.3, &ym, &mut fm);
            for i in 0..4 {
                assert!(
                    (jac[(i, j)] - (fp[i] - fm[i]) / (2.0 * h)).abs() < 1e-5,
                    "({i}, {j})"
                );
            }
        }
        let traj = crate::solve(
            &system,
            &Problem::new(0.0, 2.0, y),
            &crate::Method::Sdirk4(Options::tolerances(1e-8, 1e-10)),
        )
        .unwrap();
        assert_eq!(traj.stats.finite_difference_jacobians, 0);
        let reference = crate::solve(
            &system,
            &Problem::new(0.0, 2.0, y),
            &crate::Method::Dopri5(Options::tolerances(1e-11, 1e-13)),
        )
        .unwrap();
        let (a, b) = (traj.last().unwrap().1, reference.last().unwrap().1);
        // An order-4 method with error-per-step control is tolerance proportional: over
        // this short, non-chaotic 2 s run the global error is a small multiple of rtol
        // (DOPRI5 at the same rtol ends 4.5e-7 away). Measured: 1.0e-8 absolute (2e-9
        // relative) at v ≈ 4.7; bound 10 rtol relative, i.e. 1e-7 · max(1, |y|). (It was
        // 2e-5 away, and the bound loosened to 1e-4, while Newton stopped too early.)
        assert!(
            a.iter()
                .zip(b)
                .all(|(x, y)| (x - y).abs() < 1e-7 * y.abs().max(1.0)),
            "{a:?} vs {b:?}"
        );
    }
}
