//! The randomized agreement suite: random chains with random non-smooth elements,
//! integrated event-driven and by time-stepping, each time-stepping run compared with
//! event-driven over the whole interval, and event-driven checked for passivity. Shared
//! by `scenes/tests/agreement.rs` (a few dozen scenes) and the report (a thousand and more).
//!
//! A scene (from its seed): a planar or spatial chain of 1–7 revolute or prismatic
//! joints (rod-like links, random masses and lengths), gravity or not, springs and
//! dampers on some joints; one or two elements — Coulomb friction, linear, cubic or
//! non-monotone Bingham (S4's law, either selection), a rigid stop with restitution or a
//! spring-backed stop — and a sinusoidal
//! force on one joint or none. The initial state: moving, stuck (an element's coordinate
//! at rest), at rest on a stop, or penetrating a rigid stop (which both integrators must
//! refuse: counted apart as *refused*, never as an agreement).
//!
//! **The criterion.** Event-driven runs DOPRI5 at rtol 1e-8 (≤ 20,000 step attempts);
//! time-stepping (θ = 1, first order) at h = 1e-3, 2.5e-4, 6.25e-5, and at 4× smaller
//! steps down to 3.9e-6 while an observable is pre-asymptotic (an observed order outside
//! [½, 3⁄2]) or does not yet agree.
//! Three observables are compared, each in the norm in which Moreau's scheme converges
//! (uniformly in the positions; in L1 in time for velocities, which jump at impacts, and
//! for modes):
//! - positions: the largest difference at time-stepping's steps;
//! - velocities: `∫₀¹ |v_ts − v_ed| dt`, time-stepping's velocity constant on each step
//!   (θ = 1 advances the positions by it), largest over the coordinates;
//! - modes: `∫₀¹ |m_ts − m_ed| dt` summed over the elements, each element's mode read
//!   from the state alone — a dash-pot's slip direction (exactly `0` when stuck), a
//!   spring-backed stop pressed in — i.e. the time during which the runs disagree on a
//!   mode, so switch sequences and times are compared too; a rigid stop's switches are
//!   impacts, compared through the velocities.
//!
//! Time-stepping places a switch only at a step's end, up to one step `h` from its time:
//! each of event-driven's mode changes is allowed `h |Δm|` of the modes' distance, and
//! each velocity jump (impact) `h |Δv_c|` of the positions' and the velocities'.
//!
//! With `D` the distance between the last two time-stepping runs and `p` the order
//! observed over the last two refinements (clamped to [½, 1]: the scheme is first
//! order), Richardson's estimate of the finest run's own error is `D / (4^p − 1)`. A
//! scene agrees when, for every observable, event-driven is within `KAPPA = 2` such
//! estimates of the finest run, plus what its step cannot resolve (below), plus `FLOOR`
//! (100·rtol, what event-driven's own accuracy resolves). An event-driven solution off by
//! more than the finest run's error fails, however close both are in absolute terms.
//! Passivity: at every event-driven row, the energy (kinetic, potential, stored in
//! spring-backed stops) exceeds the initial energy plus the applied force's work (by
//! Gauss–Legendre on the dense output) by at most 100·rtol of the energy scale. Every
//! time-stepping run (θ = 1 at each h, and θ = ½ at the coarsest) is passive step by
//! step: no step ends with more energy than it began with plus the force's work over it,
//! `τ(t_n + θh) · (q_{n+1} − q_n)`, beyond 1e-12 of the energy scale, and no rigid stop
//! is passed.
//!
//! Time-stepping is refined (to at most h = 3.9e-6) until every observable is in its
//! asymptotic range and agrees; a disagreement in an observable still outside its
//! asymptotic range at the finest step is *unresolved* (counted apart: time-stepping's
//! limit is not known well enough to judge), one inside it a failure. A typed error of
//! event-driven is counted apart with its message (and fails `scenes/tests/agreement.rs`);
//! anything else that goes wrong is a failure.

use filippov::nalgebra::{Matrix3, SVector, Vector3};
use filippov::runtime::nonsmooth::{Element, ElementKind, Law, Selection, Side, StopKind};
use filippov::runtime::numeric::{Damper, JointKind, Link, Model, Scene, Spring};
use filippov::runtime::{
    ErrorKind, Method, NonSmoothMethod, NonSmoothProblem, Options, Solution, SwitchKind,
    solve_nonsmooth,
};

/// SplitMix64: a small seeded generator (also the report's, for the URDF states).
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Rng {
        Rng(seed)
    }
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
    fn below(&mut self, n: u64) -> usize {
        (self.next() % n) as usize
    }
}

/// The cubic Bingham law of theory S2/S3 (f_crit = 1): v = f² (f − 1) for f > 1.
fn cubic(f: f64) -> (f64, f64) {
    (f * f * (f - 1.0), 3.0 * f * f - 2.0 * f)
}

/// The non-monotone law of theory S4 (f_crit = 1): v = (1 + 0.1 (f² − 4)(f² − 9)) (f − 1)
/// for f > 1, which folds back between f ≈ 2 and 3.
fn non_monotone(f: f64) -> (f64, f64) {
    let g = 1.0 + 0.1 * (f * f - 4.0) * (f * f - 9.0);
    let dg = 0.1 * (2.0 * f * (f * f - 9.0) + 2.0 * f * (f * f - 4.0));
    (g * (f - 1.0), dg * (f - 1.0) + g)
}

/// How the initial state is chosen.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Start {
    Moving,
    Stuck,
    RestingOnStop,
    Penetrating,
}

