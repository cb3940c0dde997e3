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

/// [`LoadedSlider`]'s mechanism (its default masses and length) with the rail's limit
/// fixed at `f`: a rail blind to the load it carries, to compare with.
#[derive(Mechanism, Clone, Copy, Debug, PartialEq)]
#[mechanism(gravity = [0.0, -9.81, 0.0])]
#[body(slider, mass = 2.0)]
#[joint(x: prismatic(x), parent = world, child = slider)]
#[body(bob, mass = 1.0, com = [0.0, -0.5, 0.0])]
#[joint(swing: revolute(z), parent = slider, child = bob)]
#[friction(x, f_crit = f)]
pub struct FixedLimitSlider {
    pub f: f64,
}

impl FixedLimitSlider {
    /// The limit `μ (m_c + m_p) g` of `slider` at rest (its masses and length must be
    /// the defaults this mechanism is written with).
    pub fn resting_load_of(slider: &LoadedSlider) -> FixedLimitSlider {
        let d = LoadedSlider::default();
        assert_eq!(
            (slider.mc, slider.mp, slider.l, slider.g),
            (d.mc, d.mp, d.l, d.g),
            "FixedLimitSlider is written with LoadedSlider's default masses and length"
        );
        FixedLimitSlider {
            f: slider.mu * (slider.mc + slider.mp) * slider.g,
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
