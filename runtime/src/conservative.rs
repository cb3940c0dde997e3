//! A conservative mechanism integrated on its energy level as well as on its loops.
//!
//! An explicit or implicit Runge–Kutta method or BDF does not conserve energy: each step
//! loses (or gains) a little, always with the same sign, and over many periods the drift
//! grows linearly (theory.md §7, "Energy over long runs"). For a mechanism with no
//! inputs, dampers or non-smooth elements the energy `E = T(q, v) + U(q)` is a first
//! integral, and [`Conservative`] makes it one more invariant the drivers project onto
//! after every step (Hairer, Lubich & Wanner, *Geometric Numerical Integration*, §IV.4):
//! after the loop constraints ([`MechanicalSystem`]'s projection), the velocities are
//! scaled by `s = √((E₀ − U(q)) / T(q, v))`. In the mass metric that is the nearest
//! point on the energy level among the states with the same `q`, and as `G v` is
//! linear in `v` it keeps the velocity constraints.
//!
//! What it does not remove: the phase error (where along its orbit the state is), which
//! grows as before.

use nalgebra::SVector;

use crate::kernels::Energy;
use crate::mechanical::{InputFn, MechanicalSystem};
use crate::system::Mechanism;
use crate::{ErrorKind, OdeSystem};

/// The largest relative change of the kinetic energy a projection makes. Near a turning
/// point (the kinetic energy about as small as the energy error) scaling the speed
/// would be ill-conditioned; there the step is left as it is and the next step with
/// the mechanism moving corrects it.
pub const ENERGY_SCALE_LIMIT: f64 = 1e-3;

/// A [`Mechanism`] without inputs, dampers or non-smooth elements, integrated on the
/// energy level of its start: after every step its velocities are scaled back onto the
/// level `T + U = E₀` (theory.md §7, "Energy over long runs").
///
/// ```ignore
/// let system = Conservative::new(&four_bar, &y0)?;
/// let sol = solve(&system, &Problem::new(0.0, 1e3, y0), &Method::Dopri5(options))?;
/// ```
pub struct Conservative<'a, S, const N: usize> {
    system: MechanicalSystem<'a, S, InputFn<N>, N>,
    energy: f64,
}

impl<'a, S, const N: usize> Conservative<'a, S, N>
where
    S: Mechanism<N> + Energy<N>,
{
    /// The mechanism on the energy level `E₀ = T(q₀, v₀) + U(q₀)` of `y0 = [q₀; v₀]`,
    /// given as it will start (a closed mechanism's start assembled, e.g. by
    /// [`loops::assemble`](crate::loops::assemble), since projecting it onto its loops
    /// would change its energy).
    ///
    /// # Errors
    /// [`ErrorKind::InvalidInput`] when `y0` does not have `2N` finite components, and
    /// when the energy is not conserved: naming the dampers (with their coefficients)
    /// or the non-smooth elements that dissipate it.
    pub fn new(mechanism: &'a S, y0: &[f64]) -> Result<Self, ErrorKind> {
        if y0.len() != 2 * N || y0.iter().any(|x| !x.is_finite()) {
            return Err(ErrorKind::InvalidInput(format!(
                "the start of a conservative system must be [q; v] with {} finite components, \
                 got {} ({:?})",
                2 * N,
                y0.len(),
                y0
            )));
        }
        if !S::NON_SMOOTH_ELEMENTS.is_empty() {
            return Err(ErrorKind::InvalidInput(format!(
                "the scene's non-smooth elements ({}) dissipate energy: a conservative system \
                 has none (integrate the scene with `solve_nonsmooth`)",
                quoted(S::NON_SMOOTH_ELEMENTS.iter().copied())
            )));
        }
        let model = mechanism.model();
        let dampers: Vec<String> = model
            .dampers
            .iter()
            .filter(|d| d.damping != 0.0)
            .map(|d| {
                let joint = S::JOINTS.get(d.coordinate).copied().unwrap_or("?");
                format!("`{joint}` (c = {})", d.damping)
            })
            .collect();
        if !dampers.is_empty() {
            return Err(ErrorKind::InvalidInput(format!(
                "the scene's dampers dissipate energy: {}; a conservative system has none \
                 (integrate it as a `MechanicalSystem`)",
                dampers.join(", ")
            )));
        }
        let (q, v) = split::<N>(y0);
        Ok(Conservative {
            system: MechanicalSystem::unforced(mechanism),
            energy: mechanism.total_energy(&q, &v),
        })
    }

    /// The energy level `E₀` the integration is held on.
    pub fn energy(&self) -> f64 {
        self.energy
    }
}

fn quoted<'s>(names: impl Iterator<Item = &'s str>) -> String {
    names
        .map(|n| format!("`{n}`"))
        .collect::<Vec<_>>()
        .join(", ")
}

fn split<const N: usize>(y: &[f64]) -> (SVector<f64, N>, SVector<f64, N>) {
    (
        SVector::from_column_slice(&y[..N]),
        SVector::from_column_slice(&y[N..2 * N]),
    )
}

impl<S, const N: usize> OdeSystem for Conservative<'_, S, N>
where
    S: Mechanism<N> + Energy<N>,
{
    fn dim(&self) -> usize {
        2 * N
    }

    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        self.system.rhs(t, y, dy);
    }

    fn jacobian(&self, t: f64, y: &[f64], jac: &mut nalgebra::DMatrix<f64>) -> bool {
        self.system.jacobian(t, y, jac)
    }

    fn names(&self) -> Vec<String> {
        self.system.names()
    }

    fn second_order(&self) -> Option<usize> {
        Some(N)
    }

    fn validate(&self) -> Result<(), String> {
        self.system.validate()
    }

    fn output_names(&self) -> Vec<String> {
        self.system.output_names()
    }

    fn outputs(&self, t: f64, y: &[f64], out: &mut [f64]) {
        self.system.outputs(t, y, out);
    }

    /// Onto the loops ([`MechanicalSystem`]'s projection), then onto the energy level by
    /// scaling the velocities, unless that would change the kinetic energy by more than
    /// [`ENERGY_SCALE_LIMIT`] of itself.
    fn project(&self, t: f64, y: &mut [f64]) -> Result<bool, ErrorKind> {
        let mut moved = self.system.project(t, y)?;
        let (q, v) = split::<N>(y);
        let s = self.system.mechanism;
        let kinetic = s.kinetic_energy(&q, &v);
        let target = self.energy - s.potential_energy(&q);
        if kinetic > 0.0
            && target > 0.0
            && target != kinetic
            && (target - kinetic).abs() <= ENERGY_SCALE_LIMIT * kinetic
        {
            let scale = (target / kinetic).sqrt();
            for x in &mut y[N..2 * N] {
                *x *= scale;
            }
            moved = true;
        }
        Ok(moved)
    }

    /// The loops' conditioning; an open tree's energy level is never singular (`1`).
    fn conditioning(&self, y: &[f64]) -> Option<f64> {
        Some(self.system.conditioning(y).unwrap_or(1.0))
    }
}