/// The random description of a scene (everything but the element count and dof, which
/// pick the monomorphised scene type).
struct Description {
    model: Model,
    elements: Vec<Element>,
    q0: Vec<f64>,
    v0: Vec<f64>,
    force: (usize, f64, f64),
    start: Start,
}

fn describe(seed: u64) -> Description {
    let mut r = Rng::new(seed);
    let n = 1 + r.below(7);
    let planar = r.below(2) == 0;
    let gravity = if r.below(3) == 0 {
        Vector3::zeros()
    } else {
        Vector3::new(0.0, -9.81, 0.0)
    };
    let axes = [Vector3::x(), Vector3::y(), Vector3::z()];
    let mut links = Vec::new();
    let mut springs = Vec::new();
    let mut dampers = Vec::new();
    let mut moved = Vec::new();
    for i in 0..n {
        let (m, l) = (r.uniform(0.5, 2.0), r.uniform(0.3, 1.0));
        let axis = if planar {
            Vector3::z()
        } else {
            axes[r.below(3)]
        };
        let joint = if r.below(5) == 0 {
            JointKind::Prismatic { axis }
        } else {
            JointKind::Revolute { axis }
        };
        let i_rod = m * l * l / 12.0;
        // The inertia the joint moves (about the axis through the joint for a revolute
        // joint, the mass for a prismatic one; the link alone): stiffnesses are drawn
        // relative to it, so natural frequencies stay below ~30 rad/s, where time-stepping
        // at the compared steps is in its first-order regime (h ω ≤ 0.03) rather than in
        // its numerical damping (θ = 1 damps h ω ≳ 0.1 visibly within a second).
        let inertia_moved = match (&joint, axis == Vector3::x()) {
            (JointKind::Prismatic { .. }, _) => m,
            (_, true) => 0.06 * i_rod,
            _ => i_rod + m * l * l / 4.0,
        };
        moved.push(inertia_moved);
        links.push(Link {
            name: format!("b{i}"),
            parent: i.checked_sub(1),
            joint,
            coordinate: Some(i),
            origin_xyz: if i == 0 {
                Vector3::zeros()
            } else {
                Vector3::new(l, 0.0, 0.0)
            },
            origin_rpy: Vector3::zeros(),
            mass: m,
            com: Vector3::new(l / 2.0, 0.0, 0.0),
            // A rod of radius l/10 about its axis (x): m (l/10)²/2 = 0.06 i_rod.
            inertia: Matrix3::from_diagonal(&Vector3::new(0.06 * i_rod, i_rod, i_rod)),
        });
        if r.below(3) == 0 {
            springs.push(Spring {
                coordinate: i,
                stiffness: r.uniform(1.0, 50.0) * inertia_moved,
                rest: 0.0,
            });
        }
        if r.below(4) == 0 {
            dampers.push(Damper {
                coordinate: i,
                damping: r.uniform(0.01, 0.5) * inertia_moved,
            });
        }
    }
    let model = Model {
        gravity,
        links,
        springs,
        dampers,
        point_springs: Vec::new(),
    };
    let mut q0: Vec<f64> = (0..n).map(|_| r.uniform(-0.5, 0.5)).collect();
    let mut v0: Vec<f64> = (0..n).map(|_| r.uniform(-1.0, 1.0)).collect();
    let count = 1 + r.below(2);
    let mut elements: Vec<Element> = Vec::new();
    let names = ["e0", "e1"];
    let start = [
        Start::Moving,
        Start::Moving,
        Start::Stuck,
        Start::RestingOnStop,
        Start::Penetrating,
    ][r.below(5)];
    for k in 0..count {
        // Distinct coordinates (two elements on one coordinate are a separate matter).
        let c = (r.below(n as u64) + k) % n;
        if elements.iter().any(|e| e.coordinate == c) {
            continue;
        }
        let kind = match r.below(6) {
            0 => ElementKind::DashPot {
                law: Law::Coulomb,
                f_crit: r.uniform(0.1, 2.0),
            },
            1 => ElementKind::DashPot {
                law: Law::BinghamLinear {
                    eta: r.uniform(0.05, 1.0),
                },
                f_crit: r.uniform(0.1, 2.0),
            },
            2 => ElementKind::DashPot {
                law: Law::BinghamMonotone,
                f_crit: 1.0,
            },
            3 => ElementKind::DashPot {
                law: Law::BinghamNonMonotone {
                    selection: if r.below(2) == 0 {
                        Selection::NoVelocityJumps
                    } else {
                        Selection::MaximalDissipation
                    },
                },
                f_crit: 1.0,
            },
            4 => ElementKind::Stop {
                side: Side::Lower,
                position: q0[c] - r.uniform(0.05, 0.4),
                kind: StopKind::Rigid {
                    restitution: r.uniform(0.0, 0.9),
                },
            },
            _ => ElementKind::Stop {
                side: Side::Upper,
                position: q0[c] + r.uniform(0.05, 0.4),
                kind: StopKind::SpringBacked {
                    stiffness: r.uniform(1e2, 1e3) * moved[c],
                },
            },
        };
        elements.push(Element {
            name: names[k],
            coordinate: c,
            kind,
        });
    }
    // The initial state the start asks for, on the first element (moving when that
    // element has no such state).
    let e0 = elements[0];
    let c = e0.coordinate;
    let start = match (start, e0.kind) {
        (Start::Stuck, ElementKind::DashPot { .. })
        | (Start::RestingOnStop, ElementKind::Stop { .. })
        | (
            Start::Penetrating,
            ElementKind::Stop {
                kind: StopKind::Rigid { .. },
                ..
            },
        ) => start,
        _ => Start::Moving,
    };
    match (start, e0.kind) {
        (Start::Stuck, ElementKind::DashPot { .. }) => v0[c] = 0.0,
        (Start::RestingOnStop, ElementKind::Stop { position, .. }) => {
            q0[c] = position;
            v0[c] = 0.0;
        }
        (
            Start::Penetrating,
            ElementKind::Stop {
                position,
                side,
                kind: StopKind::Rigid { .. },
            },
        ) => {
            q0[c] = match side {
                Side::Lower => position - 0.05,
                Side::Upper => position + 0.05,
            };
        }
        _ => {}
    }
    let force = if r.below(2) == 0 {
        (r.below(n as u64), r.uniform(0.5, 5.0), r.uniform(1.0, 6.0))
    } else {
        (0, 0.0, 0.0)
    };
    Description {
        model,
        elements,
        q0,
        v0,
        force,
        start,
    }
}

