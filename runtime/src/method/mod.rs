//! Time-stepping methods. Each method is a small struct with a `solve` function; the
//! [`Method`] enum and [`solve`] pick one at run time.
//!
//! | method | kind | use |
//! |---|---|---|
//! | [`Rk4`] | explicit, fixed step, order 4 | convergence studies, baselines |
//! | [`Dopri5`] | explicit, adaptive 5(4), FSAL, dense output | non-stiff problems |
//! | [`Sdirk4`] | L-stable SDIRK, adaptive 4(3), simplified Newton | stiff problems |
//! | [`Bdf`] | variable-order (1–5) variable-step BDF, simplified Newton | smooth stiff problems |
//!
//! Shared rules: the problem and options are validated first ([`ErrorKind::InvalidInput`],
//! never a panic); every right-hand-side value and every new state is checked, and a
//! NaN or infinity ends the integration with [`ErrorKind::NonFinite`] (we do not try to
//! recover by shrinking the step: a non-finite derivative is almost always a modelling
//! error, and hiding it costs more than reporting it). The trajectory up to the failure
//! is returned in the [`SolveError`].

mod bdf;
mod dopri5;
mod rk4;
mod sdirk;
pub mod tableau;

pub use bdf::Bdf;
pub use dopri5::Dopri5;
pub use rk4::Rk4;
pub use sdirk::Sdirk4;

use nalgebra::DMatrix;

use crate::trajectory::Interpolant;
use crate::{ErrorKind, OdeSystem, Options, Problem, SolveError, Stats, Trajectory};

/// A method with its configuration, for [`solve`].
#[derive(Clone, Copy, Debug, PartialEq)]
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

/// Integrates `problem` for `system` with `method`.
///
/// ```
/// use filippov_runtime::{FnSystem, Method, Options, Problem, solve};
/// let decay = FnSystem::new(1, |_t, y: &[f64], dy: &mut [f64]| dy[0] = -y[0]);
/// let traj = solve(&decay, &Problem::new(0.0, 1.0, [1.0]), &Method::Dopri5(Options::tolerances(1e-8, 1e-10))).unwrap();
/// assert!((traj.last().unwrap().1[0] - (-1.0f64).exp()).abs() < 1e-7);
/// ```
pub fn solve<S: OdeSystem + ?Sized>(
    system: &S,
    problem: &Problem,
    method: &Method,
) -> Result<Trajectory, SolveError> {
    match *method {
        Method::Rk4 { h } => Rk4::new(h).solve(system, problem),
        Method::Dopri5(options) => Dopri5::new(options).solve(system, problem),
        Method::Sdirk4(options) => Sdirk4::new(options).solve(system, problem),
        Method::Bdf(options) => Bdf::new(options).solve(system, problem),
    }
}

/// One integration in progress: the system, and the trajectory being built (which
/// also carries the statistics).
pub(crate) struct Run<'a, S: ?Sized> {
    system: &'a S,
    pub traj: Trajectory,
}

impl<'a, S: OdeSystem + ?Sized> Run<'a, S> {
    /// Validates the inputs and starts an empty trajectory.
    pub fn start(
        system: &'a S,
        problem: &Problem,
        interpolant: Interpolant,
        options: Option<&Options>,
    ) -> Result<Self, SolveError> {
        let traj = Trajectory::new(system.names(), interpolant);
        let invalid = |msg: String| SolveError {
            kind: ErrorKind::InvalidInput(msg),
            trajectory: Box::new(Trajectory::new(system.names(), interpolant)),
        };
        if traj.dim() != system.dim() {
            return Err(invalid(format!(
                "the system names {} components but has dimension {}",
                traj.dim(),
                system.dim()
            )));
        }
        system.validate().map_err(invalid)?;
        problem.validate(system.dim()).map_err(invalid)?;
        if let Some(options) = options {
            options.validate().map_err(invalid)?;
        }
        Ok(Run { system, traj })
    }

    pub fn system(&self) -> &'a S {
        self.system
    }

    pub fn stats(&mut self) -> &mut Stats {
        &mut self.traj.stats
    }

    /// `dy = f(t, y)`, counted and checked for non-finite values.
    pub fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), ErrorKind> {
        self.traj.stats.rhs_evaluations += 1;
        self.system.rhs(t, y, dy);
        check_finite(t, dy)
    }

    /// The trajectory when the integration succeeded, or the error carrying it.
    pub fn finish(self, outcome: Result<(), ErrorKind>) -> Result<Trajectory, SolveError> {
        match outcome {
            Ok(()) => Ok(self.traj),
            Err(kind) => Err(self.fail(kind)),
        }
    }

    pub fn fail(self, kind: ErrorKind) -> SolveError {
        SolveError {
            kind,
            trajectory: Box::new(self.traj),
        }
    }
}

