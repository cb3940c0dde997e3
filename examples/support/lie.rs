//! Shared by the S10 example and the report: the free body of theory S10 run with the
//! Lie-group integrator, its conserved quantities, and the flip period.
#![allow(dead_code)]

use std::time::Instant;

use filippov::nalgebra::{SVector, Vector3};
use filippov::prelude::*;
use filippov::runtime::liegroup::{LieMechanical, LieMechanism};
use filippov::runtime::{LieProblem, LieState, Options, Rkmk5, SolveError, UnitQuat};
use filippov::scenes::FreeBody;

/// Theory S10: `ω0 = (0.01, 1, 0)` in the body frame, at rest otherwise.
pub fn s10_initial() -> LieState {
    let q = FreeBody::identity_configuration();
    let v = SVector::<f64, 6>::from([0.0, 0.0, 0.0, 0.01, 1.0, 0.0]);
    FreeBody::qv_to_state(&q, &v)
}

/// Kinetic energy and spatial angular momentum `R I ω + m p × ṗ` (world frame) of a
/// free-body state.
pub fn invariants(body: &FreeBody, y: &LieState) -> (f64, Vector3<f64>) {
    let (q, v) = FreeBody::state_to_qv(y);
    let r = UnitQuat::try_new(q[3], q[4], q[5], q[6])
        .expect("unit quaternion")
        .to_matrix();
    let w = Vector3::new(v[3], v[4], v[5]);
    let iw = Vector3::new(body.i1 * w[0], body.i2 * w[1], body.i3 * w[2]);
    let p = Vector3::new(q[0], q[1], q[2]);
    let pd = Vector3::new(v[0], v[1], v[2]);
    (body.kinetic_energy(&q, &v), r * iw + body.m * p.cross(&pd))
}

/// One long S10 run, in chunks (the trajectory of a chunk is dropped after its drift is
/// measured, so memory stays flat over 10⁴ periods).
pub struct S10Run {
    pub rtol: f64,
    pub periods: f64,
    pub t_end: f64,
    /// Largest `|T − T0| / T0` seen at the accepted steps.
    pub energy_drift: f64,
    /// Largest `‖L − L0‖ / ‖L0‖`.
    pub momentum_drift: f64,
    pub steps: usize,
    pub rejected: usize,
    pub seconds: f64,
    /// `(t, relative energy drift, relative momentum drift)` at chunk ends.
    pub history: Vec<(f64, f64, f64)>,
}

/// The flip period: twice the mean spacing of the sign changes of `ω_y`, from a tight
/// run over `t ∈ [0, t_end]`.
pub fn flip_period(t_end: f64) -> Result<f64, SolveError> {
    let body = FreeBody::default();
    let sys = LieMechanical::free(&body);
    let traj = Rkmk5::new(Options::tolerances(1e-11, 1e-13))
        .solve(&sys, &LieProblem::new(0.0, t_end, s10_initial()))?;
    let mut crossings = Vec::new();
    let mut prev: Option<(f64, f64)> = None;
    for k in 0..traj.len() {
        let (t, wy) = (traj.times()[k], traj.state(k).velocity[1]);
        if let Some((t0, w0)) = prev
            && w0.signum() != wy.signum()
        {
            crossings.push(t0 + (t - t0) * w0 / (w0 - wy));
        }
        prev = Some((t, wy));
    }
    match crossings.len() {
        0 | 1 => Ok(f64::NAN),
        n => Ok(2.0 * (crossings[n - 1] - crossings[0]) / (n - 1) as f64),
    }
}

pub fn s10_run(rtol: f64, periods: f64, period: f64, chunks: usize) -> Result<S10Run, SolveError> {
    let body = FreeBody::default();
    let sys = LieMechanical::free(&body);
    let method = Rkmk5::new(Options {
        max_steps: usize::MAX,
        ..Options::tolerances(rtol, rtol * 1e-3)
    });
    let t_end = periods * period;
    let mut y = s10_initial();
    let (e0, l0) = invariants(&body, &y);
    let mut run = S10Run {
        rtol,
        periods,
        t_end,
        energy_drift: 0.0,
        momentum_drift: 0.0,
        steps: 0,
        rejected: 0,
        seconds: 0.0,
        history: Vec::new(),
    };
    let start = Instant::now();
    for c in 0..chunks {
        let (t0, t1) = (
            t_end * c as f64 / chunks as f64,
            t_end * (c + 1) as f64 / chunks as f64,
        );
        let traj = method.solve(&sys, &LieProblem::new(t0, t1, y))?;
        run.steps += traj.stats.steps;
        run.rejected += traj.stats.rejected_steps;
        let mut de = 0.0f64;
        let mut dl = 0.0f64;
        for k in 0..traj.len() {
            let (e, l) = invariants(&body, &traj.state(k));
            de = de.max((e - e0).abs() / e0);
            dl = dl.max((l - l0).norm() / l0.norm());
        }
        run.energy_drift = run.energy_drift.max(de);
        run.momentum_drift = run.momentum_drift.max(dl);
        run.history.push((t1, de, dl));
        y = traj.last().expect("a non-empty run").1;
    }
    run.seconds = start.elapsed().as_secs_f64();
    Ok(run)
}
