//! The trait the derive implements for scenes with Lie-group joints (`spherical`,
//! `free`), and the adapter that integrates such a scene with [`super::Rkmk5`].
//!
//! # Coordinates
//!
//! Links are in topological order and each contributes, in that order, to
//!
//! * the **configuration** `q ∈ ℝ^NQ`: one slot per revolute or prismatic joint, four
//!   slots `(w, x, y, z)` — a unit quaternion, the rotation of the link frame relative
//!   to its joint frame — per spherical joint, and for a free joint three slots (the
//!   position of the body's frame in the joint frame's axes) followed by its quaternion;
//! * the **velocity** `v ∈ ℝ^N`: one per revolute or prismatic joint, the body angular
//!   velocity `ω` (three, in the link frame) per spherical joint, and for a free joint
//!   the translational velocity `ṗ` (three, joint-frame axes) followed by `ω`.
//!
//! A free joint is therefore SO(3) × ℝ³, not SE(3): the translation is a vector space
//! with vanishing structure constants, so the `ad` term of the Coriolis matrix is
//! confined to the 3 × 3 rotation blocks, gravity is a constant force on `ṗ`, and the
//! position integrates as `p ← p + h ṗ` — cheaper than SE(3)'s coupled
//! `ad = [[ω̂, v̂], [0, ω̂]]`, with the same configurations.
//!
//! Around the current configuration, local exponential coordinates `φ`
//! (`R = R₀ exp(φ̂)`, `φ = 0` now; `φ = q` on Euclidean coordinates) are the coordinates
//! of the derivatives: `∂/∂φ_k` is the derivative along `R₀ exp(t ê_k)` at `t = 0`.

use nalgebra::{SMatrix, SVector, Vector3};

use super::{LieState, LieSystem, UnitQuat};
use crate::model::Model;
use crate::system::{ForwardJacobian, ParameterError};
use crate::{Keep, Output, Solution};

