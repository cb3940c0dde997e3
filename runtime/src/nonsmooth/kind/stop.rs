//! Unilateral stops (theory.md §3): rigid, with Newton's impact law `v⁺ = −e v⁻`, or
//! spring-backed, a massless support on a spring `k_support` (a bilinear spring, theory
//! S7). A stop's sign is `s = +1` for an upper stop (`q ≤ position`), `−1` for a lower
//! one; its gap is `s (position − q) ≥ 0`, its contact magnitude `λ = s f ≥ 0`.
//!
//! Impacts themselves (the impulses of several stops at once, restitution, settling)
//! are the event driver's (`event.rs`), as they couple every element on the impact's
//! coordinates.

use super::dashpot;
use super::graph::{Branches, Line, Part, Point, StepState};
use super::traits::{At, Context, Forces, Found, Kind};
use crate::element::{Element, ElementKind, Mode, NonSmooth, Side, StopKind};

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

/// Whether `element` is a rigid stop.
pub(crate) fn is_rigid(element: &Element) -> bool {
    matches!(
        element.kind,
        ElementKind::Stop {
            kind: StopKind::Rigid { .. },
            ..
        }
    )
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

    /// Free: the gap; contact: `λ`; compressed: the penetration.
    fn switching(&self, _branches: &Branches, mode: Mode, at: &At) -> f64 {
        let (qc, f) = (at.qc, at.f);
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
    fn margin(&self, _branches: &Branches, mode: Mode, at: &At) -> f64 {
        let At {
            qc, vc, ac, f, wcc, ..
        } = *at;
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
}

impl<S: NonSmooth<N>, const N: usize> Forces<S, N> for Stop {
    /// Compressed: `s k_support · penetration`; free: `0`.
    fn force(&self, _cx: &Context<S>, mode: Mode, at: &At) -> f64 {
        match (self.kind, mode) {
            (StopKind::SpringBacked { stiffness }, Mode::Compressed) => {
                self.sign() * stiffness * (-self.gap(at.qc))
            }
            _ => 0.0,
        }
    }

    /// In the gap coordinate `g = σ (q − position)` (`σ = −s`) with contact force
    /// `λ ≥ 0`, element force `f = −σ λ`.
    fn on_line(&self, _cx: &Context<S>, line: Line, state: &StepState) -> Found {
        let Line { v_free, w } = line;
        let sigma = -self.sign();
        let gap = sigma * (state.q - self.position);
        let u_free = sigma * v_free;
        let open = Point {
            v: v_free,
            f: 0.0,
            part: Part::Open,
            dq: None,
        };
        match self.kind {
            StopKind::Rigid { restitution } => {
                // Moreau's velocity-level rule with Newton restitution (Acary & Brogliato
                // 2008, §10.1), 0 ≤ u − u⁺ ⊥ λ ≥ 0, u⁺ = −e·u_a, active where the step
                // starts on the stop or its smooth motion u_s (no element forces) would
                // pass it. The approach speed u_a is the smaller of the step's start and
                // smooth end, max(u_n, u_s) ≤ 0, so a rebound is never faster than the
                // velocity it reverses. A rebound within twice what the step's smooth
                // forces add towards the stop (u_n − u_s) is taken as plastic: it could
                // not leave the stop, and its flight h·u⁺ against those forces would gain
                // more potential energy than its kinetic energy holds (the event driver
                // settles such rebounds alike). Activity and target depend on the step's
                // start and smooth prediction alone, fixed while coupled elements' forces
                // are solved: the graph stays monotone.
                let u_n = sigma * state.v;
                let u_s = sigma * state.v_smooth;
                let g_s = gap + state.h * u_s;
                if gap > 0.0 && g_s >= 0.0 {
                    return Ok(open);
                }
                let rebound = -restitution * u_n.max(u_s).min(0.0);
                let pull = (u_n - u_s).max(0.0);
                let target = if rebound > 2.0 * pull { rebound } else { 0.0 };
                if u_free >= target {
                    return Ok(open);
                }
                // Reached inside the step (from a gap): the coordinate travels to the
                // stop and back at u⁺ for the part of the step its free motion would
                // have spent beyond it, g_s / u_s, so it never passes the stop and a free
                // flight's bounce is placed exactly.
                let dq = (gap > 0.0).then(|| sigma * (target * (g_s / u_s) - gap));
                let lambda = (target - u_free) / w;
                Ok(Point {
                    v: sigma * target,
                    f: -sigma * lambda,
                    part: Part::Contact,
                    dq,
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
                    dq: None,
                })
            }
        }
    }
}

/// The force `λ ≥ 0` of a support of stiffness `k` (energy `V(g) = ½ k ((−g)₊)²` in the
/// gap `g`) over a step from gap `g_a` to `g_b = g_free + c λ` (`c > 0`): the root of
/// `λ = −(V(g_b) − V(g_a)) / (g_b − g_a)`, the discrete gradient (O. Gonzalez, "Time
/// integration and discrete Hamiltonian systems", J. Nonlinear Sci. 6 (1996) 449–467).
/// With positions advanced by the mean velocity, the work of `λ` over the step equals the
/// change of `V` exactly, whatever the step: a support hit within one step gives back
/// what it stored. The right side falls as `λ` grows (`V` is convex), so the root is
/// unique; each piece of `V` gives it in closed form.
pub(crate) fn support_discrete_gradient(k: f64, g_a: f64, g_free: f64, c: f64) -> f64 {
    if g_a < 0.0 {
        // Pressed in at the start. Still pressed in at the end: λ = −½k (g_a + g_b).
        let lambda = -0.5 * k * (g_a + g_free) / (1.0 + 0.5 * k * c);
        if lambda >= 0.0 && g_free + c * lambda < 0.0 {
            return lambda;
        }
        // Released within the step: λ (g_b − g_a) = ½ k g_a², g_b ≥ 0, so
        // c λ² + (g_free − g_a) λ − ½ k g_a² = 0, the positive root.
        let b = g_free - g_a;
        let d = (b * b + 2.0 * c * k * g_a * g_a).sqrt();
        if b > 0.0 {
            k * g_a * g_a / (b + d)
        } else {
            (d - b) / (2.0 * c)
        }
    } else if g_free >= 0.0 {
        0.0
    } else {
        // Free at the start, pressed in at the end: λ (g_a − g_b) = ½ k g_b², g_b < 0:
        // with λ = (g_b − g_free)/c, (1 + ½kc) g_b² − (g_a + g_free) g_b + g_a g_free = 0,
        // whose negative root (the product of the roots is ≤ 0) is g_b; λ from g_b by the
        // balance itself (g_b − g_free cancels when kc ≪ 1).
        let a = 1.0 + 0.5 * k * c;
        let s = g_a + g_free;
        let d = (s * s - 4.0 * a * g_a * g_free).sqrt();
        let g_b = if s >= 0.0 {
            2.0 * g_a * g_free / (s + d)
        } else {
            (s - d) / (2.0 * a)
        };
        (0.5 * k * g_b * g_b / (g_a - g_b)).max(0.0)
    }
}
