//! Random planar contact scenes, shared by `scenes/tests/contact_agreement.rs` and the report:
//! boxes launched along level ground or inclines, balls dropped spinning, and rods
//! tipping over or dropped on an end (sticking, slipping both ways, landing), each with
//! random sizes, masses, friction and restitution, integrated event-driven and by
//! time-stepping at two steps, and checked by properties no closed form is needed for:
//! the energy never rises (no input acts), no contact penetrates beyond the position
//! tolerance (event-driven), and time-stepping converges to the event-driven run at
//! first order (h = 1e-3, 1e-4, 1e-5).

use filippov::nalgebra::SVector;
use filippov::prelude::*;
use filippov::runtime::contacts::Contacts;
use filippov::runtime::{
    Method, NonSmoothProblem, Options, Solution, contact_event_driven, contact_time_stepping,
};
use filippov::scenes::{FallingRod, SlidingBox, SpinningBall};

type V3 = SVector<f64, 3>;

/// One random scene: a box or a ball with its start.
#[derive(Clone, Debug)]
pub enum Scene {
    Box(SlidingBox, V3, V3),
    Ball(SpinningBall, V3, V3),
    Rod(FallingRod, V3, V3),
}

/// SplitMix64 in `[lo, hi)` (also the spatial suite's).
pub struct Draw(pub u64);

impl Draw {
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        lo + (hi - lo) * ((z >> 11) as f64 / (1u64 << 53) as f64)
    }
}

/// Scene number `seed`: boxes, balls and rods in turn.
pub fn scene(seed: u64) -> Scene {
    let mut d = Draw(seed.wrapping_mul(0x2545_F491_4F6C_DD1D) ^ 0x5EED);
    if seed % 3 == 2 {
        // A rod on its foot (or just above it), leaning, turning; friction below
        // Painlevé's least threshold 4/3, so the contact problem is always well posed.
        let s = FallingRod {
            m: d.uniform(0.2, 2.0),
            l: d.uniform(0.1, 0.6),
            mu: d.uniform(0.1, 0.8),
            e: d.uniform(0.0, 0.5),
            g: 9.81,
        };
        let lean = d.uniform(0.1, 1.2);
        let lift = if d.uniform(0.0, 1.0) < 0.5 {
            d.uniform(0.0, 0.05)
        } else {
            0.0
        };
        let q0 = V3::from([-s.l * lean.sin(), s.l * lean.cos() + lift, lean]);
        let v0 = V3::from([0.0, 0.0, d.uniform(-1.0, 3.0)]);
        Scene::Rod(s, q0, v0)
    } else if seed % 3 == 0 {
        // A box wider than μ times its height, so that it slides without tipping.
        let a = d.uniform(0.1, 0.4);
        let mu = d.uniform(0.1, 0.8);
        let b = d.uniform(0.05, 0.9 * a / mu).min(0.5);
        let s = SlidingBox {
            m: d.uniform(0.5, 3.0),
            a,
            b,
            mu,
            e: d.uniform(0.0, 0.8),
            phi: d.uniform(0.0, 0.5),
            g: 9.81,
        };
        let (sp, cp) = s.phi.sin_cos();
        let q0 = V3::from([-s.b * sp, s.b * cp, s.phi]);
        // Launched along the slope, up or down.
        let speed = d.uniform(-2.0, 2.0);
        let v0 = V3::from([speed * cp, speed * sp, 0.0]);
        Scene::Box(s, q0, v0)
    } else {
        let s = SpinningBall {
            m: d.uniform(0.2, 2.0),
            r: d.uniform(0.02, 0.2),
            mu: d.uniform(0.05, 0.8),
            e: d.uniform(0.0, 0.8),
            g: 9.81,
        };
        let q0 = V3::from([0.0, s.r + d.uniform(0.0, 0.3), 0.0]);
        let v0 = V3::from([d.uniform(-1.0, 1.0), 0.0, d.uniform(-30.0, 30.0)]);
        Scene::Ball(s, q0, v0)
    }
}

/// What one scene's runs showed.
#[derive(Clone, Debug)]
pub struct Checked {
    pub seed: u64,
    pub kind: &'static str,
    /// The largest rise of the energy over the event-driven run, relative to its scale.
    pub energy_rise: f64,
    /// The deepest penetration of any contact over the event-driven run.
    pub penetration: f64,
    /// The largest friction force beyond its cone, `|λ_T| − μ_s λ_N`, over the
    /// event-driven run, relative to the weight.
    pub cone_excess: f64,
    /// Time-stepping's largest position difference from the event-driven run over the
    /// sample times, at [`STEPS`].
    pub distance: [f64; 3],
    /// The event-driven run's switches.
    pub switches: usize,
    /// A run's error, if one failed.
    pub failure: Option<String>,
}

