//! Cost counters of one integration.

use std::fmt;

/// What an integration cost. Compared across methods and versions instead of timings.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
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
        )
    }
}
