//! Time-stepping methods, each a configuration (`Dopri5 { options }`, …) that makes a
//! [`Stepper`]: the step-level state every driver runs on ([`stepper`]). The [`Method`]
//! enum picks one at run time for [`solve`](crate::solve) and the event-driven
//! integrator.
//!
//! | method | kind | dense output | use |
//! |---|---|---|---|
//! | [`Rk4`] | explicit, fixed step, order 4 | quintic Hermite through the last three points (cubic Hermite on a first step) | convergence studies, baselines |
//! | [`Dopri5`] | explicit, adaptive 5(4), FSAL | quintic Hermite through the last three points (Dormand–Prince, degree 4, on a first step) | non-stiff problems |
//! | [`Sdirk4`] | L-stable SDIRK, adaptive 4(3), simplified Newton | quintic Hermite through the last three points (cubic Hermite on a first step) | stiff problems, frequent restarts |
//! | [`Bdf`] | variable-order (1–5) variable-step BDF, simplified Newton | its interpolating polynomial | smooth stiff problems |
//!
//! Shared rules: options are validated first ([`ErrorKind::InvalidInput`](crate::ErrorKind),
//! never a panic); every right-hand-side value and every new state is checked, and a
//! NaN or infinity ends the integration with [`ErrorKind::NonFinite`](crate::ErrorKind)
//! (we do not try to recover by shrinking the step: a non-finite derivative is almost
//! always a modelling error, and hiding it costs more than reporting it). The solution
//! up to the failure is returned in the [`SolveError`](crate::SolveError).

mod any;
mod bdf;
mod dopri5;
mod rk4;
mod sdirk;
pub mod stepper;

pub use any::AnyStepper;
pub use bdf::{Bdf, BdfStepper};
pub use dopri5::{Dopri5, Dopri5Stepper};
pub use rk4::{Rk4, Rk4Stepper};
pub use sdirk::{Sdirk4, Sdirk4Stepper};
pub use stepper::{Begin, DenseStep, Eval, StepResult, StepState, Stepper};

use crate::Options;

/// A method with its configuration, for [`solve`](crate::solve).
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum Method {
    /// Classic Runge–Kutta with fixed step `h` (the last step is shortened to hit `tf`).
    Rk4 { h: f64 },
    /// Dormand–Prince 5(4), adaptive.
    Dopri5(Options),
    /// Hairer–Wanner SDIRK4, adaptive, for stiff problems.
    Sdirk4(Options),
    /// Variable-order BDF (orders 1–5), adaptive, for smooth stiff problems.
    Bdf(Options),
}

impl Method {
    /// The method's name.
    pub fn name(&self) -> &'static str {
        match self {
            Method::Rk4 { .. } => "RK4",
            Method::Dopri5(_) => "DOPRI5",
            Method::Sdirk4(_) => "SDIRK4",
            Method::Bdf(_) => "BDF",
        }
    }

    /// The options it runs with (RK4: the defaults, its step as `h0`).
    pub fn options(&self) -> Options {
        match *self {
            Method::Rk4 { h } => Options {
                h0: Some(h),
                ..Options::default()
            },
            Method::Dopri5(o) | Method::Sdirk4(o) | Method::Bdf(o) => o,
        }
    }
}

/// Runs `$body` with `$stepper` bound to a stepper of `$method` for `$dim` components
/// (one monomorphised copy of the body per method: the drivers are generic over
/// [`Stepper`], whose methods are generic over the system).
macro_rules! with_stepper {
    ($method:expr, $dim:expr, |$stepper:ident| $body:expr) => {
        match *$method {
            $crate::Method::Rk4 { h } => {
                let mut $stepper = $crate::Rk4::new(h).stepper($dim);
                $body
            }
            $crate::Method::Dopri5(o) => {
                let mut $stepper = $crate::Dopri5::new(o).stepper($dim);
                $body
            }
            $crate::Method::Sdirk4(o) => {
                let mut $stepper = $crate::Sdirk4::new(o).stepper($dim);
                $body
            }
            $crate::Method::Bdf(o) => {
                let mut $stepper = $crate::Bdf::new(o).stepper($dim);
                $body
            }
        }
    };
}
pub(crate) use with_stepper;

#[cfg(test)]
mod tests;
