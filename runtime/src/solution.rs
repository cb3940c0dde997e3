//! The one result type of every integration — smooth, event-driven, time-stepping:
//! rows at the accepted steps (or at the times asked for), the method's own dense output
//! between them, named columns, the statistics and, for non-smooth runs, the log of
//! every switch.

use std::io::{self, Write};

use crate::Stats;
use crate::element::Mode;
use crate::events::EventHit;
use crate::numerics::dense::{DenseStep, eval_poly};

/// Which rows a [`Solution`] keeps.
#[derive(Clone, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum Output {
    /// Every accepted step, each with the method's dense output over it (default): `at`
    /// is as accurate as the method between the steps.
    #[default]
    Steps,
    /// Every `k`-th accepted step (and the last one, and both rows of every event);
    /// between the kept rows cubic Hermite on their states and derivatives. For long runs
    /// where every step would not fit in memory.
    Every(usize),
    /// Exactly the given times (increasing, inside the integration interval), evaluated
    /// on the method's dense output as the integration passes them: `times()` is the
    /// list asked for. A non-smooth run's events are in its switch log, each with the
    /// states just before and after ([`Switch::before`], [`Switch::after`]). Between the
    /// kept rows cubic Hermite.
    Times(Vec<f64>),
}

impl Output {
    /// Checks the option against the integration interval.
    pub(crate) fn validate(&self, t0: f64, tf: f64) -> Result<(), String> {
        match self {
            Output::Steps => Ok(()),
            Output::Every(0) => Err("Output::Every(k) needs k ≥ 1".into()),
            Output::Every(_) => Ok(()),
            Output::Times(ts) => {
                if let Some(t) = ts.iter().find(|t| !(t0..=tf).contains(*t)) {
                    return Err(format!(
                        "output time {t} is outside the integration interval [{t0}, {tf}]"
                    ));
                }
                if ts.windows(2).any(|w| w[1] < w[0]) {
                    return Err("output times must be increasing".into());
                }
                Ok(())
            }
        }
    }
}

/// What happened at a switch of a non-smooth run.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum SwitchKind {
    /// The element's mode changed from `from` to `to`; `jump` is the change of its force
    /// across the switch (`f⁺ − f⁻`).
    Mode,
    /// A rigid stop's impact after which the coordinate leaves the stop (it rebounds, or
    /// with `e = 0` is pulled away): `jump` is the generalised impulse `P` along its
    /// coordinate (`v⁺ = v⁻ − M⁻¹ e_c P`).
    Impact,
    /// A rigid stop's impact after which the stop is in contact: a plastic impact
    /// (`e = 0`) pressed onto the stop, or a rebound so small that it would stay within
    /// the position tolerance, taken as the Zeno limit of its bounces
    /// ([`Switch::accumulation`]); `jump` is the impulse.
    ///
    /// The rule for both: one entry per stop per impact, `Settled` when the stop's mode
    /// after the impact is [`Mode::Contact`], `Impact` otherwise; the entry's
    /// `from`/`to` are the stop's modes across it, so no separate
    /// [`Mode`](SwitchKind::Mode) entry is logged for that stop at that instant.
    Settled,
    /// Accumulating events (Zeno, chattering): the integration is handed to
    /// time-stepping from `t` on.
    HandOverToTimeStepping,
    /// Back from time-stepping to event-driven integration at `t`.
    HandBack,
    /// A user event's reset changed the state at `t` (`before` and `after` are the states
    /// across it); the modes are selected again at the new state, each element whose mode
    /// changes logged by its own entry after this one (an impact the new state makes as
    /// `Impact`/`Settled`, any other change as `Mode`).
    Reset,
}

