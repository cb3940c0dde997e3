//! Dormand–Prince 5(4): adaptive explicit Runge–Kutta with FSAL and dense output
//! ([`tableau::DOPRI5`](super::tableau::DOPRI5)), following Hairer's `dopri5.f`
//! (Hairer, Nørsett & Wanner, *Solving ODEs I*, §II.5–II.6).

use super::tableau::{DOPRI5, DOPRI5_DENSE};
use super::{Run, check_finite, error_norm, initial_step, underflow};
use crate::control::PiController;
use crate::trajectory::Interpolant;
use crate::{ErrorKind, OdeSystem, Options, Problem, SolveError, Trajectory};

/// Adaptive Dormand–Prince 5(4) with local extrapolation (the fifth-order solution is
/// propagated), a [`PiController`], and the fourth-order continuous extension stored
/// in the [`Trajectory`].
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Dopri5 {
    pub options: Options,
}

/// Stage derivatives `k_1 … k_7` of one step; `k_7 = f(t + h, y_1)` is the next `k_1`.
struct Stages {
    k: [Vec<f64>; 7],
    y1: Vec<f64>,
    scratch: Vec<f64>,
}

impl Dopri5 {
    pub fn new(options: Options) -> Self {
        Dopri5 { options }
    }

    pub fn solve<S: OdeSystem + ?Sized>(
        &self,
        system: &S,
        problem: &Problem,
    ) -> Result<Trajectory, SolveError> {
        let mut run = Run::start(system, problem, Interpolant::Dopri5, Some(&self.options))?;
        let outcome = self.integrate(&mut run, problem);
        run.finish(outcome)
    }

    fn integrate<S: OdeSystem + ?Sized>(
        &self,
        run: &mut Run<'_, S>,
        problem: &Problem,
    ) -> Result<(), ErrorKind> {
        let opts = &self.options;
        let n = problem.y0.len();
        let mut st = Stages {
            k: std::array::from_fn(|_| vec![0.0; n]),
            y1: vec![0.0; n],
            scratch: vec![0.0; n],
        };
        let mut t = problem.t0;
        let mut y = problem.y0.clone();
        run.rhs(t, &y, &mut st.k[0])?;
        run.traj.push(t, &y, &st.k[0]);
        if problem.tf == problem.t0 {
            return Ok(());
        }
        let mut h = initial_step(run, problem, &st.k[0], 5, opts)?;
        let mut controller = PiController::new(4);
        let e = DOPRI5.error_weights();
        let mut err_vec = vec![0.0; n];
        let mut r5 = vec![0.0; n];
        let mut attempts = 0;
        loop {
            if attempts >= opts.max_steps {
                return Err(ErrorKind::MaxSteps { t });
            }
            attempts += 1;
            h = h.min(opts.h_max);
            // Stretch the last step to hit tf rather than leave a sliver.
            let last = t + 1.01 * h >= problem.tf;
            if last {
                h = problem.tf - t;
            }
            if underflow(t, h, opts) {
                return Err(ErrorKind::StepSizeUnderflow { t, h });
            }
            Self::stages(run, t, h, &y, &mut st)?;
            for (i, ei) in err_vec.iter_mut().enumerate() {
                *ei = h * (0..7).map(|j| e[j] * st.k[j][i]).sum::<f64>();
            }
            let err = error_norm(&err_vec, &y, &st.y1, opts);
            if err <= 1.0 {
                for (i, r) in r5.iter_mut().enumerate() {
                    *r = h * (0..7).map(|j| DOPRI5_DENSE[j] * st.k[j][i]).sum::<f64>();
                }
                t = if last { problem.tf } else { t + h };
                y.copy_from_slice(&st.y1);
                let (first, rest) = st.k.split_at_mut(6);
                first[0].copy_from_slice(&rest[0]);
                run.traj.push(t, &y, &st.k[0]);
                run.traj.push_dense(&r5);
                run.stats().steps += 1;
                if last {
                    return Ok(());
                }
                h *= controller.accept(err);
            } else {
                run.stats().rejected_steps += 1;
                h *= controller.reject(err);
            }
        }
    }

    /// Stages 2–7 from `k_1 = f(t, y)`; leaves `y_1` (fifth order) in `st.y1`.
    fn stages<S: OdeSystem + ?Sized>(
        run: &mut Run<'_, S>,
        t: f64,
        h: f64,
        y: &[f64],
        st: &mut Stages,
    ) -> Result<(), ErrorKind> {
        for s in 1..7 {
            for (i, x) in st.scratch.iter_mut().enumerate() {
                *x = y[i] + h * (0..s).map(|j| DOPRI5.a(s, j) * st.k[j][i]).sum::<f64>();
            }
            if s == 6 {
                // Row 7 of A is b: this stage value is the new state.
                check_finite(t + h, &st.scratch)?;
                st.y1.copy_from_slice(&st.scratch);
            }
            let (_, rest) = st.k.split_at_mut(s);
            run.rhs(t + DOPRI5.c[s] * h, &st.scratch, &mut rest[0])?;
        }
        Ok(())
    }
}
