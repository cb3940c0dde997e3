//! The lossless four-bar's motion by quadrature, shared by `tests/conservative.rs` and
//! the report's four-bar table: a reference that integrates no differential equation.
//!
//! With one degree of freedom (the crank angle `θ`) and no losses, the energy
//! `E₀ = ½ m(θ) θ̇² + U(θ)` fixes the crank speed at every angle, `m(θ)` being twice the
//! kinetic energy at `θ̇ = 1` (the loops assembled at `θ`, the velocities that close them
//! given the crank's). The time to turn from `0` to `θ` is then
//! `t(θ) = ∫₀^θ dϑ / θ̇(ϑ)`, over whole turns `n T + t(θ mod 2π)` with the period
//! `T = t(2π)`. The integrand is smooth and periodic, so the trapezoidal rule on the
//! whole turn converges geometrically; on a part of a turn Gauss–Legendre panels are used.

use filippov::nalgebra::SVector;
use filippov::prelude::*;
use filippov::runtime::loops::assemble;
use filippov::scenes::FourBar;

type V3 = SVector<f64, 3>;

/// The crank's speed along the orbit of energy `energy`, with its period.
pub struct FourBarOrbit {
    fb: FourBar,
    energy: f64,
    /// The time of a whole turn.
    pub period: f64,
}

/// Trapezoidal nodes over a whole turn: far more than round-off needs for the
/// crank-rocker (the integrand's Fourier coefficients fall by orders of magnitude per
/// harmonic).
const TURN_NODES: usize = 4096;

/// The coupler's absolute angle and the rocker's angle the crank-rocker is assembled
/// near at crank angle 0 (the start the report and the tests take).
pub const START: [f64; 2] = [1.0, 1.5];

impl FourBarOrbit {
    /// The orbit of `fb` with energy `energy` (the crank must turn all the way round:
    /// its kinetic energy positive at every angle).
    pub fn new(fb: FourBar, energy: f64) -> Self {
        let mut orbit = FourBarOrbit {
            fb,
            energy,
            period: 0.0,
        };
        let h = std::f64::consts::TAU / TURN_NODES as f64;
        let mut branch = START;
        orbit.period = (0..TURN_NODES)
            .map(|k| h / orbit.crank_speed(k as f64 * h, &mut branch))
            .sum();
        orbit
    }

    /// The crank speed `θ̇ > 0` at crank angle `theta`, on the assembly branch of
    /// `branch` (the coupler's absolute angle and the rocker's angle at a nearby crank
    /// angle; updated to those at `theta`). Followed in small steps of `θ`, the closed
    /// configuration stays on the branch the run started on and never jumps to the
    /// crossed one.
    fn crank_speed(&self, theta: f64, branch: &mut [f64; 2]) -> f64 {
        let guess = V3::from([theta, branch[0] - theta, branch[1]]);
        let (q, v) = assemble(
            &self.fb,
            &guess,
            &V3::from([1.0, 0.0, 0.0]),
            &["crank_pivot"],
        )
        .expect("the crank-rocker assembles at every crank angle");
        *branch = [q[0] + q[1], q[2]];
        let mass = 2.0 * self.fb.kinetic_energy(&q, &v);
        (2.0 * (self.energy - self.fb.potential_energy(&q)) / mass).sqrt()
    }

    /// The time the crank takes from angle `0` to `theta ≥ 0` (any number of turns).
    pub fn time_to(&self, theta: f64) -> f64 {
        const NODES: [(f64, f64); 5] = [
            (-0.906_179_845_938_664, 0.236_926_885_056_189),
            (-0.538_469_310_105_683, 0.478_628_670_499_366),
            (0.0, 0.568_888_888_888_889),
            (0.538_469_310_105_683, 0.478_628_670_499_366),
            (0.906_179_845_938_664, 0.236_926_885_056_189),
        ];
        let turns = (theta / std::f64::consts::TAU).floor();
        let rest = theta - turns * std::f64::consts::TAU;
        let panels = 256;
        let h = rest / panels as f64;
        let mut branch = START;
        let part: f64 = (0..panels)
            .map(|p| {
                let mid = (p as f64 + 0.5) * h;
                NODES
                    .iter()
                    .map(|&(x, w)| 0.5 * h * w / self.crank_speed(mid + 0.5 * h * x, &mut branch))
                    .sum::<f64>()
            })
            .sum();
        turns * self.period + part
    }

    /// How far the crank angle `theta` reached at time `t` is off the orbit's: the
    /// time error `t(θ) − t` times the crank speed there.
    pub fn angle_error(&self, t: f64, theta: f64) -> f64 {
        let turns = (theta / std::f64::consts::TAU).floor();
        let mut branch = START;
        // Walk to the angle within its turn to stay on the branch.
        let rest = theta - turns * std::f64::consts::TAU;
        for k in 1..=64 {
            self.crank_speed(rest * k as f64 / 64.0, &mut branch);
        }
        (self.time_to(theta) - t) * self.crank_speed(theta, &mut branch)
    }
}
