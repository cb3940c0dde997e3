//! Shared numerics, below every method and driver: weighted error norms and step-size
//! limits (here), step-size control ([`control`]), Butcher tableaus as data
//! ([`tableau`]), polynomial dense output ([`dense`]), counted evaluation of a system
//! ([`eval`]), the simplified-Newton matrix and finite-difference Jacobians
//! ([`newton`]), and bracketing root finding on dense output ([`rootfind`]).
//!
//! Nothing here knows a method or a driver; methods (`crate::method`, the Lie-group
//! ones in `crate::liegroup`) and drivers (`crate::solve`, `crate::nonsmooth`) use it.

pub mod control;
pub mod dense;
pub(crate) mod eval;
pub(crate) mod newton;
pub mod rootfind;
pub mod tableau;

use crate::{ErrorKind, Options};

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

/// Initial step size for a method of order `order` from `(t0, y0)` with `f0 = f(t0, y0)`
/// over a span of `span` (Hairer, Nørsett & Wanner, *Solving ODEs I*, §II.4, "Starting
/// step size", p. 169). `rhs` evaluates `f` once more, at `t0 + h0`.
pub(crate) fn initial_step(
    t0: f64,
    y0: &[f64],
    f0: &[f64],
    span: f64,
    order: u32,
    options: &Options,
    mut rhs: impl FnMut(f64, &[f64], &mut [f64]) -> Result<(), ErrorKind>,
) -> Result<f64, ErrorKind> {
    if let Some(h0) = options.h0 {
        return Ok(h0.min(options.h_max).min(span));
    }
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
    rhs(t0 + h0, &y1, &mut f1)?;
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
