//! Coulomb friction: at rest `|f| ≤ f_crit`, slipping `f = f_crit sgn v` (theory.md §3).
//! Its graph is maximal monotone: a vertical segment at `v = 0` and two levels; its
//! modes, switching functions and graph are those of every [`Friction`] law.

use super::dashpot::{self, Friction};

/// Coulomb friction with critical force `f_crit ≥ 0`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Coulomb {
    pub f_crit: f64,
}

impl Friction for Coulomb {
    fn check(&self) -> Result<(), String> {
        dashpot::check_limit("critical force f_crit", self.f_crit)
    }

    fn levels(&self) -> (f64, f64) {
        (self.f_crit, self.f_crit)
    }
}
