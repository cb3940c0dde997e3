//! Shared numerics, below every method and driver: weighted error norms and step-size
//! limits (here), step-size control ([`control`]), Butcher tableaus as data
//! ([`tableau`]), polynomial dense output ([`dense`]), counted evaluation of a system
//! (`eval`), the simplified-Newton matrix and finite-difference Jacobians
//! (`newton`) with its small dense LU (`lu`), bracketing root finding on dense output ([`rootfind`]),
//! linear complementarity problems by complementary pivoting ([`lcp`]), and the
//! factorisations that drivers generic over a scene call through plain functions
//! (`factor`), so that they are compiled, optimised, in this crate, and the sines and
//! cosines of a batch of angles that the generated kernels take ([`trig`]), and the
//! switch for their fused multiply–add twins ([`fused`]).
//!
//! Nothing here knows a method or a driver; methods (`crate::method`, the Lie-group
//! ones in `crate::liegroup`) and drivers (`crate::solve`, `crate::nonsmooth`) use it.

pub mod control;
pub mod dense;
pub(crate) mod eval;
pub(crate) mod factor;
pub mod fused;
pub mod fused_lanes;
pub mod lcp;
pub(crate) mod lu;
pub(crate) mod newton;
pub mod rootfind;
pub mod tableau;
pub mod trig;

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
///
/// Without overflow or underflow for every finite input: when the ratios are far from 1
/// the squares are taken of the ratios divided by their largest magnitude (a state of
/// 1e200 with atol 1e-10 would otherwise square to infinity and make every step size
/// zero). A NaN anywhere gives NaN, which every caller treats as a failed step.
pub(crate) fn error_norm(err: &[f64], y0: &[f64], y1: &[f64], options: &Options) -> f64 {
    rms(err.iter().zip(y0.iter().zip(y1)).map(|(e, (a, b))| {
        let scale = options.atol + options.rtol * a.abs().max(b.abs());
        e / scale
    }))
}

/// [`error_norm`] with the weights `1 / (atol + rtol · |y|)` computed once
/// ([`error_weights`]), for the several norms of one Newton solve.
pub(crate) fn weighted_norm(err: &[f64], weights: &[f64]) -> f64 {
    rms(err.iter().zip(weights).map(|(e, w)| e * w))
}

/// `1 / (atol + rtol · |y|)` into `weights`.
pub(crate) fn error_weights(y: &[f64], options: &Options, weights: &mut [f64]) {
    for (w, y) in weights.iter_mut().zip(y) {
        *w = 1.0 / (options.atol + options.rtol * y.abs());
    }
}

/// The root mean square of `ratios`, exact in the common range and rescaled far outside
/// it; NaN if any ratio is.
fn rms<I: Iterator<Item = f64> + Clone>(ratios: I) -> f64 {
    let mut n = 0usize;
    // One pass for the largest ratio and the plain sum of squares; the sum is what is
    // returned in the common case (the textbook form, no rescaling round-off).
    let (mut big, mut sum) = (0.0f64, 0.0f64);
    for r in ratios.clone() {
        if r.is_nan() {
            return f64::NAN;
        }
        n += 1;
        big = big.max(r.abs());
        sum += r.powi(2);
    }
    let n = n.max(1) as f64;
    if (1e-150..=1e150).contains(&big) {
        return (sum / n).sqrt();
    }
    if big == 0.0 || big.is_infinite() {
        return big;
    }
    let sum: f64 = ratios.map(|r| (r / big).powi(2)).sum();
    big * (sum / n).sqrt()
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
    let mut y1 = vec![0.0; y0.len()];
    starting_step(y0, f0, span, f64::INFINITY, order, options, |h0, f1| {
        for ((x, y), f) in y1.iter_mut().zip(y0).zip(f0) {
            *x = y + h0 * f;
        }
        rhs(t0 + h0, &y1, f1)
    })
}

/// The algorithm of [`initial_step`] in any coordinates: `scale` are the magnitudes
/// that weight the norms (`y0` itself for a state vector), `f0` the derivative at the
/// start, `h0_max` a bound on the trial step (a Lie-group chart keeps it below 1), and
/// `f_at(h0, f1)` writes the derivative one Euler step `h0 · f0` away from the start
/// (in the same coordinates). Shared by the flat methods and, in the exponential chart
/// of each step, by the Lie-group ones.
pub(crate) fn starting_step(
    scale: &[f64],
    f0: &[f64],
    span: f64,
    h0_max: f64,
    order: u32,
    options: &Options,
    mut f_at: impl FnMut(f64, &mut [f64]) -> Result<(), ErrorKind>,
) -> Result<f64, ErrorKind> {
    if let Some(h0) = options.h0 {
        return Ok(h0.min(options.h_max).min(span));
    }
    let zero = vec![0.0; scale.len()];
    let d0 = error_norm(scale, &zero, scale, options);
    let d1 = error_norm(f0, &zero, scale, options);
    let h0 = if d0 < 1e-5 || d1 < 1e-5 {
        1e-6
    } else {
        0.01 * d0 / d1
    };
    let h0 = h0.min(options.h_max).min(span).min(h0_max);
    let mut f1 = vec![0.0; f0.len()];
    f_at(h0, &mut f1)?;
    let diff: Vec<f64> = f1.iter().zip(f0).map(|(a, b)| (a - b) / h0).collect();
    let d2 = error_norm(&diff, &zero, scale, options);
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
mod tests {
    use super::*;

    /// The norm is exact in the common range, finite and correct far outside it, and
    /// NaN in gives NaN out.
    #[test]
    fn error_norm_neither_overflows_nor_underflows() {
        let o = Options::tolerances(0.0, 1.0);
        let zero = [0.0, 0.0];
        assert_eq!(error_norm(&[3.0, 4.0], &zero, &zero, &o), (12.5f64).sqrt());
        for scale in [1e-200, 1e200, 1e300] {
            let n = error_norm(&[3.0 * scale, 4.0 * scale], &zero, &zero, &o);
            assert!(
                (n / ((12.5f64).sqrt() * scale) - 1.0).abs() < 1e-15,
                "{scale:e}: {n:e}"
            );
        }
        assert!(error_norm(&[f64::NAN, 1.0], &zero, &zero, &o).is_nan());
        assert_eq!(error_norm(&[0.0, 0.0], &zero, &zero, &o), 0.0);
    }
}
