//! The result of an integration: accepted states, their derivatives, and an interpolant.

use std::io::{self, Write};

use crate::Stats;
use crate::method::tableau::dopri5_dense;

/// How states between the stored points are reconstructed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interpolant {
    /// Cubic Hermite from the stored states and derivatives (third order; any method).
    Hermite,
    /// The continuous extension of Dormand–Prince 5(4) (fourth order; Hairer, Nørsett &
    /// Wanner, *Solving ODEs I*, §II.6, p. 192 and the `CONTD5` routine).
    Dopri5,
}

/// Accepted states `y(t_i)` with `f(t_i, y(t_i))`, stored flat (`dim` per point).
#[derive(Clone, Debug, PartialEq)]
pub struct Trajectory {
    dim: usize,
    names: Vec<String>,
    t: Vec<f64>,
    y: Vec<f64>,
    dy: Vec<f64>,
    interpolant: Interpolant,
    /// Dopri5 only: the fifth continuous-extension coefficient vector of every interval.
    dense: Vec<f64>,
    /// Cost of the integration.
    pub stats: Stats,
}

impl Trajectory {
    pub(crate) fn new(names: Vec<String>, interpolant: Interpolant) -> Self {
        Trajectory {
            dim: names.len(),
            names,
            t: Vec::new(),
            y: Vec::new(),
            dy: Vec::new(),
            interpolant,
            dense: Vec::new(),
            stats: Stats::default(),
        }
    }

    pub(crate) fn push(&mut self, t: f64, y: &[f64], dy: &[f64]) {
        self.t.push(t);
        self.y.extend_from_slice(y);
        self.dy.extend_from_slice(dy);
    }

    /// Dopri5: the dense coefficients of the interval ending at the last pushed point.
    pub(crate) fn push_dense(&mut self, r5: &[f64]) {
        self.dense.extend_from_slice(r5);
    }

    /// Number of stored points.
    pub fn len(&self) -> usize {
        self.t.len()
    }

    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }

    /// Number of state components.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// Column names of the state components.
    pub fn names(&self) -> &[String] {
        &self.names
    }

    pub fn interpolant(&self) -> Interpolant {
        self.interpolant
    }

    /// Times of the stored points, increasing.
    pub fn times(&self) -> &[f64] {
        &self.t
    }

    /// State at stored point `i`.
    pub fn state(&self, i: usize) -> &[f64] {
        &self.y[i * self.dim..(i + 1) * self.dim]
    }

    /// Derivative `f(t_i, y_i)` at stored point `i`.
    pub fn derivative(&self, i: usize) -> &[f64] {
        &self.dy[i * self.dim..(i + 1) * self.dim]
    }

    /// The last stored time and state.
    pub fn last(&self) -> Option<(f64, &[f64])> {
        let n = self.len();
        (n > 0).then(|| (self.t[n - 1], self.state(n - 1)))
    }

    /// All values of component `j`, one per stored point.
    pub fn component(&self, j: usize) -> Vec<f64> {
        self.y.iter().skip(j).step_by(self.dim).copied().collect()
    }

    /// The interpolated state at time `t`, or `None` if `t` is outside
    /// `[t_first, t_last]` (no extrapolation).
    pub fn at(&self, t: f64) -> Option<Vec<f64>> {
        let (&first, &last) = (self.t.first()?, self.t.last()?);
        if !(first..=last).contains(&t) {
            return None;
        }
        // Interval [t_i, t_{i+1}] containing t.
        let i = self.t.partition_point(|&ti| ti <= t).saturating_sub(1);
        if i + 1 >= self.len() {
            return Some(self.state(i).to_vec());
        }
        let (t0, t1) = (self.t[i], self.t[i + 1]);
        let h = t1 - t0;
        let theta = (t - t0) / h;
        let (y0, y1) = (self.state(i), self.state(i + 1));
        let (f0, f1) = (self.derivative(i), self.derivative(i + 1));
        let has_dense = self.dense.len() == (self.len() - 1) * self.dim;
        Some(match self.interpolant {
            Interpolant::Dopri5 if has_dense => {
                let r5 = &self.dense[i * self.dim..(i + 1) * self.dim];
                (0..self.dim)
                    .map(|k| dopri5_dense(theta, h, y0[k], y1[k], f0[k], f1[k], r5[k]))
                    .collect()
            }
            _ => {
                // Cubic Hermite basis.
                let (t2, t3) = (theta * theta, theta * theta * theta);
                let h00 = 2.0 * t3 - 3.0 * t2 + 1.0;
                let h10 = t3 - 2.0 * t2 + theta;
                let h01 = -2.0 * t3 + 3.0 * t2;
                let h11 = t3 - t2;
                (0..self.dim)
                    .map(|k| h00 * y0[k] + h10 * h * f0[k] + h01 * y1[k] + h11 * h * f1[k])
                    .collect()
            }
        })
    }

    /// Writes the stored points as CSV: a header `t,<names>` then one row per point.
    pub fn write_csv<W: Write>(&self, mut out: W) -> io::Result<()> {
        write!(out, "t")?;
        for name in &self.names {
            write!(out, ",{name}")?;
        }
        writeln!(out)?;
        for i in 0..self.len() {
            write!(out, "{}", self.t[i])?;
            for x in self.state(i) {
                write!(out, ",{x}")?;
            }
            writeln!(out)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hermite_is_exact_for_cubics_and_csv_has_header() {
        let y = |t: f64| t * t * t - 2.0 * t + 1.0;
        let dy = |t: f64| 3.0 * t * t - 2.0;
        let mut traj = Trajectory::new(vec!["x".into()], Interpolant::Hermite);
        for t in [0.0, 0.5, 1.5] {
            traj.push(t, &[y(t)], &[dy(t)]);
        }
        for t in [0.0, 0.1, 0.5, 0.9, 1.2, 1.5] {
            assert!((traj.at(t).unwrap()[0] - y(t)).abs() < 1e-14);
        }
        assert_eq!(traj.at(1.6), None);
        assert_eq!(traj.last().unwrap().0, 1.5);
        assert_eq!(traj.component(0).len(), 3);
        let mut csv = Vec::new();
        traj.write_csv(&mut csv).unwrap();
        let csv = String::from_utf8(csv).unwrap();
        assert_eq!(csv.lines().next(), Some("t,x"));
        assert_eq!(csv.lines().nth(1), Some("0,1"));
        assert_eq!(csv.lines().count(), 4);
    }
}