/// A rigid multibody tree with Lie-group joints: `N` velocity coordinates and `NQ`
/// configuration slots (see the [module documentation](self) for the layout).
///
/// The equations of motion are, with `v` the body velocities (quasi-velocities),
///
/// ```text
/// M(q) v̇ + C(q, v) v + g(q) = τ + τ_p(q, v)
/// ```
///
/// All methods are straight-line generated code. The quaternions in `q` must be of unit
/// norm (the rotation is formed as a quadratic polynomial in them).
pub trait LieMechanism<const N: usize, const NQ: usize> {
    /// Number of velocity coordinates (degrees of freedom).
    const DOF: usize = N;
    /// Number of configuration slots.
    const CONFIG: usize = NQ;
    /// A name for every velocity coordinate: the joint name, with `.wx`, `.wy`, `.wz`
    /// (body angular velocity) or `.x`, `.y`, `.z` (translation) for three-dof joints.
    const COORDINATES: [&'static str; N];
    /// For every rotation (spherical joints and the rotational part of free joints), in
    /// joint order: `(slot of w in q, index of ω_x in v)`.
    const ROTATIONS: &'static [(usize, usize)];
    /// For every Euclidean coordinate (revolute, prismatic, the translation of free
    /// joints), in joint order: `(slot in q, index in v)`.
    const EUCLID: &'static [(usize, usize)];

    /// Mass matrix `M(q)`, symmetric positive definite.
    fn mass_matrix(&self, q: &SVector<f64, NQ>) -> SMatrix<f64, N, N>;
    /// `v̇ = M⁻¹ (τ + τ_p − C v − g)`.
    fn forward_dynamics(
        &self,
        q: &SVector<f64, NQ>,
        v: &SVector<f64, N>,
        tau: &SVector<f64, N>,
    ) -> SVector<f64, N>;
    /// Forward dynamics with its Jacobian; `d_dq` is with respect to the local
    /// exponential coordinates `φ` (see the module documentation), `d_dv` to `v`.
    fn forward_dynamics_jacobian(
        &self,
        q: &SVector<f64, NQ>,
        v: &SVector<f64, N>,
        tau: &SVector<f64, N>,
    ) -> ForwardJacobian<N>;
    /// Checks every parameter; see [`crate::Mechanism::validate`].
    fn validate(&self) -> Result<(), ParameterError> {
        Ok(())
    }
    /// The same system as a plain numeric description (joint kinds
    /// [`JointKind::Spherical`](crate::numeric::JointKind::Spherical) and
    /// [`JointKind::Translation`](crate::numeric::JointKind::Translation) included).
    fn model(&self) -> Model;

    /// The configuration with every coordinate zero and every rotation the identity.
    fn identity_configuration() -> SVector<f64, NQ> {
        let mut q = SVector::<f64, NQ>::zeros();
        for &(s, _) in Self::ROTATIONS {
            q[s] = 1.0;
        }
        q
    }

    /// `q ⊕ φ`: the configuration at local exponential coordinates `φ` around `q` (see
    /// the module documentation): `R ← R · exp(φ_rot)` on every rotation (renormalised),
    /// `x ← x + φ` on Euclidean coordinates. For finite differences along `∂/∂φ_k`.
    ///
    /// # Panics
    /// If a quaternion of `q` is zero or not finite.
    fn retract(q: &SVector<f64, NQ>, phi: &SVector<f64, N>) -> SVector<f64, NQ> {
        let mut out = *q;
        for &(s, k) in Self::EUCLID {
            out[s] += phi[k];
        }
        for &(s, k) in Self::ROTATIONS {
            let r = quaternion(q, s);
            let step = UnitQuat::exp(&Vector3::new(phi[k], phi[k + 1], phi[k + 2]));
            let c = (r * step).normalised().coords();
            out.fixed_rows_mut::<4>(s).copy_from_slice(&c);
        }
        out
    }

    /// A name for every configuration slot: a revolute or prismatic joint's name, a free
    /// joint's translation as its coordinates' names (`joint.x`, `joint.y`, `joint.z`),
    /// and a quaternion as `joint.qw`, `joint.qx`, `joint.qy`, `joint.qz`.
    fn configuration_names() -> [String; NQ] {
        let mut names: [String; NQ] = std::array::from_fn(|_| String::new());
        for &(s, k) in Self::EUCLID {
            names[s] = Self::COORDINATES[k].to_string();
        }
        for &(s, k) in Self::ROTATIONS {
            let c = Self::COORDINATES[k];
            let joint = c.strip_suffix(".wx").unwrap_or(c);
            for (i, part) in ["qw", "qx", "qy", "qz"].iter().enumerate() {
                names[s + i] = format!("{joint}.{part}");
            }
        }
        names
    }

    /// The configuration and velocity of a [`LieState`] of [`LieMechanical`]: rotation
    /// `r` of the state goes to the slots `ROTATIONS[r].0 ..+4` of `q` (as `(w, x, y, z)`)
    /// and its `ω_r = velocity[3r..3r + 3]` to `v[ROTATIONS[r].1 ..+3]`; Euclidean
    /// coordinate `e` goes to `q[EUCLID[e].0]` and its velocity `velocity[3m + e]` to
    /// `v[EUCLID[e].1]`. The quaternions are copied as they are (the integrator keeps
    /// them unit).
    ///
    /// # Panics
    /// If the state's dimensions are not `(m, n, 3m + n)` with `m = ROTATIONS.len()`,
    /// `n = EUCLID.len()`.
    fn state_to_qv(state: &LieState) -> (SVector<f64, NQ>, SVector<f64, N>) {
        let m = Self::ROTATIONS.len();
        check_state_dimensions(state, m, Self::EUCLID.len());
        let mut q = SVector::<f64, NQ>::zeros();
        let mut v = SVector::<f64, N>::zeros();
        for (r, &(s, k)) in Self::ROTATIONS.iter().enumerate() {
            q.fixed_rows_mut::<4>(s)
                .copy_from_slice(&state.rotations[r].coords());
            v.fixed_rows_mut::<3>(k)
                .copy_from_slice(&state.velocity[3 * r..3 * r + 3]);
        }
        for (e, &(s, k)) in Self::EUCLID.iter().enumerate() {
            q[s] = state.euclid[e];
            v[k] = state.velocity[3 * m + e];
        }
        (q, v)
    }

    /// The inverse of [`state_to_qv`](Self::state_to_qv): the [`LieState`] of a
    /// configuration and velocity, each quaternion normalised.
    ///
    /// # Panics
    /// If a quaternion of `q` is zero or not finite.
    fn qv_to_state(q: &SVector<f64, NQ>, v: &SVector<f64, N>) -> LieState {
        let m = Self::ROTATIONS.len();
        let mut velocity = vec![0.0; 3 * m + Self::EUCLID.len()];
        let rotations = Self::ROTATIONS
            .iter()
            .enumerate()
            .map(|(r, &(s, k))| {
                velocity[3 * r..3 * r + 3].copy_from_slice(v.fixed_rows::<3>(k).as_slice());
                quaternion(q, s)
            })
            .collect();
        let euclid = Self::EUCLID
            .iter()
            .enumerate()
            .map(|(e, &(s, k))| {
                velocity[3 * m + e] = v[k];
                q[s]
            })
            .collect();
        LieState::new(rotations, euclid, velocity)
    }

    /// A velocity-layout vector (such as `v̇`) in the order of [`LieState::velocity`]:
    /// `(ω_1, …, ω_m, u)`, written into `out` (length `3m + n`).
    fn velocity_to_state_order(v: &SVector<f64, N>, out: &mut [f64]) {
        let m = Self::ROTATIONS.len();
        for (r, &(_, k)) in Self::ROTATIONS.iter().enumerate() {
            out[3 * r..3 * r + 3].copy_from_slice(v.fixed_rows::<3>(k).as_slice());
        }
        for (e, &(_, k)) in Self::EUCLID.iter().enumerate() {
            out[3 * m + e] = v[k];
        }
    }
}

/// A run's rows in the mechanism's layout: `flat` is a [`LieMechanical`] run of `S` as
/// the integrators store it ([`LieTrajectory::flat`](super::LieTrajectory::flat), or the
/// [`SolveError`](crate::SolveError)'s solution of a failed run: every rotation, the
/// Euclidean coordinates, then the velocities in state order), and the result has the
/// columns `q_<slot>` (the [configuration's names](LieMechanism::configuration_names), in
/// the order of `q`) then `v_<coordinate>` (the order of `v`), each row's derivative
/// reordered alike, and the run's statistics. `None` when `flat` has not the columns of
/// such a run (`NQ + N`).
///
/// Between the rows, read the trajectory's own dense output
/// ([`LieTrajectory::at`](super::LieTrajectory::at), on the group) rather than this
/// solution's, which interpolates the quaternions' slots one by one.
pub fn mechanism_rows<S, const N: usize, const NQ: usize>(flat: &Solution) -> Option<Solution>
where
    S: LieMechanism<N, NQ>,
{
    if flat.dim() != NQ + N {
        return None;
    }
    // `to[j]`: the column of flat column `j`.
    let (m, e) = (S::ROTATIONS.len(), S::EUCLID.len());
    let mut to = vec![0usize; NQ + N];
    for (r, &(s, k)) in S::ROTATIONS.iter().enumerate() {
        for c in 0..4 {
            to[4 * r + c] = s + c;
        }
        for c in 0..3 {
            to[4 * m + e + 3 * r + c] = NQ + k + c;
        }
    }
    for (i, &(s, k)) in S::EUCLID.iter().enumerate() {
        to[4 * m + i] = s;
        to[4 * m + e + 3 * m + i] = NQ + k;
    }
    let mut names: Vec<String> = S::configuration_names()
        .iter()
        .map(|c| format!("q_{c}"))
        .collect();
    names.extend(S::COORDINATES.iter().map(|c| format!("v_{c}")));
    let mut out = Solution::new(names, 0, Output::Steps);
    let (mut y, mut dy) = (vec![0.0; NQ + N], vec![0.0; NQ + N]);
    for i in 0..flat.len() {
        for (j, &k) in to.iter().enumerate() {
            y[k] = flat.state(i)[j];
            dy[k] = flat.derivative(i)[j];
        }
        out.push_step(flat.times()[i], &y, &dy, None, Keep::AsAsked);
    }
    out.stats = flat.stats;
    Some(out)
}

/// The normalised quaternion in slots `s..s + 4` of `q`.
fn quaternion<const NQ: usize>(q: &SVector<f64, NQ>, s: usize) -> UnitQuat {
    UnitQuat::try_new(q[s], q[s + 1], q[s + 2], q[s + 3]).unwrap_or_else(|| {
        panic!(
            "the quaternion in slots {s}..{} of q is zero or not finite",
            s + 4
        )
    })
}

fn check_state_dimensions(state: &LieState, m: usize, n: usize) {
    assert!(
        state.rotations.len() == m && state.euclid.len() == n && state.velocity.len() == 3 * m + n,
        "a LieState with {} rotations, {} Euclidean coordinates and {} velocities for a \
         mechanism with {m}, {n} and {}",
        state.rotations.len(),
        state.euclid.len(),
        state.velocity.len(),
        3 * m + n
    );
}

/// An input-force law `τ(t, q, v)` for [`LieMechanical`] (`q` configuration, `v`
/// velocity layout).
pub type LieInputFn<const N: usize, const NQ: usize> =
    fn(f64, &SVector<f64, NQ>, &SVector<f64, N>) -> SVector<f64, N>;

fn zero_input<const N: usize, const NQ: usize>(
    _: f64,
    _: &SVector<f64, NQ>,
    _: &SVector<f64, N>,
) -> SVector<f64, N> {
    SVector::zeros()
}

/// A generated [`LieMechanism`] driven by input forces `τ(t, q, v)`, as a [`LieSystem`]
/// for [`Rkmk5`](super::Rkmk5): the mechanical counterpart of
/// [`MechanicalSystem`](crate::MechanicalSystem).
///
/// The state's rotations are the mechanism's [`ROTATIONS`](LieMechanism::ROTATIONS)
/// in order, its Euclidean coordinates the [`EUCLID`](LieMechanism::EUCLID) in order,
/// and its velocity `(ω_1, …, ω_m, u)` in that order
/// ([`LieMechanism::state_to_qv`], [`LieMechanism::qv_to_state`] convert). The
/// right-hand side gathers `(q, v)` into stack vectors (no allocation), calls
/// [`LieMechanism::forward_dynamics`] and scatters `v̇` back into state order. The
/// kinematics `Ṙ = R ω̂`, `ẋ = u` are the integrator's: with the body velocities of
/// spherical joints and `ṗ` of translations in joint axes, `u` is exactly the rate of
/// the Euclidean slots.
pub struct LieMechanical<'a, S, F, const N: usize, const NQ: usize> {
    pub mechanism: &'a S,
    pub input: F,
}