/// One entry of a non-smooth solution's switch log.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub struct Switch {
    pub t: f64,
    pub kind: SwitchKind,
    /// The element's name as the scene declares it (`None` for hand-overs and resets).
    pub element: Option<String>,
    /// The element's index in the scene (`NonSmooth::element`), `None` for hand-overs and
    /// resets.
    pub index: Option<usize>,
    /// The element's mode before and after (equal for an impact that keeps it).
    pub from: Option<Mode>,
    pub to: Option<Mode>,
    /// Force jump or impulse (see [`SwitchKind`]); `0` for hand-overs.
    pub jump: f64,
    /// For [`SwitchKind::Settled`]: the accumulation time of the rebounds taken as
    /// settled, the Zeno limit `t + 2w / (a (1 − e))` of rebounds at speed `w = e |v⁻|`
    /// under the acceleration `a` pressing the coordinate onto its stop (`None` for
    /// `e = 1`, and for every other kind).
    pub accumulation: Option<f64>,
    /// The state `[q; v]` just before the switch (an impact's pre-impact velocities).
    pub before: Vec<f64>,
    /// The state `[q; v]` just after it.
    pub after: Vec<f64>,
}

impl Switch {
    /// An entry of the run as a whole, not of one element (a hand-over, a hand-back, a
    /// reset): the states just before and after it.
    pub(crate) fn of_run(t: f64, kind: SwitchKind, before: Vec<f64>, after: Vec<f64>) -> Self {
        Switch {
            t,
            kind,
            element: None,
            index: None,
            from: None,
            to: None,
            jump: 0.0,
            accumulation: None,
            before,
            after,
        }
    }
}

/// Whether an accepted step's row is kept whatever the [`Output`] says.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Keep {
    /// As the output says.
    AsAsked,
    /// The last step of the run: kept by [`Output::Every`], not by [`Output::Times`].
    Last,
    /// The row just before an event: kept by every output but [`Output::Times`].
    Event,
}

/// How the interval ending at a row is interpolated.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Segment {
    /// Start of its coefficients in `Solution::coeffs`.
    offset: usize,
    /// Degree of its polynomial; `0`: cubic Hermite on the two rows.
    degree: usize,
    /// A one-step method's own extension (no earlier point), to be rewritten as the
    /// two-step quintic when the next step continues smoothly (`refine_previous`).
    one_step: bool,
}

const HERMITE: Segment = Segment {
    offset: 0,
    degree: 0,
    one_step: false,
};

/// The result of an integration (see the module documentation).
///
/// Columns: `[q; v]` named `q_<joint>`, `v_<joint>` for mechanisms (`y<i>` for a plain
/// [`OdeSystem`](crate::OdeSystem)); non-smooth runs add one force column `f_<element>`
/// per element. At an event two rows share its time, before and after the switch.
///
/// ```
/// use filippov_runtime::{FnSystem, Method, Options, Problem, solve};
/// let osc = FnSystem::new(2, |_t, y: &[f64], dy: &mut [f64]| {
///     dy[0] = y[1];
///     dy[1] = -y[0];
/// });
/// let sol = solve(&osc, &Problem::new(0.0, 3.0, [1.0, 0.0]), &Method::Dopri5(Options::tolerances(1e-10, 1e-12))).unwrap();
/// let mut y = [0.0; 2];
/// assert!(sol.at_into(1.234, &mut y)); // no allocation
/// assert!((y[0] - 1.234f64.cos()).abs() < 1e-8);
/// let grid = sol.sample(&[0.5, 1.0, 2.5]).unwrap();
/// assert!((grid[2][1] + 2.5f64.sin()).abs() < 1e-8);
/// assert_eq!(sol.column("y0").unwrap().len(), sol.len());
/// ```
///
/// With the `serde` feature it serialises to a stable, versioned schema of named
/// columns, the switch log and the statistics, exact to the bit with any JSON reader
/// (`Solution::SCHEMA`, feature `serde`; the format in `solution/json.rs`).
#[derive(Clone, Debug, PartialEq)]
pub struct Solution {
    dim: usize,
    /// The leading components the dense output covers; later ones (element forces) are
    /// interpolated linearly between the rows of a polynomial segment.
    dense_dim: usize,
    names: Vec<String>,
    t: Vec<f64>,
    y: Vec<f64>,
    dy: Vec<f64>,
    /// `seg[i]`: the interval from row `i − 1` to row `i` (`seg[0]` unused).
    seg: Vec<Segment>,
    coeffs: Vec<f64>,
    /// Cost of the integration.
    pub stats: Stats,
    /// Non-smooth runs: every switch, in time order, one entry per element per event
    /// (the rules at [`SwitchKind::Settled`]). Event-driven runs log each at its located
    /// time with the states just before and after; time-stepping logs each at the end of
    /// the step in which it happened, with the states at that step's start and end (a
    /// span handed over to time-stepping logs its entries between the hand-over and the
    /// hand-back).
    pub switches: Vec<Switch>,
    /// The user events located in the run, in time order (see [`crate::events`]); the
    /// state is the row's `[q; v]` (or `y`) at the crossing.
    pub events: Vec<EventHit>,
    output: Output,
    recorder: Recorder,
    /// `Some(n)`: the first `n` columns are positions whose refined steps are the quintic
    /// in `q, q̇, q̈` (see [`OdeSystem::dense_positions`](crate::OdeSystem::dense_positions)).
    dense_positions: Option<usize>,
}