/// Event-driven's tolerances (DOPRI5).
const ED_RTOL: f64 = 1e-8;
const ED_ATOL: f64 = 1e-10;
/// What event-driven's accuracy resolves: distances below `100·rtol` (on states of
/// order one) are not told apart from agreement.
pub const FLOOR: f64 = 100.0 * ED_RTOL;
/// Time-stepping's steps: `H_COARSE / 4^j`, `j = 0, 1, …`; at least `RUNS_MIN` runs, more
/// (up to `RUNS_MAX`, h = 3.9e-6) while an observable's observed order is outside
/// `ORDER_ASYMPTOTIC`.
const H_COARSE: f64 = 1e-3;
const RUNS_MIN: usize = 3;
const RUNS_MAX: usize = 5;
/// Outside these observed orders a run pair is taken as pre-asymptotic: the scheme is
/// first order, so a distance that falls by less than 2× or by more than 8× for a 4×
/// smaller step is not yet in the range where the Richardson estimate holds.
const ORDER_ASYMPTOTIC: (f64, f64) = (0.5, 1.5);
/// Safety factor on the Richardson estimate: a distance up to twice the estimated
/// error of the finest run is agreement.
pub const KAPPA: f64 = 2.0;
/// Passivity: the energy may exceed the initial energy plus the force's work by at most
/// this fraction of the energy scale (event-driven's error in the energy at rtol 1e-8 is
/// of order `rtol`; 100·rtol leaves room for its growth over the run).
const ENERGY_TOL: f64 = 100.0 * ED_RTOL;

/// How one observable of the finest time-stepping run compares with event-driven.
#[derive(Clone, Copy, Debug)]
pub struct Convergence {
    /// Distance between event-driven and the finest time-stepping run.
    pub distance: f64,
    /// The finest run's own error, estimated from the last refinement:
    /// `D / (4^p − 1)` with `D` the distance between the last two runs and `p` the
    /// observed order (at most 1, the scheme's order).
    pub estimate: f64,
    /// The order observed over the last two refinements.
    pub order: f64,
    /// What the finest run cannot resolve: time-stepping switches only at its steps, so
    /// it places each switch to within one step `h`: modes `h Σ |Δm|` over event-driven's
    /// mode changes; positions and velocities `h Σ |Δv_c|` over its velocity jumps
    /// (largest over the coordinates).
    pub resolution: f64,
}

impl Convergence {
    /// Agreement: the distance is within `KAPPA` estimates (plus event-driven's own
    /// accuracy, `FLOOR`).
    pub fn holds(&self) -> bool {
        self.distance <= self.allowed()
    }
    /// The largest distance that is agreement.
    pub fn allowed(&self) -> f64 {
        KAPPA * self.estimate + self.resolution + FLOOR
    }
    /// The distance beyond the switches' allowance and the floor, over the estimate (1
    /// when event-driven is exactly time-stepping's first-order limit; at most `KAPPA`
    /// when the observable agrees); `0` when within the allowance and the floor.
    pub fn ratio(&self) -> f64 {
        let beyond = self.distance - self.resolution - FLOOR;
        if beyond <= 0.0 {
            0.0
        } else {
            beyond / self.estimate
        }
    }
}

/// What an integrated scene measured.
#[derive(Clone, Debug)]
pub struct Measures {
    /// Positions, largest difference at time-stepping's steps.
    pub positions: Convergence,
    /// Velocities, L1 in time on [0, 1] (largest over the coordinates).
    pub velocities: Convergence,
    /// Modes, L1 in time of each element's mode indicator, summed over the elements:
    /// the time during which the two runs disagree on a mode.
    pub modes: Convergence,
    /// The finest time-stepping step.
    pub h_finest: f64,
    /// Event-driven switch-log entries, and how many of them hand accumulating events to
    /// time-stepping.
    pub switches: usize,
    pub handovers: usize,
    /// Largest energy gain beyond the force's work along event-driven's rows, relative to
    /// the energy scale (≤ ENERGY_TOL to pass; negative: dissipated).
    pub energy_excess: f64,
}

/// What one scene came to.
#[derive(Clone, Debug)]
pub enum Verdict {
    /// Both integrators integrated it and agree (see the module documentation).
    Agreed(Measures),
    /// A penetrating start, refused by both integrators as it must be (nothing was
    /// integrated; not an agreement).
    Refused,
    /// Time-stepping had not reached its asymptotic range at the finest step (3.9e-6) in
    /// an observable that did not agree (what was seen): the comparison cannot decide.
    /// Counted apart; not an agreement.
    Unresolved(String),
    /// Event-driven ended with a typed error (the message).
    TypedError(String),
    /// A check failed (what failed).
    Failed(String),
}

