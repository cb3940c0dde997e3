//! The trait every `#[derive(Mechanism)]` implements.
//!
//! Conventions (theory.md §1–2): `q` joint coordinates, `v = q̇`, and
//!
//! ```text
//! M(q) v̇ + C(q, v) v + g(q) = τ + τ_p(q, v)
//! ```
//!
//! where `g` is the generalised gravity force `∂U_gravity/∂q`, `τ` the applied (input)
//! generalised forces and `τ_p = −k (q − q_rest) − c v` the passive forces of the linear
//! springs and viscous dampers declared on joint coordinates.

use nalgebra::{SMatrix, SVector};

use crate::model::Model;

/// Forward dynamics and its derivatives with respect to the state, from one call.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ForwardJacobian<const N: usize> {
    /// The acceleration `v̇ = FD(q, v, τ)`.
    pub acceleration: SVector<f64, N>,
    /// `∂v̇/∂q`.
    pub d_dq: SMatrix<f64, N, N>,
    /// `∂v̇/∂v`.
    pub d_dv: SMatrix<f64, N, N>,
}

/// A scene's parameters by name: the struct's fields, in declaration order (every field
/// of a derived scene is an `f64` parameter). The derive implements it for every scene;
/// the Python module builds scenes from keyword arguments with it, and an ensemble
/// varies a scene's parameters by name.
pub trait Parameters: Sized {
    /// The fields' names, in declaration order.
    const NAMES: &'static [&'static str];
    /// The fields' values, in the order of [`NAMES`](Self::NAMES).
    fn values(&self) -> Vec<f64>;
    /// The scene with these values, in the order of [`NAMES`](Self::NAMES); `None` when
    /// there are not exactly as many values as names. The values are not checked here:
    /// [`Mechanism::validate`] says which make no physical sense.
    fn from_values(values: &[f64]) -> Option<Self>;
}

/// Parameters that make a scene physically meaningless (a non-positive mass, an
/// inertia that no body has, a negative critical force, …), each naming the parameter.
#[derive(Clone, Debug, PartialEq)]
pub struct ParameterError {
    /// `(what, why)` for every violated condition, in declaration order.
    pub problems: Vec<(String, String)>,
}

impl std::fmt::Display for ParameterError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "invalid parameters:")?;
        for (what, why) in &self.problems {
            write!(f, " {what} {why};")?;
        }
        Ok(())
    }
}

impl std::error::Error for ParameterError {}

/// Checks used by the generated `validate` (public so that hand-written mechanisms can
/// use them too). Each returns `Some(reason)` when the value is invalid.
pub mod check {
    use nalgebra::Matrix3;

    pub fn finite(x: f64) -> Option<String> {
        (!x.is_finite()).then(|| format!("must be finite, got {x}"))
    }

    pub fn positive(x: f64) -> Option<String> {
        (!(x > 0.0 && x.is_finite())).then(|| format!("must be positive and finite, got {x}"))
    }

    pub fn non_negative(x: f64) -> Option<String> {
        (!(x >= 0.0 && x.is_finite())).then(|| format!("must be non-negative and finite, got {x}"))
    }

    /// Two stops on one coordinate: the lower limit below the upper one.
    pub fn below(min: f64, max: f64) -> Option<String> {
        (min.partial_cmp(&max) != Some(std::cmp::Ordering::Less))
            .then(|| format!("must be below the upper stop's {max}, got {min}"))
    }

    /// A kinetic friction force at most the static one.
    pub fn at_most(x: f64, limit: f64) -> Option<String> {
        (x.partial_cmp(&limit)
            .is_none_or(|o| o == std::cmp::Ordering::Greater))
        .then(|| format!("must be at most the static friction force {limit}, got {x}"))
    }

    pub fn unit_interval(x: f64) -> Option<String> {
        (!(0.0..=1.0).contains(&x)).then(|| format!("must lie in [0, 1], got {x}"))
    }

    /// Symmetric, positive semi-definite, and `I_xx + I_yy ≥ I_zz` (and cyclic): the
    /// rotational inertia of a real body.
    pub fn inertia(i: &Matrix3<f64>) -> Option<String> {
        if i.iter().any(|x| !x.is_finite()) {
            return Some(format!("must be finite, got {i}"));
        }
        let scale = i.abs().max().max(f64::MIN_POSITIVE);
        if (i - i.transpose()).abs().max() > 1e-12 * scale {
            return Some("must be symmetric".into());
        }
        let ev = i.symmetric_eigenvalues();
        let tol = 1e-12 * scale;
        if ev.iter().any(|&l| l < -tol) {
            return Some(format!(
                "must be positive semi-definite, eigenvalues {:?}",
                ev.as_slice()
            ));
        }
        let (a, b, c) = (i[(0, 0)], i[(1, 1)], i[(2, 2)]);
        if a + b < c - tol || b + c < a - tol || a + c < b - tol {
            return Some("violates the triangle inequality I_xx + I_yy ≥ I_zz (or cyclic): no real body has it".into());
        }
        None
    }
}

