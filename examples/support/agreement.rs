//! The randomized agreement suite: random chains with random non-smooth elements,
//! integrated event-driven and by time-stepping at two steps, checked against each other
//! and for passivity. Shared by `tests/agreement.rs` (a few dozen scenes) and the report
//! (a thousand and more).
//!
//! A scene (from its seed): a planar or spatial chain of 1–7 revolute or prismatic
//! joints (rod-like links, random masses and lengths), gravity or not, springs and
//! dampers on some joints; one or two elements — Coulomb friction, linear, cubic or
//! non-monotone Bingham (S4's law, either selection), a rigid stop with restitution or a
//! spring-backed stop — and a sinusoidal
//! force on one joint or none. The initial state: moving, stuck (an element's coordinate
//! at rest), at rest on a stop, or penetrating a rigid stop (which both integrators must
//! refuse).
//!
//! A scene passes when event-driven (DOPRI5, rtol 1e-8, within 20,000 step attempts)
//! completes, time-stepping (θ = 1) at h = 1e-3 and 2.5e-4 completes and converges to
//! event-driven at the final time (the distance falls by at least 0.6 for the 4 times
//! smaller step — first order gives 0.25 — or is below 1e-4 already), and the
//! event-driven run is passive: the energy gained is at most the
//! work of the applied force (friction, dampers and impacts only dissipate). A typed
//! error of event-driven counts apart, with its message; anything else is a failure.

use filippov::nalgebra::{Matrix3, SVector, Vector3};
use filippov::runtime::nonsmooth::{Element, ElementKind, Law, Selection, Side, StopKind};
use filippov::runtime::numeric::{Damper, JointKind, Link, Model, Scene, Spring};
use filippov::runtime::{
    ErrorKind, NonSmoothMethod, NonSmoothProblem, Options, SmoothMethod, Solution, solve_nonsmooth,
};

/// What one scene came to.
#[derive(Clone, Debug)]
pub enum Verdict {
    Passed,
    /// Event-driven ended with a typed error (the message).
    TypedError(String),
    /// A check failed (what failed).
    Failed(String),
}

/// SplitMix64: a small seeded generator (also the report's, for the URDF states).
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Rng {
        Rng(seed)
    }
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
    fn below(&mut self, n: u64) -> usize {
        (self.next() % n) as usize
    }
}

/// The cubic Bingham law of theory S2/S3 (f_crit = 1): v = f² (f − 1) for f > 1.
fn cubic(f: f64) -> (f64, f64) {
    (f * f * (f - 1.0), 3.0 * f * f - 2.0 * f)
}

/// The non-monotone law of theory S4 (f_crit = 1): v = (1 + 0.1 (f² − 4)(f² − 9)) (f − 1)
/// for f > 1, which folds back between f ≈ 2 and 3.
fn non_monotone(f: f64) -> (f64, f64) {
    let g = 1.0 + 0.1 * (f * f - 4.0) * (f * f - 9.0);
    let dg = 0.1 * (2.0 * f * (f * f - 9.0) + 2.0 * f * (f * f - 4.0));
    (g * (f - 1.0), dg * (f - 1.0) + g)
}

/// How the initial state is chosen.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Start {
    Moving,
    Stuck,
    RestingOnStop,
    Penetrating,
}

/// The random description of a scene (everything but the element count and dof, which
/// pick the monomorphised scene type).
struct Description {
    model: Model,
    elements: Vec<Element>,
    q0: Vec<f64>,
    v0: Vec<f64>,
    force: (usize, f64, f64),
    start: Start,
}

