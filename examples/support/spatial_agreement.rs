//! Random spatial contact scenes for time-stepping on the friction cone, shared by
//! `scenes/tests/contact_agreement.rs` and the report (beside `contact_agreement.rs`, whose
//! random draws it shares): three-legged tables on level ground or
//! inclines, launched sliding and spinning or dropped tilted, and pucks thrown onto
//! inclines, each with random sizes, masses, friction and restitution. The event-driven
//! integrator does not take spatial contacts, so the checks are properties: every step's
//! contact problem solved (residual at most the solver's tolerance), the energy at the
//! end no more than at the start (no input acts), no contact sinking deeper than 1e-8
//! at the finest step, and first-order convergence in `h` (2e-3, 2e-4 against 2e-5; where
//! that first decade does not shrink the distance — a coarsest step too coarse for the
//! scene's impacts — the second, 2e-4 and 2e-5 against 4e-6).

use filippov::nalgebra::{Rotation3, SVector, Vector3};
use filippov::prelude::*;
use filippov::runtime::contacts::Contacts;
use filippov::runtime::{NonSmoothProblem, Solution, Unforced, contact_time_stepping};
use filippov::scenes::{Puck, Table};

use super::contact_agreement::Draw;

/// The horizon of every run.
pub const HORIZON: f64 = 0.2;

/// The steps compared (the last is the reference).
pub const STEPS: [f64; 3] = [2e-3, 2e-4, 2e-5];

/// What one scene's runs showed.
#[derive(Clone, Debug)]
pub struct Checked {
    pub seed: u64,
    pub kind: &'static str,
    /// The largest contact-problem residual of any run.
    pub residual: f64,
    /// Energy at the end less at the start, relative to its scale (≤ 0: passive).
    pub energy_gain: f64,
    /// The deepest gap of any contact over the finest run.
    pub sinking: f64,
    /// Largest coordinate difference from the finest run over the horizon, at the two
    /// coarser steps.
    pub distance: [f64; 2],
    /// Where the first decade does not shrink the distance (a coarsest step too coarse
    /// for the scene's impacts), the differences of the two finer steps from a run at
    /// [`FINER`]: the second decade.
    pub finer: Option<[f64; 2]>,
    pub failure: Option<String>,
}

/// The reference of the second decade, run only where the first is not yet first order.
pub const FINER: f64 = 4e-6;

/// First order over a decade: the distance shrinks at least 0.3× (or is round-off).
fn first_order([d1, d2]: [f64; 2]) -> bool {
    d2 <= 0.3 * d1 || d2 <= 1e-9
}

impl Checked {
    /// Solved, passive, not sinking beyond one step's reach, first order (or within
    /// round-off of the reference).
    pub fn passed(&self) -> bool {
        self.failure.is_none()
            && self.residual <= 1e-12
            && self.energy_gain <= 1e-12
            && self.sinking <= 1e-8
            && self.first_order()
    }

    /// First order over the first decade, or (against the finer reference) the second.
    pub fn first_order(&self) -> bool {
        first_order(self.distance) || self.finer.is_some_and(first_order)
    }
}

