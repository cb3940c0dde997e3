//! Ensembles in lockstep (`runtime::lockstep`): runs integrated together in the lanes
//! of `f64x4`, each with its own parameters and initial state, against the same runs
//! one at a time (the same integrator on `f64`) and against the library's DOPRI5
//! (`solve`) on the scene itself.

mod common;

use common::Rng;
use filippov::runtime::kernels::GenericDynamics;
use filippov::runtime::lockstep::{Final, LockstepError, LockstepOptions, Run, lockstep};
use filippov::runtime::real::f64x4;
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

/// Eleven runs (three batches of four, the last with a spare lane): each lane's end state
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
    let single = lockstep::<Oblique, f64, 3, 7>(&runs, 2.0, &options).expect("single runs");
    assert_eq!(lanes.len(), 11);
    let single_states: Vec<[f64; 6]> = single
        .iter()
        .map(|f| std::array::from_fn(|i| if i < 3 { f.q[i] } else { f.v[i - 3] }))
        .collect();
    let d = largest_difference(&lanes, &single_states);
    assert!(d < 1e-7, "lanes against single runs: {d:.2e}");
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
