//! Running diffsol on an [`Ode`], and timing.

use std::time::Instant;

use diffsol::{
    DiffsolError, MatrixCommon, NalgebraLU, NalgebraMat, NalgebraVec, OdeBuilder, OdeEquations,
    OdeSolverMethod, OdeSolverStopReason, Vector,
};

use crate::ode::Ode;

type M = NalgebraMat<f64>;
type LS = NalgebraLU<f64>;

/// The diffsol solvers measured (all with dense nalgebra matrices and LU).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Solver {
    /// Variable-order BDF (NDF variant, as ode15s).
    Bdf,
    /// ESDIRK34 (Jørgensen et al. 2018).
    Esdirk34,
    /// TR-BDF2 (Hosea & Shampine 1996).
    TrBdf2,
    /// Tsitouras 5(4), explicit.
    Tsit45,
}

impl Solver {
    pub fn name(self) -> &'static str {
        match self {
            Solver::Bdf => "diffsol BDF",
            Solver::Esdirk34 => "diffsol ESDIRK34",
            Solver::TrBdf2 => "diffsol TR-BDF2",
            Solver::Tsit45 => "diffsol TSIT45",
        }
    }
}

/// One diffsol solve: the states at the grid times and the solver's counts.
pub struct Run {
    /// `values[i]` is the state at `grid[i]`.
    pub values: Vec<Vec<f64>>,
    pub steps: usize,
    pub error_test_failures: usize,
    pub newton_iterations: usize,
    pub lu_setups: usize,
    /// Right-hand-side calls and Jacobian evaluations counted by the [`Ode`].
    pub rhs_calls: usize,
    pub jacobians: usize,
    /// Velocity zeros `(t, x)` (component 1 changes sign, located by bisection on the
    /// solver's interpolant), when asked for.
    pub velocity_zeros: Vec<(f64, f64)>,
}

/// Solves `ode` from `y0` at `t0` with `solver` and returns the states at `grid` (increasing,
/// starting at or after `t0`, ending at the final time) through diffsol's `solve_dense`.
/// With `zeros`, the solve steps manually instead and also locates the sign changes of
/// component 1 (used only for the untimed switch-point measurement; the steps are the
/// same as `solve_dense`'s, which also stops only at the last grid time).
#[allow(clippy::too_many_arguments)]
pub fn solve<O: Ode>(
    ode: &O,
    solver: Solver,
    rtol: f64,
    atol: f64,
    t0: f64,
    y0: &[f64],
    grid: &[f64],
    zeros: bool,
) -> Result<Run, String> {
    ode.reset_counts();
    let y0 = y0.to_vec();
    let problem = OdeBuilder::<M>::new()
        .t0(t0)
        .rtol(rtol)
        .atol([atol])
        .rhs_implicit(
            |x, _p, t, y| ode.rhs(t, x, y),
            |x, _p, t, w, y| ode.jac_mul(t, x, w, y),
        )
        .init(move |_p, _t, y| y.copy_from_slice(&y0), ode.dim())
        .build()
        .map_err(|e| format!("build: {e}"))?;
    let outcome = match solver {
        Solver::Bdf => drive(problem.bdf::<LS>(), grid, zeros),
        Solver::Esdirk34 => drive(problem.esdirk34::<LS>(), grid, zeros),
        Solver::TrBdf2 => drive(problem.tr_bdf2::<LS>(), grid, zeros),
        Solver::Tsit45 => drive(problem.tsit45(), grid, zeros),
    };
    let mut run = outcome.map_err(|e| e.to_string())?;
    (run.rhs_calls, run.jacobians) = ode.counts();
    Ok(run)
}

fn drive<'a, Eqn, S>(
    solver: Result<S, DiffsolError>,
    grid: &[f64],
    zeros: bool,
) -> Result<Run, DiffsolError>
where
    Eqn: OdeEquations<T = f64, V = NalgebraVec<f64>> + 'a,
    S: OdeSolverMethod<'a, Eqn>,
{
    let mut s = solver?;
    let (values, velocity_zeros) = if zeros {
        step_with_zeros(&mut s, grid)?
    } else {
        let (ys, _stop) = s.solve_dense(grid)?;
        let m = ys.inner();
        let values = (0..m.ncols())
            .map(|j| m.column(j).iter().copied().collect())
            .collect();
        (values, Vec::new())
    };
    let st = s.get_statistics();
    Ok(Run {
        values,
        steps: st.number_of_steps,
        error_test_failures: st.number_of_error_test_failures,
        newton_iterations: st.number_of_nonlinear_solver_iterations,
        lu_setups: st.number_of_linear_solver_setups,
        rhs_calls: 0,
        jacobians: 0,
        velocity_zeros,
    })
}

