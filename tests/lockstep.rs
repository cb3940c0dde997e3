//! Ensembles in lockstep (`runtime::lockstep`): runs integrated together in the lanes
//! of `f64x4`, each with its own parameters and initial state, against the same runs
//! one at a time (the same integrator on `f64`) and against the library's DOPRI5
//! (`solve`) on the scene itself.

mod common;

use common::Rng;
use filippov::runtime::kernels::GenericDynamics;
use filippov::runtime::lockstep::{Final, LockstepError, LockstepOptions, Run, lockstep};
use filippov::runtime::real::{f64x2, f64x4};
use filippov::runtime::{MechanicalSystem, Method, Options, Problem, solve};

#[path = "common/oblique.rs"]
mod oblique;
use oblique::{OBLIQUE, Oblique};

fn scene(p: &[f64; 7]) -> Oblique {
    let [m1, m2, m3, l, k, c, g] = *p;
    Oblique {
        m1,
        m2,
        m3,
        l,
        k,
        c,
        g,
    }
}

/// Runs with every parameter moved by up to ±20 % and random initial states.
fn runs(rng: &mut Rng, count: usize) -> Vec<Run<3, 7>> {
    (0..count)
        .map(|_| Run {
            parameters: OBLIQUE
                .parameters()
                .map(|p| p * (1.0 + rng.uniform(-0.2, 0.2))),
            q0: rng.vector::<3>(1.0).into(),
            v0: rng.vector::<3>(1.0).into(),
        })
        .collect()
}

fn largest_difference(a: &[Final<3>], b: &[[f64; 6]]) -> f64 {
    a.iter()
        .zip(b)
        .flat_map(|(x, y)| {
            x.q.iter()
                .chain(&x.v)
                .zip(y)
                .map(|(u, w)| (u - w).abs() / w.abs().max(1.0))
        })
        .fold(0.0, f64::max)
}

/// Eleven runs (three batches of four, the last with a spare lane; six of two in
/// `f64x2`, the last with a spare lane): each lane's end state
/// equals the same run integrated alone, and the library's DOPRI5 on the scene built
/// with the run's parameters, within the tolerances.
#[test]
fn lanes_agree_with_single_runs_and_with_solve() {
    let mut rng = Rng::new(11);
    let runs = runs(&mut rng, 11);
    let options = LockstepOptions {
        rtol: 1e-10,
        atol: 1e-12,
        ..LockstepOptions::default()
    };
    let lanes = lockstep::<Oblique, f64x4, 3, 7>(&runs, 2.0, &options).expect("lanes");
    let halves = lockstep::<Oblique, f64x2, 3, 7>(&runs, 2.0, &options).expect("halves");
    let single = lockstep::<Oblique, f64, 3, 7>(&runs, 2.0, &options).expect("single runs");
    assert_eq!(lanes.len(), 11);
    assert_eq!(halves.len(), 11);
    let single_states: Vec<[f64; 6]> = single
        .iter()
        .map(|f| std::array::from_fn(|i| if i < 3 { f.q[i] } else { f.v[i - 3] }))
        .collect();
    let d = largest_difference(&lanes, &single_states);
    assert!(d < 1e-7, "lanes against single runs: {d:.2e}");
    let d = largest_difference(&halves, &single_states);
    assert!(d < 1e-7, "f64x2 lanes against single runs: {d:.2e}");
    let method = Method::Dopri5(Options::tolerances(1e-10, 1e-12));
    let reference: Vec<[f64; 6]> = runs
        .iter()
        .map(|r| {
            let y0: Vec<f64> = r.q0.iter().chain(&r.v0).copied().collect();
            let s = scene(&r.parameters);
            let sol = solve(
                &MechanicalSystem::unforced(&s),
                &Problem::new(0.0, 2.0, y0),
                &method,
            )
            .expect("solve");
            let y = sol.last().expect("a state").1;
            std::array::from_fn(|i| y[i])
        })
        .collect();
    let d = largest_difference(&lanes, &reference);
    assert!(d < 1e-7, "lanes against solve: {d:.2e}");
}