/// `NonFinite` at the first NaN or infinite component of `x`.
pub(crate) fn check_finite(t: f64, x: &[f64]) -> Result<(), ErrorKind> {
    match x.iter().position(|v| !v.is_finite()) {
        Some(component) => Err(ErrorKind::NonFinite { t, component }),
        None => Ok(()),
    }
}

/// Weighted RMS norm of `err` with weights `atol + rtol · max(|y0|, |y1|)`
/// (Hairer, Nørsett & Wanner, *Solving ODEs I*, §II.4, eq. 4.11).
pub(crate) fn error_norm(err: &[f64], y0: &[f64], y1: &[f64], options: &Options) -> f64 {
    let sum: f64 = err
        .iter()
        .zip(y0.iter().zip(y1))
        .map(|(e, (a, b))| {
            let scale = options.atol + options.rtol * a.abs().max(b.abs());
            (e / scale).powi(2)
        })
        .sum();
    (sum / err.len().max(1) as f64).sqrt()
}

/// Whether step `h` at time `t` is too small: below `h_min`, or lost in round-off.
pub(crate) fn underflow(t: f64, h: f64, options: &Options) -> bool {
    h < options.h_min || h <= 16.0 * f64::EPSILON * t.abs() || h <= f64::MIN_POSITIVE
}

/// `∂f/∂y(t, y)` into `jac`: from the system, or by forward differences with increments
/// `√(ε max(10⁻⁵, |y_j|))` (Hairer & Wanner II, §IV.8) around `f`. With `fresh`, `f` is
/// first overwritten by `f(t, y)` (only when differences are needed): for methods whose
/// stored derivative is not `f(t, y)` itself (BDF's is the formula's), differencing
/// against it would mix the Newton error into `J`.
pub(crate) fn jacobian<S: OdeSystem + ?Sized>(
    run: &mut Run<'_, S>,
    t: f64,
    y: &[f64],
    f: &mut [f64],
    fresh: bool,
    jac: &mut DMatrix<f64>,
) -> Result<(), ErrorKind> {
    run.stats().jacobian_evaluations += 1;
    if !run.system().jacobian(t, y, jac) {
        run.stats().finite_difference_jacobians += 1;
        if fresh {
            run.rhs(t, y, f)?;
        }
        let mut yp = y.to_vec();
        let mut fp = vec![0.0; y.len()];
        for j in 0..y.len() {
            let delta = (f64::EPSILON * y[j].abs().max(1e-5)).sqrt();
            yp[j] = y[j] + delta;
            run.rhs(t, &yp, &mut fp)?;
            for i in 0..y.len() {
                jac[(i, j)] = (fp[i] - f[i]) / delta;
            }
            yp[j] = y[j];
        }
    }
    match jac.iter().position(|x| !x.is_finite()) {
        Some(p) => Err(ErrorKind::NonFinite {
            t,
            component: p % y.len(),
        }),
        None => Ok(()),
    }
}

/// Initial step size for a method of order `order` (Hairer, Nørsett & Wanner, *Solving
/// ODEs I*, §II.4, "Starting step size", p. 169; one extra rhs evaluation).
pub(crate) fn initial_step<S: OdeSystem + ?Sized>(
    run: &mut Run<'_, S>,
    problem: &Problem,
    f0: &[f64],
    order: u32,
    options: &Options,
) -> Result<f64, ErrorKind> {
    let span = problem.tf - problem.t0;
    if let Some(h0) = options.h0 {
        return Ok(h0.min(options.h_max).min(span));
    }
    let y0 = &problem.y0;
    let zero = vec![0.0; y0.len()];
    let d0 = error_norm(y0, &zero, y0, options);
    let d1 = error_norm(f0, &zero, y0, options);
    let h0 = if d0 < 1e-5 || d1 < 1e-5 {
        1e-6
    } else {
        0.01 * d0 / d1
    };
    let h0 = h0.min(options.h_max).min(span);
    let y1: Vec<f64> = y0.iter().zip(f0).map(|(y, f)| y + h0 * f).collect();
    let mut f1 = vec![0.0; y0.len()];
    run.rhs(problem.t0 + h0, &y1, &mut f1)?;
    let diff: Vec<f64> = f1.iter().zip(f0).map(|(a, b)| (a - b) / h0).collect();
    let d2 = error_norm(&diff, &zero, y0, options);
    let d = d1.max(d2);
    let h1 = if d <= 1e-15 {
        (h0 * 1e-3).max(1e-6)
    } else {
        (0.01 / d).powf(1.0 / f64::from(order + 1))
    };
    Ok((100.0 * h0)
        .min(h1)
        .min(options.h_max)
        .min(span)
        .max(options.h_min))
}

#[cfg(test)]
mod tests;