/// What the row filter of [`Output`] remembers between steps.
#[derive(Clone, Debug, Default, PartialEq)]
struct Recorder {
    /// Accepted steps since the last kept row (`Every`).
    skipped: usize,
    /// Next requested time (`Times`).
    next: usize,
    /// The last accepted point, kept or not.
    t: f64,
    row: Vec<f64>,
    drow: Vec<f64>,
    started: bool,
}

#[cfg(feature = "serde")]
mod json;

impl Solution {
    /// The schema a serialised solution carries and is read with (feature `serde`):
    /// `filippov.solution/1`.
    #[cfg(feature = "serde")]
    pub const SCHEMA: &'static str = json::SCHEMA;

    /// An empty solution with these column names, of which the first `dense_dim` are
    /// covered by dense output.
    pub(crate) fn new(names: Vec<String>, dense_dim: usize, output: Output) -> Self {
        Solution {
            dim: names.len(),
            dense_dim: dense_dim.min(names.len()),
            names,
            t: Vec::new(),
            y: Vec::new(),
            dy: Vec::new(),
            seg: Vec::new(),
            coeffs: Vec::new(),
            stats: Stats::default(),
            switches: Vec::new(),
            events: Vec::new(),
            output,
            recorder: Recorder::default(),
            dense_positions: None,
        }
    }

    /// Appends columns computed from each stored row, `fill(t, row, out)` writing their
    /// values (a closed mechanism's constraint forces from its state): their derivatives
    /// are stored as zero, and between rows they are read back linearly, like element
    /// forces. The dense output keeps covering the columns it covered.
    pub(crate) fn append_columns(
        &mut self,
        names: Vec<String>,
        mut fill: impl FnMut(f64, &[f64], &mut [f64]),
    ) {
        let (old, extra) = (self.dim, names.len());
        if extra == 0 {
            return;
        }
        let dim = old + extra;
        let mut y = vec![0.0; self.len() * dim];
        let mut dy = vec![0.0; self.len() * dim];
        for (i, &t) in self.t.iter().enumerate() {
            let (from, to) = (i * old..(i + 1) * old, i * dim..i * dim + old);
            y[to.clone()].copy_from_slice(&self.y[from.clone()]);
            dy[to].copy_from_slice(&self.dy[from.clone()]);
            let (row, out) = y[i * dim..(i + 1) * dim].split_at_mut(old);
            fill(t, row, out);
        }
        self.y = y;
        self.dy = dy;
        self.dim = dim;
        self.names.extend(names);
    }

    /// The first `n` columns are positions read back with the quintic in `q, q̇, q̈` (see
    /// [`OdeSystem::dense_positions`](crate::OdeSystem::dense_positions)).
    pub(crate) fn with_dense_positions(mut self, n: Option<usize>) -> Self {
        self.dense_positions = n;
        self
    }

    /// Stores a row as it is, interpolated from the previous row by `segment`.
    fn store(&mut self, t: f64, y: &[f64], dy: &[f64], segment: Segment) {
        self.t.push(t);
        self.y.extend_from_slice(y);
        self.dy.extend_from_slice(dy);
        self.seg.push(segment);
    }

    /// The first point of an integration (or of a piece of one).
    pub(crate) fn push_start(&mut self, t: f64, y: &[f64], dy: &[f64]) {
        let keep = match &self.output {
            Output::Times(ts) => {
                let r = &mut self.recorder;
                // Requested times before the start are not reachable (validated away).
                while r.next < ts.len() && ts[r.next] < t {
                    r.next += 1;
                }
                if r.next < ts.len() && ts[r.next] == t {
                    r.next += 1;
                    true
                } else {
                    false
                }
            }
            _ => true,
        };
        if keep {
            self.store(t, y, dy, HERMITE);
        }
        self.remember(t, y, dy);
    }

