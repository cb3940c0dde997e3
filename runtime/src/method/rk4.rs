//! The classic fourth-order Runge–Kutta method with a fixed step ([`tableau::RK4`]).

use super::tableau::RK4;
use super::{Run, check_finite};
use crate::trajectory::Interpolant;
use crate::{ErrorKind, OdeSystem, Problem, SolveError, Trajectory};

/// Fixed-step classic Runge–Kutta (Kutta 1901; Hairer, Nørsett & Wanner, *Solving ODEs
/// I*, §II.1). The last step is shortened to end exactly at `tf`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rk4 {
    /// Step size, positive.
    pub h: f64,
}

impl Rk4 {
    pub fn new(h: f64) -> Self {
        Rk4 { h }
    }

    pub fn solve<S: OdeSystem + ?Sized>(
        &self,
        system: &S,
        problem: &Problem,
    ) -> Result<Trajectory, SolveError> {
        let mut run = Run::start(system, problem, Interpolant::Hermite, None)?;
        if !(self.h.is_finite() && self.h > 0.0) {
            return Err(run.fail(ErrorKind::InvalidInput(format!(
                "step size h = {} must be positive and finite",
                self.h
            ))));
        }
        let outcome = self.integrate(&mut run, problem);
        run.finish(outcome)
    }

    fn integrate<S: OdeSystem + ?Sized>(
        &self,
        run: &mut Run<'_, S>,
        problem: &Problem,
    ) -> Result<(), ErrorKind> {
        let n = problem.y0.len();
        let mut t = problem.t0;
        let mut y = problem.y0.clone();
        let mut k: Vec<Vec<f64>> = vec![vec![0.0; n]; 4];
        let mut stage = vec![0.0; n];
        let mut f_next = vec![0.0; n];
        run.rhs(t, &y, &mut k[0])?;
        run.traj.push(t, &y, &k[0]);
        // Number of steps fixed up front so that round-off cannot add a sliver step.
        let steps = ((problem.tf - problem.t0) / self.h * (1.0 - 1e-12)).ceil() as usize;
        for step in 0..steps {
            let h = if step + 1 == steps {
                problem.tf - t
            } else {
                self.h
            };
            for s in 1..4 {
                for i in 0..n {
                    stage[i] = y[i] + h * (0..s).map(|j| RK4.a(s, j) * k[j][i]).sum::<f64>();
                }
                let (_, rest) = k.split_at_mut(s);
                run.rhs(t + RK4.c[s] * h, &stage, &mut rest[0])?;
            }
            for i in 0..n {
                y[i] += h * (0..4).map(|j| RK4.b[j] * k[j][i]).sum::<f64>();
            }
            t = if step + 1 == steps { problem.tf } else { t + h };
            check_finite(t, &y)?;
            run.rhs(t, &y, &mut f_next)?;
            k[0].copy_from_slice(&f_next);
            run.traj.push(t, &y, &f_next);
            run.stats().steps += 1;
        }
        Ok(())
    }
}