/// Column names of a mechanism's state `[q; v]`, the same for every integrator:
/// `q_<joint>` then `v_<joint>` (`q<i>`, `v<i>` for a joint without a name).
pub fn state_names(joints: &[&str]) -> Vec<String> {
    let name = |prefix: &str, (i, j): (usize, &&str)| {
        if j.is_empty() {
            format!("{prefix}{i}")
        } else {
            format!("{prefix}_{j}")
        }
    };
    let q = joints.iter().enumerate().map(|p| name("q", p));
    let v = joints.iter().enumerate().map(|p| name("v", p));
    q.chain(v).collect()
}

/// The solution's column names of a closed mechanism's constraint forces: `λ_<row>` for
/// each row of [`Mechanism::LOOP_CONSTRAINTS`] (`λ_rocker_pin.x`).
pub fn loop_force_names(rows: &[&str]) -> Vec<String> {
    rows.iter().map(|r| format!("λ_{r}")).collect()
}

/// A rigid multibody tree with `N` scalar joint coordinates, as generated by the derive.
///
/// All methods are straight-line generated code: no allocation, no dynamic dispatch.
/// This trait carries what the integrators call; the other kernels (Christoffel
/// symbols, Coriolis matrix, gravity, bias, inverse dynamics, energies) are traits of
/// their own in [`crate::kernels`], emitted when the scene asks for them
/// (`#[mechanism(emit = [...])]`).
pub trait Mechanism<const N: usize> {
    /// Number of degrees of freedom.
    const DOF: usize = N;
    /// Names of the joints, in the order of the coordinates.
    const JOINTS: [&'static str; N];
    /// Names of the scene's non-smooth elements (friction, dash-pots, stops); empty for
    /// a smooth scene. The smooth integrators refuse a scene that has any
    /// ([`MechanicalSystem`](crate::MechanicalSystem)), unless told to ignore them.
    const NON_SMOOTH_ELEMENTS: &'static [&'static str] = &[];

    /// Mass matrix `M(q)`, symmetric positive definite.
    fn mass_matrix(&self, q: &SVector<f64, N>) -> SMatrix<f64, N, N>;
    /// `v̇ = M⁻¹ (τ + τ_p − C v − g)`.
    fn forward_dynamics(
        &self,
        q: &SVector<f64, N>,
        v: &SVector<f64, N>,
        tau: &SVector<f64, N>,
    ) -> SVector<f64, N>;
    /// Forward dynamics with its symbolic Jacobian with respect to `(q, v)`, `τ` held fixed.
    fn forward_dynamics_jacobian(
        &self,
        q: &SVector<f64, N>,
        v: &SVector<f64, N>,
        tau: &SVector<f64, N>,
    ) -> ForwardJacobian<N>;
    /// Checks every parameter (finite fields, positive masses, realisable inertias,
    /// non-negative critical forces and dampings, restitutions in `[0, 1]`, …) and names
    /// each one that is wrong. The derive generates it; the default accepts everything
    /// (for hand-written mechanisms that check elsewhere).
    fn validate(&self) -> Result<(), ParameterError> {
        Ok(())
    }
    /// The same system as a plain numeric description, for the independent numeric
    /// implementation in [`crate::numeric`].
    fn model(&self) -> Model;
    /// Names of the constraint rows of the scene's loop joints (`#[loop_joint]`), empty
    /// for a tree; see [`LoopConstraints`](crate::loops::LoopConstraints).
    const LOOP_CONSTRAINTS: &'static [&'static str] = &[];
    /// Projects `(q, v)` onto the loops' constraint manifold, the coordinates marked in
    /// `held` kept ([`loops::project`](crate::loops::project)); a tree has nothing to
    /// project.
    /// Returns whether anything moved. The integrators call it after each accepted step.
    fn project_onto_loops(
        &self,
        _q: &mut SVector<f64, N>,
        _v: &mut SVector<f64, N>,
        _held: &[bool],
    ) -> Result<bool, crate::loops::error::LoopError> {
        Ok(false)
    }
    /// How far the loops' constraints are from losing rank at `q`
    /// ([`loops::conditioning`](crate::loops::conditioning)); `1` for a tree.
    fn loop_conditioning(&self, _q: &SVector<f64, N>) -> f64 {
        1.0
    }
    /// The loop joints' constraint forces `λ` at `(q, v)` under the generalised forces
    /// `tau` (inputs and elements), one per row of
    /// [`LOOP_CONSTRAINTS`](Self::LOOP_CONSTRAINTS), written into `out` (of that
    /// length): [`LoopConstraints::constrained_forward_dynamics`](crate::loops::LoopConstraints::constrained_forward_dynamics)
    /// (crate::loops::LoopConstraints::constrained_forward_dynamics)'s. Nothing for a
    /// tree.
    fn loop_forces(
        &self,
        _q: &SVector<f64, N>,
        _v: &SVector<f64, N>,
        _tau: &SVector<f64, N>,
        _out: &mut [f64],
    ) {
    }
}