fn describe(seed: u64) -> Description {
    let mut r = Rng::new(seed);
    let n = 1 + r.below(7);
    let planar = r.below(2) == 0;
    let gravity = if r.below(3) == 0 {
        Vector3::zeros()
    } else {
        Vector3::new(0.0, -9.81, 0.0)
    };
    let axes = [Vector3::x(), Vector3::y(), Vector3::z()];
    let mut links = Vec::new();
    let mut springs = Vec::new();
    let mut dampers = Vec::new();
    let mut moved = Vec::new();
    for i in 0..n {
        let (m, l) = (r.uniform(0.5, 2.0), r.uniform(0.3, 1.0));
        let axis = if planar {
            Vector3::z()
        } else {
            axes[r.below(3)]
        };
        let joint = if r.below(5) == 0 {
            JointKind::Prismatic { axis }
        } else {
            JointKind::Revolute { axis }
        };
        let i_rod = m * l * l / 12.0;
        // The inertia the joint moves (about the axis through the joint for a revolute
        // joint, the mass for a prismatic one; the link alone): stiffnesses are drawn
        // relative to it, so natural frequencies stay below ~30 rad/s, where time-stepping
        // at the compared steps is in its first-order regime (h ω ≤ 0.03) rather than in
        // its numerical damping (θ = 1 damps h ω ≳ 0.1 visibly within a second).
        let inertia_moved = match (&joint, axis == Vector3::x()) {
            (JointKind::Prismatic { .. }, _) => m,
            (_, true) => 0.06 * i_rod,
            _ => i_rod + m * l * l / 4.0,
        };
        moved.push(inertia_moved);
        links.push(Link {
            name: format!("b{i}"),
            parent: i.checked_sub(1),
            joint,
            coordinate: Some(i),
            origin_xyz: if i == 0 {
                Vector3::zeros()
            } else {
                Vector3::new(l, 0.0, 0.0)
            },
            origin_rpy: Vector3::zeros(),
            mass: m,
            com: Vector3::new(l / 2.0, 0.0, 0.0),
            // A rod of radius l/10 about its axis (x): m (l/10)²/2 = 0.06 i_rod.
            inertia: Matrix3::from_diagonal(&Vector3::new(0.06 * i_rod, i_rod, i_rod)),
        });
        if r.below(3) == 0 {
            springs.push(Spring {
                coordinate: i,
                stiffness: r.uniform(1.0, 50.0) * inertia_moved,
                rest: 0.0,
            });
        }
        if r.below(4) == 0 {
            dampers.push(Damper {
                coordinate: i,
                damping: r.uniform(0.01, 0.5) * inertia_moved,
            });
        }
    }
    let model = Model {
        gravity,
        links,
        springs,
        dampers,
    };
    let mut q0: Vec<f64> = (0..n).map(|_| r.uniform(-0.5, 0.5)).collect();
    let mut v0: Vec<f64> = (0..n).map(|_| r.uniform(-1.0, 1.0)).collect();
    let count = 1 + r.below(2);
    let mut elements: Vec<Element> = Vec::new();
    let names = ["e0", "e1"];
    let start = [
        Start::Moving,
        Start::Moving,
        Start::Stuck,
        Start::RestingOnStop,
        Start::Penetrating,
    ][r.below(5)];
    for k in 0..count {
        // Distinct coordinates (two elements on one coordinate are a separate matter).
        let c = (r.below(n as u64) + k) % n;
        if elements.iter().any(|e| e.coordinate == c) {
            continue;
        }
        let kind = match r.below(6) {
            0 => ElementKind::DashPot {
                law: Law::Coulomb,
                f_crit: r.uniform(0.1, 2.0),
            },
            1 => ElementKind::DashPot {
                law: Law::BinghamLinear {
                    eta: r.uniform(0.05, 1.0),
                },
                f_crit: r.uniform(0.1, 2.0),
            },
            2 => ElementKind::DashPot {
                law: Law::BinghamMonotone,
                f_crit: 1.0,
            },
            3 => ElementKind::DashPot {
                law: Law::BinghamNonMonotone {
                    selection: if r.below(2) == 0 {
                        Selection::NoVelocityJumps
                    } else {
                        Selection::MaximalDissipation
                    },
                },
                f_crit: 1.0,
            },
            4 => ElementKind::Stop {
                side: Side::Lower,
                position: q0[c] - r.uniform(0.05, 0.4),
                kind: StopKind::Rigid {
                    restitution: r.uniform(0.0, 0.9),
                },
            },
            _ => ElementKind::Stop {
                side: Side::Upper,
                position: q0[c] + r.uniform(0.05, 0.4),
                kind: StopKind::SpringBacked {
                    stiffness: r.uniform(1e2, 1e3) * moved[c],
                },
            },
        };
        elements.push(Element {
            name: names[k],
            coordinate: c,
            kind,
        });
    }
    // The initial state the start asks for, on the first element (moving when that
    // element has no such state).
    let e0 = elements[0];
    let c = e0.coordinate;
    let start = match (start, e0.kind) {
        (Start::Stuck, ElementKind::DashPot { .. })
        | (Start::RestingOnStop, ElementKind::Stop { .. })
        | (
            Start::Penetrating,
            ElementKind::Stop {
                kind: StopKind::Rigid { .. },
                ..
            },
        ) => start,
        _ => Start::Moving,
    };
    match (start, e0.kind) {
        (Start::Stuck, ElementKind::DashPot { .. }) => v0[c] = 0.0,
        (Start::RestingOnStop, ElementKind::Stop { position, .. }) => {
            q0[c] = position;
            v0[c] = 0.0;
        }
        (
            Start::Penetrating,
            ElementKind::Stop {
                position,
                side,
                kind: StopKind::Rigid { .. },
            },
        ) => {
            q0[c] = match side {
                Side::Lower => position - 0.05,
                Side::Upper => position + 0.05,
            };
        }
        _ => {}
    }
    let force = if r.below(2) == 0 {
        (r.below(n as u64), r.uniform(0.5, 5.0), r.uniform(1.0, 6.0))
    } else {
        (0, 0.0, 0.0)
    };
    Description {
        model,
        elements,
        q0,
        v0,
        force,
        start,
    }
}

