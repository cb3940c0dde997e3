//! The two traits every kind of element implements ([`Kind`]: its modes; [`Forces`]: its
//! forces as functions of the state), and what their methods are handed.

use super::graph::{Branches, Fold, LawError, Line, Point, StepState};
use crate::element::{Mode, NonSmooth};

/// Where an element is at an instant: its coordinate's position, velocity and
/// acceleration, its force, and `W_cc` (the Delassus entry of its coordinate). A switching
/// function reads `qc`, `vc` and `f`; a margin all five.
#[derive(Clone, Copy, Debug)]
pub(crate) struct At {
    pub qc: f64,
    pub vc: f64,
    pub ac: f64,
    pub f: f64,
    pub wcc: f64,
}

impl At {
    /// The state `(q_c, v_c)` and force `f` without acceleration (a switching function).
    pub(crate) fn state(qc: f64, vc: f64, f: f64) -> At {
        At {
            qc,
            vc,
            ac: f64::NAN,
            f,
            wcc: f64::NAN,
        }
    }
}

/// What an element's forces need besides the state: the system (user laws), the element's
/// index, the branches of a non-monotone law (event-driven) and its folds (time-stepping).
pub(crate) struct Context<'a, S> {
    pub system: &'a S,
    pub index: usize,
    pub branches: &'a Branches,
    pub folds: &'a [Fold],
}

/// No branches: every law but the non-monotone one, and every time-stepping context.
pub(crate) static NO_BRANCHES: Branches = Branches {
    slip: Vec::new(),
    plateaus: Vec::new(),
};

/// The modes of one kind of element (sign conventions as in the `mode` module).
pub(crate) trait Kind {
    /// The parameters' check, as a message without the element's name (`Ok` when valid).
    fn check(&self) -> Result<(), String>;

    /// Every mode the element can take at a mode selection (`v_c = 0` for dash-pots,
    /// gap `0` for stops).
    fn candidates(&self) -> &'static [Mode];

    /// A mode without a constraint, to measure the force needed to hold the coordinate
    /// (the scale of a selection's margins).
    fn unconstrained(&self) -> Mode;

    /// A force scale of the element's law (a dash-pot's force held at rest; `0` for
    /// stops).
    fn force_scale(&self) -> f64 {
        0.0
    }

    /// The gap `s (position − q_c)` of a stop (`≥ 0` when admissible); `+∞` otherwise.
    fn gap(&self, _qc: f64) -> f64 {
        f64::INFINITY
    }

    /// The switching function of `mode`: positive while the mode holds, crossing zero
    /// where it ends.
    fn switching(&self, branches: &Branches, mode: Mode, at: &At) -> f64;

    /// How consistently `mode` holds at an event, in force units (`≥ 0` consistent; `±∞`
    /// where the state already moves into or out of the mode).
    fn margin(&self, branches: &Branches, mode: Mode, at: &At) -> f64;

    /// Whether the law prefers rest: where both a mode at rest and a slip are consistent,
    /// the one at rest is taken (static friction: *rest persists*).
    fn rest_persists(&self) -> bool {
        false
    }
}

/// The forces one kind of element carries as functions of the state.
pub(crate) trait Forces<S: NonSmooth<N>, const N: usize> {
    /// The force in `mode` where it is a function of the state (slipping, compressed,
    /// free); never asked for a constraint mode ([`Mode::is_constraint`]).
    fn force(&self, cx: &Context<S>, mode: Mode, at: &At) -> f64;

    /// The intersection of a step's line `v = v_free − w f` with the element's graph.
    fn on_line(&self, cx: &Context<S>, line: Line, state: &StepState) -> Found;

    /// The force of a finite slip velocity `v ≠ 0` where the law gives one (`previous`:
    /// the force before, for laws whose state is their branch); `None` for stops.
    fn force_of_velocity(&self, _cx: &Context<S>, _v: f64, _previous: f64) -> Slip {
        Ok(None)
    }

    /// The velocity of a force where the law is a function of the force (`0` in a
    /// dash-pot's dead zone); `None` for friction (not a function of the force) and stops.
    fn velocity_of_force(&self, _cx: &Context<S>, _f: f64) -> Option<f64> {
        None
    }
}

/// A point of a graph met by a line, or why there is none.
pub(crate) type Found = Result<Point, LawError>;

/// A slip force, if the law gives one, or why it could not be computed.
pub(crate) type Slip = Result<Option<f64>, LawError>;