/// A function of time that is constant on each step: `(t_end, value)` pieces, each
/// valid on `(t_previous_end, t_end]`.
type Steps = Vec<(f64, f64)>;

/// `∫ |a − b| dt` of two step functions starting at t = 0 (where every run starts).
fn steps_l1(a: &[(f64, f64)], b: &[(f64, f64)]) -> f64 {
    let (mut i, mut j, mut t, mut sum) = (0, 0, 0.0, 0.0);
    while i < a.len() && j < b.len() {
        let end = a[i].0.min(b[j].0);
        sum += (end - t).max(0.0) * (a[i].1 - b[j].1).abs();
        t = end;
        if a[i].0 <= end {
            i += 1;
        }
        if b[j].0 <= end {
            j += 1;
        }
    }
    sum
}

/// An element's mode as a number, read from the state alone (the same rule for both
/// integrators, using neither's mode vocabulary): a dash-pot's slip direction (`0`
/// exactly when stuck, `±1` moving); a spring-backed stop `1` while pressed in.
///
/// A rigid stop reads `0` always: its switches are impacts, compared through the
/// velocities (an impact misplaced by `δt` costs `|Δv| δt` of their L1), and its resting
/// contact after rebounds with restitution `e > 0` is reached by time-stepping only as
/// the limit of ever smaller bounces, which no rule on time-stepping's state tells apart
/// from contact.
fn mode_value(el: &Element, q_c: f64, v_c: f64) -> f64 {
    match el.kind {
        ElementKind::DashPot { .. } => {
            if v_c == 0.0 {
                0.0
            } else {
                v_c.signum()
            }
        }
        ElementKind::Stop {
            kind: StopKind::Rigid { .. },
            ..
        } => 0.0,
        ElementKind::Stop { side, position, .. } => {
            let pen = match side {
                Side::Upper => q_c - position,
                Side::Lower => position - q_c,
            };
            f64::from(pen > 0.0)
        }
        // `ElementKind` is non-exhaustive; a kind this suite does not generate.
        _ => unreachable!("the suite generates dash-pots and stops only"),
    }
}

/// Time-stepping's modes, per element, as step functions: on each step the mode of the
/// state at its end (the mode the step solved for).
fn mode_steps(sol: &Solution, elements: &[Element], n: usize) -> Vec<Steps> {
    let times = sol.times();
    elements
        .iter()
        .map(|el| {
            (1..times.len())
                .map(|i| {
                    let y = sol.state(i);
                    (
                        times[i],
                        mode_value(el, y[el.coordinate], y[n + el.coordinate]),
                    )
                })
                .collect()
        })
        .collect()
}

/// Event-driven's modes, per element, as step functions: on each step the mode of the
/// dense output's state at its middle (the rows at an event's two sides are snapped onto
/// the switching point, so a step's end row may already read as the next mode).
fn dense_mode_steps(sol: &Solution, elements: &[Element], n: usize) -> Vec<Steps> {
    let times = sol.times();
    let mut y = vec![0.0; sol.dim()];
    let mut out: Vec<Steps> = vec![Vec::new(); elements.len()];
    for i in (1..times.len()).filter(|&i| times[i] > times[i - 1]) {
        sol.at_into(0.5 * (times[i - 1] + times[i]), &mut y);
        for (steps, el) in out.iter_mut().zip(elements) {
            steps.push((
                times[i],
                mode_value(el, y[el.coordinate], y[n + el.coordinate]),
            ));
        }
    }
    out
}

/// Time-stepping's velocities as step functions (each step's end velocity is the mean
/// velocity over the step: `q_{n+1} = q_n + h v_{n+1}` at θ = 1), per coordinate.
fn velocity_steps(sol: &Solution, n: usize) -> Vec<Steps> {
    let times = sol.times();
    (0..n)
        .map(|c| {
            (1..times.len())
                .map(|i| (times[i], sol.state(i)[n + c]))
                .collect()
        })
        .collect()
}

/// One time-stepping run, reduced to what the comparisons need.
struct Run {
    sol: Solution,
    velocities: Vec<Steps>,
    modes: Vec<Steps>,
}

/// Distances of one time-stepping run to event-driven: positions (largest at the
/// steps), velocities (L1, largest over coordinates; the integral split at event-driven's
/// events and taken by the midpoint rule on each piece), modes (L1, largest over
/// elements).
/// The switch log's rules (runtime `SwitchKind::Settled`), checked on every event-driven
/// run: at most one entry per element per instant; each entry's states are `[q; v]`; an
/// entry for a mode change keeps the state; an impact changes only velocities; every
/// instant with two rows (an event) is in the log.
fn switch_log_broken(ed: &Solution, n: usize) -> Option<String> {
    use filippov::runtime::SwitchKind;
    let log = &ed.switches;
    // Time-stepping's entries in a hand-over span span a step: their states differ.
    let mut handed_over = false;
    for (i, a) in log.iter().enumerate() {
        match a.kind {
            SwitchKind::HandOverToTimeStepping => handed_over = true,
            SwitchKind::HandBack => handed_over = false,
            _ => {}
        }
        if a.before.len() != 2 * n || a.after.len() != 2 * n {
            return Some(format!("entry {i} carries states of the wrong size"));
        }
        if a.index.is_some()
            && log[i + 1..]
                .iter()
                .any(|b| b.t == a.t && b.index == a.index)
        {
            return Some(format!("two entries for {:?} at t = {}", a.element, a.t));
        }
        match a.kind {
            _ if handed_over => {}
            SwitchKind::Mode if a.before[..n] != a.after[..n] => {
                return Some(format!("mode switch {i} moved the positions"));
            }
            SwitchKind::Impact | SwitchKind::Settled if a.before[..n] != a.after[..n] => {
                return Some(format!("impact {i} moved the positions"));
            }
            _ => {}
        }
    }
    if let Some(why) = chain_broken(log) {
        return Some(why);
    }
    let t = ed.times();
    (1..t.len())
        .find(|&i| t[i] == t[i - 1] && !log.iter().any(|s| s.t == t[i]))
        .map(|i| format!("the event at t = {} is not in the log", t[i]))
}

