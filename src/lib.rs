//! # filippov
//!
//! Compile-time specialised simulators for rigid multibody systems. A struct whose
//! fields are physical parameters, described with attributes, becomes straight-line
//! Rust for what the integrators call — the mass matrix, forward dynamics and its
//! Jacobian (and, with friction, dash-pots or stops, `M⁻¹` and the element laws). Other
//! kernels are emitted when the scene asks for them by name, `#[mechanism(emit = [...])]`:
//! Christoffel symbols, Coriolis matrix, gravity, bias, passive and inverse dynamics,
//! energies, and the DAE residuals, Delassus operator and switching functions of a
//! non-smooth scene ([`runtime::kernels`]). Nothing a scene does not ask for is built:
//! the Christoffel symbols alone are most of a long chain's code.
//!
//! ```
//! use filippov::prelude::*;
//!
//! #[derive(Mechanism)]
//! #[mechanism(gravity = [0.0, -9.81, 0.0], emit = [energy])]
//! #[body(upper, mass = m1, com = [l1 / 2.0, 0.0, 0.0], inertia = rod(m1, l1))]
//! #[joint(shoulder: revolute(z), parent = world, child = upper)]
//! #[body(lower, mass = m2, com = [l2 / 2.0, 0.0, 0.0], inertia = rod(m2, l2))]
//! #[joint(elbow: revolute(z), parent = upper, child = lower, origin = [l1, 0.0, 0.0])]
//! struct DoublePendulum { m1: f64, l1: f64, m2: f64, l2: f64 }
//!
//! let p = DoublePendulum { m1: 1.0, l1: 1.0, m2: 0.5, l2: 0.7 };
//! let q = SVector::<f64, 2>::new(0.3, -0.2);
//! let v = SVector::<f64, 2>::new(1.0, 0.0);
//! let m = p.mass_matrix(&q);
//! assert!((m[(0, 1)] - m[(1, 0)]).abs() == 0.0);
//! // Asked for with `emit = [energy]`: ½ vᵀ M v.
//! assert!((p.kinetic_energy(&q, &v) - 0.5 * m[(0, 0)]).abs() < 1e-15);
//! ```
//!
//! ## A non-smooth run driven by a controller
//!
//! Friction, dash-pots and stops make a scene non-smooth; `solve_nonsmooth` integrates
//! it in one call, and its step-level [`Integrator`](runtime::nonsmooth::Integrator)
//! lets a controller drive it: set the input, advance to the next sample, read the
//! state. Every switch (stick, slip, impact) is in the solution's log.
//!
//! ```
//! use filippov::prelude::*;
//! use filippov::runtime::nonsmooth::Integrator;
//! use filippov::runtime::{NonSmoothMethod, NonSmoothProblem};
//!
//! #[derive(Mechanism)]
//! #[mechanism(inputs = [x])]
//! #[body(block, mass = m, com = [0.0, 0.0, 0.0], inertia = point)]
//! #[joint(x: prismatic(x), parent = world, child = block)]
//! #[friction(x, f_crit = mu_m_g)]
//! #[stop(x, max = 1.0, restitution = 0.0)]
//! struct Block { m: f64, mu_m_g: f64 }
//!
//! let block = Block { m: 1.0, mu_m_g: 2.0 };
//! let problem = NonSmoothProblem::new(0.0, 3.0, SVector::from([0.0]), SVector::from([0.0]));
//! let mut run = Integrator::held(&block, &problem, &NonSmoothMethod::default()).unwrap();
//! for k in 0..3000 {
//!     // A PD controller at 1 kHz towards x = 1.2, past the stop at 1.0.
//!     let u = 20.0 * (1.2 - run.q()[0]) - 5.0 * run.v()[0];
//!     run.set_input(Block::input_forces(&SVector::from([u]))).unwrap();
//!     run.advance_to((k + 1) as f64 * 1e-3).unwrap();
//! }
//! // The block rests on the stop, held there by the controller's force.
//! assert_eq!(run.q()[0], 1.0);
//! assert_eq!(run.v()[0], 0.0);
//! let solution = run.into_solution();
//! assert!(solution.switches.iter().any(|s| s.element.as_deref() == Some("stop_x")));
//! ```
//!
//! ## Attributes
//! - `#[mechanism(gravity = [gx, gy, gz], inputs = [joint, …], emit = [kernel, …])]` —
//!   all optional; no gravity code without gravity; `inputs` names the actuated joints
//!   and adds the constant `Scene::INPUTS` and the associated function
//!   `Scene::input_forces(u: &SVector<f64, INPUTS>) -> SVector<f64, N>` (the map
//!   `τ = B u`, for the input of a run: `&|t, q, v| Scene::input_forces(&u(t, q, v))`,
//!   or [`Integrator::set_input`](runtime::nonsmooth::Integrator::set_input)); `emit` lists the
//!   optional kernels — `christoffel`, `coriolis`, `gravity`, `bias`, `passive_forces`,
//!   `inverse_dynamics`, `energy`, `delassus`, `dae_residuals`, `switching_functions`,
//!   `kinematics` (poses and Jacobians of every body and frame) — or says `emit = all`. Each is a trait of [`runtime::kernels`] (in the [`prelude`]);
//!   calling one the scene did not ask for is a compile error naming the option.
//!   `forward_dynamics = auto | crba | aba` chooses how forward dynamics, its Jacobian
//!   and `M⁻¹` solve with the mass matrix: `crba` (the mass matrix, then its sparse
//!   `LᵀDL`), `aba` (the articulated-body algorithm, unrolled per link), or `auto`, the
//!   default, which takes per kernel whichever emits fewer operations for the scene —
//!   `crba` for short chains and bushy trees, `aba` for long chains
//!   (`cargo run --release --example expansion` prints both counts on chains and trees).
//! - `#[body(name, mass = m, com = [x, y, z], inertia = …)]` — inertia about the centre
//!   of mass in the link frame: `rod(m, l)` (along x), `cylinder(m, r, h)` (along z),
//!   `cuboid(m, a, b, c)`, `sphere(m, r)`, `diag(ixx, iyy, izz)`, a symmetric 3×3 array,
//!   or `point`.
//! - `#[joint(name: revolute(axis) | prismatic(axis) | spherical | free | fixed,
//!   parent = world | body, child = body, origin = [x, y, z], rpy = [roll, pitch, yaw])]`
//!   — URDF convention; the axis is `x`, `y`, `z`, `-x`, … or three numbers. With a
//!   `spherical` (SO(3)) or `free` (SO(3) × ℝ³) joint the scene implements
//!   [`runtime::liegroup::LieMechanism`] instead of [`Mechanism`]: quaternion
//!   configurations, body angular velocities (see that trait for the layout). A body of
//!   mass `0.0` is an intermediate frame and must carry other bodies.
//! - `#[frame(name, parent = body | frame | world, origin = [x, y, z], rpy = [r, p, y])]`
//!   — a frame fixed to a body (a tool point, a sensor); declaring one emits the
//!   [`Kinematics`] kernel: `frame_pose` (an `Isometry3`) and `frame_jacobian` (`6 × N`,
//!   `ṗ` then `ω` in world axes) of every body and frame, by [`FrameId`].
//! - `#[spring(joint, k = …, rest = …)]` or `#[spring(joint, potential = U(x))]` (a
//!   non-linear spring by its energy in the coordinate `x`; force `−dU/dx` derived
//!   symbolically), `#[damper(joint, c = …)]` on joint coordinates;
//!   `#[spring(name: between(a, b), k = …, rest = …, from = [x, y, z], to = [x, y, z])]`
//!   a linear spring between a point of `a` (a body or `world`) and a point of body `b`,
//!   given in their frames.
//! - `#[loop_joint(name: revolute(axis) | prismatic(axis) | spherical | fixed, parent =
//!   world | body, child = body, origin = […], rpy = […], child_origin = […],
//!   child_rpy = […])]` — a joint that closes a kinematic loop between bodies the tree
//!   already connects, its frame given on both sides; it becomes constraints on the
//!   tree's coordinates, which the derive writes out with the closed mechanism's
//!   dynamics ([`runtime::loops::LoopConstraints`]), and every integrator keeps on them
//!   ([`runtime::loops`]; trees with spherical or free joints are not closed yet).
//! - `#[contact(name: point | sphere(r), body = body, at = […], plane = world | body,
//!   origin = […], rpy = […], normal = axis, mu = …, mu_static = …, restitution = …)]`
//!   — a point or sphere on a body touching a plane (`mu_static ≥ mu`: static and
//!   kinetic friction); the derive writes out its gap, normal and tangential Jacobians
//!   and `γ` terms ([`runtime::contacts::Contacts`]); contacts are integrated by
//!   [`runtime::contact_event_driven`] (planar) and [`runtime::contact_time_stepping`]
//!   (planar and spatial, beside joint friction and stops).
//! - Non-smooth elements: `#[friction(joint, f_crit = …)]` (Coulomb),
//!   `#[friction(joint, f_static = …, f_kinetic = …)]` (static and kinetic friction: held
//!   at rest up to `f_static`, slipping at `f_kinetic ≤ f_static`; where rest and slip
//!   are both consistent, rest persists),
//!   `#[bingham(joint, f_crit = …, eta = …)]`, `#[bingham(joint, f_crit = …, law = φ(f))]`
//!   (`select = no_jumps | max_dissipation` for a non-monotone law),
//!   `#[stop(joint, max = L | min = L, restitution = e | k_support = k)]`; both `min` and
//!   `max` in one attribute (or one stop per side) for two-sided joint limits, named
//!   `stop_<joint>_min` and `stop_<joint>_max`.
//!
//! - `#[body(name: kind, parent = …, origin = …, rpy = …, mass = …, com = …, inertia = …)]`
//!   declares a body and the joint it hangs from (named like the body) in one attribute:
//!   rustc expands at most 128 derive helper attributes on one struct, so a chain of 64
//!   links needs this form (65 attributes) or `#![recursion_limit = "256"]` in its crate.
//! - `#[mechanism(urdf = "robots/arm.urdf", lock = […], limits = stops(restitution = e),
//!   joint_friction = true, joint_damping = true, base = free)]` (feature `urdf`) reads
//!   the scene from a URDF file, relative to the crate's `Cargo.toml`, at compile time;
//!   `#[urdf_param(link.mass = m, joint.friction = f, joint.upper = l)]` binds values to
//!   fields. See "Robots from URDF" in `docs/guide.md`.
//! - `#[mechanism(crate = fil)]` when the crate is a renamed dependency
//!   (`fil = { package = "filippov", … }`).
//!
//! Values are expressions over the struct's `f64` fields, numbers, `PI`, `+ - * /`,
//! `sqrt`, `sin`, `cos`, `exp`, `ln` and `powi`; every number and constant part must be a
//! finite `f64`. A field may be named like a function (`sin` is the field, `sin(x)` the
//! function) but not `PI`. Expressions nest at most 256 brackets deep and an attribute
//! holds at most 20,000 tokens; each limit is a spanned error.