impl<'a, S, F, const N: usize, const NQ: usize> LieMechanical<'a, S, F, N, NQ>
where
    S: LieMechanism<N, NQ>,
    F: Fn(f64, &SVector<f64, NQ>, &SVector<f64, N>) -> SVector<f64, N>,
{
    pub fn new(mechanism: &'a S, input: F) -> Self {
        LieMechanical { mechanism, input }
    }

    /// Kinetic plus potential energy at a state (scenes with `emit = [energy]`).
    pub fn energy(&self, state: &LieState) -> f64
    where
        S: crate::kernels::Energy<N, NQ>,
    {
        let (q, v) = S::state_to_qv(state);
        self.mechanism.kinetic_energy(&q, &v) + self.mechanism.potential_energy(&q)
    }
}

impl<'a, S: LieMechanism<N, NQ>, const N: usize, const NQ: usize>
    LieMechanical<'a, S, LieInputFn<N, NQ>, N, NQ>
{
    /// The mechanism with no input forces (only gravity, springs and dampers act).
    pub fn free(mechanism: &'a S) -> Self {
        LieMechanical {
            mechanism,
            input: zero_input::<N, NQ>,
        }
    }
}

impl<S, F, const N: usize, const NQ: usize> LieSystem for LieMechanical<'_, S, F, N, NQ>
where
    S: LieMechanism<N, NQ>,
    F: Fn(f64, &SVector<f64, NQ>, &SVector<f64, N>) -> SVector<f64, N>,
{
    fn n_rot(&self) -> usize {
        S::ROTATIONS.len()
    }

    fn n_euclid(&self) -> usize {
        S::EUCLID.len()
    }

    fn rhs(&self, t: f64, state: &LieState, dv: &mut [f64]) {
        let (q, v) = S::state_to_qv(state);
        let tau = (self.input)(t, &q, &v);
        let a = self.mechanism.forward_dynamics(&q, &v, &tau);
        S::velocity_to_state_order(&a, dv);
    }

    /// [`LieMechanism::forward_dynamics_jacobian`] with rows and columns permuted from
    /// the velocity layout into the state's order `(ω_1, …, ω_m, u)` (the mechanism's
    /// `φ` are the same local exponential coordinates as [`LieSystem::jacobian`]'s).
    ///
    /// Like [`MechanicalSystem`](crate::MechanicalSystem)'s, the Jacobian holds the input
    /// `τ` fixed: exact for inputs that depend on `t` only, an approximation (which still
    /// serves a simplified Newton iteration) for state feedback `τ(t, q, v)`.
    fn jacobian(&self, t: f64, state: &LieState, dq: &mut [f64], dv: &mut [f64]) -> bool {
        let (q, v) = S::state_to_qv(state);
        let tau = (self.input)(t, &q, &v);
        let jac = self.mechanism.forward_dynamics_jacobian(&q, &v, &tau);
        // `layout[i]`: the velocity-layout index of state-order index `i`.
        let mut layout = [0usize; N];
        let m = S::ROTATIONS.len();
        for (r, &(_, k)) in S::ROTATIONS.iter().enumerate() {
            for c in 0..3 {
                layout[3 * r + c] = k + c;
            }
        }
        for (e, &(_, k)) in S::EUCLID.iter().enumerate() {
            layout[3 * m + e] = k;
        }
        for (i, &li) in layout.iter().enumerate() {
            for (j, &lj) in layout.iter().enumerate() {
                dq[i * N + j] = jac.d_dq[(li, lj)];
                dv[i * N + j] = jac.d_dv[(li, lj)];
            }
        }
        true
    }

    /// The layout (`3m + n = N`, `4m + n = NQ`, and `ROTATIONS`, `EUCLID` those of
    /// [`LieMechanism::model`], see [`Model::rotation_slots`]), then the mechanism's
    /// parameters ([`LieMechanism::validate`]).
    fn validate(&self) -> Result<(), String> {
        let (m, n) = (S::ROTATIONS.len(), S::EUCLID.len());
        if 3 * m + n != N || 4 * m + n != NQ {
            return Err(format!(
                "{m} rotations and {n} Euclidean coordinates do not make {N} velocities \
                 and {NQ} configuration slots"
            ));
        }
        let model = self.mechanism.model();
        if model.rotation_slots() != S::ROTATIONS || model.euclid_slots() != S::EUCLID {
            return Err(format!(
                "the layout (ROTATIONS {:?}, EUCLID {:?}) is not the model's ({:?}, {:?})",
                S::ROTATIONS,
                S::EUCLID,
                model.rotation_slots(),
                model.euclid_slots()
            ));
        }
        self.mechanism.validate().map_err(|e| e.to_string())
    }
}

#[cfg(test)]
mod tests;