/// Each element's entries follow on from each other: an entry starts in the mode the
/// element's previous entry ended in.
fn chain_broken(log: &[filippov::runtime::Switch]) -> Option<String> {
    let mut last: std::collections::HashMap<usize, filippov::runtime::Mode> =
        std::collections::HashMap::new();
    for (i, s) in log.iter().enumerate() {
        let (Some(e), Some(from), Some(to)) = (s.index, s.from, s.to) else {
            continue;
        };
        if let Some(&prev) = last.get(&e)
            && prev != from
        {
            return Some(format!(
                "entry {i} ({:?} at t = {}) starts in {from:?}, but the element was left in {prev:?}",
                s.element, s.t
            ));
        }
        last.insert(e, to);
    }
    None
}

/// The rules of time-stepping's log (runtime `SwitchKind::Settled`): every entry at the
/// end of a step, with that step's start and end states; at most one entry per element
/// per step; each element's entries follow on from each other.
fn time_stepping_log_broken(ts: &Solution, n: usize) -> Option<String> {
    let log = &ts.switches;
    let times = ts.times();
    for (i, a) in log.iter().enumerate() {
        let Some(row) = times.iter().position(|&t| t == a.t) else {
            return Some(format!("entry {i} at t = {} is not at a step's end", a.t));
        };
        if row == 0 {
            return Some(format!("entry {i} is at the first row"));
        }
        if a.after[..] != ts.state(row)[..2 * n] || a.before[..] != ts.state(row - 1)[..2 * n] {
            return Some(format!(
                "entry {i} at t = {} does not carry its step's states",
                a.t
            ));
        }
        if a.index.is_some()
            && log[i + 1..]
                .iter()
                .any(|b| b.t == a.t && b.index == a.index)
        {
            return Some(format!("two entries for {:?} at t = {}", a.element, a.t));
        }
    }
    chain_broken(log)
}

fn to_event_driven(
    run: &Run,
    ed: &Solution,
    ed_modes: &[Steps],
    events: &[f64],
    n: usize,
) -> [f64; 3] {
    let times = run.sol.times();
    let mut y = vec![0.0; ed.dim()];
    let mut dq: f64 = 0.0;
    for i in 1..times.len() {
        ed.at_into(times[i], &mut y);
        let row = run.sol.state(i);
        for c in 0..n {
            dq = dq.max((row[c] - y[c]).abs());
        }
    }
    let mut dv = vec![0.0; n];
    let mut k = 0;
    for i in 1..times.len() {
        let (a, b) = (times[i - 1], times[i]);
        let row = run.sol.state(i);
        while k < events.len() && events[k] <= a {
            k += 1;
        }
        let mut start = a;
        let mut m = k;
        loop {
            let end = if m < events.len() && events[m] < b {
                events[m]
            } else {
                b
            };
            if end > start {
                ed.at_into(0.5 * (start + end), &mut y);
                for c in 0..n {
                    dv[c] += (end - start) * (row[n + c] - y[n + c]).abs();
                }
            }
            if end >= b {
                break;
            }
            start = end;
            m += 1;
        }
    }
    let dm = run
        .modes
        .iter()
        .zip(ed_modes)
        .map(|(a, b)| steps_l1(a, b))
        .sum();
    [dq, dv.into_iter().fold(0.0, f64::max), dm]
}

/// Distances between two consecutive time-stepping runs (the second at a 4× smaller
/// step): positions at the coarser run's steps, velocities and modes in L1.
fn between_runs(a: &Run, b: &Run, n: usize) -> [f64; 3] {
    let (ta, tb) = (a.sol.times(), b.sol.times());
    let mut dq: f64 = 0.0;
    for i in 0..ta.len() {
        let j = (4 * i).min(tb.len() - 1);
        debug_assert!((ta[i] - tb[j]).abs() <= 1e-9, "step grids are nested");
        let (ra, rb) = (a.sol.state(i), b.sol.state(j));
        for c in 0..n {
            dq = dq.max((ra[c] - rb[c]).abs());
        }
    }
    let dv = a
        .velocities
        .iter()
        .zip(&b.velocities)
        .map(|(x, y)| steps_l1(x, y))
        .fold(0.0, f64::max);
    let dm = a
        .modes
        .iter()
        .zip(&b.modes)
        .map(|(x, y)| steps_l1(x, y))
        .sum();
    [dq, dv, dm]
}

/// The observed order and the Richardson estimate of the finest run's error from the
/// last three runs' distances `d_prev` (runs j−2, j−1) and `d_last` (runs j−1, j).
///
/// The estimate is `d_last / (4^p − 1)` with `p` the observed order clamped to
/// `[ORDER_ASYMPTOTIC.0, 1]`: the scheme is first order, so a higher observed order (a
/// lucky pair) must not shrink the estimate below what first order gives (`d_last / 3`),
/// and a lower one enlarges it, at most to `d_last` (order ½).
fn order_and_estimate(d_prev: f64, d_last: f64) -> (f64, f64) {
    if d_last <= 0.0 {
        return (1.0, 0.0);
    }
    let order = if d_prev <= FLOOR {
        // Converged to event-driven's accuracy already: the order is not observable.
        1.0
    } else {
        (d_prev / d_last).log(4.0)
    };
    let p = order.clamp(ORDER_ASYMPTOTIC.0, 1.0);
    (order, d_last / (4f64.powf(p) - 1.0))
}