    fn remember(&mut self, t: f64, y: &[f64], dy: &[f64]) {
        let r = &mut self.recorder;
        r.t = t;
        r.row.clear();
        r.row.extend_from_slice(y);
        r.drow.clear();
        r.drow.extend_from_slice(dy);
        r.started = true;
    }

    /// An accepted step ending at `(t, y)` with derivative `dy`, and the method's dense
    /// output over it (covering the first `dense_dim` columns), if it has one.
    pub(crate) fn push_step(
        &mut self,
        t: f64,
        y: &[f64],
        dy: &[f64],
        dense: Option<&DenseStep>,
        keep: Keep,
    ) {
        match self.output {
            Output::Steps => {
                if let Some(d) = dense {
                    self.refine_previous(d, t, y, dy);
                }
                let segment = match dense {
                    Some(d) => {
                        let offset = self.coeffs.len();
                        self.coeffs.extend_from_slice(d.coefficients());
                        Segment {
                            offset,
                            degree: d.degree(),
                            one_step: d.third_node().is_none(),
                        }
                    }
                    None => HERMITE,
                };
                self.store(t, y, dy, segment);
            }
            Output::Every(k) => {
                self.recorder.skipped += 1;
                if keep != Keep::AsAsked || self.recorder.skipped >= k {
                    self.recorder.skipped = 0;
                    self.store(t, y, dy, HERMITE);
                }
            }
            Output::Times(_) => self.push_requested(t, y, dy, dense),
        }
        self.remember(t, y, dy);
    }

    /// A one-step method's first step after a start or restart has only its own
    /// extension (DOPRI5's quartic, a cubic Hermite): one order less than the two-step
    /// quintic Hermite of the steps after it, which lost up to 2.2 times the step error on
    /// S4's output grid, where every event restarts. When the step after it arrives with a
    /// two-step extension whose first node is that step's start (so the solution is
    /// smooth across both), the finished step's extension is rewritten as the quintic
    /// through its two ends and the new point `(t, y, dy)`.
    fn refine_previous(&mut self, next: &DenseStep, t: f64, y: &[f64], dy: &[f64]) {
        let (len, nd) = (self.len(), self.dense_dim);
        if len < 2 || next.third_node() != Some(self.t[len - 2]) {
            return;
        }
        let seg = self.seg[len - 1];
        if seg.degree == 0
            || !seg.one_step
            || seg.offset + (seg.degree + 1) * nd != self.coeffs.len()
        {
            return;
        }
        let (tp, ta) = (self.t[len - 2], self.t[len - 1]);
        let mut refined = DenseStep::new(nd);
        refined.set_hermite5(
            self.dense_positions.unwrap_or(0),
            t,
            &y[..nd],
            &dy[..nd],
            tp,
            ta - tp,
            &self.state(len - 2)[..nd],
            &self.derivative(len - 2)[..nd],
            &self.state(len - 1)[..nd],
            &self.derivative(len - 1)[..nd],
        );
        if let Some(n) = self.dense_positions {
            refined.set_positions_quintic(
                n,
                &self.state(len - 2)[..nd],
                &self.derivative(len - 2)[..nd],
                &self.state(len - 1)[..nd],
                &self.derivative(len - 1)[..nd],
            );
        }
        self.coeffs.truncate(seg.offset);
        self.coeffs.extend_from_slice(refined.coefficients());
        self.seg[len - 1].degree = 5;
        self.seg[len - 1].one_step = false;
    }

