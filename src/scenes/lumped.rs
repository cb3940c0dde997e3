//! The thesis's lumped systems (theory.md §3–4, scenes S1–S7): a mass on one prismatic
//! joint `x`, a linear spring to the wall, and a non-smooth element in parallel. External
//! forces `F(t)` are given at run time as the input.

use filippov::Mechanism;

/// S1: linear Bingham dash-pot (`v = (f − sgn(f) f_crit)/η` outside the dead zone).
#[derive(Mechanism, Clone, Copy, Debug, PartialEq)]
#[mechanism(emit = all)]
#[body(block, mass = m)]
#[joint(x: prismatic(x), parent = world, child = block)]
#[spring(x, k = k)]
#[bingham(x, f_crit = f_crit, eta = eta)]
pub struct BinghamOscillator {
    pub m: f64,
    pub k: f64,
    pub f_crit: f64,
    pub eta: f64,
}

/// S2, S3: Bingham dash-pot with the cubic law of thesis eq. 4.7b,
/// `v = γ f² (f − sgn(f) f_crit)`.
#[derive(Mechanism, Clone, Copy, Debug, PartialEq)]
#[mechanism(emit = all)]
#[body(block, mass = m)]
#[joint(x: prismatic(x), parent = world, child = block)]
#[spring(x, k = k)]
#[bingham(x, f_crit = f_crit, law = gamma * f * f * (f - f_crit))]
pub struct CubicBingham {
    pub m: f64,
    pub k: f64,
    pub f_crit: f64,
    pub gamma: f64,
}

/// S4, approach 1: the non-monotone law of thesis eq. 4.9b,
/// `v = (1 + 0.1 (f² − 4)(f² − 9)) (f − sgn(f) f_crit)`, without velocity jumps.
#[derive(Mechanism, Clone, Copy, Debug, PartialEq)]
#[mechanism(emit = all)]
#[body(block, mass = m)]
#[joint(x: prismatic(x), parent = world, child = block)]
#[spring(x, k = k)]
#[bingham(x, f_crit = f_crit, law = (1.0 + 0.1 * (f * f - 4.0) * (f * f - 9.0)) * (f - f_crit), select = no_jumps)]
pub struct NonMonotoneNoJumps {
    pub m: f64,
    pub k: f64,
    pub f_crit: f64,
}

/// S4, approach 2: the same law with maximal dissipation.
#[derive(Mechanism, Clone, Copy, Debug, PartialEq)]
#[mechanism(emit = all)]
#[body(block, mass = m)]
#[joint(x: prismatic(x), parent = world, child = block)]
#[spring(x, k = k)]
#[bingham(x, f_crit = f_crit, law = (1.0 + 0.1 * (f * f - 4.0) * (f * f - 9.0)) * (f - f_crit), select = max_dissipation)]
pub struct NonMonotoneMaxDissipation {
    pub m: f64,
    pub k: f64,
    pub f_crit: f64,
}

/// A block on a spring lying on a moving belt, with static and kinetic friction between
/// them (theory.md §5), in the belt's frame: the coordinate is `y = x − v_b t`; the input
/// `−k v_b t` adds the rest of the spring's force.
#[derive(Mechanism, Clone, Copy, Debug, PartialEq)]
#[mechanism(emit = all)]
#[body(block, mass = m)]
#[joint(y: prismatic(x), parent = world, child = block)]
#[spring(y, k = k)]
#[friction(y, f_static = f_static, f_kinetic = f_kinetic)]
pub struct BeltFriction {
    pub m: f64,
    pub k: f64,
    pub f_static: f64,
    pub f_kinetic: f64,
}

/// S5, S6: Coulomb friction.
#[derive(Mechanism, Clone, Copy, Debug, PartialEq)]
#[mechanism(emit = all)]
#[body(block, mass = m)]
#[joint(x: prismatic(x), parent = world, child = block)]
#[spring(x, k = k)]
#[friction(x, f_crit = f_crit)]
pub struct CoulombOscillator {
    pub m: f64,
    pub k: f64,
    pub f_crit: f64,
}

