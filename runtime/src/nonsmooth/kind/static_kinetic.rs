//! Static and kinetic friction (theory.md §3): at rest the element holds any force up to
//! `f_static`; slipping it resists with `f_kinetic ≤ f_static`, so the force drops at
//! breakaway — a Filippov system with a jump in the force itself, not only in its
//! direction. Where a body at rest could both stay and slip (the holding force between
//! `f_kinetic` and `f_static`), rest persists: the mode selection takes the stick, and the
//! implicit step the rest segment.
//!
//! The stick switches where the holding force reaches `f_static` (breakaway), a slip
//! where the velocity returns to `0` — the switching functions of every [`Friction`] law.

use super::dashpot::{self, Friction};

/// Static/kinetic friction: held up to `f_static`, slipping at `f_kinetic`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct StaticKinetic {
    pub f_static: f64,
    pub f_kinetic: f64,
}

impl Friction for StaticKinetic {
    fn check(&self) -> Result<(), String> {
        dashpot::check_limit("static friction force f_static", self.f_static)?;
        dashpot::check_limit("kinetic friction force f_kinetic", self.f_kinetic)?;
        if self.f_kinetic > self.f_static {
            return Err(format!(
                "kinetic friction f_kinetic = {} exceeds static friction f_static = {}; \
                 the force held at rest is at least the force while slipping",
                self.f_kinetic, self.f_static
            ));
        }
        Ok(())
    }

    fn levels(&self) -> (f64, f64) {
        (self.f_static, self.f_kinetic)
    }

    fn rest_persists(&self) -> bool {
        true
    }
}
