//! Python bindings for filippov scenes, through PyO3: the glue that
//! [`filippov::python::module!`](crate::module) expands to. Not used directly: turn on
//! the `python` feature of `filippov` and write one line in a `cdylib` crate that
//! maturin builds (docs/python.md):
//!
//! ```ignore
//! filippov::python::module!(arms, [Arm { nonsmooth }, Panda { kinematics, inverse_dynamics }]);
//! ```
//!
//! Each scene becomes a Python class of the same name, constructed from its parameters
//! as keyword arguments (`Arm(fc=20.0)`), with its kernels on NumPy arrays (one state of
//! shape `(n,)` or a batch of shape `(batch, n)`), `solve`, `solve_nonsmooth` and
//! `integrator` and `ensemble`. The module also holds
//! [`Solution`](solution::PySolution), [`Integrator`](integrator::PyIntegrator),
//! [`Ensemble`](ensemble::PyEnsemble), the exceptions ([`errors`]) and
//! `fused_kernels`, the switch for the kernels' fused multiply–add twins.
//!
//! * `arrays`: NumPy in and out, shapes checked against the scene's coordinates.
//! * `options`: a run's options by name.
//! * `scene`: what every scene class does, generic over the scene and its kind (`Flat`:
//!   revolute and prismatic joints; `lie`: spherical or free joints).
//! * `contact`: runs of scenes with contacts.
//! * `solution`, `integrator`, `ensemble`, `errors`: the classes the module adds.

pub mod arrays;
pub mod contact;
pub mod ensemble;
pub mod errors;
pub mod integrator;
pub mod lie;
pub mod options;
pub mod scene;
pub mod solution;

pub use lie::Lie;
pub use numpy;
pub use pyo3;
pub use scene::Flat;

use pyo3::prelude::*;

/// Adds what every module has: `Solution`, `Integrator` and the exceptions, each
/// reporting `module` as its `__module__` so that pickle finds it.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add_class::<solution::PySolution>()?;
    m.add_class::<integrator::PyIntegrator>()?;
    m.add_class::<ensemble::PyEnsemble>()?;
    m.add_function(pyo3::wrap_pyfunction!(ensemble::_rebuild_ensemble, m)?)?;
    m.add_function(pyo3::wrap_pyfunction!(fused_kernels, m)?)?;
    m.add("FilippovError", py.get_type::<errors::FilippovError>())?;
    m.add("SolveError", py.get_type::<errors::SolveError>())?;
    m.add("ParameterError", py.get_type::<errors::ParameterError>())?;
    for name in ["Solution", "Integrator", "Ensemble"] {
        adopt(m, name)?;
    }
    Ok(())
}

/// `fused_kernels(on=None)`: whether the scenes' forward dynamics and mass matrix run
/// their fused multiply–add twins (on processors with AVX2 and FMA;
/// `runtime::numerics::fused`). With `on`, turns them on (where the processor has them)
/// or off for the whole process first: off, every machine gives the same bits.
#[pyfunction]
#[pyo3(signature = (on = None))]
fn fused_kernels(on: Option<bool>) -> bool {
    match on {
        Some(on) => filippov_runtime::numerics::fused::set_enabled(on),
        None => filippov_runtime::numerics::fused::enabled(),
    }
}

/// Sets the class `name`'s `__module__` to `m`'s name.
pub fn adopt(m: &Bound<'_, PyModule>, name: &str) -> PyResult<()> {
    m.getattr(name)?.setattr("__module__", m.name()?)
}

/// The scene type of a `module!` entry: `Name` alone is `super::Name`.
#[doc(hidden)]
#[macro_export]
macro_rules! __scene_type {
    ($name:ident) => {
        super::$name
    };
    ($name:ident, $path:path) => {
        $path
    };
}

