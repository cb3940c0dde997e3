//! Ensembles in lockstep: independent runs of one scene (each with its own parameters
//! and initial state) integrated together in the lanes of a SIMD batch
//! ([`Lanes`]: `f64x4` holds four runs, `f64x2` two; [`F64Lanes`](crate::real::F64Lanes)
//! is the width to use: four on x86-64, where the kernels' fused twins run four lanes
//! in one AVX2 register), every right-hand side one
//! call of the scene's generic forward dynamics for all lanes at once.
//!
//! The lanes share one step: Dormand–Prince 5(4) with the step chosen by the worst
//! lane's error estimate (each lane's error measured in its own weighted RMS norm). A
//! lane whose own step could be longer takes the shorter one, which costs steps but not
//! accuracy. On `f64` (one lane) the same code is the plain scalar integrator, which is
//! what the ensemble is measured against.
//!
//! Non-smooth scenes run in lockstep by time-stepping: [`time_stepping_lockstep`] (in
//! [`crate::nonsmooth::lockstep`]), where the runs keep their own steps and element
//! solves and share the kernels' arithmetic.

pub use crate::nonsmooth::lockstep::{NonSmoothRun, time_stepping_lockstep};

use crate::kernels::GenericDynamics;
use crate::numerics::control::PiController;
use crate::numerics::tableau::DOPRI5;
use crate::real::Lanes;

/// One run of an ensemble: the scene's parameters (its `f64` fields in declaration
/// order, as [`GenericDynamics::parameters`] gives them) and the initial state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Run<const N: usize, const P: usize> {
    pub parameters: [f64; P],
    pub q0: [f64; N],
    pub v0: [f64; N],
}

/// Tolerances and limits of a lockstep integration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LockstepOptions {
    pub rtol: f64,
    pub atol: f64,
    /// The first step's size.
    pub first_step: f64,
    /// Steps (accepted and rejected) per batch before giving up.
    pub max_steps: usize,
}

impl Default for LockstepOptions {
    fn default() -> Self {
        LockstepOptions {
            rtol: 1e-6,
            atol: 1e-9,
            first_step: 1e-4,
            max_steps: 1_000_000,
        }
    }
}

/// A run's state at the end time, and what its batch cost.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Final<const N: usize> {
    pub q: [f64; N],
    pub v: [f64; N],
    /// Accepted steps of the run's batch.
    pub steps: usize,
    /// Rejected steps of the run's batch.
    pub rejected: usize,
}

/// Why a batch stopped before the end time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LockstepError {
    /// Run `run` (its index in the ensemble) left the finite numbers at time `t`.
    NonFinite { run: usize, t: f64 },
    /// The batch holding run `run` took `LockstepOptions::max_steps` steps by time `t`.
    StepLimit { run: usize, t: f64 },
    /// The batch holding run `run` needed a step too small to advance time at `t`.
    StepTooSmall { run: usize, t: f64 },
    /// An option (or the end time) cannot be used: `what` names it and says why.
    InvalidOptions { what: &'static str },
}

impl std::fmt::Display for LockstepError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            LockstepError::NonFinite { run, t } => {
                write!(f, "run {run} of the ensemble became non-finite at t = {t}")
            }
            LockstepError::StepLimit { run, t } => write!(
                f,
                "the batch holding run {run} reached the step limit at t = {t}; raise \
                 `LockstepOptions::max_steps` or loosen the tolerances"
            ),
            LockstepError::StepTooSmall { run, t } => write!(
                f,
                "the batch holding run {run} needed a step too small to advance t = {t}"
            ),
            LockstepError::InvalidOptions { what } => write!(f, "lockstep: {what}"),
        }
    }
}

impl std::error::Error for LockstepError {}

/// Integrates every run from `t = 0` to `t_end` without applied forces, `L::LANES` runs
/// per batch (the last batch's spare lanes repeat its last run), and returns each run's
/// final state or the first failing batch's error. Runs of one batch end with the same
/// step sequence; a run's result depends on the other runs of its batch only through
/// that sequence, within the tolerances.
pub fn lockstep<S, L, const N: usize, const P: usize>(
    runs: &[Run<N, P>],
    t_end: f64,
    options: &LockstepOptions,
) -> Result<Vec<Final<N>>, LockstepError>
where
    S: GenericDynamics<N, N, P>,
    L: Lanes,
{
    let bad = if !(t_end.is_finite() && t_end >= 0.0) {
        Some("the end time must be finite and ≥ 0")
    } else if !(options.first_step.is_finite() && options.first_step > 0.0) {
        Some("`first_step` must be finite and > 0")
    } else if !(options.rtol >= 0.0 && options.atol >= 0.0) || options.rtol + options.atol <= 0.0 {
        Some("`rtol` and `atol` must be ≥ 0, not both zero")
    } else {
        None
    };
    if let Some(what) = bad {
        return Err(LockstepError::InvalidOptions { what });
    }
    let mut out = Vec::with_capacity(runs.len());
    for (b, batch) in runs.chunks(L::LANES).enumerate() {
        let first = b * L::LANES;
        let lane =
            |f: &dyn Fn(&Run<N, P>) -> f64| L::from_fn(|i| f(&batch[i.min(batch.len() - 1)]));
        let p: [L; P] = std::array::from_fn(|k| lane(&|r| r.parameters[k]));
        let q: [L; N] = std::array::from_fn(|k| lane(&|r| r.q0[k]));
        let v: [L; N] = std::array::from_fn(|k| lane(&|r| r.v0[k]));
        let (q, v, steps, rejected) =
            batch_dopri5::<S, L, N, P>(&p, q, v, t_end, options, batch.len(), first)?;
        for i in 0..batch.len() {
            out.push(Final {
                q: q.map(|x| x.lane(i)),
                v: v.map(|x| x.lane(i)),
                steps,
                rejected,
            });
        }
    }
    Ok(out)
}

