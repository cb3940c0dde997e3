//! Each kind of non-smooth element in one file, behind one trait that both integrators
//! use.
//!
//! | element | file | modes |
//! |---|---|---|
//! | Coulomb friction | [`coulomb`] | stick, slip |
//! | static/kinetic friction | [`static_kinetic`] | stick, slip (force drops at breakaway) |
//! | Bingham dash-pots (linear, monotone and non-monotone user laws) | [`bingham`] | stick, slip on a branch, plateau |
//! | stops, rigid and spring-backed | [`stop`] | free, contact, compressed |
//!
//! What is common to every dash-pot (its stick and slip switching functions and
//! consistency margins, its stick segment in the implicit step) sits in [`dashpot`], below
//! the law files, with the [`Friction`](dashpot::Friction) trait: a friction law gives its
//! two levels (held at rest, sliding) and gets the whole of [`Kind`] from them.
//!
//! The event driver (`mode.rs`: the smooth dynamics of a mode, the switching functions,
//! the consistency margins of a mode selection) and the time-stepper (`law.rs`: the
//! intersection of a step's line with the element's graph) ask an element's [`Kind`]
//! through [`of`]. Adding a law: a variant of [`Law`](crate::element::Law) on the ground
//! floor, one file here implementing [`Kind`] (or [`Friction`](dashpot::Friction)), one
//! arm in [`of`] and in `each!`.

use super::law::{Branches, Graph, LawError, Line, Point, StepState};
use crate::element::{Element, ElementKind, Law, Mode, NonSmooth, StopKind};

pub(crate) mod bingham;
pub(crate) mod coulomb;
pub(crate) mod dashpot;
pub(crate) mod static_kinetic;
pub(crate) mod stop;

/// What a kind's smooth force needs besides the state: the system (user laws), the
/// element's index and its branches (non-monotone laws).
pub(crate) struct Context<'a, S> {
    pub system: &'a S,
    pub index: usize,
    pub branches: &'a Branches,
}

/// The behaviour of one kind of element: its parameters' checks, its modes, the force
/// it carries where that force is a function of the state, the switching function and
/// consistency margin of each mode (event-driven), and its graph met by a line (implicit
/// time-stepping). Sign conventions as in [`crate::nonsmooth`]'s `mode` module.
pub(crate) trait Kind {
    /// The parameters' check, as a message without the element's name (`Ok` when valid).
    fn check(&self) -> Result<(), String>;

    /// Every mode the element can take at a mode selection (`v_c = 0` for dash-pots,
    /// gap `0` for stops).
    fn candidates(&self) -> &'static [Mode];

    /// A mode without a constraint, used to measure the force needed to hold the
    /// coordinate (the scale of the selection's margins).
    fn unconstrained(&self) -> Mode;

    /// A force scale of the element's law (a dash-pot's critical force; `0` for stops).
    fn force_scale(&self) -> f64 {
        0.0
    }

    /// The gap `s (position − q_c)` of a stop (`≥ 0` when admissible); `+∞` otherwise.
    fn gap(&self, _qc: f64) -> f64 {
        f64::INFINITY
    }

    /// The element's force in `mode` where it is a function of the state (slipping,
    /// compressed, free); never asked for a constraint mode ([`Mode::is_constraint`]).
    fn force<S: NonSmooth<N>, const N: usize>(
        &self,
        cx: &Context<S>,
        mode: Mode,
        qc: f64,
        vc: f64,
    ) -> f64;

    /// The switching function of `mode`: positive while the mode holds, crossing zero
    /// where it ends (`f`: the element's force).
    fn switching(&self, branches: &Branches, mode: Mode, qc: f64, vc: f64, f: f64) -> f64;

    /// How consistently `mode` holds at an event, in force units (`≥ 0` consistent;
    /// `±∞` where the state already moves into or out of the mode).
    #[allow(clippy::too_many_arguments)]
    fn margin(
        &self,
        branches: &Branches,
        mode: Mode,
        qc: f64,
        vc: f64,
        ac: f64,
        f: f64,
        wcc: f64,
    ) -> f64;

    /// Whether the law prefers rest: where both a constraint mode at rest and a slip are
    /// consistent, the one at rest is taken (static friction: *rest persists*).
    fn rest_persists(&self) -> bool {
        false
    }

    /// The intersection of a step's line `v = v_free − w f` with the element's graph.
    fn on_line<S: NonSmooth<N>, const N: usize>(
        &self,
        graph: &Graph,
        system: &S,
        line: Line,
        state: &StepState,
    ) -> Result<Point, LawError>;

