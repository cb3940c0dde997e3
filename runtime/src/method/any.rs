//! A stepper of any [`Method`], chosen at run time: for drivers that keep one stepper
//! in a struct across calls (the step-level [`Integrator`](crate::nonsmooth::Integrator)),
//! where [`with_stepper!`](super::with_stepper) cannot monomorphise the caller. Each call
//! is one `match`, outside the method's stage loops.

use super::{Bdf, Dopri5, Method, Rk4, Sdirk4};
use super::{BdfStepper, Dopri5Stepper, Rk4Stepper, Sdirk4Stepper, StepState, Stepper};
use crate::OdeSystem;
use crate::method::stepper::{Begin, DenseStep, Eval, StepResult};

/// The stepper of one of the [`Method`]s.
#[derive(Debug)]
pub enum AnyStepper {
    Rk4(Rk4Stepper),
    Dopri5(Dopri5Stepper),
    Sdirk4(Sdirk4Stepper),
    Bdf(BdfStepper),
}

impl Method {
    /// A stepper of this method for `dim` components.
    pub fn stepper(&self, dim: usize) -> AnyStepper {
        match *self {
            Method::Rk4 { h } => AnyStepper::Rk4(Rk4::new(h).stepper(dim)),
            Method::Dopri5(o) => AnyStepper::Dopri5(Dopri5::new(o).stepper(dim)),
            Method::Sdirk4(o) => AnyStepper::Sdirk4(Sdirk4::new(o).stepper(dim)),
            Method::Bdf(o) => AnyStepper::Bdf(Bdf::new(o).stepper(dim)),
        }
    }
}

/// `$body` with `$s` bound to the inner stepper.
macro_rules! each {
    ($self:expr, |$s:ident| $body:expr) => {
        match $self {
            AnyStepper::Rk4($s) => $body,
            AnyStepper::Dopri5($s) => $body,
            AnyStepper::Sdirk4($s) => $body,
            AnyStepper::Bdf($s) => $body,
        }
    };
}

impl Stepper for AnyStepper {
    fn state(&self) -> &StepState {
        each!(self, |s| s.state())
    }

    fn state_mut(&mut self) -> &mut StepState {
        each!(self, |s| s.state_mut())
    }

    fn nudge<S: OdeSystem + ?Sized>(&mut self, ev: &mut Eval<'_, S>, y: &[f64]) -> StepResult {
        each!(self, |s| s.nudge(ev, y))
    }

    fn begin<S: OdeSystem + ?Sized>(&mut self, ev: &mut Eval<'_, S>, at: Begin) -> StepResult {
        each!(self, |s| s.begin(ev, at))
    }

    fn step<S: OdeSystem + ?Sized>(&mut self, ev: &mut Eval<'_, S>, t_end: f64) -> StepResult {
        each!(self, |s| s.step(ev, t_end))
    }

    fn prepare_dense(&mut self) {
        each!(self, |s| s.prepare_dense())
    }

    fn dense(&self) -> &DenseStep {
        each!(self, |s| s.dense())
    }
}
