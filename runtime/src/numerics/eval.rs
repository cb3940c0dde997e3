//! Counted, checked evaluation of a system: what every method calls instead of the
//! system itself, so that statistics and non-finite checks live in one place.

use crate::numerics::check_finite;
use crate::{ErrorKind, OdeSystem, Stats};

/// A system being integrated, with the statistics its evaluations are counted in.
pub struct Eval<'a, S: ?Sized> {
    pub system: &'a S,
    pub stats: &'a mut Stats,
}

impl<'a, S: OdeSystem + ?Sized> Eval<'a, S> {
    pub fn new(system: &'a S, stats: &'a mut Stats) -> Self {
        Eval { system, stats }
    }

    /// `dy = f(t, y)`, counted and checked for non-finite values.
    pub fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), ErrorKind> {
        self.stats.rhs_evaluations += 1;
        self.system.rhs(t, y, dy);
        check_finite(t, dy)
    }
}