    /// [`Output::Times`]: the requested times inside the step, then the row itself if
    /// it is to be kept.
    fn push_requested(&mut self, t: f64, y: &[f64], dy: &[f64], dense: Option<&DenseStep>) {
        if !self.requested_by(t, true) {
            return;
        }
        let Output::Times(ts) = std::mem::take(&mut self.output) else {
            unreachable!("called for Output::Times only")
        };
        let (n, nd) = (self.dim, self.dense_dim);
        let t0 = self.recorder.t;
        let mut val = vec![0.0; n];
        let mut der = vec![0.0; n];
        while self.recorder.next < ts.len() && ts[self.recorder.next] <= t {
            let tau = ts[self.recorder.next];
            self.recorder.next += 1;
            if tau == t {
                // The step's end itself: the accepted state, not the polynomial's
                // rounding of it (a stuck velocity stays exactly 0.0).
                self.store(t, y, dy, HERMITE);
                continue;
            }
            let r = &self.recorder;
            let h = t - t0;
            let theta = if h > 0.0 { (tau - t0) / h } else { 1.0 };
            match dense {
                Some(d) => {
                    d.eval(tau, &mut val[..nd]);
                    d.eval_derivative(tau, &mut der[..nd]);
                }
                None => {
                    hermite(
                        theta,
                        h,
                        &r.row[..nd],
                        &r.drow[..nd],
                        &y[..nd],
                        &dy[..nd],
                        &mut val[..nd],
                    );
                    hermite_slope(
                        theta,
                        h,
                        &r.row[..nd],
                        &r.drow[..nd],
                        &y[..nd],
                        &dy[..nd],
                        &mut der[..nd],
                    );
                }
            }
            for i in nd..n {
                val[i] = r.row[i] + theta * (y[i] - r.row[i]);
                der[i] = if h > 0.0 { (y[i] - r.row[i]) / h } else { 0.0 };
            }
            self.store(tau, &val, &der, HERMITE);
        }
        self.output = Output::Times(ts);
    }

    /// Whether a row is wanted at a requested time up to `t` (up to and including `t`
    /// with `inclusive`) not yet stored ([`Output::Times`] only).
    fn requested_by(&self, t: f64, inclusive: bool) -> bool {
        match &self.output {
            Output::Times(ts) => ts
                .get(self.recorder.next)
                .is_some_and(|&tau| tau < t || (inclusive && tau == t)),
            _ => false,
        }
    }

    /// Whether [`push_step`](Self::push_step) of a step ending at `t` reads the step's
    /// dense output: always for [`Output::Steps`], for [`Output::Times`] when a
    /// requested time falls inside the step, never for [`Output::Every`]. A stepper that
    /// builds its extension on demand need not build it otherwise.
    pub(crate) fn needs_dense(&self, t: f64) -> bool {
        match self.output {
            Output::Steps => true,
            Output::Every(_) => false,
            Output::Times(_) => self.requested_by(t, false),
        }
    }

    /// A row at the same time as the previous one, after a jump (the second row of an
    /// event). Kept unless only given times are asked for ([`Output::Times`]).
    pub(crate) fn push_jump(&mut self, t: f64, y: &[f64], dy: &[f64]) {
        if !matches!(self.output, Output::Times(_)) {
            self.store(t, y, dy, HERMITE);
        }
        self.remember(t, y, dy);
    }