/// A run that blows up is named by its index, with the time.
#[test]
fn a_failing_run_is_named() {
    let mut rng = Rng::new(12);
    let mut runs = runs(&mut rng, 6);
    runs[5].parameters[0] = f64::NAN;
    let err = lockstep::<Oblique, f64x4, 3, 7>(&runs, 1.0, &LockstepOptions::default())
        .expect_err("a NaN mass");
    assert_eq!(err, LockstepError::NonFinite { run: 5, t: 0.0 });
    let bad = LockstepOptions {
        first_step: 0.0,
        ..LockstepOptions::default()
    };
    assert!(matches!(
        lockstep::<Oblique, f64x4, 3, 7>(&runs[..4], 1.0, &bad),
        Err(LockstepError::InvalidOptions { .. })
    ));
    assert_eq!(
        Oblique::PARAMETERS,
        ["m1", "m2", "m3", "l", "k", "c", "g"],
        "the runs' parameters are in declaration order"
    );
}

mod nonsmooth {
    //! Non-smooth ensembles (`time_stepping_lockstep`): each run in the lanes against
    //! the same run by `time_stepping` alone.

    use super::common::Rng;
    use filippov::nalgebra::SVector;
    use filippov::prelude::*;
    use filippov::runtime::lockstep::{NonSmoothRun, time_stepping_lockstep};
    use filippov::runtime::nonsmooth::time_stepping;
    use filippov::runtime::real::{f64x2, f64x4};
    use filippov::runtime::{ErrorKind, NonSmoothProblem, Solution};

    type V3 = SVector<f64, 3>;

    /// The oblique tree of the smooth ensembles with Coulomb friction on its slide, a
    /// Bingham dash-pot in its wrist and stops on its shoulder, every element's
    /// constants parameters.
    #[derive(Mechanism, Clone, Copy, Debug)]
    #[mechanism(emit = [generic], gravity = [0.0, 0.0, -9.81])]
    #[body(base, mass = m1, com = [0.1, 0.0, 0.05], inertia = sphere(m1, 0.2))]
    #[joint(slide: prismatic([0.6, 0.0, 0.8]), parent = world, child = base, origin = [0.0, 0.0, 1.0], rpy = [0.1, 0.2, 0.3])]
    #[spring(slide, k = k)]
    #[friction(slide, f_crit = fc)]
    #[body(arm, mass = m2, com = [0.2, 0.05, 0.0], inertia = rod(m2, 0.4))]
    #[joint(shoulder: revolute([0.0, 0.6, 0.8]), parent = base, child = arm, origin = [0.1, 0.2, 0.0], rpy = [0.3, -0.2, 0.5])]
    #[stop(shoulder, min = -0.5, max = 0.5, restitution = e)]
    #[body(hand, mass = m3, com = [0.05, 0.0, 0.02], inertia = sphere(m3, 0.05))]
    #[joint(wrist: revolute([1.0, 1.0, 0.0]), parent = arm, child = hand, origin = [0.4, 0.0, 0.1], rpy = [-0.2, 0.1, 0.0])]
    #[bingham(wrist, f_crit = yield_, eta = eta)]
    pub struct Rough {
        pub m1: f64,
        pub m2: f64,
        pub m3: f64,
        pub k: f64,
        pub fc: f64,
        pub e: f64,
        pub yield_: f64,
        pub eta: f64,
    }

    /// Random scenes (every constant drawn) and states (the shoulder inside its stops).
    fn runs(rng: &mut Rng, count: usize) -> Vec<NonSmoothRun<Rough, 3>> {
        (0..count)
            .map(|_| {
                let system = Rough {
                    m1: rng.uniform(0.5, 2.0),
                    m2: rng.uniform(0.3, 1.0),
                    m3: rng.uniform(0.1, 0.5),
                    k: rng.uniform(5.0, 50.0),
                    fc: rng.uniform(0.0, 8.0),
                    e: rng.uniform(0.0, 0.9),
                    yield_: rng.uniform(0.0, 0.3),
                    eta: rng.uniform(0.05, 1.0),
                };
                let q0 = V3::new(
                    rng.uniform(-0.3, 0.3),
                    rng.uniform(-0.45, 0.45),
                    rng.uniform(-1.0, 1.0),
                );
                let tf = rng.uniform(0.2, 0.6);
                let problem = NonSmoothProblem::new(0.0, tf, q0, rng.vector::<3>(2.0));
                NonSmoothRun { system, problem }
            })
            .collect()
    }

    fn zero(_t: f64, _q: &V3, _v: &V3) -> V3 {
        V3::zeros()
    }