// The derive and the trait share a name, as serde's do: one lives in the macro
// namespace, the other in the type namespace.
// The derive's output names the crate `::filippov`; so may the scenes module inside it.
extern crate self as filippov;

#[cfg(feature = "scenes")]
pub mod scenes;

pub use filippov_macros::Mechanism;
/// Python extension modules of scenes (feature `python`): `module!(name, [Scene, …])`
/// makes each scene a Python class with its kernels on NumPy arrays and its runs; see
/// docs/python.md.
#[cfg(feature = "python")]
pub use filippov_python as python;
pub use filippov_runtime as runtime;
pub use filippov_runtime::kernels::{
    Bias, Christoffel, Coriolis, Energy, FrameId, GenericDynamics, GenericJacobian, Gravity,
    InverseDynamics, Kinematics, PassiveForces,
};
pub use filippov_runtime::liegroup::LieMechanism;
pub use filippov_runtime::system::{ForwardJacobian, Mechanism};
pub use nalgebra;

/// The names most programs need: the core traits, the traits of the kernels a scene
/// asks for with `emit = [...]` (so that their methods can be called), and nalgebra's
/// fixed-size vectors.
pub mod prelude {
    pub use crate::{
        Bias, Christoffel, Coriolis, Energy, ForwardJacobian, FrameId, GenericDynamics, Gravity,
        InverseDynamics, Kinematics, LieMechanism, Mechanism, PassiveForces,
    };
    pub use nalgebra::{SMatrix, SVector};
}

/// The README's quick starts, compiled and run as doctests: a program copied from the
/// README builds unchanged.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