impl Checked {
    /// Passive, not penetrating beyond the tolerance, time-stepping converging at first
    /// order over one of the two decades of steps (or already within round-off). One
    /// decade alone can hide it: two first-order errors of opposite sign (the θ-method's
    /// lag, a sliding reversal's stuck step) can cancel at one step size.
    pub fn passed(&self) -> bool {
        let [d1, d2, d3] = self.distance;
        self.failure.is_none()
            && self.energy_rise <= 1e-8
            && self.penetration <= 1e-8
            && self.cone_excess <= 1e-9
            && (d2 <= 0.3 * d1 || d3 <= 0.3 * d2 || d3 <= 1e-9)
    }
}

/// The horizon of every run.
pub const HORIZON: f64 = 0.5;

/// Time-stepping's steps, compared with the event-driven run.
pub const STEPS: [f64; 3] = [1e-3, 1e-4, 1e-5];

fn energy<S, const K: usize, const T: usize>(s: &S, g: f64, m: f64, y: &[f64]) -> f64
where
    S: Mechanism<3> + Contacts<3, K, T>,
{
    let q = V3::from_column_slice(&y[..3]);
    let v = V3::from_column_slice(&y[3..6]);
    0.5 * v.dot(&(s.mass_matrix(&q) * v)) + m * g * y[1]
}

fn check_scene<S, const K: usize, const T: usize>(
    s: &S,
    (g, m): (f64, f64),
    q0: V3,
    v0: V3,
    seed: u64,
    kind: &'static str,
) -> Checked
where
    S: Mechanism<3> + Contacts<3, K, T>,
{
    let input = |_: f64, _: &V3, _: &V3| V3::zeros();
    let p = NonSmoothProblem::new(0.0, HORIZON, q0, v0);
    let method = Method::Dopri5(Options {
        max_steps: 200_000,
        ..Options::tolerances(1e-10, 1e-12)
    });
    let mut out = Checked {
        seed,
        kind,
        energy_rise: 0.0,
        penetration: 0.0,
        cone_excess: 0.0,
        distance: [f64::NAN; 3],
        switches: 0,
        failure: None,
    };
    let ed = match contact_event_driven(s, &input, &p, &method) {
        Ok(sol) => sol,
        Err(e) => {
            out.failure = Some(format!("event-driven: {e}"));
            return out;
        }
    };
    out.switches = ed.switches.len();
    let e0 = energy(s, g, m, ed.state(0));
    let scale = e0.abs().max(m * g * 0.1).max(1e-12);
    for (_, y) in ed.rows() {
        out.energy_rise = out.energy_rise.max((energy(s, g, m, y) - e0) / scale);
        let gaps = s.contact_gaps(&V3::from_column_slice(&y[..3]));
        out.penetration = out.penetration.max(-gaps.min());
        // Columns after the state: λ_N of each contact, then λ_T of each tangent.
        let mu = s.contact_static_friction();
        for r in 0..T {
            let k = S::TANGENT_OF[r];
            let excess = y[6 + K + r].abs() - mu[k] * y[6 + k];
            out.cone_excess = out.cone_excess.max(excess / (m * g));
        }
    }
    let sample = |sol: &Solution, t: f64| sol.at(t).expect("inside the run");
    for (i, h) in STEPS.into_iter().enumerate() {
        match contact_time_stepping(s, &input, &p, h) {
            Ok(ts) => {
                out.distance[i] = (0..=50)
                    .map(|k| {
                        let t = HORIZON * k as f64 / 50.0;
                        let (a, b) = (sample(&ed, t), sample(&ts, t));
                        (0..3).map(|j| (a[j] - b[j]).abs()).fold(0.0, f64::max)
                    })
                    .fold(0.0, f64::max);
            }
            Err(e) => {
                out.failure = Some(format!("time-stepping h = {h}: {e}"));
                return out;
            }
        }
    }
    out
}

/// Scene `seed`, generated, run and checked.
pub fn run(seed: u64) -> Checked {
    match scene(seed) {
        Scene::Box(s, q0, v0) => check_scene(&s, (s.g, s.m), q0, v0, seed, "box"),
        Scene::Ball(s, q0, v0) => check_scene(&s, (s.g, s.m), q0, v0, seed, "ball"),
        Scene::Rod(s, q0, v0) => check_scene(&s, (s.g, s.m), q0, v0, seed, "rod"),
    }
}
