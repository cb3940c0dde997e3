//! Kernels no integrator calls, which the derive emits only when a scene asks for them
//! by name: `#[mechanism(emit = [coriolis, energy, …])]`, or `emit = all`.
//!
//! Each is its own trait so that a scene that did not ask has no such code at all (the
//! Christoffel symbols alone are O(n³) expressions: most of a long chain's code), and a
//! program that needs one fails to compile with a message naming the option. The core
//! traits, [`Mechanism`](crate::Mechanism) and [`LieMechanism`](crate::LieMechanism),
//! carry what the integrators call: the mass matrix, forward dynamics and its Jacobian.
//!
//! | `emit = [...]` | trait | methods |
//! |---|---|---|
//! | `christoffel` | [`Christoffel`] | `christoffel_symbols` (not for Lie-group scenes) |
//! | `coriolis` | [`Coriolis`] | `coriolis_matrix` |
//! | `gravity` | [`Gravity`] | `gravity` |
//! | `bias` | [`Bias`] | `bias` |
//! | `passive_forces` | [`PassiveForces`] | `passive_forces` |
//! | `inverse_dynamics` | [`InverseDynamics`] | `inverse_dynamics` |
//! | `energy` | [`Energy`] | `kinetic_energy`, `potential_energy` |
//! | `delassus` | inherent | `delassus` (scenes with non-smooth elements) |
//! | `dae_residuals` | inherent | `momentum_residual`, `constitutive_residual` |
//! | `switching_functions` | inherent | `switching_functions` |
//! | `kinematics` (or any `#[frame]`) | [`Kinematics`] | `frame_pose`, `frame_jacobian`, `frame_velocity` |
//! | `generic` | [`GenericDynamics`] | `forward_dynamics_generic`, `mass_matrix_generic`, `inverse_dynamics_generic`, `forward_dynamics_jacobian_generic` on any [`Real`](crate::Real) |
//!
//! The traits take the number of velocity coordinates `N` and of configuration slots
//! `NQ` (equal to `N` unless the scene has spherical or free joints, whose quaternions
//! take four slots for three velocities).

use std::marker::PhantomData;

use nalgebra::{
    Isometry3, Matrix3, Rotation3, SMatrix, SVector, Translation3, UnitQuaternion, Vector3,
};