/// Energy of a scene's state: kinetic, potential (gravity, springs) and what
/// spring-backed stops store.
fn energy<S, const N: usize>(scene: &S, elements: &[Element], y: &[f64]) -> f64
where
    S: filippov::Energy<N>,
{
    let q = SVector::<f64, N>::from_column_slice(&y[..N]);
    let v = SVector::<f64, N>::from_column_slice(&y[N..2 * N]);
    let mut e = scene.kinetic_energy(&q, &v) + scene.potential_energy(&q);
    for el in elements {
        if let ElementKind::Stop {
            side,
            position,
            kind: StopKind::SpringBacked { stiffness },
        } = el.kind
        {
            let pen = match side {
                Side::Upper => q[el.coordinate] - position,
                Side::Lower => position - q[el.coordinate],
            };
            e += 0.5 * stiffness * pen.max(0.0).powi(2);
        }
    }
    e
}

/// Where a time-stepping run `sol` at `theta` gains energy in a step beyond the force's
/// work `τ(t_n + θh) · (q_{n+1} − q_n)` by more than 1e-12 of the energy scale, or passes
/// a rigid stop.
fn time_stepping_not_passive<S, const N: usize>(
    scene: &S,
    elements: &[Element],
    sol: &Solution,
    theta: f64,
    tau: &dyn Fn(f64) -> SVector<f64, N>,
) -> Option<String>
where
    S: filippov::Energy<N>,
{
    let t = sol.times();
    let mut scale = energy::<_, N>(scene, elements, sol.state(0)).abs().max(1.0);
    for i in 1..t.len() {
        let (a, b) = (sol.state(i - 1), sol.state(i));
        let f = tau(t[i - 1] + theta * (t[i] - t[i - 1]));
        let work: f64 = (0..N).map(|c| f[c] * (b[c] - a[c])).sum();
        let (ea, eb) = (
            energy::<_, N>(scene, elements, a),
            energy::<_, N>(scene, elements, b),
        );
        scale = scale.max(eb.abs());
        let gain = (eb - ea - work) / scale;
        if gain > 1e-12 {
            return Some(format!(
                "the step to t = {:.6} gains {gain:.2e} of the energy scale beyond the work",
                t[i]
            ));
        }
        for el in elements {
            if let ElementKind::Stop {
                side,
                position,
                kind: StopKind::Rigid { .. },
            } = el.kind
            {
                let q = b[el.coordinate];
                let passed = match side {
                    Side::Upper => q > position,
                    Side::Lower => q < position,
                };
                if passed {
                    return Some(format!(
                        "at t = {:.6} `{}` is passed: q = {q} beyond {position}",
                        t[i], el.name
                    ));
                }
            }
        }
    }
    None
}

