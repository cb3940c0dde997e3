//! What a Lie-group run integrates and what it returns: the problem ([`LieProblem`]),
//! the run in progress ([`LieRun`]: the system and the trajectory so far) and the result
//! ([`LieTrajectory`], with its dense output on the group). Below the driver, the event
//! tracker and the methods, which all build on it.

use nalgebra::Vector3;

use super::chart::retract;
use super::{LieState, LieSystem};
use crate::geometry::UnitQuat;
use crate::numerics::tableau::dopri5_dense;
use crate::{ErrorKind, Keep, Output, Solution, Stats};

/// An initial-value problem for a [`LieSystem`]: integrate from `(t0, y0)` to `tf ≥ t0`.
#[derive(Clone, Debug, PartialEq)]
pub struct LieProblem {
    pub t0: f64,
    pub tf: f64,
    pub y0: LieState,
    /// Which rows the trajectory shows (every step by default). The dense output on the
    /// group ([`LieTrajectory::at`]) keeps every step whatever the rows.
    pub output: Output,
}

impl LieProblem {
    pub fn new(t0: f64, tf: f64, y0: LieState) -> Self {
        LieProblem {
            t0,
            tf,
            y0,
            output: Output::Steps,
        }
    }

    /// The same problem showing the rows `output` says: [`Output::Every`] every `k`-th
    /// step and the last, [`Output::Times`] exactly the given times (each on the dense
    /// output on the group).
    pub fn with_output(mut self, output: Output) -> Self {
        self.output = output;
        self
    }

    pub(super) fn validate<S: LieSystem + ?Sized>(&self, system: &S) -> Result<(), String> {
        if !self.t0.is_finite() || !self.tf.is_finite() || self.tf < self.t0 {
            return Err(format!(
                "need finite t0 ≤ tf (t0 = {}, tf = {})",
                self.t0, self.tf
            ));
        }
        let y = &self.y0;
        let (m, n) = (system.n_rot(), system.n_euclid());
        if y.rotations.len() != m || y.euclid.len() != n || y.velocity.len() != 3 * m + n {
            return Err(format!(
                "y0 has {} rotations, {} Euclidean coordinates and {} velocities; the system \
                 needs {m}, {n} and 3·{m} + {n} = {}",
                y.rotations.len(),
                y.euclid.len(),
                y.velocity.len(),
                3 * m + n
            ));
        }
        self.output.validate(self.t0, self.tf)?;
        let finite = |x: &[f64]| x.iter().all(|v| v.is_finite());
        let quats_finite = y.rotations.iter().all(|q| finite(&q.coords()));
        if !finite(&y.euclid) || !finite(&y.velocity) || !quats_finite {
            return Err("y0 has a NaN or infinite component".into());
        }
        Ok(())
    }
}

/// One integration in progress.
pub(super) struct LieRun<'a, S: ?Sized> {
    pub(super) system: &'a S,
    pub(super) traj: LieTrajectory,
}

impl<S: LieSystem + ?Sized> LieRun<'_, S> {
    /// `dv = f(t, y)`, counted and checked; a non-finite component is reported at its
    /// index in the flat layout of [`LieTrajectory::flat`].
    pub(super) fn rhs(&mut self, t: f64, y: &LieState, dv: &mut [f64]) -> Result<(), ErrorKind> {
        self.traj.flat.stats.rhs_evaluations += 1;
        self.system.rhs(t, y, dv);
        match dv.iter().position(|x| !x.is_finite()) {
            Some(j) => Err(ErrorKind::NonFinite {
                t,
                component: 4 * y.rotations.len() + y.euclid.len() + j,
            }),
            None => Ok(()),
        }
    }
}

/// The accepted states of a Lie-group integration with their dense output.
///
/// Stored twice over: as a flat [`Solution`] (per point the quaternions `w, x, y, z`
/// of every rotation, then `x`, then `v`; derivatives `q̇ = ½ q ⊗ (0, ω)`, `ẋ = u`,
/// `v̇ = f`; its own interpolation is cubic Hermite and leaves the group), and per step
/// the local-coordinate data of the continuous extension (Dormand–Prince for
/// [`Rkmk5`](super::Rkmk5), quartic through the previous point for [`LieSdirk`](super::LieSdirk)),
/// used by
/// [`at`](Self::at).
#[derive(Clone, Debug, PartialEq)]
pub struct LieTrajectory {
    n_rot: usize,
    n_euclid: usize,
    pub(super) flat: Solution,
    /// Cost of the integration (as [`Solution::stats`]).
    pub stats: Stats,
    /// Per interval: `Θ₁, K₁, K₇, r₅`, each of the local dimension (`K₁`, `K₇` the
    /// derivatives of `Θ` at the ends; `r₅` the quartic term, `0` for the cubic Hermite).
    chart: Vec<f64>,
    /// Per interval: the step's length `h` (the chart's time scale; longer than the
    /// interval when a terminal event cut the step short).
    steps: Vec<f64>,
    /// The rows the problem's [`Output`] asked for, when not every step (sampled at the
    /// end of the run); `flat` keeps every step for the dense output.
    rows: Option<Solution>,
}