#[allow(clippy::type_complexity)]
fn batch_dopri5<S, L, const N: usize, const P: usize>(
    p: &[L; P],
    mut q: [L; N],
    mut v: [L; N],
    t_end: f64,
    o: &LockstepOptions,
    used: usize,
    first: usize,
) -> Result<([L; N], [L; N], usize, usize), LockstepError>
where
    S: GenericDynamics<N, N, P>,
    L: Lanes,
{
    let tab = &DOPRI5;
    let zero = L::cst(0.0);
    let tau = [zero; N];
    let f = |q: &[L; N], v: &[L; N]| S::forward_dynamics_generic(p, q, v, &tau);
    let e: Vec<f64> = tab.error_weights();
    let mut kq = [[zero; N]; 7];
    let mut kv = [[zero; N]; 7];
    kq[0] = v;
    kv[0] = f(&q, &v);
    let (mut t, mut h) = (0.0f64, o.first_step.min(t_end));
    let (mut steps, mut rejected) = (0usize, 0usize);
    let mut control = PiController::new(4);
    while t < t_end {
        if steps + rejected >= o.max_steps {
            return Err(LockstepError::StepLimit { run: first, t });
        }
        if h <= 16.0 * f64::EPSILON * t.abs() || h <= f64::MIN_POSITIVE {
            return Err(LockstepError::StepTooSmall { run: first, t });
        }
        h = h.min(t_end - t);
        let hl = L::cst(h);
        let mut qs = q;
        let mut vs = v;
        for s in 1..7 {
            qs = q;
            vs = v;
            for j in 0..s {
                let a = tab.a(s, j);
                if a != 0.0 {
                    let ha = hl * L::cst(a);
                    for k in 0..N {
                        qs[k] = qs[k] + ha * kq[j][k];
                        vs[k] = vs[k] + ha * kv[j][k];
                    }
                }
            }
            kq[s] = vs;
            kv[s] = f(&qs, &vs);
        }
        // The 7th stage's argument is the 5th-order solution (first same as last).
        let (q1, v1) = (qs, vs);
        // Each lane's weighted RMS error; the batch steps by the worst. A lane whose new
        // state is not finite stops the batch, naming its run; a finite state with a huge
        // error is only a rejected step.
        let mut worst = 0.0f64;
        for lane in 0..used {
            let finite = (0..N).all(|k| {
                q1[k].lane(lane).is_finite()
                    && v1[k].lane(lane).is_finite()
                    && kv[6][k].lane(lane).is_finite()
            });
            if !finite {
                return Err(LockstepError::NonFinite {
                    run: first + lane,
                    t,
                });
            }
            let mut scaled = [[0.0f64; 2]; N];
            for (k, pair) in scaled.iter_mut().enumerate() {
                for (slot, (y0, y1, kk)) in [(q[k], q1[k], &kq), (v[k], v1[k], &kv)]
                    .into_iter()
                    .enumerate()
                {
                    let err: f64 = h * (0..7).map(|j| e[j] * kk[j][k].lane(lane)).sum::<f64>();
                    let scale = o.atol + o.rtol * y0.lane(lane).abs().max(y1.lane(lane).abs());
                    pair[slot] = (err / scale).abs();
                }
            }
            // RMS without overflow: scaled by the largest entry first.
            let big = scaled.iter().flatten().fold(0.0f64, |m, x| m.max(*x));
            let norm = if big == 0.0 || !big.is_finite() {
                big
            } else {
                let sum: f64 = scaled.iter().flatten().map(|x| (x / big) * (x / big)).sum();
                big * (sum / (2 * N) as f64).sqrt()
            };
            worst = worst.max(norm);
        }
        if worst <= 1.0 {
            t += h;
            q = q1;
            v = v1;
            kq[0] = kq[6];
            kv[0] = kv[6];
            steps += 1;
            h *= control.accept(worst);
        } else {
            rejected += 1;
            h *= control.reject(worst);
        }
    }
    Ok((q, v, steps, rejected))
}
