//! Bearing friction (`#[friction(joint, mu = …, radius = …)]`): Coulomb friction whose
//! limit is `f_crit + μ r |F_⊥|`, where `F_⊥` is the reaction force the joint transmits
//! (theory.md §8). The load depends on the acceleration, and the acceleration on the
//! friction: each time step solves for both, a fixed point on the limits around the
//! step's friction problem ([`Bearings::update`] after each solve, until the limits stop
//! changing). The time-steppers (`time_stepping`, `contact_time_stepping`) take bearings;
//! the event-driven integrators refuse them by name ([`refuse`]).

use nalgebra::SVector;

use crate::element::{Element, ElementKind, NonSmooth};

/// Relative change of every limit below which a step's limits have settled.
pub(crate) const BEARING_TOL: f64 = 1e-12;

/// The most solves of one step's friction problem with updated limits.
pub(crate) const BEARING_ITERATIONS: usize = 100;

/// The bearings of a scene: which elements they are, the constant part of each limit,
/// and the last load-dependent part.
#[derive(Clone, Debug)]
pub(crate) struct Bearings {
    /// Element indices.
    pub elements: Vec<usize>,
    /// `f_crit` of each.
    base: Vec<f64>,
    /// `μ r |F_⊥|` of each, from the last update.
    load: Vec<f64>,
    scratch: Vec<f64>,
}

impl Bearings {
    /// The bearings among `elements` (indices `which`), with no load yet.
    pub(crate) fn new(which: &[usize], elements: &[Element]) -> Bearings {
        let base = which
            .iter()
            .map(|&i| match elements[i].kind {
                ElementKind::DashPot { f_crit, .. } => f_crit,
                ElementKind::Stop { .. } => 0.0,
            })
            .collect();
        Bearings {
            elements: which.to_vec(),
            base,
            load: vec![0.0; which.len()],
            scratch: vec![0.0; which.len()],
        }
    }

    pub(crate) fn is_empty(&self) -> bool {
        self.elements.is_empty()
    }

    /// Bearing `b`'s whole limit.
    pub(crate) fn limit(&self, b: usize) -> f64 {
        self.base[b] + self.load[b]
    }

    /// New loads from `loads` (which writes `μ r |F_⊥|` of each bearing); the largest
    /// relative change of a limit, or `Err(element)` of a bearing whose load is not
    /// finite.
    pub(crate) fn update(&mut self, loads: impl FnOnce(&mut [f64])) -> Result<f64, usize> {
        loads(&mut self.scratch);
        let floor = f64::MIN_POSITIVE
            + 1e-12
                * (0..self.load.len())
                    .map(|b| self.limit(b))
                    .fold(0.0, f64::max);
        let mut change: f64 = 0.0;
        for b in 0..self.load.len() {
            let new = self.scratch[b];
            if !(new.is_finite() && new >= 0.0) {
                return Err(self.elements[b]);
            }
            let d = (new - self.load[b]).abs();
            change = change.max(d / (self.base[b] + new.max(self.load[b]) + floor));
            self.load[b] = new;
        }
        Ok(change)
    }

    /// `(element, limit)` of each bearing.
    pub(crate) fn limits(&self) -> impl Iterator<Item = (usize, f64)> + '_ {
        (self.elements.iter().enumerate()).map(|(b, &e)| (e, self.limit(b)))
    }
}

/// Sets a Coulomb element's limit `f_crit`.
pub(crate) fn set_limit(element: &mut Element, limit: f64) {
    if let ElementKind::DashPot { f_crit, .. } = &mut element.kind {
        *f_crit = limit;
    }
}

/// A step's motion from `v` to `v_new` over `h`, as the bearings' loads are taken at:
/// the velocity `v + θ (v_new − v)` and the acceleration `(v_new − v)/h`.
pub(crate) fn motion<const N: usize>(
    v: &SVector<f64, N>,
    v_new: &SVector<f64, N>,
    h: f64,
    theta: f64,
) -> (SVector<f64, N>, SVector<f64, N>) {
    let dv = v_new - v;
    (v + theta * dv, dv / h)
}

/// The event-driven integrators' refusal of bearing friction, naming the elements.
pub(crate) fn refuse<S: NonSmooth<N>, const N: usize>(system: &S) -> Result<(), String> {
    if S::BEARINGS.is_empty() {
        return Ok(());
    }
    let names: Vec<String> = S::BEARINGS
        .iter()
        .map(|&e| format!("`{}`", system.element(e).name))
        .collect();
    Err(format!(
        "bearing friction ({}) takes its limit from its joint's load, which depends on the \
         acceleration; the event-driven integrator does not take it yet: integrate the scene \
         with `time_stepping` (or `contact_time_stepping` with contacts)",
        names.join(", ")
    ))
}

/// The message of a step whose limits did not settle after `tries` updates.
pub(crate) fn unsettled(names: &[&str], tries: usize) -> String {
    let names: Vec<String> = names.iter().map(|n| format!("`{n}`")).collect();
    format!(
        "the limits of bearing friction ({}) did not settle on their joints' loads after \
         {tries} updates: the friction coefficient may be too large for the \
         step to have one solution (a Painlevé-like case); a smaller step h or a smaller μ \
         may help",
        names.join(", ")
    )
}