/// The final state's coordinates of a solution.
fn final_q(sol: &Solution, n: usize) -> Vec<f64> {
    sol.last().map(|(_, y)| y[..n].to_vec()).unwrap_or_default()
}

/// The time-stepping steps: `H_COARSE / 4^k`, `k = 0, 1, …`, refined while the runs are
/// not yet in their asymptotic range, down to `H_FINEST`.
const H_COARSE: f64 = 1e-3;
const H_FINEST: f64 = 1e-3 / 256.0;

fn check<const N: usize, const E: usize>(d: Description) -> Verdict {
    let elements: [Element; E] = std::array::from_fn(|k| d.elements[k]);
    let Some(mut scene) = Scene::<N, E>::new(d.model.clone(), elements) else {
        return Verdict::Failed("model and dof disagree".into());
    };
    for (k, el) in elements.iter().enumerate() {
        if matches!(
            el.kind,
            ElementKind::DashPot {
                law: Law::BinghamMonotone,
                ..
            }
        ) {
            scene.laws[k] = Some(cubic);
        }
        if matches!(
            el.kind,
            ElementKind::DashPot {
                law: Law::BinghamNonMonotone { .. },
                ..
            }
        ) {
            scene.laws[k] = Some(non_monotone);
        }
    }
    let (fc, amp, w) = d.force;
    let input = move |t: f64, _q: &SVector<f64, N>, _v: &SVector<f64, N>| {
        let mut tau = SVector::<f64, N>::zeros();
        tau[fc] = amp * (w * t).sin();
        tau
    };
    let tf = 1.0;
    let p = NonSmoothProblem::new(
        0.0,
        tf,
        SVector::from_column_slice(&d.q0),
        SVector::from_column_slice(&d.v0),
    );
    let ed_method = NonSmoothMethod::EventDriven {
        method: SmoothMethod::Dopri5,
        options: Options {
            max_steps: 20_000,
            ..Options::tolerances(1e-8, 1e-10)
        },
    };
    let ts = |h: f64| NonSmoothMethod::TimeStepping { h, theta: 1.0 };
    let ed = solve_nonsmooth(&scene, &input, &p, &ed_method);
    if d.start == Start::Penetrating {
        let ts_run = solve_nonsmooth(&scene, &input, &p, &ts(1e-3));
        let refused = |r: &Result<Solution, filippov::runtime::SolveError>| matches!(r, Err(e) if matches!(e.kind, ErrorKind::InconsistentInitialData(_)));
        return if refused(&ed) && refused(&ts_run) {
            Verdict::Passed
        } else {
            Verdict::Failed("a penetrating initial state was not refused by both".into())
        };
    }
    let ed = match ed {
        Ok(sol) => sol,
        Err(e)
            if matches!(
                e.kind,
                ErrorKind::InvalidInput(_) | ErrorKind::InconsistentInitialData(_)
            ) =>
        {
            return Verdict::Failed(format!("refused valid input: {e}"));
        }
        Err(e) => return Verdict::TypedError(e.kind.to_string()),
    };
    let x_ed = final_q(&ed, N);
    let dist = |a: &[f64], b: &[f64]| {
        a.iter()
            .zip(b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max)
    };
    // First order: each 4× smaller step should about quarter the distance to the
    // event-driven end state. Near impacts and stick–slip transitions the first steps
    // can be pre-asymptotic (the distance even grows), so the step is refined until a
    // refinement both contracts the distance (≤ 0.6×) and reaches a new minimum, or the
    // run agrees to 1e-4; failing that down to H_FINEST, time-stepping does not converge
    // to the event-driven solution.
    let mut h = H_COARSE;
    let mut distances: Vec<(f64, f64)> = Vec::new();
    let converged = loop {
        let d = match solve_nonsmooth(&scene, &input, &p, &ts(h)) {
            Ok(sol) => dist(&final_q(&sol, N), &x_ed),
            Err(e) => return Verdict::Failed(format!("time-stepping at h = {h:e}: {e}")),
        };
        let best = distances.iter().map(|x| x.1).fold(f64::INFINITY, f64::min);
        let contracts = distances
            .last()
            .is_some_and(|&(_, prev)| d <= 0.6 * prev && d < best);
        distances.push((h, d));
        if (distances.len() >= 2 && d <= 1e-4) || contracts {
            break true;
        }
        if h <= H_FINEST * 1.000001 {
            break false;
        }
        h /= 4.0;
    };
    if !converged {
        let list: Vec<String> = distances
            .iter()
            .map(|(h, d)| format!("{d:.2e} at h = {h:e}"))
            .collect();
        return Verdict::Failed(format!(
            "time-stepping does not converge to event-driven: distance at tf {}",
            list.join(", ")
        ));
    }
    // Passivity along the event-driven run: E(tf) − E(0) ≤ work of τ (trapezoid on a
    // fine grid of the dense output), up to the integration tolerance.
    let energy = |y: &[f64]| {
        let q = SVector::<f64, N>::from_column_slice(&y[..N]);
        let v = SVector::<f64, N>::from_column_slice(&y[N..2 * N]);
        let mut e = filippov::Energy::kinetic_energy(&scene, &q, &v)
            + filippov::Energy::potential_energy(&scene, &q);
        for el in &elements {
            if let ElementKind::Stop {
                side,
                position,
                kind: StopKind::SpringBacked { stiffness },
            } = el.kind
            {
                let pen = match side {
                    Side::Upper => q[el.coordinate] - position,
                    Side::Lower => position - q[el.coordinate],
                };
                e += 0.5 * stiffness * pen.max(0.0).powi(2);
            }
        }
        e
    };
    let steps = 4000;
    let mut work = 0.0;
    let mut prev = ed.at(0.0).expect("starts at 0");
    let power = |t: f64, y: &[f64]| amp * (w * t).sin() * y[N + fc];
    for k in 1..=steps {
        let t = tf * k as f64 / steps as f64;
        let y = ed.at(t).expect("inside");
        work += 0.5 * (tf / steps as f64) * (power(t - tf / steps as f64, &prev) + power(t, &y));
        prev = y;
    }
    let (e0, e1) = (energy(ed.state(0)), energy(ed.last().expect("rows").1));
    let scale = e0.abs().max(work.abs()).max(1.0);
    if e1 - e0 - work > 1e-3 * scale {
        return Verdict::Failed(format!(
            "not passive: energy gained {:.3e} beyond the work {work:.3e}",
            e1 - e0
        ));
    }
    Verdict::Passed
}

