//! Configuration of the adaptive methods.

/// Tolerances and step-size limits of the adaptive methods ([`Dopri5`](crate::Dopri5),
/// [`Sdirk4`](crate::Sdirk4)).
///
/// The local error estimate `e` of a step from `y0` to `y1` is accepted when
/// `sqrt(mean((e_i / (atol + rtol · max(|y0_i|, |y1_i|)))²)) ≤ 1` (Hairer, Nørsett &
/// Wanner, *Solving ODEs I*, §II.4, eq. 4.11).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Options {
    /// Relative tolerance (default `1e-6`).
    pub rtol: f64,
    /// Absolute tolerance (default `1e-9`).
    pub atol: f64,
    /// Initial step; `None` chooses it automatically (Hairer I, §II.4, p. 169).
    pub h0: Option<f64>,
    /// Below this step size the integration stops with
    /// [`StepSizeUnderflow`](crate::ErrorKind::StepSizeUnderflow) (default `0`: only
    /// the round-off limit `h < 16 ε |t|` applies).
    pub h_min: f64,
    /// Largest step (default `∞`; `null` in formats without infinity, such as JSON).
    #[cfg_attr(feature = "serde", serde(with = "unbounded"))]
    pub h_max: f64,
    /// Largest number of step attempts, accepted or rejected (default `100 000`).
    pub max_steps: usize,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            rtol: 1e-6,
            atol: 1e-9,
            h0: None,
            h_min: 0.0,
            h_max: f64::INFINITY,
            max_steps: 100_000,
        }
    }
}

impl Options {
    /// Default options with the given tolerances.
    pub fn tolerances(rtol: f64, atol: f64) -> Self {
        Options {
            rtol,
            atol,
            ..Options::default()
        }
    }

    pub(crate) fn validate(&self) -> Result<(), String> {
        let nonneg = |x: f64| x.is_finite() && x >= 0.0;
        if !nonneg(self.rtol) || !nonneg(self.atol) || self.rtol + self.atol == 0.0 {
            return Err(format!(
                "tolerances must be finite, non-negative and not both zero (rtol = {}, atol = {})",
                self.rtol, self.atol
            ));
        }
        if let Some(h0) = self.h0
            && !(h0.is_finite() && h0 > 0.0)
        {
            return Err(format!("h0 = {h0} must be positive and finite"));
        }
        if !nonneg(self.h_min) || self.h_max.is_nan() || self.h_max <= self.h_min {
            return Err(format!(
                "need 0 ≤ h_min < h_max (h_min = {}, h_max = {})",
                self.h_min, self.h_max
            ));
        }
        if self.max_steps == 0 {
            return Err("max_steps must be positive".into());
        }
        Ok(())
    }
}

/// `h_max = ∞` as `None`: JSON has no infinity.
#[cfg(feature = "serde")]
mod unbounded {
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    pub fn serialize<S: Serializer>(x: &f64, s: S) -> Result<S::Ok, S::Error> {
        x.is_finite().then_some(*x).serialize(s)
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
        Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::INFINITY))
    }
}
