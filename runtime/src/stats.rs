//! Cost counters of one integration.

use std::fmt;

/// What an integration cost. Compared across methods and versions instead of timings.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Stats {
    /// Accepted steps.
    pub steps: usize,
    /// Rejected step attempts (error too large or Newton failure).
    pub rejected_steps: usize,
    /// Evaluations of the right-hand side, including those for finite differences.
    pub rhs_evaluations: usize,
    /// Jacobian evaluations, analytic or by finite differences.
    pub jacobian_evaluations: usize,
    /// Of those, Jacobians computed by finite differences.
    pub finite_difference_jacobians: usize,
    /// LU factorisations of the Newton matrix.
    pub lu_factorisations: usize,
    /// Simplified-Newton iterations (each one linear solve and one rhs evaluation).
    pub newton_iterations: usize,
    /// Event-driven non-smooth integration: located switching instants.
    pub events: usize,
    /// Element mode changes at those instants (several per event when elements switch
    /// together).
    pub mode_changes: usize,
    /// Spans of accumulating events (Zeno, chattering) detected.
    pub zeno_detected: usize,
    /// Of those, spans handed to time-stepping (then back to event-driven).
    pub zeno_handovers: usize,
    /// Event-driven non-smooth integration: the mechanical energy (kinetic, potential
    /// and the supports' springs) removed where spring-backed stops were taken as
    /// resting on their supports — each support vibration dropped on coming to rest,
    /// and what re-anchoring a held coordinate gave up (see the guide, "Resting on a
    /// stiff support"). Zero where no stop rested.
    #[cfg_attr(feature = "serde", serde(default))]
    pub resting_energy_dropped: f64,
    /// Time-stepping of spatial contacts: Gauss–Seidel sweeps over the contacts, summed
    /// over the steps.
    #[cfg_attr(feature = "serde", serde(default))]
    pub contact_sweeps: usize,
    /// Time-stepping of spatial contacts: the largest residual the contact problem of any
    /// step was left with — De Saxcé's natural map in velocity units, relative to the
    /// step's free contact velocities; `0` where every step solved its cone laws
    /// exactly, at most the solver's tolerance where each converged.
    #[cfg_attr(feature = "serde", serde(default))]
    pub contact_residual: f64,
}

impl fmt::Display for Stats {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "steps {} (rejected {}), rhs {}, jacobians {} (finite differences {}), LU {}, Newton {}",
            self.steps,
            self.rejected_steps,
            self.rhs_evaluations,
            self.jacobian_evaluations,
            self.finite_difference_jacobians,
            self.lu_factorisations,
            self.newton_iterations
        )?;
        if self.events > 0 || self.zeno_detected > 0 {
            write!(
                f,
                ", events {}, mode changes {}, Zeno spans {} (handed over {})",
                self.events, self.mode_changes, self.zeno_detected, self.zeno_handovers
            )?;
        }
        if self.contact_sweeps > 0 {
            write!(
                f,
                ", contact sweeps {} (residual {:.1e})",
                self.contact_sweeps, self.contact_residual
            )?;
        }
        if self.resting_energy_dropped != 0.0 {
            write!(
                f,
                ", energy dropped resting {:.3e}",
                self.resting_energy_dropped
            )?;
        }
        Ok(())
    }
}
