//! Dormand–Prince 5(4): adaptive explicit Runge–Kutta with FSAL and dense output
//! ([`tableau::DOPRI5`](crate::tableau::DOPRI5)), following Hairer's `dopri5.f`
//! (Hairer, Nørsett & Wanner, *Solving ODEs I*, §II.5–II.6).

use super::stepper::{Begin, Eval, StepResult, StepState, Stepper, check_budget};
use crate::numerics::control::PiController;
use crate::numerics::tableau::{DOPRI5, DOPRI5_DENSE};
use crate::numerics::{check_finite, error_norm, underflow};
use crate::{ErrorKind, OdeSystem, Options};

/// Adaptive Dormand–Prince 5(4) with local extrapolation (the fifth-order solution is
/// propagated), a [`PiController`], and as dense output the quintic Hermite through the
/// last three points (the fourth-order continuous extension on the first step after a
/// start or restart; see [`DenseStep`](crate::method::DenseStep)).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Dopri5 {
    pub options: Options,
}

impl Dopri5 {
    pub fn new(options: Options) -> Self {
        Dopri5 { options }
    }

    /// The stepping state for states of `dim` components.
    pub fn stepper(&self, dim: usize) -> Dopri5Stepper {
        Dopri5Stepper {
            s: StepState::new(dim, self.options),
            controller: PiController::new(4),
            k: std::array::from_fn(|_| vec![0.0; dim]),
            y1: vec![0.0; dim],
            scratch: vec![0.0; dim],
            err: vec![0.0; dim],
            r5: vec![0.0; dim],
        }
    }
}

/// The state of a [`Dopri5`] integration (see [`Stepper`]).
#[derive(Clone, Debug)]
pub struct Dopri5Stepper {
    s: StepState,
    controller: PiController,
    /// Stage derivatives `k_1 … k_7` (`k_1 = f`); `k_7 = f(t + h, y_1)` is the next `k_1`.
    k: [Vec<f64>; 7],
    y1: Vec<f64>,
    scratch: Vec<f64>,
    err: Vec<f64>,
    r5: Vec<f64>,
}

impl Dopri5Stepper {
    /// Stages 2–7 from `k_1 = f(t, y)`; leaves `y_1` (fifth order) in `y1`.
    fn stages<S: OdeSystem + ?Sized>(
        &mut self,
        ev: &mut Eval<'_, S>,
        h: f64,
    ) -> Result<(), ErrorKind> {
        let (t, y) = (self.s.t, &self.s.y);
        for s in 1..7 {
            for (i, x) in self.scratch.iter_mut().enumerate() {
                *x = y[i] + h * (0..s).map(|j| DOPRI5.a(s, j) * self.k[j][i]).sum::<f64>();
            }
            if s == 6 {
                // Row 7 of A is b: this stage value is the new state.
                check_finite(t + h, &self.scratch)?;
                self.y1.copy_from_slice(&self.scratch);
            }
            let (_, rest) = self.k.split_at_mut(s);
            ev.rhs(t + DOPRI5.c[s] * h, &self.scratch, &mut rest[0])?;
        }
        Ok(())
    }
}

impl Stepper for Dopri5Stepper {
    fn state(&self) -> &StepState {
        &self.s
    }

    fn state_mut(&mut self) -> &mut StepState {
        &mut self.s
    }

    /// As the default, and `k_1` (the first stage, kept from the last step's seventh:
    /// first same as last) taken from the new point too: a stale
    /// `k_1` would step from the projected state with the derivative of the one before.
    fn nudge<S: OdeSystem + ?Sized>(&mut self, ev: &mut Eval<'_, S>, y: &[f64]) -> StepResult {
        self.s.y.copy_from_slice(y);
        ev.rhs(self.s.t, y, &mut self.s.f)?;
        self.k[0].copy_from_slice(&self.s.f);
        Ok(())
    }

    fn begin<S: OdeSystem + ?Sized>(&mut self, ev: &mut Eval<'_, S>, at: Begin) -> StepResult {
        self.s.enter(ev, at, 5, self.s.h)?;
        self.k[0].copy_from_slice(&self.s.f);
        self.controller = PiController::new(4);
        Ok(())
    }

    fn step<S: OdeSystem + ?Sized>(&mut self, ev: &mut Eval<'_, S>, t_end: f64) -> StepResult {
        let e = DOPRI5.error_weights();
        loop {
            check_budget(ev.stats, &self.s.options, self.s.t)?;
            let t = self.s.t;
            let mut h = self.s.h.min(self.s.options.h_max);
            // Stretch the last step to hit t_end rather than leave a sliver.
            let last = t + 1.01 * h >= t_end;
            if last {
                h = t_end - t;
            }
            if underflow(t, h, &self.s.options) {
                return Err(ErrorKind::StepSizeUnderflow { t, h });
            }
            self.stages(ev, h)?;
            for (i, ei) in self.err.iter_mut().enumerate() {
                *ei = h * (0..7).map(|j| e[j] * self.k[j][i]).sum::<f64>();
            }
            let err = error_norm(&self.err, &self.s.y, &self.y1, &self.s.options);
            if err <= 1.0 {
                for (i, r) in self.r5.iter_mut().enumerate() {
                    *r = h * (0..7).map(|j| DOPRI5_DENSE[j] * self.k[j][i]).sum::<f64>();
                }
                let (y1, f1, r5) = (&self.y1, &self.k[6], &self.r5);
                self.s.set_dense(h, y1, f1, |dense, y0, f0| {
                    dense.set_dopri5(t, h, y0, y1, f0, f1, r5)
                });
                self.s.advance(if last { t_end } else { t + h }, y1, f1);
                let (first, rest) = self.k.split_at_mut(6);
                first[0].copy_from_slice(&rest[0]);
                ev.stats.steps += 1;
                self.s.h = h * self.controller.accept(err);
                return Ok(());
            }
            ev.stats.rejected_steps += 1;
            self.s.h = h * self.controller.reject(err);
        }
    }
}