    /// Number of stored rows.
    pub fn len(&self) -> usize {
        self.t.len()
    }

    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }

    /// Number of columns.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// Column names.
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// Index of the column called `name`.
    pub fn column_index(&self, name: &str) -> Option<usize> {
        self.names.iter().position(|n| n == name)
    }

    /// The rows kept ([`Output`]).
    pub fn output(&self) -> &Output {
        &self.output
    }

    /// Times of the stored rows, non-decreasing (an event's two rows share a time).
    pub fn times(&self) -> &[f64] {
        &self.t
    }

    /// Row `i`.
    pub fn state(&self, i: usize) -> &[f64] {
        &self.y[i * self.dim..(i + 1) * self.dim]
    }

    /// The time derivative stored with row `i` (`f(t_i, y_i)` for the state columns).
    pub fn derivative(&self, i: usize) -> &[f64] {
        &self.dy[i * self.dim..(i + 1) * self.dim]
    }

    /// The last stored time and row.
    pub fn last(&self) -> Option<(f64, &[f64])> {
        let n = self.len();
        (n > 0).then(|| (self.t[n - 1], self.state(n - 1)))
    }

    /// All rows as `(t, row)`.
    pub fn rows(&self) -> impl ExactSizeIterator<Item = (f64, &[f64])> + '_ {
        self.t
            .iter()
            .copied()
            .zip(self.y.chunks_exact(self.dim.max(1)))
    }

    /// All values of column `j`, one per row.
    pub fn component(&self, j: usize) -> Vec<f64> {
        self.y.iter().skip(j).step_by(self.dim).copied().collect()
    }

    /// All values of the column called `name`, one per row.
    pub fn column(&self, name: &str) -> Option<Vec<f64>> {
        self.column_index(name).map(|j| self.component(j))
    }

    /// The state at `t` into `out` (length [`dim`](Self::dim)), without allocating:
    /// the method's dense output over the step containing `t` (after an event, the
    /// state just after it); `false` if `t` is outside `[t_first, t_last]` (no
    /// extrapolation).
    pub fn at_into(&self, t: f64, out: &mut [f64]) -> bool {
        let (Some(&first), Some(&last)) = (self.t.first(), self.t.last()) else {
            return false;
        };
        if !(first..=last).contains(&t) {
            return false;
        }
        // Interval [t_i, t_{i+1}] containing t.
        let i = self.t.partition_point(|&ti| ti <= t).saturating_sub(1);
        if i + 1 >= self.len() {
            out.copy_from_slice(self.state(i));
            return true;
        }
        let (t0, t1) = (self.t[i], self.t[i + 1]);
        let h = t1 - t0;
        let theta = (t - t0) / h;
        let (y0, y1) = (self.state(i), self.state(i + 1));
        let seg = self.seg[i + 1];
        if seg.degree > 0 {
            let nd = self.dense_dim;
            let len = (seg.degree + 1) * nd;
            eval_poly(
                &self.coeffs[seg.offset..seg.offset + len],
                nd,
                seg.degree,
                theta,
                &mut out[..nd],
            );
            for k in nd..self.dim {
                out[k] = y0[k] + theta * (y1[k] - y0[k]);
            }
        } else {
            let (f0, f1) = (self.derivative(i), self.derivative(i + 1));
            hermite(theta, h, y0, f0, y1, f1, out);
        }
        true
    }

    /// The state at `t` (see [`at_into`](Self::at_into)), or `None` outside the
    /// solution's interval.
    pub fn at(&self, t: f64) -> Option<Vec<f64>> {
        let mut out = vec![0.0; self.dim];
        self.at_into(t, &mut out).then_some(out)
    }

    /// The states at `times`, one row each; `None` if any is outside the interval.
    pub fn sample(&self, times: &[f64]) -> Option<Vec<Vec<f64>>> {
        times.iter().map(|&t| self.at(t)).collect()
    }

    /// Writes the stored rows as CSV: a header `t,<names>` then one row per point.
    pub fn write_csv<W: Write>(&self, mut out: W) -> io::Result<()> {
        write!(out, "t")?;
        for name in &self.names {
            write!(out, ",{name}")?;
        }
        writeln!(out)?;
        for (t, row) in self.rows() {
            write!(out, "{t}")?;
            for x in row {
                write!(out, ",{x}")?;
            }
            writeln!(out)?;
        }
        Ok(())
    }

    /// Writes the switch log as CSV: `t,kind,element,from,to,jump`.
    pub fn write_switches_csv<W: Write>(&self, mut out: W) -> io::Result<()> {
        writeln!(out, "t,kind,element,from,to,jump")?;
        for s in &self.switches {
            let opt = |m: Option<Mode>| m.map(|m| format!("{m:?}")).unwrap_or_default();
            writeln!(
                out,
                "{},{:?},{},{},{},{}",
                s.t,
                s.kind,
                s.element.as_deref().unwrap_or(""),
                opt(s.from),
                opt(s.to),
                s.jump
            )?;
        }
        Ok(())
    }
}

/// Cubic Hermite between `(y0, f0)` and `(y1, f1)` at fraction `theta` of a step `h`.
fn hermite(theta: f64, h: f64, y0: &[f64], f0: &[f64], y1: &[f64], f1: &[f64], out: &mut [f64]) {
    let (t2, t3) = (theta * theta, theta * theta * theta);
    let h00 = 2.0 * t3 - 3.0 * t2 + 1.0;
    let h10 = t3 - 2.0 * t2 + theta;
    let h01 = -2.0 * t3 + 3.0 * t2;
    let h11 = t3 - t2;
    for k in 0..out.len() {
        out[k] = h00 * y0[k] + h10 * h * f0[k] + h01 * y1[k] + h11 * h * f1[k];
    }
}