/// The dynamics on any scalar, `#[mechanism(emit = [generic])]`: the same
/// straight-line code as [`Mechanism`](crate::Mechanism)'s forward dynamics, its
/// Jacobian and mass matrix and as [`InverseDynamics`], generic over
/// [`Real`](crate::Real), with the scene's parameters (its `f64` fields, in declaration
/// order) as an input of that scalar too — so that on [`Dual`](crate::Dual) numbers it
/// gives the derivatives with respect to the coordinates, velocities, torques and
/// parameters alike, and on SIMD lanes ([`Lanes`](crate::real::Lanes)) a batch of
/// states per call. `P` is the number of parameters.
///
/// Matrices are arrays of rows: `m[i][j]` is `M_ij`.
#[diagnostic::on_unimplemented(
    message = "`{Self}` has no generic forward dynamics: it is emitted only on request",
    label = "needs `forward_dynamics_generic`",
    note = "add `emit = [generic]` (or `emit = all`) to the scene's `#[mechanism(...)]`"
)]
pub trait GenericDynamics<const N: usize, const NQ: usize, const P: usize> {
    /// The parameters' names, as declared (the struct's fields).
    const PARAMETERS: [&'static str; P];
    /// The parameters' values, in the order of [`PARAMETERS`](Self::PARAMETERS).
    fn parameters(&self) -> [f64; P];
    /// `v̇ = M⁻¹ (τ + τ_p − C v − g)` at parameters `p`.
    fn forward_dynamics_generic<T: crate::Real>(
        p: &[T; P],
        q: &[T; NQ],
        v: &[T; N],
        tau: &[T; N],
    ) -> [T; N];
    /// [`forward_dynamics_generic`](Self::forward_dynamics_generic) at this scene's
    /// parameters (constants of `T`).
    fn forward_dynamics_as<T: crate::Real>(&self, q: &[T; NQ], v: &[T; N], tau: &[T; N]) -> [T; N] {
        Self::forward_dynamics_generic(&self.parameters().map(T::cst), q, v, tau)
    }
    /// The mass matrix `M(q)` at parameters `p`.
    fn mass_matrix_generic<T: crate::Real>(p: &[T; P], q: &[T; NQ]) -> [[T; N]; N];
    /// [`mass_matrix_generic`](Self::mass_matrix_generic) at this scene's parameters.
    fn mass_matrix_as<T: crate::Real>(&self, q: &[T; NQ]) -> [[T; N]; N] {
        Self::mass_matrix_generic(&self.parameters().map(T::cst), q)
    }
    /// Inverse dynamics `τ = M a + C v + g − τ_p` at parameters `p` (of the tree, as
    /// [`InverseDynamics`]).
    fn inverse_dynamics_generic<T: crate::Real>(
        p: &[T; P],
        q: &[T; NQ],
        v: &[T; N],
        a: &[T; N],
    ) -> [T; N];
    /// [`inverse_dynamics_generic`](Self::inverse_dynamics_generic) at this scene's
    /// parameters.
    fn inverse_dynamics_as<T: crate::Real>(&self, q: &[T; NQ], v: &[T; N], a: &[T; N]) -> [T; N] {
        Self::inverse_dynamics_generic(&self.parameters().map(T::cst), q, v, a)
    }
    /// Forward dynamics and its symbolic Jacobian with respect to `(q, v)` at parameters
    /// `p`, as [`Mechanism::forward_dynamics_jacobian`](crate::Mechanism::forward_dynamics_jacobian).
    fn forward_dynamics_jacobian_generic<T: crate::Real>(
        p: &[T; P],
        q: &[T; NQ],
        v: &[T; N],
        tau: &[T; N],
    ) -> GenericJacobian<T, N>;
    /// [`forward_dynamics_jacobian_generic`](Self::forward_dynamics_jacobian_generic) at
    /// this scene's parameters.
    fn forward_dynamics_jacobian_as<T: crate::Real>(
        &self,
        q: &[T; NQ],
        v: &[T; N],
        tau: &[T; N],
    ) -> GenericJacobian<T, N> {
        Self::forward_dynamics_jacobian_generic(&self.parameters().map(T::cst), q, v, tau)
    }
}

/// Forward dynamics and its Jacobian on any scalar
/// ([`GenericDynamics::forward_dynamics_jacobian_generic`]); the matrices are arrays of
/// rows, `d_dq[i][j] = ∂v̇_i/∂q_j` (along the tangent coordinates for Lie-group scenes,
/// as [`ForwardJacobian`](crate::ForwardJacobian)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GenericJacobian<T, const N: usize> {
    /// `v̇`.
    pub acceleration: [T; N],
    /// `∂v̇/∂q`.
    pub d_dq: [[T; N]; N],
    /// `∂v̇/∂v`.
    pub d_dv: [[T; N]; N],
}

/// Christoffel symbols of the first kind, `#[mechanism(emit = [christoffel])]`.
#[diagnostic::on_unimplemented(
    message = "`{Self}` has no Christoffel symbols: they are emitted only on request",
    label = "needs `christoffel_symbols`",
    note = "add `emit = [christoffel]` (or `emit = all`) to the scene's `#[mechanism(...)]`"
)]
pub trait Christoffel<const N: usize> {
    /// `out[i][(j, k)] = c_ijk = ½ (∂M_ij/∂q_k + ∂M_ik/∂q_j − ∂M_jk/∂q_i)`.
    fn christoffel_symbols(&self, q: &SVector<f64, N>) -> [SMatrix<f64, N, N>; N];
}

/// The Coriolis matrix, `#[mechanism(emit = [coriolis])]`.
#[diagnostic::on_unimplemented(
    message = "`{Self}` has no Coriolis matrix: it is emitted only on request",
    label = "needs `coriolis_matrix`",
    note = "add `emit = [coriolis]` (or `emit = all`) to the scene's `#[mechanism(...)]`"
)]
pub trait Coriolis<const N: usize, const NQ: usize = N> {
    /// `C_ij = Σ_k c_ijk v_k` (for Lie-group scenes plus `(M v)·[e_i, e_j]`, see
    /// [`LieMechanism`](crate::LieMechanism)); `Ṁ − 2C` is skew-symmetric.
    fn coriolis_matrix(&self, q: &SVector<f64, NQ>, v: &SVector<f64, N>) -> SMatrix<f64, N, N>;
}

