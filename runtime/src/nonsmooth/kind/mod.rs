//! Each kind of non-smooth element in one file, behind the traits that both integrators
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
//! two levels (held at rest, sliding) and gets the rest from them.
//!
//! An element's kind answers two traits: [`Kind`], its modes (candidates at a selection,
//! switching functions, consistency margins), and [`Forces`], the forces it carries as
//! functions of the state (a mode's smooth force for the event driver, its graph met by a
//! step's line for the time-stepper). The event driver (`mode.rs`) and the time-stepper
//! (`law.rs`, `timestepping.rs`) reach an element's kind through [`with_kind!`].
//!
//! Adding a law: a variant of [`Law`](crate::element::Law) on the ground floor, one file
//! here implementing [`Kind`] and [`Forces`] (or [`Friction`](dashpot::Friction)), and one
//! arm in [`with_kind!`].

pub(crate) mod bingham;
pub(crate) mod coulomb;
pub(crate) mod dashpot;
pub(crate) mod graph;
pub(crate) mod static_kinetic;
pub(crate) mod stop;
mod traits;

pub(crate) use traits::{At, Context, Forces, Kind, NO_BRANCHES};

/// `$body` with `$k` bound to the kind of `$element` (an [`Element`](crate::element::Element)),
/// with its parameters: the one place an element description becomes its kind.
macro_rules! with_kind {
    ($element:expr, |$k:ident| $body:expr) => {{
        use $crate::element::{ElementKind, Law};
        use $crate::nonsmooth::kind::{bingham, coulomb, static_kinetic, stop};
        match $element.kind {
            ElementKind::DashPot {
                law: Law::Coulomb,
                f_crit,
            } => {
                let $k = coulomb::Coulomb { f_crit };
                $body
            }
            ElementKind::DashPot {
                law: Law::StaticKinetic { f_kinetic },
                f_crit,
            } => {
                let $k = static_kinetic::StaticKinetic {
                    f_static: f_crit,
                    f_kinetic,
                };
                $body
            }
            ElementKind::DashPot { law, f_crit } => {
                let $k = bingham::Bingham { law, f_crit };
                $body
            }
            ElementKind::Stop {
                side,
                position,
                kind,
            } => {
                let $k = stop::Stop {
                    side,
                    position,
                    kind,
                };
                $body
            }
        }
    }};
}
pub(crate) use with_kind;
