use filippov::Mechanism;

/// A slider on a rail with a pendulum hanging from it, the rail's friction a bearing:
/// its limit is `μ |F_⊥|`, with `F_⊥` the force the rail carries across its axis — the
/// slider's and the swinging pendulum's weight and the pendulum's centripetal pull
/// (theory §8). The slider (mass `mc`) moves along `x`; the pendulum (a point mass `mp`
/// on a massless rod of length `l`) swings about `z` by `swing` from hanging straight
/// down. The same mechanism as [`CartOnRail`](super::CartOnRail) with the cart held on
/// the rail by its joint instead of resting on it through contacts.
#[derive(Mechanism, Clone, Copy, Debug, PartialEq)]
#[mechanism(gravity = [0.0, -g, 0.0])]
#[body(slider, mass = mc)]
#[joint(x: prismatic(x), parent = world, child = slider)]
#[body(bob, mass = mp, com = [0.0, -l, 0.0])]
#[joint(swing: revolute(z), parent = slider, child = bob)]
#[friction(x, mu = mu)]
pub struct LoadedSlider {
    pub mc: f64,
    pub mp: f64,
    pub l: f64,
    pub mu: f64,
    pub g: f64,
}

impl Default for LoadedSlider {
    /// A 2 kg slider, a 1 kg pendulum 0.5 m long, `μ = 0.2` (as `CartOnRail`).
    fn default() -> Self {
        LoadedSlider {
            mc: 2.0,
            mp: 1.0,
            l: 0.5,
            mu: 0.2,
            g: 9.81,
        }
    }
}

/// A pendulum on a journal bearing: a point mass `m` on a massless rod of length `l`
/// swings about `z` by `swing`, and the pin of radius `r` resists with the friction
/// torque `μ r |F_⊥|`, `F_⊥` the force the pin carries (weight and centripetal pull;
/// theory §8).
#[derive(Mechanism, Clone, Copy, Debug, PartialEq)]
#[mechanism(gravity = [0.0, -g, 0.0])]
#[body(bob, mass = m, com = [0.0, -l, 0.0])]
#[joint(swing: revolute(z), parent = world, child = bob)]
#[friction(swing, mu = mu, radius = r)]
pub struct JournalPendulum {
    pub m: f64,
    pub l: f64,
    pub mu: f64,
    pub r: f64,
    pub g: f64,
}

impl Default for JournalPendulum {
    /// A 1 kg bob on a 0.5 m rod, a pin 1 cm in radius, `μ = 0.3`.
    fn default() -> Self {
        JournalPendulum {
            m: 1.0,
            l: 0.5,
            mu: 0.3,
            r: 0.01,
            g: 9.81,
        }
    }
}