/// The methods of one scene's class: the ones every scene has, then those its
/// capabilities (`kinematics`, `inverse_dynamics`) add.
#[doc(hidden)]
#[macro_export]
macro_rules! __scene_methods {
    ($name:ident, $ty:ty, $kind:ident, [kinematics $(, $rest:ident)*], [$($acc:tt)*]) => {
        $crate::__scene_methods!($name, $ty, $kind, [$($rest),*], [$($acc)*
            /// The frames `frame_pose` and `frame_jacobian` take: the bodies, then the
            /// declared frames.
            #[classattr]
            fn frames() -> ::std::vec::Vec<&'static str> {
                $crate::scene::frames::<$ty, _, _>()
            }

            /// The world pose of `frame` at `q` as a 4 × 4 homogeneous matrix
            /// (`(batch, 4, 4)` for a batch of states).
            fn frame_pose<'py>(
                &self,
                py: $crate::pyo3::Python<'py>,
                frame: &str,
                q: &$crate::pyo3::Bound<'py, $crate::pyo3::PyAny>,
            ) -> $crate::pyo3::PyResult<$crate::pyo3::Bound<'py, $crate::pyo3::PyAny>> {
                $crate::scene::frame_pose::<$crate::$kind<$ty>, _, _>(py, stringify!($name), &self.0, frame, q)
            }

            /// The Jacobian of `frame` at `q`, rows `(ṗ, ω)` in world axes: `(6, n)`
            /// (`(batch, 6, n)`).
            fn frame_jacobian<'py>(
                &self,
                py: $crate::pyo3::Python<'py>,
                frame: &str,
                q: &$crate::pyo3::Bound<'py, $crate::pyo3::PyAny>,
            ) -> $crate::pyo3::PyResult<$crate::pyo3::Bound<'py, $crate::pyo3::PyAny>> {
                $crate::scene::frame_jacobian::<$crate::$kind<$ty>, _, _>(py, stringify!($name), &self.0, frame, q)
            }
        ]);
    };
    ($name:ident, $ty:ty, $kind:ident, [inverse_dynamics $(, $rest:ident)*], [$($acc:tt)*]) => {
        $crate::__scene_methods!($name, $ty, $kind, [$($rest),*], [$($acc)*
            /// `τ = M(q) a + C(q, v) v + g(q) − τ_p`: the forces that give acceleration `a`.
            fn inverse_dynamics<'py>(
                &self,
                py: $crate::pyo3::Python<'py>,
                q: &$crate::pyo3::Bound<'py, $crate::pyo3::PyAny>,
                v: &$crate::pyo3::Bound<'py, $crate::pyo3::PyAny>,
                a: &$crate::pyo3::Bound<'py, $crate::pyo3::PyAny>,
            ) -> $crate::pyo3::PyResult<$crate::pyo3::Bound<'py, $crate::pyo3::PyAny>> {
                $crate::scene::inverse_dynamics::<$crate::$kind<$ty>, _, _>(py, stringify!($name), &self.0, q, v, a)
            }
        ]);
    };
    ($name:ident, $ty:ty, Flat, [nonsmooth $(, $rest:ident)*], [$($acc:tt)*]) => {
        $crate::__scene_methods!($name, $ty, Flat, [$($rest),*], [$($acc)*
            /// A non-smooth run: `method="event_driven"` (default; `smooth=` the method
            /// between events, DOPRI5 at rtol 1e-8, atol 1e-10) or `"time_stepping"`
            /// (`h`, `theta` = 1); other options as `solve`'s. The solution has the
            /// element forces as columns and the switch log as `switches`.
            #[pyo3(signature = (t_end, q0, v0=None, **options))]
            fn solve_nonsmooth(
                &self,
                py: $crate::pyo3::Python<'_>,
                t_end: f64,
                q0: &$crate::pyo3::Bound<'_, $crate::pyo3::PyAny>,
                v0: ::core::option::Option<&$crate::pyo3::Bound<'_, $crate::pyo3::PyAny>>,
                options: ::core::option::Option<&$crate::pyo3::Bound<'_, $crate::pyo3::types::PyDict>>,
            ) -> $crate::pyo3::PyResult<$crate::solution::PySolution> {
                $crate::scene::solve_nonsmooth(py, stringify!($name), &self.0, t_end, q0, v0, options)
            }

            /// Runs of this scene drawn reproducibly: `parameters` maps parameter names to
            /// draws over the scene's own values (a number, `("uniform", low, high)`, or
            /// a list of grid values), `q0` and `v0` give a draw per coordinate (zero by
            /// default); `samples` random draws at each point of the grids' product,
            /// from `seed`; `solve_nonsmooth`'s method and tolerances as options.
            #[pyo3(signature = (t_end, parameters=None, q0=None, v0=None, samples=1, seed=0, **options))]
            fn ensemble(
                slf: &$crate::pyo3::Bound<'_, Self>,
                t_end: f64,
                parameters: ::core::option::Option<&$crate::pyo3::Bound<'_, $crate::pyo3::types::PyDict>>,
                q0: ::core::option::Option<&$crate::pyo3::Bound<'_, $crate::pyo3::PyAny>>,
                v0: ::core::option::Option<&$crate::pyo3::Bound<'_, $crate::pyo3::PyAny>>,
                samples: usize,
                seed: u64,
                options: ::core::option::Option<&$crate::pyo3::Bound<'_, $crate::pyo3::types::PyDict>>,
            ) -> $crate::pyo3::PyResult<$crate::ensemble::PyEnsemble> {
                $crate::ensemble::new(
                    stringify!($name),
                    &slf.get().0,
                    slf.as_any(),
                    t_end, parameters, q0, v0, samples, seed, options,
                )
            }

            /// A non-smooth run driven step by step (`set_input`, `advance_to`, `step`),
            /// with `solve_nonsmooth`'s options.
            #[pyo3(signature = (t_end, q0, v0=None, **options))]
            fn integrator(
                &self,
                py: $crate::pyo3::Python<'_>,
                t_end: f64,
                q0: &$crate::pyo3::Bound<'_, $crate::pyo3::PyAny>,
                v0: ::core::option::Option<&$crate::pyo3::Bound<'_, $crate::pyo3::PyAny>>,
                options: ::core::option::Option<&$crate::pyo3::Bound<'_, $crate::pyo3::types::PyDict>>,
            ) -> $crate::pyo3::PyResult<$crate::integrator::PyIntegrator> {
                $crate::scene::integrator(py, stringify!($name), &self.0, t_end, q0, v0, options)
            }
        ]);
    };
    ($name:ident, $ty:ty, Flat, [contacts $(, $rest:ident)*], [$($acc:tt)*]) => {
        $crate::__scene_methods!($name, $ty, Flat, [$($rest),*], [$($acc)*
            /// The contacts' names, as declared.
            #[classattr]
            fn contacts() -> ::std::vec::Vec<&'static str> {
                $crate::contact::contacts::<$ty, _, _, _>()
            }

            /// A run with the contacts: `method="event_driven"` (default; contacts
            /// alone, `smooth=` the method between events) or `"time_stepping"` (Moreau–Jean
            /// with step `h`, beside joint friction and stops); other options as
            /// `solve_nonsmooth`'s. The contact forces are columns: `λ_<contact>.n`, then
            /// the tangential `λ_<contact>.<axis>`.
            #[pyo3(signature = (t_end, q0, v0=None, **options))]
            fn solve_contacts(
                &self,
                py: $crate::pyo3::Python<'_>,
                t_end: f64,
                q0: &$crate::pyo3::Bound<'_, $crate::pyo3::PyAny>,
                v0: ::core::option::Option<&$crate::pyo3::Bound<'_, $crate::pyo3::PyAny>>,
                options: ::core::option::Option<&$crate::pyo3::Bound<'_, $crate::pyo3::types::PyDict>>,
            ) -> $crate::pyo3::PyResult<$crate::solution::PySolution> {
                $crate::contact::solve_contacts::<$ty, _, _, _>(py, stringify!($name), &self.0, t_end, q0, v0, options)
            }
        ]);
    };
    ($name:ident, $ty:ty, Flat, [lie $(, $rest:ident)*], [$($acc:tt)*]) => {
        $crate::__scene_methods!($name, $ty, Lie, [$($rest),*], [$($acc)*]);
    };
    ($name:ident, $ty:ty, Lie, [nonsmooth $(, $rest:ident)*], [$($acc:tt)*]) => {
        ::core::compile_error!(concat!(
            stringify!($name), ": `nonsmooth` is for scenes on revolute and prismatic joints; \
             a scene with spherical or free joints (`lie`) has the smooth `solve` on its Lie group"
        ));
    };
    ($name:ident, $ty:ty, $kind:ident, [$other:ident $(, $rest:ident)*], [$($acc:tt)*]) => {
        ::core::compile_error!(concat!(
            "unknown capability `", stringify!($other), "` for ", stringify!($name),
            "; the capabilities are nonsmooth (a scene with friction, dash-pots or stops), \
             contacts (a scene with `#[contact]`s), lie (first, for a scene with spherical \
             or free joints), kinematics and inverse_dynamics (each of these two needs the \
             scene to emit that kernel: `#[mechanism(emit = [kinematics, inverse_dynamics])]`)"
        ));
    };
    ($name:ident, $ty:ty, $kind:ident, [], [$($acc:tt)*]) => {
        #[$crate::pyo3::pymethods]
        #[pyo3(crate = "::filippov::python::pyo3")]
        impl $name {
            /// The scene from its parameters, each by name.
            #[new]
            #[pyo3(signature = (**parameters))]
            fn __new__(
                parameters: ::core::option::Option<&$crate::pyo3::Bound<'_, $crate::pyo3::types::PyDict>>,
            ) -> $crate::pyo3::PyResult<Self> {
                $crate::scene::new::<$crate::$kind<$ty>, _, _>(stringify!($name), parameters).map($name)
            }

            /// The velocity coordinates' names (the joints, in the scene's order; a
            /// spherical joint's `joint.wx`, `.wy`, `.wz`, a free joint's `joint.x`, `.y`,
            /// `.z` then its angular velocity).
            #[classattr]
            fn joints() -> ::std::vec::Vec<&'static str> {
                $crate::scene::joints::<$crate::$kind<$ty>, _, _>()
            }

            /// The configuration's slots, the order of `q`: the joints, except that a
            /// spherical or free joint has a unit quaternion `joint.qw` … `joint.qz` (after
            /// a free joint's position `joint.x`, `joint.y`, `joint.z`).
            #[classattr]
            fn configuration() -> ::std::vec::Vec<::std::string::String> {
                $crate::scene::configuration::<$crate::$kind<$ty>, _, _>()
            }

            /// The number of coordinates (of `v`, `τ`, `v̇`).
            #[classattr]
            fn dof() -> usize {
                $crate::scene::joints::<$crate::$kind<$ty>, _, _>().len()
            }

            /// The parameters' names, in declaration order.
            #[classattr]
            fn parameter_names() -> ::std::vec::Vec<&'static str> {
                <$ty as $crate::__runtime::system::Parameters>::NAMES.to_vec()
            }

            /// The non-smooth elements (friction, dash-pots, stops, contacts) by name.
            #[classattr]
            fn elements() -> ::std::vec::Vec<&'static str> {
                $crate::scene::elements::<$crate::$kind<$ty>, _, _>()
            }

            /// `{parameter: value}`.
            #[getter]
            fn parameters<'py>(
                &self,
                py: $crate::pyo3::Python<'py>,
            ) -> $crate::pyo3::PyResult<$crate::pyo3::Bound<'py, $crate::pyo3::types::PyDict>> {
                $crate::scene::parameters(py, &self.0)
            }

            fn __repr__(&self) -> ::std::string::String {
                $crate::scene::repr(stringify!($name), &self.0)
            }

            /// Pickling (for process pools and clusters): rebuilt from its parameters.
            fn __getnewargs_ex__<'py>(
                &self,
                py: $crate::pyo3::Python<'py>,
            ) -> $crate::pyo3::PyResult<(
                (),
                $crate::pyo3::Bound<'py, $crate::pyo3::types::PyDict>,
            )> {
                Ok(((), $crate::scene::parameters(py, &self.0)?))
            }

            /// `M(q)`: `(n, n)`, or `(batch, n, n)` for a batch of states.
            fn mass_matrix<'py>(
                &self,
                py: $crate::pyo3::Python<'py>,
                q: &$crate::pyo3::Bound<'py, $crate::pyo3::PyAny>,
            ) -> $crate::pyo3::PyResult<$crate::pyo3::Bound<'py, $crate::pyo3::PyAny>> {
                $crate::scene::mass_matrix::<$crate::$kind<$ty>, _, _>(py, stringify!($name), &self.0, q)
            }

            /// `v̇ = FD(q, v, τ)` (`τ` zero by default): `(n,)`, or `(batch, n)`.
            #[pyo3(signature = (q, v, tau=None))]
            fn forward_dynamics<'py>(
                &self,
                py: $crate::pyo3::Python<'py>,
                q: &$crate::pyo3::Bound<'py, $crate::pyo3::PyAny>,
                v: &$crate::pyo3::Bound<'py, $crate::pyo3::PyAny>,
                tau: ::core::option::Option<&$crate::pyo3::Bound<'py, $crate::pyo3::PyAny>>,
            ) -> $crate::pyo3::PyResult<$crate::pyo3::Bound<'py, $crate::pyo3::PyAny>> {
                $crate::scene::forward_dynamics::<$crate::$kind<$ty>, _, _>(py, stringify!($name), &self.0, q, v, tau)
            }

            /// `(v̇, ∂v̇/∂q, ∂v̇/∂v)` at `(q, v, τ)`, exact (generated code).
            #[pyo3(signature = (q, v, tau=None))]
            fn forward_dynamics_jacobian<'py>(
                &self,
                py: $crate::pyo3::Python<'py>,
                q: &$crate::pyo3::Bound<'py, $crate::pyo3::PyAny>,
                v: &$crate::pyo3::Bound<'py, $crate::pyo3::PyAny>,
                tau: ::core::option::Option<&$crate::pyo3::Bound<'py, $crate::pyo3::PyAny>>,
            ) -> $crate::pyo3::PyResult<$crate::pyo3::Bound<'py, $crate::pyo3::types::PyTuple>> {
                $crate::scene::forward_dynamics_jacobian::<$crate::$kind<$ty>, _, _>(py, stringify!($name), &self.0, q, v, tau)
            }

            /// A smooth run from `(q0, v0)` (`v0` zero by default) to `t_end`. Options:
            /// `method` (`"dopri5"` default, `"sdirk4"`, `"bdf"`, `"rk4"` with `h`; for a
            /// scene with spherical or free joints `"rkmk5"` default or `"lie_sdirk"`,
            /// adaptive or with a fixed step `h`), `rtol`, `atol`, `h0`, `h_max`,
            /// `max_steps`, `t0`, `times` (rows at these times only), `every` (every k-th
            /// step), `tau` (constant applied forces).
            #[pyo3(signature = (t_end, q0, v0=None, **options))]
            fn solve(
                &self,
                py: $crate::pyo3::Python<'_>,
                t_end: f64,
                q0: &$crate::pyo3::Bound<'_, $crate::pyo3::PyAny>,
                v0: ::core::option::Option<&$crate::pyo3::Bound<'_, $crate::pyo3::PyAny>>,
                options: ::core::option::Option<&$crate::pyo3::Bound<'_, $crate::pyo3::types::PyDict>>,
            ) -> $crate::pyo3::PyResult<$crate::solution::PySolution> {
                $crate::scene::solve::<$crate::$kind<$ty>, _, _>(py, stringify!($name), &self.0, t_end, q0, v0, options)
            }

            $($acc)*
        }
    };
}