    /// The force of a slip velocity `v ≠ 0` where the law gives one (`previous`: the force
    /// before, for laws whose state is their branch); `None` for stops.
    fn force_of_velocity<S: NonSmooth<N>, const N: usize>(
        &self,
        graph: &Graph,
        system: &S,
        v: f64,
        previous: f64,
    ) -> Result<Option<f64>, LawError>;

    /// The velocity of a force where the law is a function of the force (`0` in a
    /// dash-pot's dead zone); `None` for laws that are not (Coulomb's) and for stops.
    fn velocity_of_force<S: NonSmooth<N>, const N: usize>(
        &self,
        system: &S,
        index: usize,
        f: f64,
    ) -> Option<f64>;
}

/// An element's kind, with its parameters.
#[derive(Clone, Copy, Debug)]
pub(crate) enum AnyKind {
    Coulomb(coulomb::Coulomb),
    StaticKinetic(static_kinetic::StaticKinetic),
    Bingham(bingham::Bingham),
    Stop(stop::Stop),
}

/// The kind of `element`.
pub(crate) fn of(element: &Element) -> AnyKind {
    match element.kind {
        ElementKind::DashPot {
            law: Law::Coulomb,
            f_crit,
        } => AnyKind::Coulomb(coulomb::Coulomb { f_crit }),
        ElementKind::DashPot {
            law: Law::StaticKinetic { f_kinetic },
            f_crit,
        } => AnyKind::StaticKinetic(static_kinetic::StaticKinetic {
            f_static: f_crit,
            f_kinetic,
        }),
        ElementKind::DashPot { law, f_crit } => AnyKind::Bingham(bingham::Bingham { law, f_crit }),
        ElementKind::Stop {
            side,
            position,
            kind,
        } => AnyKind::Stop(stop::Stop {
            side,
            position,
            kind,
        }),
    }
}

/// Calls the same method on whichever kind `$any` holds.
macro_rules! each {
    ($any:expr, $k:ident => $body:expr) => {
        match $any {
            AnyKind::Coulomb($k) => $body,
            AnyKind::StaticKinetic($k) => $body,
            AnyKind::Bingham($k) => $body,
            AnyKind::Stop($k) => $body,
        }
    };
}

impl Kind for AnyKind {
    fn check(&self) -> Result<(), String> {
        each!(self, k => k.check())
    }
    fn candidates(&self) -> &'static [Mode] {
        each!(self, k => k.candidates())
    }
    fn unconstrained(&self) -> Mode {
        each!(self, k => k.unconstrained())
    }
    fn force_scale(&self) -> f64 {
        each!(self, k => k.force_scale())
    }
    fn gap(&self, qc: f64) -> f64 {
        each!(self, k => k.gap(qc))
    }
    fn force<S: NonSmooth<N>, const N: usize>(
        &self,
        cx: &Context<S>,
        mode: Mode,
        qc: f64,
        vc: f64,
    ) -> f64 {
        each!(self, k => k.force(cx, mode, qc, vc))
    }
    fn switching(&self, branches: &Branches, mode: Mode, qc: f64, vc: f64, f: f64) -> f64 {
        each!(self, k => k.switching(branches, mode, qc, vc, f))
    }
    fn margin(
        &self,
        branches: &Branches,
        mode: Mode,
        qc: f64,
        vc: f64,
        ac: f64,
        f: f64,
        wcc: f64,
    ) -> f64 {
        each!(self, k => k.margin(branches, mode, qc, vc, ac, f, wcc))
    }
    fn rest_persists(&self) -> bool {
        each!(self, k => k.rest_persists())
    }
    fn on_line<S: NonSmooth<N>, const N: usize>(
        &self,
        graph: &Graph,
        system: &S,
        line: Line,
        state: &StepState,
    ) -> Result<Point, LawError> {
        each!(self, k => k.on_line(graph, system, line, state))
    }
    fn force_of_velocity<S: NonSmooth<N>, const N: usize>(
        &self,
        graph: &Graph,
        system: &S,
        v: f64,
        previous: f64,
    ) -> Result<Option<f64>, LawError> {
        each!(self, k => k.force_of_velocity(graph, system, v, previous))
    }
    fn velocity_of_force<S: NonSmooth<N>, const N: usize>(
        &self,
        system: &S,
        index: usize,
        f: f64,
    ) -> Option<f64> {
        each!(self, k => k.velocity_of_force(system, index, f))
    }
}

/// Whether `element` is a rigid stop.
pub(crate) fn is_rigid_stop(element: &Element) -> bool {
    matches!(
        element.kind,
        ElementKind::Stop {
            kind: StopKind::Rigid { .. },
            ..
        }
    )
}
