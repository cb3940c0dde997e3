//! What an element's graph and a step's line are made of (theory.md §3): the line
//! `v = v_free − w f` of one element's discrete momentum balance, what the step knows at
//! its start, the point where line and graph meet and which part of the graph it lies on,
//! the folds and branches of a non-monotone law, and the scalar root finders the kinds
//! use. Re-exported by `law`, which builds an element's graph.

use std::fmt;

/// Iteration cap of every scalar root finder (bisection halves the bracket each time).
pub(crate) const MAX_ITER: usize = 200;

/// The discrete momentum balance of one element: `v = v_free − w f`, `w > 0`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Line {
    pub v_free: f64,
    pub w: f64,
}

/// What one step knows about the element's coordinate at its start `t_n`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepState {
    /// Coordinate value `q_c(t_n)` (stops: the gap).
    pub q: f64,
    /// Coordinate velocity `v_c(t_n)` (rigid stops: the pre-impact velocity).
    pub v: f64,
    /// Step size.
    pub h: f64,
    /// The weight of `v_{n+1}` in the coordinate's position update
    /// `q_{n+1} = q_n + h ((1 − θ_q) v_n + θ_q v_{n+1})` (see
    /// [`crate::nonsmooth::time_stepping`] and [`position_weight`](crate::nonsmooth::law::position_weight)). A spring-backed stop
    /// takes its force at the step's end when θ_q = 1 (implicit Euler); when θ_q < 1 its
    /// force is the discrete gradient of its energy between `q_n` and `q_{n+1}`, exact in
    /// energy at θ_q = ½ (pressed in over the whole step, it is the force at the
    /// midpoint).
    pub theta_q: f64,
    /// The element's force at `t_n` (approach 1: the current branch).
    pub force: f64,
    /// The coordinate's velocity at the step's end under the smooth forces alone (no
    /// element force): fixed while coupled elements' forces are solved, so a rigid stop
    /// decides from it whether the step reaches it, and its graph stays monotone.
    pub v_smooth: f64,
}

/// Which part of the graph a point lies on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Part {
    /// Dash-pot in its dead zone: `v = 0` exactly, `|f| ≤ f_crit`.
    Stick,
    /// Dash-pot slipping on its slip law.
    Slip,
    /// Non-monotone law, approach 2: constant speed `|v| = v_min` on a filled jump.
    Plateau,
    /// Stop without contact force.
    Open,
    /// Stop carrying a contact force.
    Contact,
}

/// A point `(v, f)` on an element's graph.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Point {
    pub v: f64,
    pub f: f64,
    pub part: Part,
    /// The coordinate's displacement over the step where it is not `h v` (a rigid stop
    /// reached inside the step: it travels to the stop, then back at `v`).
    pub dq: Option<f64>,
}

/// A local extremum of a non-monotone slip law on `f > f_crit`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fold {
    pub force: f64,
    pub velocity: f64,
    /// `true` at a local minimum of `φ`, `false` at a local maximum.
    pub minimum: bool,
}

/// An increasing piece of a non-monotone slip law on the positive side (`f > f_crit`;
/// the law is odd), as the event-driven integrator slips on it: while slipping with
/// `|v| ∈ [v_lo, v_hi]` the force `|f| ∈ [f_lo, f_hi]` is the inverse of `φ` there.
/// `f_hi = v_hi = ∞` for the last piece.
///
/// Approach 2 may cut a piece below its fold, at a plateau's speed; `f_top`, `v_top`
/// keep where the piece itself ends (its fold, or `∞`), equal to `f_hi`, `v_hi` where
/// nothing is cut. Past a cut end the slip force continues on the piece, so the
/// right-hand side stays smooth across the switching point and a step that straddles it
/// keeps its order.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Branch {
    pub f_lo: f64,
    pub f_hi: f64,
    pub v_lo: f64,
    pub v_hi: f64,
    pub f_top: f64,
    pub v_top: f64,
}

/// Approach 2's constant-speed mode between two branches: `|v| = velocity` exactly, the
/// force anywhere in `[f_lo, f_hi]` (the two branch forces at that speed).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlateauLevel {
    pub velocity: f64,
    pub f_lo: f64,
    pub f_hi: f64,
}

/// The branches a selection rule slips on, by increasing force, and (approach 2) the
/// plateaus between consecutive ones: `plateaus[i]` joins `slip[i]` (its top) and
/// `slip[i + 1]` (its bottom). Empty for every law but the non-monotone one.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Branches {
    pub slip: Vec<Branch>,
    pub plateaus: Vec<PlateauLevel>,
}

/// Why a graph could not be built or evaluated.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum LawError {
    /// The element's parameters are invalid (message names the element).
    InvalidElement(String),
    /// The law or the line produced a NaN or an infinity.
    NonFinite,
    /// A root finder hit its iteration cap (the law is not of the documented kind).
    NoConvergence,
}

impl fmt::Display for LawError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LawError::InvalidElement(msg) => write!(f, "{msg}"),
            LawError::NonFinite => write!(f, "non-finite value in a constitutive law"),
            LawError::NoConvergence => write!(f, "constitutive-law root finder did not converge"),
        }
    }
}

/// Bisection of a continuous `g` with a sign change on `[a, b]` (either order), to
/// round-off.
pub(crate) fn bisect(g: impl Fn(f64) -> f64, a: f64, b: f64) -> Result<f64, LawError> {
    let (mut lo, mut hi) = (a, b);
    let glo = g(lo);
    if glo == 0.0 {
        return Ok(lo);
    }
    for _ in 0..MAX_ITER {
        let mid = 0.5 * (lo + hi);
        if mid == lo || mid == hi {
            return Ok(mid);
        }
        let gm = g(mid);
        if !gm.is_finite() {
            return Err(LawError::NonFinite);
        }
        if gm == 0.0 {
            return Ok(mid);
        }
        if (gm > 0.0) == (glo > 0.0) {
            lo = mid
        } else {
            hi = mid
        }
    }
    Ok(0.5 * (lo + hi))
}

/// Smallest `f_crit · 2^k`-type point where an eventually increasing `g` is ≥ 0.
pub(crate) fn upper_bound(g: impl Fn(f64) -> f64, f_crit: f64) -> Result<f64, LawError> {
    let mut x = 2.0 * f_crit + 1.0;
    for _ in 0..MAX_ITER {
        let gx = g(x);
        if !gx.is_finite() {
            return Err(LawError::NonFinite);
        }
        if gx >= 0.0 {
            return Ok(x);
        }
        x *= 2.0;
    }
    Err(LawError::NoConvergence)
}