fn check<const N: usize, const E: usize>(d: Description) -> Verdict {
    let elements: [Element; E] = std::array::from_fn(|k| d.elements[k]);
    let Some(mut scene) = Scene::<N, E>::new(d.model.clone(), elements) else {
        return Verdict::Failed("model and dof disagree".into());
    };
    for (k, el) in elements.iter().enumerate() {
        if let ElementKind::DashPot { law, .. } = el.kind {
            match law {
                Law::BinghamMonotone => scene.laws[k] = Some(cubic),
                Law::BinghamNonMonotone { .. } => scene.laws[k] = Some(non_monotone),
                _ => {}
            }
        }
    }
    let (fc, amp, w) = d.force;
    let input = move |t: f64, _q: &SVector<f64, N>, _v: &SVector<f64, N>| {
        let mut tau = SVector::<f64, N>::zeros();
        tau[fc] = amp * (w * t).sin();
        tau
    };
    let tf = 1.0;
    let p = NonSmoothProblem::new(
        0.0,
        tf,
        SVector::from_column_slice(&d.q0),
        SVector::from_column_slice(&d.v0),
    );
    let ed_method = NonSmoothMethod::EventDriven(Method::Dopri5(Options {
        max_steps: 20_000,
        ..Options::tolerances(ED_RTOL, ED_ATOL)
    }));
    let ts = |h: f64| NonSmoothMethod::TimeStepping { h, theta: 1.0 };
    let tau_of = move |t: f64| {
        let mut tau = SVector::<f64, N>::zeros();
        tau[fc] = amp * (w * t).sin();
        tau
    };
    let ed = solve_nonsmooth(&scene, &input, &p, &ed_method);
    if d.start == Start::Penetrating {
        // The description put the coordinate past its rigid stop (by 0.05); both
        // integrators must refuse to start there.
        let ts_run = solve_nonsmooth(&scene, &input, &p, &ts(H_COARSE));
        let refused = |r: &Result<Solution, filippov::runtime::SolveError>| matches!(r, Err(e) if matches!(e.kind, ErrorKind::InconsistentInitialData(_)));
        return if refused(&ed) && refused(&ts_run) {
            Verdict::Refused
        } else {
            Verdict::Failed("a penetrating initial state was not refused by both".into())
        };
    }
    let ed = match ed {
        Ok(sol) => sol,
        Err(e)
            if matches!(
                e.kind,
                ErrorKind::InvalidInput(_) | ErrorKind::InconsistentInitialData(_)
            ) =>
        {
            return Verdict::Failed(format!("refused valid input: {e}"));
        }
        Err(e) => return Verdict::TypedError(e.kind.to_string()),
    };
    if let Some(why) = switch_log_broken(&ed, N) {
        return Verdict::Failed(format!("switch log: {why}"));
    }
    let ed_times = ed.times();
    let events: Vec<f64> = (1..ed_times.len())
        .filter(|&i| ed_times[i] == ed_times[i - 1])
        .map(|i| ed_times[i])
        .collect();
    let ed_modes = dense_mode_steps(&ed, &elements, N);
    // Σ |Δv_c| over event-driven's velocity jumps (impacts), per coordinate, largest
    // over the coordinates: an impact placed by time-stepping at a step's end, up to one
    // step `h` from its time, moves the positions after it by up to `|Δv| h` and costs
    // `|Δv| h` of velocity L1.
    let jumps: f64 = (0..N)
        .map(|c| {
            (1..ed_times.len())
                .filter(|&i| ed_times[i] == ed_times[i - 1])
                .map(|i| (ed.state(i)[N + c] - ed.state(i - 1)[N + c]).abs())
                .sum::<f64>()
        })
        .fold(0.0, f64::max);
    // Σ |Δm| over event-driven's mode changes: a change from slipping forwards to
    // backwards (−1 → +1) misplaced by one step costs 2 steps of L1.
    let mode_changes: f64 = ed_modes
        .iter()
        .map(|s| s.windows(2).map(|w| (w[1].1 - w[0].1).abs()).sum::<f64>())
        .sum();
    // θ = ½ is held to passivity too (it is not part of the convergence study).
    let midpoint = NonSmoothMethod::TimeStepping {
        h: H_COARSE,
        theta: 0.5,
    };
    match solve_nonsmooth(&scene, &input, &p, &midpoint) {
        Ok(sol) => {
            if let Some(why) = time_stepping_not_passive(&scene, &elements, &sol, 0.5, &tau_of) {
                return Verdict::Failed(format!("time-stepping at θ = ½: {why}"));
            }
        }
        Err(e) => return Verdict::Failed(format!("time-stepping at θ = ½: {e}")),
    }
    // Time-stepping at 4× smaller steps until every observable is in its asymptotic range
    // and agrees (or RUNS_MAX runs): a disagreement must persist at the finest step.
    let mut to_ed: Vec<[f64; 3]> = Vec::new();
    let mut between: Vec<[f64; 3]> = Vec::new();
    let mut previous: Option<Run> = None;
    let mut h = H_COARSE;
    let (convergence, asymptotic) = loop {
        let sol = match solve_nonsmooth(&scene, &input, &p, &ts(h)) {
            Ok(sol) => sol,
            Err(e) => return Verdict::Failed(format!("time-stepping at h = {h:e}: {e}")),
        };
        if let Some(why) = time_stepping_log_broken(&sol, N) {
            return Verdict::Failed(format!("time-stepping's switch log at h = {h:e}: {why}"));
        }
        if let Some(why) = time_stepping_not_passive(&scene, &elements, &sol, 1.0, &tau_of) {
            return Verdict::Failed(format!("time-stepping at h = {h:e}: {why}"));
        }
        let run = Run {
            velocities: velocity_steps(&sol, N),
            modes: mode_steps(&sol, &elements, N),
            sol,
        };
        to_ed.push(to_event_driven(&run, &ed, &ed_modes, &events, N));
        if let Some(prev) = &previous {
            between.push(between_runs(prev, &run, N));
        }
        previous = Some(run);
        let runs = to_ed.len();
        if runs >= RUNS_MIN {
            let k = between.len();
            let conv = |o: usize| {
                let (order, estimate) = order_and_estimate(between[k - 2][o], between[k - 1][o]);
                Convergence {
                    distance: to_ed[runs - 1][o],
                    estimate,
                    order,
                    resolution: h * if o == 2 { mode_changes } else { jumps },
                }
            };
            let c = [conv(0), conv(1), conv(2)];
            // In its asymptotic range, or converged to event-driven's accuracy.
            let asymptotic: [bool; 3] = std::array::from_fn(|o| {
                between[k - 2][o] <= FLOOR
                    || between[k - 1][o] <= FLOOR
                    || (ORDER_ASYMPTOTIC.0..=ORDER_ASYMPTOTIC.1).contains(&c[o].order)
            });
            if c.iter().zip(&asymptotic).all(|(c, &a)| a && c.holds()) || runs == RUNS_MAX {
                break (c, asymptotic);
            }
        }
        h /= 4.0;
    };
    let h_finest = h;
    let [positions, velocities, modes] = convergence;
    for (name, c, o) in [
        ("positions", positions, 0),
        ("velocities (L1)", velocities, 1),
        ("modes (L1)", modes, 2),
    ] {
        if c.holds() {
            continue;
        }
        let history: Vec<String> = to_ed
            .iter()
            .zip(std::iter::successors(Some(H_COARSE), |h| Some(h / 4.0)))
            .map(|(d, h)| format!("{:.2e} at h = {h:.3e}", d[o]))
            .collect();
        if !asymptotic[o] {
            return Verdict::Unresolved(format!(
                "{name}: time-stepping is not in its asymptotic range at h = {h_finest:.3e} (observed order {:.2}), so its limit is not known well enough to judge event-driven, {:.2e} away; distance {}",
                c.order,
                c.distance,
                history.join(", ")
            ));
        }
        return Verdict::Failed(format!(
            "{name}: event-driven is {:.2e} from the finest time-stepping run, whose own error is estimated at {:.2e} (observed order {:.2}); allowed {KAPPA}× that + {:.2e} (one step per switch) + {FLOOR:.0e}; distance {}",
            c.distance,
            c.estimate,
            c.order,
            c.resolution,
            history.join(", ")
        ));
    }

    // Passivity along the event-driven run: at every row, E(t) − E(0) ≤ work of τ over
    // [0, t], the work by 3-point Gauss–Legendre on each step's dense output (exact to
    // the integration's accuracy; steps never straddle an event).
    let power = |t: f64, y: &[f64]| amp * (w * t).sin() * y[N + fc];
    let gauss = [
        (0.5 - 0.5 * (0.6f64).sqrt(), 5.0 / 18.0),
        (0.5, 8.0 / 18.0),
        (0.5 + 0.5 * (0.6f64).sqrt(), 5.0 / 18.0),
    ];
    let e0 = energy::<_, N>(&scene, &elements, ed.state(0));
    let mut work = 0.0;
    let mut y = vec![0.0; ed.dim()];
    let mut excess = f64::NEG_INFINITY;
    let mut worst = (0.0, 0.0, 0.0);
    for i in 1..ed_times.len() {
        let (a, b) = (ed_times[i - 1], ed_times[i]);
        if b > a {
            for (x, wgt) in gauss {
                let t = a + x * (b - a);
                ed.at_into(t, &mut y);
                work += wgt * (b - a) * power(t, &y);
            }
        }
        let e = energy::<_, N>(&scene, &elements, ed.state(i));
        let scale = e0.abs().max(e.abs()).max(work.abs()).max(1.0);
        let gain = (e - e0 - work) / scale;
        if gain > excess {
            excess = gain;
            worst = (b, e - e0, work);
        }
    }
    if excess > ENERGY_TOL {
        return Verdict::Failed(format!(
            "not passive: at t = {:.6} the energy gained {:.3e} exceeds the work {:.3e} by {excess:.2e} of the energy scale",
            worst.0, worst.1, worst.2
        ));
    }
    Verdict::Agreed(Measures {
        positions,
        velocities,
        modes,
        h_finest,
        switches: ed.switches.len(),
        handovers: ed
            .switches
            .iter()
            .filter(|s| s.kind == SwitchKind::HandOverToTimeStepping)
            .count(),
        energy_excess: excess,
    })
}