impl LieTrajectory {
    pub(super) fn new(n_rot: usize, n_euclid: usize) -> Self {
        let mut names = Vec::new();
        for k in 0..n_rot {
            names.extend(["w", "x", "y", "z"].map(|c| format!("q{k}_{c}")));
        }
        names.extend((0..n_euclid).map(|i| format!("x{i}")));
        names.extend((0..3 * n_rot + n_euclid).map(|j| format!("v{j}")));
        LieTrajectory {
            n_rot,
            n_euclid,
            flat: Solution::new(names, 0, Output::Steps),
            stats: Stats::default(),
            chart: Vec::new(),
            steps: Vec::new(),
            rows: None,
        }
    }

    /// The rows shown: the sampled ones, or every step.
    fn shown(&self) -> &Solution {
        self.rows.as_ref().unwrap_or(&self.flat)
    }

    /// The flat row `y` as a state.
    fn decode(&self, y: &[f64]) -> LieState {
        let m4 = 4 * self.n_rot;
        let rotations = y[..m4]
            .chunks(4)
            .map(|c| UnitQuat::from_coords_unchecked(c[0], c[1], c[2], c[3]))
            .collect();
        let euclid = y[m4..m4 + self.n_euclid].to_vec();
        let velocity = y[m4 + self.n_euclid..].to_vec();
        LieState::new(rotations, euclid, velocity)
    }

    /// The rows `output` asks for, from the steps stored (`rhs`: the derivative at a
    /// sampled state): every `k`-th step and the last, or the given times on the dense
    /// output (those up to the last step: a terminal event may end the run early).
    pub(super) fn sample(
        &self,
        output: &Output,
        mut rhs: impl FnMut(f64, &LieState, &mut [f64]) -> Result<(), ErrorKind>,
    ) -> Result<Option<Solution>, ErrorKind> {
        let mut rows = Solution::new(self.flat.names().to_vec(), 0, Output::Steps);
        let n = self.flat.len();
        match output {
            Output::Steps => return Ok(None),
            Output::Every(k) => {
                for i in (0..n).filter(|&i| i % k == 0 || i + 1 == n) {
                    let (t, y, dy) = (
                        self.flat.times()[i],
                        self.flat.state(i),
                        self.flat.derivative(i),
                    );
                    rows.push_step(t, y, dy, None, Keep::AsAsked);
                }
            }
            Output::Times(ts) => {
                let Some(mut y) = self.last().map(|(_, y)| y) else {
                    return Ok(Some(rows));
                };
                let mut f = vec![0.0; y.velocity.len()];
                for &t in ts {
                    if !self.at_into(t, &mut y) {
                        break;
                    }
                    rhs(t, &y, &mut f)?;
                    let (flat, dflat) = encode(&y, &f);
                    rows.push_step(t, &flat, &dflat, None, Keep::AsAsked);
                }
            }
        }
        rows.stats = self.flat.stats;
        Ok(Some(rows))
    }

    /// Shows `rows` (from [`sample`](Self::sample)).
    pub(super) fn show(&mut self, rows: Option<Solution>) {
        self.rows = rows;
    }

    fn local_dim(&self) -> usize {
        6 * self.n_rot + 2 * self.n_euclid
    }

    pub(super) fn push(&mut self, y: &LieState, t: f64, f: &[f64]) {
        let (flat, dflat) = encode(y, f);
        self.flat.push_step(t, &flat, &dflat, None, Keep::AsAsked);
    }

    /// The continuous extension of the interval ending at the last pushed point: a step
    /// of length `h` reaching `Θ₁`, with `Θ'` = `k1` at its start and `k7` at its end.
    pub(super) fn push_chart(
        &mut self,
        h: f64,
        theta1: &[f64],
        k1: &[f64],
        k7: &[f64],
        r5: &[f64],
    ) {
        for part in [theta1, k1, k7, r5] {
            self.chart.extend_from_slice(part);
        }
        self.steps.push(h);
    }

