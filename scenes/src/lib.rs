//! Canonical multibody scenes (theory.md §4), declared with the derive exactly as a user
//! would. Examples, tests, benchmarks and the report use these; their expansions are
//! snapshot-tested.

mod arm3;
mod double_pendulum;
mod lie;
mod lumped;
mod panda;
pub mod references;
mod s9;
mod tree;

pub use arm3::PlanarArm3;
pub use double_pendulum::DoublePendulum;
pub use lie::{BallChain, EulerBody, FreeBody, Satellite, SphericalBody};
pub use lumped::{
    BeltFriction, BilinearOscillator, BinghamBlock, BinghamOscillator, BouncingBall,
    CoulombOscillator, CubicBingham, DuffingBingham, FrictionChain, NonMonotoneMaxDissipation,
    NonMonotoneNoJumps, SupportedStop,
};
pub use panda::Panda;
pub use s9::PandaS9;
pub use tree::BranchedTree;
