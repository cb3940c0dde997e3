//! What every dash-pot shares, whatever its slip law: the modes it selects among at rest,
//! the critical force's check, the switching functions and consistency margins of stick,
//! slip and plateau, and the stick segment of its graph in the implicit step; and the
//! whole behaviour of a friction law (a segment at rest and two constant slip levels),
//! given its two levels ([`Friction`]).

use super::graph::{Branches, Line, Part, Point, StepState};
use super::traits::{At, Context, Forces, Found, Kind, Slip};
use crate::element::{Mode, NonSmooth};

/// A dash-pot at rest may stick or start to slip either way.
const CANDIDATES: &[Mode] = &[Mode::Stick, Mode::SlipPos(0), Mode::SlipNeg(0)];

/// `f_crit` (the half-width of the dead zone, the largest force held at rest) must be
/// finite and `≥ 0`.
pub(crate) fn check_limit(name: &str, value: f64) -> Result<(), String> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(format!("{name} = {value} must be finite and ≥ 0"))
    }
}

/// `±1` of a slip or plateau mode.
fn direction(mode: Mode) -> f64 {
    match mode {
        Mode::SlipPos(_) | Mode::PlateauPos(_) => 1.0,
        _ => -1.0,
    }
}

/// The switching function of a dash-pot holding at most `limit` at rest: stick
/// `limit − |f|`; slip `±v_c`, and on a branch of a non-monotone law the distance of
/// `±v_c` to the nearer end of the branch's velocity range (a fold, or approach 2's
/// plateau speed); plateau: the distance of `±f` to the nearer end of its force interval.
pub(crate) fn switching(limit: f64, branches: &Branches, mode: Mode, vc: f64, f: f64) -> f64 {
    match mode {
        Mode::Stick => limit - f.abs(),
        Mode::SlipPos(k) | Mode::SlipNeg(k) => {
            let w = direction(mode) * vc;
            match branches.slip.get(k) {
                Some(b) => (w - b.v_lo).min(b.v_hi - w),
                None => w,
            }
        }
        Mode::PlateauPos(i) | Mode::PlateauNeg(i) => {
            let d = direction(mode);
            let p = branches.plateaus[i];
            (d * f - p.f_lo).min(p.f_hi - d * f)
        }
        // Modes that do not belong to a dash-pot never switch.
        _ => f64::INFINITY,
    }
}

/// `+∞` (`−∞`) when `v_c` already moves in (against) direction `d`, else the
/// acceleration in direction `d` in force units, `d a_c / W_cc`.
pub(crate) fn directed(d: f64, vc: f64, ac: f64, wcc: f64) -> f64 {
    if d * vc > 0.0 {
        f64::INFINITY
    } else if d * vc < 0.0 {
        f64::NEG_INFINITY
    } else {
        d * ac / wcc
    }
}

/// The consistency margin of a dash-pot's mode: stick `limit − |f|`; slip at `v_c = 0`
/// the acceleration in the slip direction divided by `W_cc`; slip on a non-monotone
/// branch at an end of its velocity range the acceleration into the range divided by
/// `W_cc`; plateau at its speed the distance of the constraint force to the ends of its
/// interval.
pub(crate) fn margin(limit: f64, branches: &Branches, mode: Mode, at: &At) -> f64 {
    let At { vc, ac, f, wcc, .. } = *at;
    match mode {
        Mode::Stick => limit - f.abs(),
        Mode::SlipPos(k) | Mode::SlipNeg(k) => {
            let d = direction(mode);
            match branches.slip.get(k) {
                None => directed(d, vc, ac, wcc),
                Some(b) => {
                    let w = d * vc;
                    if w > b.v_lo && w < b.v_hi {
                        f64::INFINITY
                    } else if w == b.v_lo {
                        d * ac / wcc
                    } else if w == b.v_hi {
                        -d * ac / wcc
                    } else {
                        f64::NEG_INFINITY
                    }
                }
            }
        }
        Mode::PlateauPos(i) | Mode::PlateauNeg(i) => {
            let d = direction(mode);
            match branches.plateaus.get(i) {
                Some(p) if d * vc == p.velocity => (d * f - p.f_lo).min(p.f_hi - d * f),
                _ => f64::NEG_INFINITY,
            }
        }
        _ => f64::NEG_INFINITY,
    }
}