/// Manual stepping to the last grid time: grid values by interpolation within each step,
/// and the sign changes of component 1 located by bisection on the interpolant.
#[allow(clippy::type_complexity)]
fn step_with_zeros<'a, Eqn, S>(
    s: &mut S,
    grid: &[f64],
) -> Result<(Vec<Vec<f64>>, Vec<(f64, f64)>), DiffsolError>
where
    Eqn: OdeEquations<T = f64, V = NalgebraVec<f64>> + 'a,
    S: OdeSolverMethod<'a, Eqn>,
{
    let tf = *grid.last().expect("non-empty grid");
    s.set_stop_time(tf)?;
    let mut values = Vec::with_capacity(grid.len());
    let mut zeros: Vec<(f64, f64)> = Vec::new();
    let mut col = 0;
    let (mut t_prev, mut v_prev) = (s.state().t, s.state().y.get_index(1));
    while col < grid.len() && grid[col] <= t_prev {
        values.push(s.state().y.clone_as_vec());
        col += 1;
    }
    loop {
        let stop = s.step()?;
        let (t, v) = (s.state().t, s.state().y.get_index(1));
        while col < grid.len() && grid[col] <= t {
            values.push(s.interpolate(grid[col])?.clone_as_vec());
            col += 1;
        }
        if v_prev != 0.0 && (v == 0.0 || v.signum() != v_prev.signum()) {
            let (mut lo, mut hi) = (t_prev, t);
            if v != 0.0 {
                for _ in 0..60 {
                    let c = 0.5 * (lo + hi);
                    let vc = s.interpolate(c)?.get_index(1);
                    if vc != 0.0 && vc.signum() == v_prev.signum() {
                        lo = c;
                    } else {
                        hi = c;
                    }
                }
            }
            zeros.push((hi, s.interpolate(hi)?.get_index(0)));
        }
        (t_prev, v_prev) = (t, v);
        if matches!(stop, OdeSolverStopReason::TstopReached) || t >= tf {
            break;
        }
    }
    Ok((values, zeros))
}

/// Wall time of `repeats` calls after one warm-up, in milliseconds: the median and the
/// fastest and slowest call.
#[derive(Clone, Copy, Debug)]
pub struct Wall {
    pub median: f64,
    pub min: f64,
    pub max: f64,
}

impl Wall {
    /// No time (a run that failed).
    pub const NONE: Wall = Wall {
        median: f64::NAN,
        min: f64::NAN,
        max: f64::NAN,
    };
}

/// Times every job `repeats` times after one warm-up call each, in rounds: round `r`
/// runs each job once, starting from job `r` (so no job is always first or last). A
/// slow-down of the machine during the rounds reaches every job alike, so the ratios of
/// their times stay meaningful on a shared machine. Each job keeps its own result.
pub fn interleaved(repeats: usize, jobs: &mut [Box<dyn FnMut() + '_>]) -> Vec<Wall> {
    let n = jobs.len();
    for job in jobs.iter_mut() {
        job();
    }
    let mut times = vec![Vec::with_capacity(repeats); n];
    for round in 0..repeats {
        for k in 0..n {
            let j = (round + k) % n;
            let start = Instant::now();
            jobs[j]();
            times[j].push(start.elapsed().as_secs_f64() * 1e3);
        }
    }
    times.into_iter().map(wall).collect()
}

/// Median, fastest and slowest of `times` (ms).
fn wall(mut times: Vec<f64>) -> Wall {
    times.sort_by(f64::total_cmp);
    let n = times.len();
    if n == 0 {
        return Wall::NONE;
    }
    let median = if n % 2 == 1 {
        times[n / 2]
    } else {
        0.5 * (times[n / 2 - 1] + times[n / 2])
    };
    Wall {
        median,
        min: times[0],
        max: times[n - 1],
    }
}