    /// The interval of zero length between the two points of a reset (the state before
    /// it and after it, at one time): never interpolated (a time there reads the point
    /// after it), its chart data zero.
    pub(super) fn push_jump_interval(&mut self) {
        let d = self.local_dim();
        self.chart.extend(std::iter::repeat_n(0.0, 4 * d));
        self.steps.push(1.0);
    }

    /// Replaces the last point by `(t, y)` with `f = f(t, y)`, `t` inside the last
    /// interval (a terminal event); the interval keeps its step's interpolant.
    pub(super) fn truncate_last(&mut self, t: f64, y: &LieState, f: &[f64]) {
        let n = self.len();
        let mut flat = Solution::new(self.flat.names().to_vec(), 0, Output::Steps);
        for i in 0..n - 1 {
            flat.push_step(
                self.flat.times()[i],
                self.flat.state(i),
                self.flat.derivative(i),
                None,
                Keep::AsAsked,
            );
        }
        flat.stats = self.flat.stats;
        self.flat = flat;
        self.push(y, t, f);
    }

    /// Number of rows (every step, or those the problem's [`Output`] asked for).
    pub fn len(&self) -> usize {
        self.shown().len()
    }

    pub fn is_empty(&self) -> bool {
        self.shown().is_empty()
    }

    /// Times of the rows, increasing.
    pub fn times(&self) -> &[f64] {
        self.shown().times()
    }

    /// State at row `i`.
    pub fn state(&self, i: usize) -> LieState {
        self.decode(self.shown().state(i))
    }

    /// The last stored time and state.
    pub fn last(&self) -> Option<(f64, LieState)> {
        let n = self.len();
        (n > 0).then(|| (self.times()[n - 1], self.state(n - 1)))
    }

    /// The state at `t` from the continuous extension in the local coordinates of the
    /// step containing `t` (on the group; fourth order for [`Rkmk5`](super::Rkmk5), third for
    /// [`LieSdirk`](super::LieSdirk)), or `None` outside `[t_first, t_last]`.
    pub fn at(&self, t: f64) -> Option<LieState> {
        let mut y = self.last()?.1;
        self.at_into(t, &mut y).then_some(y)
    }

    /// [`at`](Self::at) written into `out` (shaped like the trajectory's states);
    /// `false`, and `out` untouched, outside `[t_first, t_last]`.
    pub fn at_into(&self, t: f64, out: &mut LieState) -> bool {
        let times = self.flat.times();
        let (Some(&first), Some(&last)) = (times.first(), times.last()) else {
            return false;
        };
        if !(first..=last).contains(&t) {
            return false;
        }
        let i = times.partition_point(|&ti| ti <= t).saturating_sub(1);
        let base = self.decode(self.flat.state(i));
        if i + 1 >= times.len() {
            out.clone_from(&base);
            return true;
        }
        let h = self.steps[i];
        let s = (t - times[i]) / h;
        let d = self.local_dim();
        let data = &self.chart[4 * d * i..4 * d * (i + 1)];
        let (th1, rest) = data.split_at(d);
        let (k1, rest) = rest.split_at(d);
        let (k7, r5) = rest.split_at(d);
        let theta: Vec<f64> = (0..d)
            .map(|c| dopri5_dense(s, h, 0.0, th1[c], k1[c], k7[c], r5[c]))
            .collect();
        retract(&base, &theta, out);
        for q in &mut out.rotations {
            *q = q.normalised();
        }
        true
    }

    /// The flat trajectory's rows (layout in the type's documentation), e.g. for CSV
    /// output.
    pub fn flat(&self) -> &Solution {
        self.shown()
    }
}

/// A state and its derivative `f` as a flat row and its derivative (layout in
/// [`LieTrajectory`]'s documentation).
fn encode(y: &LieState, f: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let (mut flat, mut dflat) = (Vec::new(), Vec::new());
    for (k, q) in y.rotations.iter().enumerate() {
        let [w, x, yy, z] = q.coords();
        let u = Vector3::new(x, yy, z);
        let om = y.omega(k);
        let du = (om * w + u.cross(&om)) * 0.5;
        flat.extend_from_slice(&q.coords());
        dflat.extend_from_slice(&[-0.5 * u.dot(&om), du.x, du.y, du.z]);
    }
    flat.extend_from_slice(&y.euclid);
    flat.extend_from_slice(&y.velocity);
    dflat.extend_from_slice(y.euclid_velocity());
    dflat.extend_from_slice(f);
    (flat, dflat)
}