/// Generalised gravity forces, `#[mechanism(emit = [gravity])]`.
#[diagnostic::on_unimplemented(
    message = "`{Self}` has no `gravity` kernel: it is emitted only on request",
    label = "needs `gravity`",
    note = "add `emit = [gravity]` (or `emit = all`) to the scene's `#[mechanism(...)]`"
)]
pub trait Gravity<const N: usize, const NQ: usize = N> {
    /// `g(q) = ∂U_gravity/∂q`.
    fn gravity(&self, q: &SVector<f64, NQ>) -> SVector<f64, N>;
}

/// Bias forces, `#[mechanism(emit = [bias])]`.
#[diagnostic::on_unimplemented(
    message = "`{Self}` has no `bias` kernel: it is emitted only on request",
    label = "needs `bias`",
    note = "add `emit = [bias]` (or `emit = all`) to the scene's `#[mechanism(...)]`"
)]
pub trait Bias<const N: usize, const NQ: usize = N> {
    /// `C(q, v) v + g(q)`.
    fn bias(&self, q: &SVector<f64, NQ>, v: &SVector<f64, N>) -> SVector<f64, N>;
}

/// Spring and damper forces, `#[mechanism(emit = [passive_forces])]`.
#[diagnostic::on_unimplemented(
    message = "`{Self}` has no `passive_forces` kernel: it is emitted only on request",
    label = "needs `passive_forces`",
    note = "add `emit = [passive_forces]` (or `emit = all`) to the scene's `#[mechanism(...)]`"
)]
pub trait PassiveForces<const N: usize, const NQ: usize = N> {
    /// Passive forces of springs and dampers on joint coordinates, `τ_p(q, v)`.
    fn passive_forces(&self, q: &SVector<f64, NQ>, v: &SVector<f64, N>) -> SVector<f64, N>;
}

/// Inverse dynamics, `#[mechanism(emit = [inverse_dynamics])]`.
#[diagnostic::on_unimplemented(
    message = "`{Self}` has no `inverse_dynamics` kernel: it is emitted only on request",
    label = "needs `inverse_dynamics`",
    note = "add `emit = [inverse_dynamics]` (or `emit = all`) to the scene's `#[mechanism(...)]`"
)]
pub trait InverseDynamics<const N: usize, const NQ: usize = N> {
    /// `τ = M a + C v + g − τ_p`: the input forces that produce acceleration `a`.
    fn inverse_dynamics(
        &self,
        q: &SVector<f64, NQ>,
        v: &SVector<f64, N>,
        a: &SVector<f64, N>,
    ) -> SVector<f64, N>;
}

/// Kinetic and potential energy, `#[mechanism(emit = [energy])]`.
#[diagnostic::on_unimplemented(
    message = "`{Self}` has no energy kernels: they are emitted only on request",
    label = "needs `kinetic_energy` and `potential_energy`",
    note = "add `emit = [energy]` (or `emit = all`) to the scene's `#[mechanism(...)]`"
)]
pub trait Energy<const N: usize, const NQ: usize = N> {
    /// Kinetic energy `½ vᵀ M v`.
    fn kinetic_energy(&self, q: &SVector<f64, NQ>, v: &SVector<f64, N>) -> f64;
    /// Potential energy of gravity and springs.
    fn potential_energy(&self, q: &SVector<f64, NQ>) -> f64;
    /// `kinetic_energy + potential_energy`.
    fn total_energy(&self, q: &SVector<f64, NQ>, v: &SVector<f64, N>) -> f64 {
        self.kinetic_energy(q, v) + self.potential_energy(q)
    }
}

/// A frame of scene `M`: one of its bodies or a frame it declares with `#[frame(…)]`.
/// Obtained from [`Kinematics::frame`] (by name) or [`Kinematics::frame_at`] (by
/// index), so it is always valid for `M`; look it up once and keep it.
pub struct FrameId<M: ?Sized> {
    index: usize,
    scene: PhantomData<fn() -> M>,
}

impl<M: ?Sized> FrameId<M> {
    /// The frame's position in [`Kinematics::FRAMES`].
    pub fn index(self) -> usize {
        self.index
    }
}