/// A one-line description of the scene of `seed`, for failure reports.
pub fn summary(seed: u64) -> String {
    let d = describe(seed);
    format!(
        "{} joints {:?}, elements {:?}, q0 {:?}, v0 {:?}, force {:?}, start {:?}",
        d.model.links.len(),
        d.model.links.iter().map(|l| l.joint).collect::<Vec<_>>(),
        d.elements
            .iter()
            .map(|e| (e.coordinate, e.kind))
            .collect::<Vec<_>>(),
        d.q0,
        d.v0,
        d.force,
        d.start
    )
}

/// Runs the scene of `seed`.
pub fn run(seed: u64) -> Verdict {
    let d = describe(seed);
    let n = d.model.links.len();
    macro_rules! dispatch {
        ($(($n:literal, $e:literal)),*) => {
            match (n, d.elements.len()) {
                $(($n, $e) => check::<$n, $e>(d),)*
                (n, e) => Verdict::Failed(format!("no monomorphisation for {n} joints, {e} elements")),
            }
        };
    }
    dispatch!(
        (1, 1),
        (2, 1),
        (2, 2),
        (3, 1),
        (3, 2),
        (4, 1),
        (4, 2),
        (5, 1),
        (5, 2),
        (6, 1),
        (6, 2),
        (7, 1),
        (7, 2)
    )
}

/// Seeds `first..first + count`: (passed, typed errors with seed and message, failures
/// with seed and reason).
pub fn suite(first: u64, count: u64) -> (usize, Vec<(u64, String)>, Vec<(u64, String)>) {
    let mut passed = 0;
    let (mut typed, mut failed) = (Vec::new(), Vec::new());
    for seed in first..first + count {
        match run(seed) {
            Verdict::Passed => passed += 1,
            Verdict::TypedError(m) => typed.push((seed, m)),
            Verdict::Failed(m) => failed.push((seed, m)),
        }
    }
    (passed, typed, failed)
}