    /// The largest difference between two solutions' rows, relative to max(|x|, 1),
    /// after checking that they have the same times and the same switch log.
    fn difference(a: &Solution, b: &Solution) -> f64 {
        assert_eq!(a.times(), b.times(), "the same steps");
        let kinds = |s: &Solution| -> Vec<_> {
            s.switches
                .iter()
                .map(|w| (w.t, w.element.clone(), w.kind))
                .collect()
        };
        assert_eq!(kinds(a), kinds(b), "the same switches");
        a.rows()
            .zip(b.rows())
            .flat_map(|((_, x), (_, y))| x.iter().zip(y))
            .map(|(x, y)| (x - y).abs() / y.abs().max(1.0))
            .fold(0.0, f64::max)
    }

    /// Nineteen random runs of different lengths (lanes refill as runs end), at θ = 1
    /// and θ = ½: every run in the lanes of `f64x4`, of `f64x2` and of `f64` is the run
    /// `time_stepping` makes alone — the same steps, the same switches, the same states
    /// up to the kernels' rounding.
    #[test]
    fn every_run_is_its_own_time_stepping_run() {
        let mut rng = Rng::new(31);
        let runs = runs(&mut rng, 19);
        for theta in [1.0, 0.5] {
            let h = 2e-3;
            let lanes = time_stepping_lockstep::<_, f64x4, _, 3, 8>(&runs, &zero, h, theta);
            let halves = time_stepping_lockstep::<_, f64x2, _, 3, 8>(&runs, &zero, h, theta);
            let single = time_stepping_lockstep::<_, f64, _, 3, 8>(&runs, &zero, h, theta);
            assert_eq!(lanes.len(), runs.len());
            assert_eq!(halves.len(), runs.len());
            let mut switches = 0;
            for (i, run) in runs.iter().enumerate() {
                let alone = time_stepping(&run.system, &zero, &run.problem, h, theta)
                    .unwrap_or_else(|e| panic!("run {i} alone: {e}"));
                let lane = lanes[i].as_ref().unwrap_or_else(|e| panic!("run {i}: {e}"));
                let one = single[i]
                    .as_ref()
                    .unwrap_or_else(|e| panic!("run {i}: {e}"));
                assert_eq!(lane.stats.steps, alone.stats.steps);
                let d = difference(lane, &alone);
                assert!(
                    d < 1e-9,
                    "run {i}, θ = {theta}: lanes against alone {d:.2e}"
                );
                let d = difference(one, &alone);
                assert!(d < 1e-9, "run {i}, θ = {theta}: f64 against alone {d:.2e}");
                let half = halves[i]
                    .as_ref()
                    .unwrap_or_else(|e| panic!("run {i}: {e}"));
                assert_eq!(half.stats.steps, alone.stats.steps);
                let d = difference(half, &alone);
                assert!(
                    d < 1e-9,
                    "run {i}, θ = {theta}: f64x2 against alone {d:.2e}"
                );
                switches += alone.switches.len();
            }
            assert!(
                switches > 2 * runs.len(),
                "the runs switch ({switches} switches)"
            );
        }
    }

    /// A run with a bad element (negative friction limit) or a bad start (the shoulder
    /// past its stop) returns its own typed error; the runs beside it are unaffected.
    #[test]
    fn a_bad_run_fails_alone() {
        let mut rng = Rng::new(32);
        let mut runs = runs(&mut rng, 6);
        runs[1].system.fc = -1.0;
        runs[4].problem.q0[1] = 0.7;
        let out = time_stepping_lockstep::<_, f64x4, _, 3, 8>(&runs, &zero, 2e-3, 1.0);
        for (i, result) in out.iter().enumerate() {
            match (i, result) {
                (1, Err(e)) => {
                    assert!(matches!(e.kind, ErrorKind::InvalidInput(_)), "{e}");
                    assert!(e.to_string().contains("slide"), "names the element: {e}");
                }
                (4, Err(e)) => assert!(
                    matches!(e.kind, ErrorKind::InconsistentInitialData(_)),
                    "{e}"
                ),
                (1 | 4, Ok(_)) => panic!("run {i} should fail"),
                (_, r) => {
                    let alone = time_stepping(&runs[i].system, &zero, &runs[i].problem, 2e-3, 1.0)
                        .expect("alone");
                    let lane = r.as_ref().expect("a good run");
                    assert!(difference(lane, &alone) < 1e-9);
                }
            }
        }
    }
}
