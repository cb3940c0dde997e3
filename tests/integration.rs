//! Generated kernels driven by the runtime's integrators.

mod common;

use filippov::nalgebra::SVector;
use filippov::prelude::*;
use filippov::runtime::{MechanicalSystem, Method, NumericSystem, Options, Problem, solve};
use filippov_scenes::{DoublePendulum, Panda};

fn energy<S: Energy<N>, const N: usize>(sys: &S, y: &[f64]) -> f64 {
    let q = SVector::<f64, N>::from_column_slice(&y[..N]);
    let v = SVector::<f64, N>::from_column_slice(&y[N..]);
    sys.kinetic_energy(&q, &v) + sys.potential_energy(&q)
}

/// The free double pendulum (S8) conserves energy to the integrator's tolerance: every
/// accepted step commits a local error of at most about `rtol·‖y‖ + atol`, so the drift
/// over the run is bounded by the sum of those (with the energy's sensitivity to the
/// state as the constant); and it shrinks as the tolerance does.
#[test]
fn double_pendulum_energy_conserved_to_tolerance() {
    let p = DoublePendulum::default();
    let sys = MechanicalSystem::unforced(&p);
    let y0 = [1.2, -0.6, 0.0, 0.0];
    let e0 = energy(&p, &y0);
    let mut drifts = Vec::new();
    for rtol in [1e-6, 1e-9] {
        let traj = solve(
            &sys,
            &Problem::new(0.0, 10.0, y0),
            &Method::Dopri5(Options::tolerances(rtol, rtol * 1e-2)),
        )
        .expect("solves");
        let drift = (0..traj.len())
            .map(|i| (energy(&p, traj.state(i)) - e0).abs())
            .fold(0.0, f64::max);
        // ‖∇E‖ ≤ ~60 on this orbit (|v| ≤ 8, M ≤ 2, g·m·l ≤ 15); local error ≤ rtol·‖y‖ ≤ 10 rtol.
        let bound = 60.0 * 10.0 * rtol * traj.stats.steps as f64;
        assert!(
            drift <= bound,
            "rtol {rtol}: drift {drift:.3e} > bound {bound:.3e}"
        );
        drifts.push(drift);
    }
    assert!(
        drifts[1] < drifts[0] * 1e-2,
        "drift must fall with the tolerance: {drifts:?}"
    );
}

/// The generated system and the numeric reference give the same trajectory.
#[test]
fn generated_and_numeric_trajectories_agree() {
    let p = Panda::default();
    let model = p.model();
    let y0: Vec<f64> = (0..14)
        .map(|i| {
            if i < 7 {
                0.3 * (i as f64 + 1.0).sin()
            } else {
                0.0
            }
        })
        .collect();
    let method = Method::Dopri5(Options::tolerances(1e-10, 1e-12));
    let problem = Problem::new(0.0, 0.5, y0);
    let a = solve(&MechanicalSystem::unforced(&p), &problem, &method).expect("generated");
    let b = solve(&NumericSystem::unforced(&model), &problem, &method).expect("numeric");
    let (ya, yb) = (a.last().unwrap().1, b.last().unwrap().1);
    let diff = ya
        .iter()
        .zip(yb)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    assert!(diff < 1e-8, "final states differ by {diff:.3e}");
}

/// The stiff method with the generated Jacobian takes no finite-difference Jacobians and
/// agrees with the explicit method.
#[test]
fn stiff_method_uses_symbolic_jacobian() {
    let p = DoublePendulum::default();
    let sys = MechanicalSystem::unforced(&p);
    let problem = Problem::new(0.0, 2.0, [0.5, 0.5, 0.0, 0.0]);
    let a = solve(
        &sys,
        &problem,
        &Method::Sdirk4(Options::tolerances(1e-8, 1e-10)),
    )
    .expect("sdirk");
    let b = solve(
        &sys,
        &problem,
        &Method::Dopri5(Options::tolerances(1e-11, 1e-13)),
    )
    .expect("dopri");
    assert_eq!(a.stats.finite_difference_jacobians, 0);
    assert!(a.stats.jacobian_evaluations > 0);
    let (ya, yb) = (a.last().unwrap().1, b.last().unwrap().1);
    let diff = ya
        .iter()
        .zip(yb)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    assert!(diff < 1e-5, "SDIRK4 vs DOPRI5: {diff:.3e}");
}

/// The JSON export of a model is valid JSON with every link, read back by Python's json
/// module (Python 3 is one of the two things the project assumes on a machine).
#[test]
fn model_json_export() {
    let json = Panda::default().model().to_json();
    assert_eq!(json.matches("\"joint\": \"revolute\"").count(), 7);
    assert!(json.contains("\"gravity\": [0e0, 0e0, -9.81e0]"), "{json}");
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR"));
    let path = dir.join("panda.json");
    std::fs::write(&path, &json).unwrap();
    let out = std::process::Command::new("python3")
        .args(["-c", "import json,sys; m=json.load(open(sys.argv[1])); print(len(m['links']), m['links'][6]['mass'])"])
        .arg(&path)
        .output()
        .expect("python3 runs (install Python 3: the project assumes it)");
    assert!(
        out.status.success(),
        "Python's json module rejects the export: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(String::from_utf8_lossy(&out.stdout).trim(), "7 0.735522");
}