impl<M: ?Sized> Clone for FrameId<M> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<M: ?Sized> Copy for FrameId<M> {}
impl<M: ?Sized> PartialEq for FrameId<M> {
    fn eq(&self, o: &Self) -> bool {
        self.index == o.index
    }
}
impl<M: ?Sized> Eq for FrameId<M> {}
impl<M: ?Sized> std::hash::Hash for FrameId<M> {
    fn hash<H: std::hash::Hasher>(&self, h: &mut H) {
        self.index.hash(h)
    }
}
impl<M: ?Sized> std::fmt::Debug for FrameId<M> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "FrameId({})", self.index)
    }
}

/// Forward kinematics, `#[mechanism(emit = [kinematics])]` or any `#[frame(…)]`: the
/// world pose and the Jacobian of every body and declared frame, generated per frame
/// as straight-line code (one `sin`/`cos` per joint on the frame's path, nothing for
/// joints off it).
///
/// ```ignore
/// let tool = Arm::frame("tool").expect("declared with #[frame(tool, …)]");
/// let pose = arm.frame_pose(tool, &q);          // nalgebra::Isometry3<f64>
/// let j = arm.frame_jacobian(tool, &q);         // 6 × N: ṗ then ω, world axes
/// let (p_dot, omega) = arm.frame_velocity(tool, &q, &v);
/// ```
///
/// The Jacobian follows Pinocchio's `LOCAL_WORLD_ALIGNED` convention: rows 0–2 map the
/// velocity coordinates `v` to the velocity of the frame's origin, rows 3–5 to its
/// angular velocity, both in world axes. For spherical and free joints `v` holds their
/// body angular velocities (and, for a free joint, the world velocity of its origin),
/// as everywhere in the runtime.
#[diagnostic::on_unimplemented(
    message = "`{Self}` has no forward kinematics: it is emitted only on request",
    label = "needs `frame_pose` / `frame_jacobian`",
    note = "add `emit = [kinematics]` (or `emit = all`) to the scene's `#[mechanism(...)]`, or declare a frame with `#[frame(name, parent = <body>, origin = [x, y, z])]`"
)]
pub trait Kinematics<const N: usize, const NQ: usize = N>: Sized {
    /// Frame names: the bodies in the scene's tree order, then the declared frames.
    const FRAMES: &'static [&'static str];

    /// The frame called `name` (a body or a declared frame), or `None`.
    fn frame(name: &str) -> Option<FrameId<Self>> {
        Self::FRAMES
            .iter()
            .position(|f| *f == name)
            .map(|index| FrameId {
                index,
                scene: PhantomData,
            })
    }

    /// The frame at `index` in [`FRAMES`](Self::FRAMES), or `None` past its end.
    fn frame_at(index: usize) -> Option<FrameId<Self>> {
        (index < Self::FRAMES.len()).then_some(FrameId {
            index,
            scene: PhantomData,
        })
    }

    /// The frame's pose in the world: `p_world = pose * p_frame`.
    fn frame_pose(&self, frame: FrameId<Self>, q: &SVector<f64, NQ>) -> Isometry3<f64>;

    /// `J(q)` with `(ṗ, ω) = J v`: rows 0–2 the velocity of the frame's origin, rows
    /// 3–5 its angular velocity, world axes (columns of joints off the frame's path are
    /// zero).
    fn frame_jacobian(&self, frame: FrameId<Self>, q: &SVector<f64, NQ>) -> SMatrix<f64, 6, N>;

    /// `(ṗ, ω)`: the world velocity of the frame's origin and its angular velocity.
    fn frame_velocity(
        &self,
        frame: FrameId<Self>,
        q: &SVector<f64, NQ>,
        v: &SVector<f64, N>,
    ) -> (Vector3<f64>, Vector3<f64>) {
        let t = self.frame_jacobian(frame, q) * v;
        (
            t.fixed_rows::<3>(0).into_owned(),
            t.fixed_rows::<3>(3).into_owned(),
        )
    }
}

/// The pose of a generated rotation (row-major) and origin; used by the generated
/// `frame_pose`.
#[doc(hidden)]
#[inline]
pub fn isometry(r: [f64; 9], p: [f64; 3]) -> Isometry3<f64> {
    let m = Matrix3::new(r[0], r[1], r[2], r[3], r[4], r[5], r[6], r[7], r[8]);
    Isometry3::from_parts(
        Translation3::new(p[0], p[1], p[2]),
        UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(m)),
    )
}
