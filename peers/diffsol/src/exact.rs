//! The exact solution of S6: the Coulomb oscillator `m x'' + k x + f_crit·sgn(v) ∋ 0`,
//! released from rest at `x0`, no forcing.
//!
//! With ω = √(k/m) and x_F = f_crit/k: while the block slides with velocity of sign `s`,
//! `m x'' = −k x − s·f_crit`, a harmonic oscillation about the shifted centre `−s·x_F`.
//! From rest at `a` with `|a| > x_F` it slides towards the origin (`s = −sgn a`), so the
//! centre is `c = sgn(a)·x_F`, and it comes to rest again half a period `π/ω` later at
//! `2c − a`: the amplitude about the origin shrinks by `2 x_F` per half swing. At a rest
//! point with `|a| ≤ x_F` the spring force `k|a| ≤ f_crit` is held by friction and the block
//! sticks for good.

use std::f64::consts::PI;

/// The piecewise closed form of S6.
pub struct CoulombFreeDecay {
    omega: f64,
    /// Start time, start position and centre of each half swing; the block sticks at
    /// `stuck.1` from `stuck.0` on.
    swings: Vec<(f64, f64, f64)>,
    stuck: (f64, f64),
}

impl CoulombFreeDecay {
    pub fn new(m: f64, k: f64, f_crit: f64, t0: f64, x0: f64) -> Self {
        let omega = (k / m).sqrt();
        let x_f = f_crit / k;
        let half = PI / omega;
        let mut swings = Vec::new();
        let (mut t, mut a) = (t0, x0);
        while a.abs() > x_f {
            let c = a.signum() * x_f;
            swings.push((t, a, c));
            a = 2.0 * c - a;
            t += half;
        }
        CoulombFreeDecay {
            omega,
            swings,
            stuck: (t, a),
        }
    }

    /// `(x, v)` at time `t`.
    pub fn at(&self, t: f64) -> (f64, f64) {
        if t >= self.stuck.0 {
            return (self.stuck.1, 0.0);
        }
        let i = self.swings.partition_point(|s| s.0 <= t).max(1) - 1;
        let (ts, a, c) = self.swings[i];
        let phase = self.omega * (t - ts);
        (
            c + (a - c) * phase.cos(),
            -(a - c) * self.omega * phase.sin(),
        )
    }

    /// The turning points `(t, x)` (velocity zeros, the last one the stick onset).
    pub fn turning_points(&self) -> Vec<(f64, f64)> {
        let mut out: Vec<(f64, f64)> = self.swings.iter().skip(1).map(|s| (s.0, s.1)).collect();
        out.push(self.stuck);
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn s6_turning_points() {
        let s = CoulombFreeDecay::new(1.0, 1.0, 0.1, 0.0, 1.0);
        let tp = s.turning_points();
        let expect = [
            (PI, -0.8),
            (2.0 * PI, 0.6),
            (3.0 * PI, -0.4),
            (4.0 * PI, 0.2),
            (5.0 * PI, 0.0),
        ];
        assert_eq!(tp.len(), expect.len());
        for ((t, x), (te, xe)) in tp.iter().zip(expect) {
            assert!((t - te).abs() < 1e-12 && (x - xe).abs() < 1e-12, "{t} {x}");
        }
        // Continuity across the switches and rest after sticking.
        for (t, x) in tp {
            let (xl, vl) = s.at(t - 1e-9);
            let (xr, vr) = s.at(t + 1e-9);
            assert!((xl - x).abs() < 1e-8 && (xr - x).abs() < 1e-8);
            assert!(vl.abs() < 1e-8 && vr.abs() < 1e-8);
        }
        assert_eq!(s.at(30.0), (s.turning_points().last().unwrap().1, 0.0));
        // Energy: during a swing about c, (x − c)² + (v/ω)² is constant.
        let (x, v) = s.at(1.0);
        assert!(((x - 0.1).powi(2) + v * v - 0.81).abs() < 1e-12);
    }
}
