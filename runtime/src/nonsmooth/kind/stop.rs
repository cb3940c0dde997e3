//! Unilateral stops (theory.md §3): rigid, with Newton's impact law `v⁺ = −e v⁻`, or
//! spring-backed, a massless support on a spring `k_support` (a bilinear spring, theory
//! S7). A stop's sign is `s = +1` for an upper stop (`q ≤ position`), `−1` for a lower
//! one; its gap is `s (position − q) ≥ 0`, its contact magnitude `λ = s f ≥ 0`.
//!
//! Impacts themselves (the impulses of several stops at once, restitution, settling)
//! are the event driver's (`event.rs`), as they couple every element on the impact's
//! coordinates.

use super::super::law::{
    Branches, Graph, LawError, Line, Part, Point, StepState, support_discrete_gradient,
};
use super::{Context, Kind, dashpot};
use crate::element::{Mode, NonSmooth, Side, StopKind};

/// A stop at `position` on `side`, rigid or spring-backed.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Stop {
    pub side: Side,
    pub position: f64,
    pub kind: StopKind,
}

/// `s = +1` for an upper stop (`q ≤ position`), `−1` for a lower one.
pub(crate) fn side_sign(side: Side) -> f64 {
    match side {
        Side::Upper => 1.0,
        Side::Lower => -1.0,
    }
}

impl Stop {
    fn sign(&self) -> f64 {
        side_sign(self.side)
    }

    fn rigid(&self) -> bool {
        matches!(self.kind, StopKind::Rigid { .. })
    }
}

impl Kind for Stop {
    fn check(&self) -> Result<(), String> {
        if !self.position.is_finite() {
            return Err(format!("stop position {} must be finite", self.position));
        }
        match self.kind {
            StopKind::Rigid { restitution } if !(0.0..=1.0).contains(&restitution) => Err(format!(
                "restitution e = {restitution} must lie in [0, 1] (0 plastic, 1 elastic)"
            )),
            StopKind::SpringBacked { stiffness } if !(stiffness.is_finite() && stiffness > 0.0) => {
                Err(format!(
                    "support stiffness {stiffness} must be finite and > 0 (use a rigid stop for ∞)"
                ))
            }
            _ => Ok(()),
        }
    }

    /// A rigid stop at gap `0` may close or open; a spring-backed one switches by the sign
    /// of its penetration rate, but is offered both at a selection.
    fn candidates(&self) -> &'static [Mode] {
        if self.rigid() {
            &[Mode::Contact, Mode::Free]
        } else {
            &[Mode::Free, Mode::Compressed]
        }
    }

    fn unconstrained(&self) -> Mode {
        Mode::Free
    }

    fn gap(&self, qc: f64) -> f64 {
        self.sign() * (self.position - qc)
    }

    /// Compressed: `s k_support · penetration`; free: `0`.
    fn force<S: NonSmooth<N>, const N: usize>(
        &self,
        _cx: &Context<S>,
        mode: Mode,
        qc: f64,
        _vc: f64,
    ) -> f64 {
        match (self.kind, mode) {
            (StopKind::SpringBacked { stiffness }, Mode::Compressed) => {
                self.sign() * stiffness * (-self.gap(qc))
            }
            _ => 0.0,
        }
    }

    /// Free: the gap; contact: `λ`; compressed: the penetration.
    fn switching(&self, _branches: &Branches, mode: Mode, qc: f64, _vc: f64, f: f64) -> f64 {
        match mode {
            Mode::Free => self.gap(qc),
            Mode::Contact => self.sign() * f,
            Mode::Compressed => -self.gap(qc),
            _ => f64::INFINITY,
        }
    }

    /// Contact: `λ`; a rigid stop free at gap `0` and rest: the gap acceleration divided
    /// by `W_cc` (`+∞` while the gap is open or opening); a spring-backed stop is always
    /// consistent (its force is a function of the state).
    fn margin(
        &self,
        _branches: &Branches,
        mode: Mode,
        qc: f64,
        vc: f64,
        ac: f64,
        f: f64,
        wcc: f64,
    ) -> f64 {
        match (self.kind, mode) {
            (_, Mode::Contact) => self.sign() * f,
            (StopKind::Rigid { .. }, Mode::Free) => {
                if self.gap(qc) > 0.0 {
                    f64::INFINITY
                } else {
                    // Gap rate −s v_c, gap acceleration −s a_c.
                    dashpot::directed(-self.sign(), vc, ac, wcc)
                }
            }
            (StopKind::SpringBacked { .. }, Mode::Free | Mode::Compressed) => f64::INFINITY,
            _ => f64::NEG_INFINITY,
        }
    }

    /// In the gap coordinate `g = σ (q − position)` (`σ = −s`) with contact force
    /// `λ ≥ 0`, element force `f = −σ λ`.
    fn on_line<S: NonSmooth<N>, const N: usize>(
        &self,
        _graph: &Graph,
        _system: &S,
        line: Line,
        state: &StepState,
    ) -> Result<Point, LawError> {
        let Line { v_free, w } = line;
        let sigma = -self.sign();
        let gap = sigma * (state.q - self.position);
        let u_free = sigma * v_free;
        let open = Point {
            v: v_free,
            f: 0.0,
            part: Part::Open,
        };
        match self.kind {
            StopKind::Rigid { restitution } => {
                // Moreau's velocity-level rule with Newton restitution, active set from
                // the gap predicted half a step ahead (Acary & Brogliato 2008, §10.1):
                // 0 ≤ u + e·min(u_n, 0) ⊥ λ ≥ 0.
                let u_n = sigma * state.v;
                let active = gap + 0.5 * state.h * u_n <= 0.0;
                let target = -restitution * u_n.min(0.0);
                if !active || u_free >= target {
                    return Ok(open);
                }
                let lambda = (target - u_free) / w;
                Ok(Point {
                    v: sigma * target,
                    f: -sigma * lambda,
                    part: Part::Contact,
                })
            }
            StopKind::SpringBacked { stiffness } => {
                // u = u_free + w λ; the gap at the step's end is
                // g_end = g_n + h((1 − θ_q) u_n + θ_q u) = g_free + c λ.
                let th = state.theta_q;
                let u_n = sigma * state.v;
                let g_free = gap + state.h * ((1.0 - th) * u_n + th * u_free);
                let c = state.h * th * w;
                let lambda = if th >= 1.0 {
                    // θ_q = 1: λ = k (−g_end)₊, implicit Euler: any k is stable, and a
                    // contact loses energy, more the larger h√(k/m).
                    stiffness * (-g_free).max(0.0) / (1.0 + stiffness * c)
                } else {
                    // θ_q < 1: the discrete gradient of the support's energy between the
                    // step's ends, exact in energy at θ_q = ½.
                    support_discrete_gradient(stiffness, gap, g_free, c)
                };
                if lambda <= 0.0 {
                    return Ok(open);
                }
                Ok(Point {
                    v: sigma * (u_free + w * lambda),
                    f: -sigma * lambda,
                    part: Part::Contact,
                })
            }
        }
    }

    fn force_of_velocity<S: NonSmooth<N>, const N: usize>(
        &self,
        _graph: &Graph,
        _system: &S,
        _v: f64,
        _previous: f64,
    ) -> Result<Option<f64>, LawError> {
        Ok(None)
    }

    fn velocity_of_force<S: NonSmooth<N>, const N: usize>(
        &self,
        _system: &S,
        _index: usize,
        _f: f64,
    ) -> Option<f64> {
        None
    }
}