/// A one-line description of the scene of `seed`, for failure reports.
pub fn summary(seed: u64) -> String {
    let d = describe(seed);
    format!(
        "{} joints {:?}, elements {:?}, q0 {:?}, v0 {:?}, force {:?}, start {:?}",
        d.model.links.len(),
        d.model.links.iter().map(|l| l.joint).collect::<Vec<_>>(),
        d.elements
            .iter()
            .map(|e| (e.coordinate, e.kind))
            .collect::<Vec<_>>(),
        d.q0,
        d.v0,
        d.force,
        d.start
    )
}

/// Runs the scene of `seed`.
pub fn run(seed: u64) -> Verdict {
    let d = describe(seed);
    let n = d.model.links.len();
    macro_rules! dispatch {
        ($(($n:literal, $e:literal)),*) => {
            match (n, d.elements.len()) {
                $(($n, $e) => check::<$n, $e>(d),)*
                (n, e) => Verdict::Failed(format!("no monomorphisation for {n} joints, {e} elements")),
            }
        };
    }
    dispatch!(
        (1, 1),
        (2, 1),
        (2, 2),
        (3, 1),
        (3, 2),
        (4, 1),
        (4, 2),
        (5, 1),
        (5, 2),
        (6, 1),
        (6, 2),
        (7, 1),
        (7, 2)
    )
}

/// The verdicts of seeds `first..first + count`, in order, on all cores (each scene is
/// independent; seeds are taken in turn by the threads).
pub fn suite(first: u64, count: u64) -> Vec<(u64, Verdict)> {
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let next = std::sync::atomic::AtomicU64::new(first);
    let mut verdicts: Vec<(u64, Verdict)> = std::thread::scope(|s| {
        let workers: Vec<_> = (0..threads)
            .map(|_| {
                s.spawn(|| {
                    let mut mine = Vec::new();
                    loop {
                        let seed = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                        if seed >= first + count {
                            break mine;
                        }
                        mine.push((seed, run(seed)));
                    }
                })
            })
            .collect();
        workers
            .into_iter()
            .flat_map(|w| w.join().expect("a scene's thread panicked"))
            .collect()
    });
    verdicts.sort_by_key(|(seed, _)| *seed);
    verdicts
}

/// Counts of a suite's verdicts.
#[derive(Clone, Debug, Default)]
pub struct Tally {
    pub agreed: usize,
    pub refused: usize,
    /// Seed and what was seen, for each scene time-stepping did not resolve.
    pub unresolved: Vec<(u64, String)>,
    /// Seed and message of each typed error.
    pub typed: Vec<(u64, String)>,
    /// Seed and reason of each failure.
    pub failed: Vec<(u64, String)>,
}

impl Tally {
    pub fn of(verdicts: &[(u64, Verdict)]) -> Tally {
        let mut t = Tally::default();
        for (seed, v) in verdicts {
            match v {
                Verdict::Agreed(_) => t.agreed += 1,
                Verdict::Refused => t.refused += 1,
                Verdict::Unresolved(m) => t.unresolved.push((*seed, m.clone())),
                Verdict::TypedError(m) => t.typed.push((*seed, m.clone())),
                Verdict::Failed(m) => t.failed.push((*seed, m.clone())),
            }
        }
        t
    }
}