/// A Python extension module of the given scenes: one line in a `cdylib` crate whose
/// library name is the module's (`[lib] name = "arms"`, built by maturin).
///
/// ```ignore
/// use filippov::prelude::*;
/// #[derive(Mechanism)] /* … */ struct Arm { fc: f64 }
/// filippov::python::module!(arms, [Arm { nonsmooth }, Panda = filippov::scenes::Panda { inverse_dynamics }]);
/// ```
///
/// Each entry is a scene type in scope (`Arm`), or a class name and a path
/// (`Panda = filippov::scenes::Panda`), optionally followed by what the scene has beyond
/// the kernels and the smooth `solve` every scene has:
///
/// * `lie` (first): a scene with spherical or free joints, whose configuration `q` holds
///   unit quaternions; its `solve` integrates on the Lie group (`method="rkmk5"` or
///   `"lie_sdirk"`);
/// * `nonsmooth`: `solve_nonsmooth` and `integrator` (the step-level run a controller
///   drives), for a scene with friction, dash-pots or stops;
/// * `contacts`: `solve_contacts` (the contact integrators), for a scene with
///   `#[contact]`s;
/// * `kinematics`: frame poses and Jacobians (the scene emits `kinematics`);
/// * `inverse_dynamics`: `inverse_dynamics(q, v, a)` (the scene emits it).
#[macro_export]
macro_rules! module {
    ($module:ident, [$($name:ident $(= $path:path)? $({ $($cap:ident),* $(,)? })?),* $(,)?]) => {
        #[allow(non_snake_case, unused_imports, clippy::too_many_arguments)]
        mod __filippov_python {
            use super::*;
            $(
                /// A filippov scene.
                #[$crate::pyo3::pyclass(frozen)]
                #[pyo3(crate = "::filippov::python::pyo3")]
                pub struct $name(pub $crate::__scene_type!($name $(, $path)?));

                $crate::__scene_methods!(
                    $name,
                    $crate::__scene_type!($name $(, $path)?),
                    Flat,
                    [$($($cap),*)?],
                    []
                );
            )*
        }

        #[$crate::pyo3::pymodule]
        #[pyo3(crate = "::filippov::python::pyo3")]
        fn $module(m: &$crate::pyo3::Bound<'_, $crate::pyo3::types::PyModule>) -> $crate::pyo3::PyResult<()> {
            use $crate::pyo3::types::PyModuleMethods as _;
            $crate::register(m)?;
            $(
                m.add_class::<__filippov_python::$name>()?;
                $crate::adopt(m, stringify!($name))?;
            )*
            Ok(())
        }
    };
}

#[doc(hidden)]
pub use filippov_runtime as __runtime;
