//! A spring-backed stop resting on its support (theory.md §3, "Resting on a stiff
//! support").
//!
//! Pressed onto a support of stiffness `k`, a coordinate vibrates about the static
//! compression `λ/k` at `ω = √(k W_cc)` (`W = M⁻¹`); the model has no damping to end it.
//! With `k = 1e9` on an arm the vibration has thousands of periods per second and an
//! amplitude of nanoradians: an explicit method is held to `h ≈ 3/ω` by stability, a
//! stiff one by accuracy while the vibration is above the tolerance, and both spend the
//! step budget on it. So while the vibration stays below the static compression (the
//! support never lets go) and either is within the tolerance or would last more than
//! [`RESTING_PERIODS`] periods in the rest of the run, the event driver takes the stop
//! as *resting*: its coordinate is held at the static compression (mode
//! [`Mode::Contact`], `v_c = 0`, the force `λ` from the constraint, as for a rigid stop
//! in contact), and the vibration is dropped: the switch to `Contact` is logged with
//! the states before and after it, and the energy dropped is below `λ²/2k`.
//!
//! While resting, the coordinate is re-anchored whenever the static compression `λ/k`
//! has moved from it by more than [`RESTING_DRIFT`] of itself or the position
//! tolerance (an event with a second row), put as far past the compression as it lagged
//! behind so that the energy the lag took is given back, and the stop lifts off (mode
//! `Free`, at its position) when `λ` falls to zero.

use crate::element::{Element, ElementKind, StopKind};
use crate::nonsmooth::kind::stop::side_sign;

/// A support vibration is not followed when more than this many of its periods are
/// left in the run at `rtol ≥ 1e-8` (and it would not let go of the support), more at
/// tighter tolerances ([`resting_periods`]): resolving it costs ten to twenty steps a
/// period, and a hundred periods already cost more than time-stepping's whole run of a
/// typical scene.
pub const RESTING_PERIODS: f64 = 100.0;

/// How many periods of a support vibration, left in the run, are followed at `rtol`:
/// [`RESTING_PERIODS`] at `rtol ≥ 1e-8`, growing as `1/√rtol` below, so that a tight
/// tolerance follows a vibration it would notice for longer (1000 periods at 1e-10).
pub fn resting_periods(rtol: f64) -> f64 {
    RESTING_PERIODS * (1e-8 / rtol).sqrt().max(1.0)
}

/// While resting, the held coordinate is re-anchored when the static compression `λ/k`
/// has moved from it by more than this fraction of itself (or the position tolerance,
/// where that is larger). Resting already drops a vibration of up to the whole static
/// compression; a lag of a twentieth of it errs by a four-hundredth of that energy per
/// re-anchoring, and keeps the re-anchorings to about twenty per doubling of the load
/// whatever the stiffness (at the position tolerance alone, a support of 1e6 under a
/// load changing by 60 N/s needed a million per second at rtol 1e-10).
pub const RESTING_DRIFT: f64 = 0.05;

/// The fraction of its lag by which a re-anchored coordinate is put past the static
/// compression ([`Support::reanchor`]): just under one, so that the drift margin starts
/// positive, and the spring energy the lag took is given back but for `1 − MIRROR²`
/// of it.
const MIRROR: f64 = 0.999;

/// The support of a spring-backed stop: stiffness `k`, side sign `s`, position.
#[derive(Clone, Copy, Debug)]
pub(super) struct Support {
    pub k: f64,
    pub s: f64,
    pub position: f64,
}

impl Support {
    /// `element`'s support if it is a spring-backed stop.
    pub fn of(element: &Element) -> Option<Support> {
        match element.kind {
            ElementKind::Stop {
                kind: StopKind::SpringBacked { stiffness },
                side,
                position,
            } => Some(Support {
                k: stiffness,
                s: side_sign(side),
                position,
            }),
            _ => None,
        }
    }

    /// The penetration `s (q_c − position)` (positive pressed in).
    pub fn penetration(&self, qc: f64) -> f64 {
        self.s * (qc - self.position)
    }

    /// The coordinate at the static compression under the contact force `λ ≥ 0`.
    pub fn anchor(&self, lambda: f64) -> f64 {
        self.position + self.s * lambda.max(0.0) / self.k
    }

    /// The energy of the vibration about the static compression under `λ`: the
    /// support's spring energy about it and the kinetic energy of the coordinate's
    /// velocity `v_c` at its effective mass `1 / W_cc`.
    pub fn vibration_energy(&self, qc: f64, vc: f64, lambda: f64, wcc: f64) -> f64 {
        let d = self.penetration(qc) - lambda / self.k;
        0.5 * self.k * d * d + 0.5 * vc * vc / wcc
    }

    /// Whether the stop, pressed with the hold force `λ`, is taken as resting: the
    /// vibration's amplitude is below the static compression (it never lets go), and it
    /// is within the tolerance `(tol_q, tol_v)` of the coordinate or would last more
    /// than [`resting_periods`]`(rtol)` periods in the `remaining` time.
    pub fn rests(&self, at: Pressed, tol: (f64, f64), rtol: f64, remaining: f64) -> bool {
        let Pressed {
            qc,
            vc,
            lambda,
            wcc,
        } = at;
        if !(lambda > 0.0 && wcc > 0.0) {
            return false;
        }
        let e = self.vibration_energy(qc, vc, lambda, wcc);
        // `≤`: a coordinate let go at rest exactly at the stop's position grazes it.
        let holds = 0.5 * lambda * lambda / self.k;
        if e.is_nan() || e > holds {
            return false;
        }
        let (tol_q, tol_v) = tol;
        // Within the tolerance: the vibration's amplitude and speed are, or its energy
        // is below the load's work over the position tolerance, `λ tol_q` (what a
        // position error of the tolerance makes in the energy).
        let within =
            e <= (0.5 * self.k * tol_q * tol_q + 0.5 * tol_v * tol_v / wcc).max(lambda * tol_q);
        let omega = (self.k * wcc).sqrt();
        within || remaining * omega / std::f64::consts::TAU > resting_periods(rtol)
    }