fn check<S, const N: usize, const K: usize, const T: usize>(
    s: &S,
    (q0, v0): (SVector<f64, N>, SVector<f64, N>),
    energy: impl Fn(&[f64]) -> f64,
    (seed, kind): (u64, &'static str),
) -> Checked
where
    S: Mechanism<N> + Contacts<N, K, T>,
{
    let mut out = Checked {
        seed,
        kind,
        residual: 0.0,
        energy_gain: 0.0,
        sinking: 0.0,
        distance: [f64::NAN; 2],
        finer: None,
        failure: None,
    };
    let p = NonSmoothProblem::new(0.0, HORIZON, q0, v0);
    let mut runs: Vec<Solution> = Vec::new();
    for h in STEPS {
        let sol = match contact_time_stepping(s, &Unforced, &p, h) {
            Ok(sol) => sol,
            Err(e) => {
                out.failure = Some(format!("h = {h}: {e}"));
                return out;
            }
        };
        out.residual = out.residual.max(sol.stats.contact_residual);
        let (e0, e1) = (energy(sol.state(0)), energy(sol.last().expect("rows").1));
        let scale = e0.abs().max(1e-12);
        out.energy_gain = out.energy_gain.max((e1 - e0) / scale);
        if h == STEPS[2] {
            for (_, y) in sol.rows() {
                let gaps = s.contact_gaps(&SVector::from_column_slice(&y[..N]));
                out.sinking = out.sinking.max(-gaps.min());
            }
        }
        runs.push(sol);
    }
    let distance = |run: &Solution, reference: &Solution| {
        (0..=30)
            .map(|k| {
                let t = HORIZON * k as f64 / 30.0;
                let (a, b) = (run.at(t).expect("inside"), reference.at(t).expect("inside"));
                (0..N).map(|j| (a[j] - b[j]).abs()).fold(0.0, f64::max)
            })
            .fold(0.0, f64::max)
    };
    out.distance = [distance(&runs[0], &runs[2]), distance(&runs[1], &runs[2])];
    if !first_order(out.distance) {
        match contact_time_stepping(s, &Unforced, &p, FINER) {
            Ok(finer) => {
                out.residual = out.residual.max(finer.stats.contact_residual);
                out.finer = Some([distance(&runs[1], &finer), distance(&runs[2], &finer)]);
            }
            Err(e) => out.failure = Some(format!("h = {FINER}: {e}")),
        }
    }
    out
}

/// Scene `seed`, generated, run and checked: tables (two in three) and pucks.
pub fn run(seed: u64) -> Checked {
    let mut d = Draw(seed.wrapping_mul(0x2545_F491_4F6C_DD1D) ^ 0x7AB1E);
    if seed % 3 == 2 {
        let s = Puck {
            m: d.uniform(0.2, 2.0),
            mu: d.uniform(0.05, 0.8),
            e: d.uniform(0.0, 0.6),
            phi: d.uniform(0.0, 0.5),
            g: 9.81,
        };
        let q0 = SVector::<f64, 3>::from([0.0, 0.0, d.uniform(0.0, 0.05)]);
        let v0 = SVector::<f64, 3>::from([
            d.uniform(-2.0, 2.0),
            d.uniform(-2.0, 2.0),
            d.uniform(-1.0, 0.0),
        ]);
        let energy = |y: &[f64]| {
            0.5 * s.m * (y[3] * y[3] + y[4] * y[4] + y[5] * y[5])
                + s.m * s.g * y[2]
                + s.m * s.g * 1.0
        };
        return check(&s, (q0, v0), energy, (seed, "puck"));
    }
    let mu = d.uniform(0.1, 0.8);
    let r = d.uniform(0.15, 0.4);
    // Legs short enough that the friction's moment does not tip it (d μ < r / 2).
    let s = Table {
        m: d.uniform(0.5, 5.0),
        a: d.uniform(0.2, 0.5),
        c: d.uniform(0.01, 0.05),
        r,
        d: d.uniform(0.05, 0.8) * r / (2.0 * mu),
        mu,
        e: d.uniform(0.0, 0.5),
        phi: d.uniform(0.0, 0.35),
        g: 9.81,
    };
    let lift = if d.uniform(0.0, 1.0) < 0.5 {
        d.uniform(0.0, 0.03)
    } else {
        0.0
    };
    // Half the tables on level ground, spun about the vertical; the others on their
    // incline, not spun (a yaw rate about the world's z would turn the legs out of the
    // plane).
    let level = d.uniform(0.0, 1.0) < 0.5;
    let s = Table {
        phi: if level { 0.0 } else { s.phi },
        ..s
    };
    let (sp, cp) = s.phi.sin_cos();
    // Turned by ψ about the plane's normal and tilted no more than the lift lets every
    // leg clear the ground: R = Rx(φ) Rz(ψ) Ry(tilt), read back as the chain's yaw (z),
    // pitch (y), roll (x).
    let (psi, tilt) = (d.uniform(-1.0, 1.0), d.uniform(-0.5, 0.5) * lift / r);
    let rot = Rotation3::from_axis_angle(&Vector3::x_axis(), s.phi)
        * Rotation3::from_axis_angle(&Vector3::z_axis(), psi)
        * Rotation3::from_axis_angle(&Vector3::y_axis(), tilt);
    let (roll, pitch, yaw) = rot.euler_angles();
    let q0 =
        SVector::<f64, 6>::from([0.0, -(s.d + lift) * sp, (s.d + lift) * cp, yaw, pitch, roll]);
    let v0 = SVector::<f64, 6>::from([
        d.uniform(-1.5, 1.5),
        d.uniform(-1.5, 1.5) * cp,
        d.uniform(-1.5, 1.5) * sp,
        if level { d.uniform(-5.0, 5.0) } else { 0.0 },
        0.0,
        0.0,
    ]);
    let energy = |y: &[f64]| {
        let q = SVector::<f64, 6>::from_column_slice(&y[..6]);
        let v = SVector::<f64, 6>::from_column_slice(&y[6..12]);
        0.5 * v.dot(&(s.mass_matrix(&q) * v)) + s.m * s.g * (y[2] + 1.0)
    };
    check(&s, (q0, v0), energy, (seed, "table"))
}
