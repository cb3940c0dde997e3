//! The classic fourth-order Runge–Kutta method with a fixed step ([`tableau::RK4`](crate::tableau::RK4)).

use super::stepper::{Begin, Eval, StepResult, StepState, Stepper};
use crate::numerics::check_finite;
use crate::numerics::tableau::RK4;
use crate::{ErrorKind, OdeSystem, Options};

/// Fixed-step classic Runge–Kutta (Kutta 1901; Hairer, Nørsett & Wanner, *Solving ODEs
/// I*, §II.1). The last step before `t_end` is shortened to end exactly there; the
/// dense output is the quintic Hermite through the last three points (cubic Hermite on
/// the first step after a start or restart).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rk4 {
    /// Step size, positive.
    pub h: f64,
}

impl Rk4 {
    pub fn new(h: f64) -> Self {
        Rk4 { h }
    }

    /// The stepping state for states of `dim` components.
    pub fn stepper(&self, dim: usize) -> Rk4Stepper {
        let options = Options {
            h0: Some(self.h),
            max_steps: usize::MAX,
            ..Options::default()
        };
        let mut s = StepState::new(dim, options);
        s.h = self.h;
        Rk4Stepper {
            s,
            k: vec![vec![0.0; dim]; 4],
            stage: vec![0.0; dim],
            f_next: vec![0.0; dim],
            plan: (f64::NAN, 0),
        }
    }
}

/// The state of an [`Rk4`] integration (see [`Stepper`]).
#[derive(Clone, Debug)]
pub struct Rk4Stepper {
    /// `s.h` is the fixed step; `s.options` the defaults with it as `h0`.
    s: StepState,
    /// Stage derivatives; `k[0] = f(t, y)`.
    k: Vec<Vec<f64>>,
    stage: Vec<f64>,
    f_next: Vec<f64>,
    /// The `t_end` the steps were counted for, and how many are left: counted once, so
    /// that round-off in the accumulated time cannot add a sliver step.
    plan: (f64, usize),
}

impl Stepper for Rk4Stepper {
    fn state(&self) -> &StepState {
        &self.s
    }

    fn state_mut(&mut self) -> &mut StepState {
        &mut self.s
    }

    /// As the default, and `k_1` (the first stage, kept from the last step's end) taken
    /// from the new point too: a stale `k_1` would step from the projected state with
    /// the derivative of the one before.
    fn nudge<S: OdeSystem + ?Sized>(&mut self, ev: &mut Eval<'_, S>, y: &[f64]) -> StepResult {
        self.s.y.copy_from_slice(y);
        ev.rhs(self.s.t, y, &mut self.s.f)?;
        self.k[0].copy_from_slice(&self.s.f);
        Ok(())
    }

    /// A fixed step needs no first-step choice; afresh or not, the stepper begins at
    /// `(t, y)` with `f(t, y)`.
    fn begin<S: OdeSystem + ?Sized>(&mut self, ev: &mut Eval<'_, S>, at: Begin) -> StepResult {
        if at.fresh && !(self.s.h.is_finite() && self.s.h > 0.0) {
            return Err(ErrorKind::InvalidInput(format!(
                "step size h = {} must be positive and finite",
                self.s.h
            )));
        }
        self.s.forget();
        self.s.t = at.t;
        self.s.y.copy_from_slice(at.y);
        self.plan = (f64::NAN, 0);
        ev.rhs(at.t, at.y, &mut self.s.f)?;
        self.k[0].copy_from_slice(&self.s.f);
        Ok(())
    }

    fn step<S: OdeSystem + ?Sized>(&mut self, ev: &mut Eval<'_, S>, t_end: f64) -> StepResult {
        let n = self.s.y.len();
        let t = self.s.t;
        if self.plan.0 != t_end {
            self.plan = (
                t_end,
                ((t_end - t) / self.s.h * (1.0 - 1e-12)).ceil() as usize,
            );
        }
        let last = self.plan.1 <= 1;
        self.plan.1 = self.plan.1.saturating_sub(1);
        let h = if last { t_end - t } else { self.s.h };
        for s in 1..4 {
            for i in 0..n {
                self.stage[i] =
                    self.s.y[i] + h * (0..s).map(|j| RK4.a(s, j) * self.k[j][i]).sum::<f64>();
            }
            let (_, rest) = self.k.split_at_mut(s);
            ev.rhs(t + RK4.c[s] * h, &self.stage, &mut rest[0])?;
        }
        // y1 into `stage`, keeping y for the dense output.
        for i in 0..n {
            self.stage[i] = self.s.y[i] + h * (0..4).map(|j| RK4.b[j] * self.k[j][i]).sum::<f64>();
        }
        let t1 = if last { t_end } else { t + h };
        check_finite(t1, &self.stage)?;
        ev.rhs(t1, &self.stage, &mut self.f_next)?;
        let (y1, f1) = (&self.stage, &self.f_next);
        self.s.set_dense(h, y1, f1, |dense, y0, f0| {
            dense.set_hermite(t, h, y0, f0, y1, f1)
        });
        self.s.advance(t1, y1, f1);
        self.k[0].copy_from_slice(f1);
        ev.stats.steps += 1;
        Ok(())
    }
}