    /// Where a held coordinate `qc` is re-anchored under the hold force `λ`, having
    /// drifted to the edge of its margin ([`Support::drift_margin`]): past the static
    /// compression by [`MIRROR`] of its lag, so that the jump gives back the spring
    /// energy the lag took (a jump of `Δ` from a lag `δ` changes the energy by
    /// `k δ Δ − k Δ²/2`: zero at `Δ = 2δ`, `−k δ²/2` at the static compression). A lag
    /// beyond the margin (the load changed at once, at another element's switch) is
    /// mirrored only as far as the margin, and the mirror is not taken where it would
    /// leave the support.
    pub fn reanchor(&self, qc: f64, lambda: f64, tol_q: f64) -> f64 {
        let anchor = self.anchor(lambda);
        let bound = (tol_q).max(RESTING_DRIFT * lambda / self.k);
        let lag = anchor - qc;
        let mirror = anchor + MIRROR * lag.clamp(-bound, bound);
        if self.penetration(mirror) >= 0.0 {
            mirror
        } else {
            anchor
        }
    }

    /// How far the spring force at the held compression `k · penetration` may still
    /// move from the hold force `λ` before the held position is off the static
    /// compression by [`RESTING_DRIFT`] of it or the tolerance `tol_q`, whichever is
    /// larger: `max(k tol_q, RESTING_DRIFT · λ) − |k · penetration − λ|` (re-anchoring
    /// at `0`).
    pub fn drift_margin(&self, qc: f64, lambda: f64, tol_q: f64) -> f64 {
        (self.k * tol_q).max(RESTING_DRIFT * lambda)
            - (self.k * self.penetration(qc) - lambda).abs()
    }
}

/// A pressed stop's coordinate, velocity, hold force and `W_cc`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Pressed {
    pub qc: f64,
    pub vc: f64,
    pub lambda: f64,
    pub wcc: f64,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::Side;

    fn lower(k: f64) -> Support {
        Support::of(&Element {
            name: "s",
            coordinate: 0,
            kind: ElementKind::Stop {
                side: Side::Lower,
                position: -0.5,
                kind: StopKind::SpringBacked { stiffness: k },
            },
        })
        .unwrap()
    }

    #[test]
    fn anchor_is_the_static_compression_and_rests_below_it() {
        let s = lower(1e9);
        let lambda = 13.0;
        let q = s.anchor(lambda);
        // To the rounding of q near the stop position 0.5.
        assert!((s.penetration(q) - lambda / 1e9).abs() < 4.0 * f64::EPSILON);
        assert!(q < -0.5, "a lower stop is pressed below its position");
        assert!(s.vibration_energy(q, 0.0, lambda, 1.0) < 1e-20);
        let at = |qc, vc| Pressed {
            qc,
            vc,
            lambda,
            wcc: 1.0,
        };
        // Vibration above the static compression (it would let go): not resting.
        let big = (lambda / 1e9) * (1e9f64).sqrt() * 1.01;
        assert!(!s.rests(at(q, big), (1e-12, 1e-12), 1e-10, 10.0));
        // Below it with ~5000 periods left: resting; with 1 period left, only within
        // the tolerance; with 500 left, at rtol 1e-8 but not at 1e-10.
        let small = 0.5 * big;
        assert!(s.rests(at(q, small), (1e-12, 1e-12), 1e-10, 1.0));
        assert!(!s.rests(at(q, small), (1e-12, 1e-12), 1e-10, 2e-4));
        assert!(s.rests(at(q, 1e-13), (1e-12, 1e-12), 1e-10, 2e-4));
        let five_hundred = 500.0 * std::f64::consts::TAU / 1e9f64.sqrt();
        assert!(s.rests(at(q, small), (1e-12, 1e-12), 1e-8, five_hundred));
        assert!(!s.rests(at(q, small), (1e-12, 1e-12), 1e-10, five_hundred));
        // Pulling (λ ≤ 0) never rests.
        assert!(!s.rests(
            Pressed {
                lambda: -1.0,
                ..at(q, 0.0)
            },
            (1.0, 1.0),
            1e-8,
            10.0
        ));
    }

    #[test]
    fn drift_margin_is_a_fraction_of_the_compression_or_the_tolerance() {
        let s = lower(1e6);
        let q = s.anchor(10.0);
        // RESTING_DRIFT · λ = 0.5 N beats k · tol = 1e-3 N.
        assert!((s.drift_margin(q, 10.0, 1e-9) - 0.5).abs() < 1e-6);
        // λ moved by about that much: on the boundary.
        assert!(s.drift_margin(q, 10.0 / 0.95, 1e-9).abs() < 1e-6);
        // A loose tolerance wins where it is larger.
        assert!((s.drift_margin(q, 10.0, 1e-6) - 1.0).abs() < 1e-6);
    }
}
