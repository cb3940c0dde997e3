//! The canonical multibody scenes of `docs/theory.md` §4 (feature `scenes`), declared with
//! the derive exactly as a user would: the theory's lumped scenes S1–S7 with their
//! non-smooth elements, the double pendulum, a planar three-link arm, a branched tree,
//! the Panda (as attributes, and as S9 with friction and stops), bodies on spherical
//! and free joints, closed linkages (a four-bar and a slider-crank, §7), and bodies touching the ground
//! through contacts (§8), and joints whose friction carries their load (bearings, §8). The
//! examples run on them; `references` holds the closed forms and reference solutions
//! the tests and the report compare against. With the `urdf` feature too: the UR5,
//! a three-link arm, Solo12 and a humanoid, read from `robots/`. A program of its own enables them with
//! `filippov = { version = "0.1", features = ["scenes"] }`; without the feature none of
//! them is compiled.

mod arm3;
mod bearings;
mod contacts;
mod double_pendulum;
mod lie;
mod loops;
mod lumped;
mod panda;
pub mod references;
mod resting_arm;
#[cfg(feature = "urdf")]
mod robots;
mod s9;
mod tree;

pub use arm3::PlanarArm3;
pub use bearings::{FixedLimitSlider, JournalPendulum, LoadedSlider};
pub use contacts::{CartOnRail, FallingRod, Puck, SlidingBox, SpinningBall, Table};
pub use double_pendulum::DoublePendulum;
pub use lie::{BallChain, EulerBody, FreeBody, Satellite, SphericalBody};
pub use loops::{AndrewsSqueezer, Delta, FourBar, SliderCrank};
pub use lumped::{
    BeltFriction, BilinearOscillator, BinghamBlock, BinghamOscillator, BouncingBall,
    CoulombOscillator, CubicBingham, DuffingBingham, FrictionChain, NonMonotoneMaxDissipation,
    NonMonotoneNoJumps, SupportedStop,
};
pub use panda::Panda;
pub use resting_arm::RestingArm;
#[cfg(feature = "urdf")]
pub use robots::{Humanoid, Solo12, ThreeLinkArm, Ur5};
pub use s9::PandaS9;
pub use tree::BranchedTree;