/// The implicit step's stick: the line meets the graph's segment `v = 0`,
/// `|f| ≤ limit`, iff `|v_free| ≤ w · limit`; the force is then `v_free / w`, the
/// velocity exactly `0`.
pub(crate) fn stick_on_line(line: Line, limit: f64) -> Option<Point> {
    (line.v_free.abs() <= line.w * limit).then(|| Point {
        v: 0.0,
        f: line.v_free / line.w,
        part: Part::Stick,
        dq: None,
    })
}

/// The point of the line at force `f`, slipping.
pub(crate) fn slip_on_line(line: Line, f: f64) -> Point {
    Point {
        v: line.v_free - line.w * f,
        f,
        part: Part::Slip,
        dq: None,
    }
}

/// A dash-pot, whatever its slip law: a dead zone `|f| ≤ limit` where it sticks. Its modes,
/// switching functions and margins follow ([`Kind`]).
pub(crate) trait DashPot {
    /// The parameters' check.
    fn check(&self) -> Result<(), String>;
    /// The largest force held at rest (`f_crit`, or the static friction force).
    fn limit(&self) -> f64;
    /// Whether rest persists where both rest and slip are consistent.
    fn rest_persists(&self) -> bool {
        false
    }
}

impl<D: DashPot> Kind for D {
    fn check(&self) -> Result<(), String> {
        DashPot::check(self)
    }

    fn candidates(&self) -> &'static [Mode] {
        CANDIDATES
    }

    fn unconstrained(&self) -> Mode {
        Mode::SlipPos(0)
    }

    fn force_scale(&self) -> f64 {
        self.limit()
    }

    fn switching(&self, branches: &Branches, mode: Mode, at: &At) -> f64 {
        switching(self.limit(), branches, mode, at.vc, at.f)
    }

    fn margin(&self, branches: &Branches, mode: Mode, at: &At) -> f64 {
        margin(self.limit(), branches, mode, at)
    }

    fn rest_persists(&self) -> bool {
        DashPot::rest_persists(self)
    }
}

/// A friction law: at rest it holds any force up to [`held`](Friction::held), slipping
/// it resists with the constant [`sliding`](Friction::sliding) `≤ held`. Everything a
/// [`Kind`] does follows from the two levels.
pub(crate) trait Friction {
    /// The parameters' check.
    fn check(&self) -> Result<(), String>;
    /// `(held, sliding)`: the largest force held at rest (the stick segment's
    /// half-length) and the force while slipping.
    fn levels(&self) -> (f64, f64);
    /// The largest force held at rest.
    fn held(&self) -> f64 {
        self.levels().0
    }
    /// The force while slipping.
    fn sliding(&self) -> f64 {
        self.levels().1
    }
    /// Whether rest persists where both rest and slip are consistent.
    fn rest_persists(&self) -> bool {
        false
    }
}

impl<F: Friction> DashPot for F {
    fn check(&self) -> Result<(), String> {
        Friction::check(self)
    }

    fn limit(&self) -> f64 {
        self.held()
    }

    fn rest_persists(&self) -> bool {
        Friction::rest_persists(self)
    }
}

impl<F: Friction, S: NonSmooth<N>, const N: usize> Forces<S, N> for F {
    /// Slipping in direction `d`: `d · sliding` (the mode's direction, not `sgn v_c`, so
    /// the force stays smooth while a root finder looks just past `v_c = 0`).
    fn force(&self, _cx: &Context<S>, mode: Mode, _at: &At) -> f64 {
        mode.slip().map_or(0.0, |(d, _)| d * self.sliding())
    }

    /// Within one step the graph is Coulomb's at the level the step starts in: at rest
    /// (`v_c = 0`), held up to `held` and slipping at `held` for the step it breaks away
    /// in (rest persists); moving, at `sliding`. Each step's graph is then monotone, so
    /// coupled elements' forces converge (with the graph's jump from `held` down to
    /// `sliding` inside one step they can cycle for ever), and the breakaway step's
    /// force is off by `held − sliding` for one step: first order, as the scheme.
    fn on_line(&self, _cx: &Context<S>, line: Line, state: &StepState) -> Found {
        let level = if state.v == 0.0 {
            self.held()
        } else {
            self.sliding()
        };
        Ok(stick_on_line(line, level)
            .unwrap_or_else(|| slip_on_line(line, line.v_free.signum() * level)))
    }

    fn force_of_velocity(&self, _cx: &Context<S>, v: f64, _previous: f64) -> Slip {
        Ok(Some(v.signum() * self.sliding()))
    }
}