/// Time derivative of [`hermite`].
fn hermite_slope(
    theta: f64,
    h: f64,
    y0: &[f64],
    f0: &[f64],
    y1: &[f64],
    f1: &[f64],
    out: &mut [f64],
) {
    if h == 0.0 {
        out.copy_from_slice(f1);
        return;
    }
    let t2 = theta * theta;
    let d00 = (6.0 * t2 - 6.0 * theta) / h;
    let d10 = 3.0 * t2 - 4.0 * theta + 1.0;
    let d01 = -d00;
    let d11 = 3.0 * t2 - 2.0 * theta;
    for k in 0..out.len() {
        out[k] = d00 * y0[k] + d10 * f0[k] + d01 * y1[k] + d11 * f1[k];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cubic_solution(output: Output) -> Solution {
        let y = |t: f64| t * t * t - 2.0 * t + 1.0;
        let dy = |t: f64| 3.0 * t * t - 2.0;
        let mut sol = Solution::new(vec!["x".into()], 1, output);
        sol.push_start(0.0, &[y(0.0)], &[dy(0.0)]);
        for (a, b) in [(0.0, 0.5), (0.5, 1.5)] {
            let mut d = DenseStep::new(1);
            d.set_hermite(a, b - a, &[y(a)], &[dy(a)], &[y(b)], &[dy(b)]);
            let keep = if b == 1.5 { Keep::Last } else { Keep::AsAsked };
            sol.push_step(b, &[y(b)], &[dy(b)], Some(&d), keep);
        }
        sol
    }

    #[test]
    fn dense_segments_reproduce_cubics_and_csv_has_header() {
        let y = |t: f64| t * t * t - 2.0 * t + 1.0;
        let sol = cubic_solution(Output::Steps);
        for t in [0.0, 0.1, 0.5, 0.9, 1.2, 1.5] {
            assert!((sol.at(t).unwrap()[0] - y(t)).abs() < 1e-14);
        }
        assert_eq!(sol.at(1.6), None);
        assert_eq!(sol.last().unwrap().0, 1.5);
        assert_eq!(sol.component(0).len(), 3);
        let mut csv = Vec::new();
        sol.write_csv(&mut csv).unwrap();
        let csv = String::from_utf8(csv).unwrap();
        assert_eq!(csv.lines().next(), Some("t,x"));
        assert_eq!(csv.lines().nth(1), Some("0,1"));
        assert_eq!(csv.lines().count(), 4);
    }

    #[test]
    fn requested_times_are_evaluated_on_the_dense_output() {
        let y = |t: f64| t * t * t - 2.0 * t + 1.0;
        let sol = cubic_solution(Output::Times(vec![0.25, 0.5, 1.0, 1.4]));
        assert_eq!(sol.times(), [0.25, 0.5, 1.0, 1.4]);
        for (t, row) in sol.rows() {
            assert!((row[0] - y(t)).abs() < 1e-14, "{t}");
        }
        // Between the kept rows: Hermite on exact values and slopes of a cubic.
        assert!((sol.at(0.7).unwrap()[0] - y(0.7)).abs() < 1e-14);
    }

    #[test]
    fn every_kth_step_keeps_the_last() {
        let sol = cubic_solution(Output::Every(5));
        assert_eq!(sol.times(), [0.0, 1.5]);
        assert!(Output::Every(0).validate(0.0, 1.0).is_err());
        assert!(Output::Times(vec![0.5, 0.2]).validate(0.0, 1.0).is_err());
        assert!(Output::Times(vec![1.5]).validate(0.0, 1.0).is_err());
    }
}

#[cfg(all(test, feature = "serde"))]
mod serde_tests {
    use nalgebra::SVector;

    use crate::nonsmooth::{NonSmoothMethod, NonSmoothProblem, law::test_systems::*};
    use crate::{Options, Solution, Stats, solve_nonsmooth};

    type V1 = SVector<f64, 1>;

    fn free(_t: f64, _q: &V1, _v: &V1) -> V1 {
        V1::zeros()
    }

    /// A non-smooth solution (rows, dense segments, switch log, statistics) and the
    /// options survive a JSON round trip with plain serde_json unchanged to the bit, and
    /// the restored solution interpolates as the original. The JSON is the schema's: a
    /// reader that knows nothing of this crate finds the named columns, the switch log
    /// and the statistics.
    #[test]
    fn solution_round_trips_through_json() {
        let sys = oscillator(
            1.0,
            1.0,
            [dashpot("friction", 0, crate::nonsmooth::Law::Coulomb, 0.1)],
            cubic,
        );
        let p = NonSmoothProblem::new(0.0, 20.0, V1::new(1.0), V1::new(0.0));
        let sol = solve_nonsmooth(&sys, &free, &p, &NonSmoothMethod::default()).unwrap();
        assert!(!sol.switches.is_empty());
        let json = serde_json::to_string(&sol).unwrap();
        let back: Solution = serde_json::from_str(&json).unwrap();
        assert_eq!(back, sol);
        assert_eq!(back.at(3.3), sol.at(3.3));
        let value: serde_json::Value = serde_json::from_str(&json).unwrap();
        assert_eq!(value["schema"], Solution::SCHEMA);
        assert_eq!(value["columns"][0]["name"], "q0");
        assert_eq!(value["columns"][2]["name"], "f_friction");
        let t1: f64 = value["t"][1].as_str().unwrap().parse().unwrap();
        assert_eq!(t1, sol.times()[1]);
        assert_eq!(value["switches"][0]["element"], "friction");
        assert_eq!(value["stats"]["steps"], sol.stats.steps);
        // Another schema is refused, naming both.
        let other = json.replace(Solution::SCHEMA, "filippov.solution/0");
        let err = serde_json::from_str::<Solution>(&other)
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("filippov.solution/0") && err.contains(Solution::SCHEMA),
            "{err}"
        );
        let stats: Stats =
            serde_json::from_str(&serde_json::to_string(&sol.stats).unwrap()).unwrap();
        assert_eq!(stats, sol.stats);
        let o = Options::tolerances(1e-7, 1e-9);
        let back: Options = serde_json::from_str(&serde_json::to_string(&o).unwrap()).unwrap();
        assert_eq!(back, o);
    }

    /// Every bit of every double survives, whatever its exponent (serde_json parses JSON
    /// numbers to within an ulp only without its float_roundtrip feature): random bit
    /// patterns in a solution's rows, times, switch log and requested output times.
    #[test]
    fn every_bit_round_trips_with_plain_serde_json() {
        let mut x: u64 = 0x9e37_79b9_7f4a_7c15;
        let mut next = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            // Every double but NaN (whose payload is not kept: all NaNs read back as one).
            let f = f64::from_bits(x);
            if f.is_nan() { f64::NEG_INFINITY } else { f }
        };
        let names: Vec<String> = (0..3).map(|i| format!("c{i}")).collect();
        let mut sol = Solution::new(names.clone(), 2, crate::Output::Steps);
        for i in 0..200 {
            let y: Vec<f64> = (0..3).map(|_| next()).collect();
            let dy: Vec<f64> = (0..3).map(|_| next()).collect();
            if i == 0 {
                sol.push_start(0.0, &y, &dy);
            } else {
                sol.push_jump(next(), &y, &dy);
            }
        }
        sol.switches.push(crate::Switch::of_run(
            next(),
            crate::SwitchKind::Reset,
            vec![next(), f64::INFINITY, f64::MIN_POSITIVE],
            vec![-0.0, next()],
        ));
        let json = serde_json::to_string(&sol).unwrap();
        let back: Solution = serde_json::from_str(&json).unwrap();
        let bits = |s: &Solution| -> Vec<u64> {
            s.rows()
                .flat_map(|(t, y)| std::iter::once(t).chain(y.iter().copied()))
                .chain(s.switches[0].before.iter().copied())
                .chain(s.switches[0].after.iter().copied())
                .map(f64::to_bits)
                .collect()
        };
        assert_eq!(bits(&back), bits(&sol));
        let times = crate::Output::Times((0..50).map(|_| next()).collect());
        let empty = Solution::new(names, 2, times);
        let back: Solution = serde_json::from_str(&serde_json::to_string(&empty).unwrap()).unwrap();
        assert_eq!(back, empty);
    }
}