/// S7: linear Bingham dash-pot and a stop at `x = l` backed by a massless support on a
/// spring `k_support`.
#[derive(Mechanism, Clone, Copy, Debug, PartialEq)]
#[mechanism(emit = all)]
#[body(block, mass = m)]
#[joint(x: prismatic(x), parent = world, child = block)]
#[spring(x, k = k)]
#[bingham(x, f_crit = f_crit, eta = eta)]
#[stop(x, max = l, k_support = k_support)]
pub struct SupportedStop {
    pub m: f64,
    pub k: f64,
    pub f_crit: f64,
    pub eta: f64,
    pub l: f64,
    pub k_support: f64,
}

/// A mass falling onto a rigid floor at `x = 0` with Newton restitution `e` (Zeno
/// bouncing under gravity along −x).
#[derive(Mechanism, Clone, Copy, Debug, PartialEq)]
#[mechanism(emit = all, gravity = [-g, 0.0, 0.0])]
#[body(ball, mass = m)]
#[joint(x: prismatic(x), parent = world, child = ball)]
#[stop(x, min = 0.0, restitution = e)]
pub struct BouncingBall {
    pub m: f64,
    pub g: f64,
    pub e: f64,
}

/// A Bingham dash-pot alone (no spring): under a constant force `F > f_crit` the
/// velocity approaches `(F − f_crit)/η` (theory §5).
#[derive(Mechanism, Clone, Copy, Debug, PartialEq)]
#[mechanism(emit = all)]
#[body(block, mass = m)]
#[joint(x: prismatic(x), parent = world, child = block)]
#[bingham(x, f_crit = f_crit, eta = eta)]
pub struct BinghamBlock {
    pub m: f64,
    pub f_crit: f64,
    pub eta: f64,
}

/// S7's elastic case: spring and spring-backed stop, no dash-pot (a bilinear
/// oscillator with a closed-form period, theory §5).
#[derive(Mechanism, Clone, Copy, Debug, PartialEq)]
#[mechanism(emit = all)]
#[body(block, mass = m)]
#[joint(x: prismatic(x), parent = world, child = block)]
#[spring(x, k = k)]
#[stop(x, max = l, k_support = k_support)]
pub struct BilinearOscillator {
    pub m: f64,
    pub k: f64,
    pub l: f64,
    pub k_support: f64,
}

/// Two blocks in a chain, each on a spring and with Coulomb friction on its own
/// coordinate (the second coordinate is relative to the first): coupled stick–slip.
#[derive(Mechanism, Clone, Copy, Debug, PartialEq)]
#[mechanism(emit = all)]
#[body(lower, mass = m1)]
#[joint(x1: prismatic(x), parent = world, child = lower)]
#[body(upper, mass = m2)]
#[joint(x2: prismatic(x), parent = lower, child = upper)]
#[spring(x1, k = k1)]
#[spring(x2, k = k2)]
#[friction(x1, f_crit = f1)]
#[friction(x2, f_crit = f2)]
pub struct FrictionChain {
    pub m1: f64,
    pub m2: f64,
    pub k1: f64,
    pub k2: f64,
    pub f1: f64,
    pub f2: f64,
}

impl FrictionChain {
    /// The stiff chain of the extreme suite: unit masses, `k1 = 1`, friction levels 0.1
    /// and 0.2, and the second block on a spring `k2` times stiffer than the first.
    pub fn stiff(k2: f64) -> Self {
        FrictionChain {
            m1: 1.0,
            m2: 1.0,
            k1: 1.0,
            k2,
            f1: 0.1,
            f2: 0.2,
        }
    }
}

/// A hardening (Duffing) spring declared by its potential, `U = ½ k x² + ¼ k3 x⁴`, with a
/// linear Bingham dash-pot: the spring force `−dU/dx` is derived symbolically.
#[derive(Mechanism, Clone, Copy, Debug, PartialEq)]
#[mechanism(emit = all)]
#[body(block, mass = m)]
#[joint(x: prismatic(x), parent = world, child = block)]
#[spring(x, potential = 0.5 * k * x * x + 0.25 * k3 * x.powi(4))]
#[bingham(x, f_crit = f_crit, eta = eta)]
pub struct DuffingBingham {
    pub m: f64,
    pub k: f64,
    pub k3: f64,
    pub f_crit: f64,
    pub eta: f64,
}
