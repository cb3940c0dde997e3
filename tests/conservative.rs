//! [`Conservative`]: a lossless mechanism projected onto its energy level after every
//! step. Checked against references that integrate nothing: the four-bar's orbit by
//! quadrature (`examples/support/four_bar_orbit.rs`, the crank angle the energy allows
//! at each time), and the energy of the start.

#[path = "../examples/support/four_bar_orbit.rs"]
mod four_bar_orbit;

use filippov::nalgebra::SVector;
use filippov::prelude::*;
use filippov::runtime::loops::{LoopConstraints, assemble};
use filippov::runtime::{
    Conservative, ErrorKind, MechanicalSystem, Method, OdeSystem, Options, Problem, Solution, solve,
};
use filippov::scenes::{DoublePendulum, FourBar, PlanarArm3, SliderCrank};
use four_bar_orbit::{FourBarOrbit, START};

type V3 = SVector<f64, 3>;

fn methods(rtol: f64) -> [(&'static str, Method); 3] {
    let o = Options {
        max_steps: 10_000_000,
        ..Options::tolerances(rtol, rtol * 1e-2)
    };
    [
        ("DOPRI5", Method::Dopri5(o)),
        ("SDIRK4", Method::Sdirk4(o)),
        ("BDF", Method::Bdf(o)),
    ]
}

/// The largest relative energy error over the rows of `sol`, from the energy `e0`.
fn drift<S: Energy<N>, const N: usize>(s: &S, sol: &Solution, e0: f64) -> f64 {
    sol.rows()
        .map(|(_, y)| {
            let q = SVector::<f64, N>::from_column_slice(&y[..N]);
            let v = SVector::<f64, N>::from_column_slice(&y[N..2 * N]);
            (s.total_energy(&q, &v) - e0).abs() / e0.abs()
        })
        .fold(0.0, f64::max)
}

/// The crank-rocker turning fifty times without losses, with each method at rtol 1e-10:
/// on its energy level, the energy stays at round-off and the crank angle on the
/// quadrature's orbit closer than the same method's run without the energy projection
/// (whose energy drifts and whose phase error therefore grows with the square of the
/// time); the loops stay closed.
#[test]
fn four_bar_on_its_energy_level_stays_on_its_orbit() {
    let fb = FourBar::default();
    let (q0, v0) = assemble(
        &fb,
        &V3::from([0.0, START[0], START[1]]),
        &V3::from([12.0, 0.0, 0.0]),
        &["crank_pivot"],
    )
    .expect("the crank-rocker assembles at crank angle 0");
    let mut y0 = q0.as_slice().to_vec();
    y0.extend_from_slice(v0.as_slice());
    let e0 = fb.total_energy(&q0, &v0);
    let orbit = FourBarOrbit::new(fb, e0);
    let tf = 50.0 * orbit.period;
    let problem = Problem::new(0.0, tf, y0.clone());
    let conservative = Conservative::new(&fb, &y0).expect("the four-bar has no losses");
    assert_eq!(conservative.energy(), e0);
    for (name, method) in methods(1e-10) {
        let plain = solve(&MechanicalSystem::unforced(&fb), &problem, &method)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let held =
            solve(&conservative, &problem, &method).unwrap_or_else(|e| panic!("{name}: {e}"));
        let phase = |sol: &Solution| {
            let (t, y) = sol.last().expect("rows");
            orbit.angle_error(t, y[0])
        };
        let (drift_plain, drift_held) = (drift(&fb, &plain, e0), drift(&fb, &held, e0));
        let (phase_plain, phase_held) = (phase(&plain), phase(&held));
        let mut closure = [0.0f64; 2];
        for (_, y) in held.rows() {
            let q = V3::from_column_slice(&y[..3]);
            let v = V3::from_column_slice(&y[3..6]);
            closure[0] = closure[0].max(fb.constraint_residual(&q).amax());
            closure[1] = closure[1].max((fb.constraint_jacobian(&q) * v).amax());
        }
        eprintln!(
            "{name}: energy drift {drift_plain:.1e} → {drift_held:.1e}, crank angle error \
             {phase_plain:.1e} → {phase_held:.1e} rad after 50 turns; |Φ| ≤ {:.1e}, |G v| ≤ {:.1e}",
            closure[0], closure[1]
        );
        // Each projection leaves the energy within a few roundings of E₀.
        assert!(drift_held <= 1e-13, "{name}: energy drift {drift_held:e}");
        assert!(drift_plain > drift_held, "{name}: {drift_plain:e}");
        assert!(
            phase_held.abs() < phase_plain.abs() && phase_held.abs() <= 1e-7,
            "{name}: crank angle error {phase_held:e} (without the energy: {phase_plain:e})"
        );
        assert!(
            closure[0] <= 1e-12 && closure[1] <= 1e-12,
            "{name}: {closure:?}"
        );
    }
}

/// An open tree (the double pendulum, chaotic at this energy): the energy stays at its
/// start's to round-off, and over the first half second, before chaos separates them,
/// the run agrees with the run without the projection to the tolerance.
#[test]
fn double_pendulum_on_its_energy_level() {
    let dp = DoublePendulum::default();
    let y0 = [0.3, 1.2, 2.0, -1.5];
    let q0 = SVector::<f64, 2>::from([y0[0], y0[1]]);
    let v0 = SVector::<f64, 2>::from([y0[2], y0[3]]);
    let e0 = dp.total_energy(&q0, &v0);
    let conservative = Conservative::new(&dp, &y0).expect("no losses");
    for (name, method) in methods(1e-9) {
        let problem = Problem::new(0.0, 20.0, y0);
        let held =
            solve(&conservative, &problem, &method).unwrap_or_else(|e| panic!("{name}: {e}"));
        let plain = solve(&MechanicalSystem::unforced(&dp), &problem, &method)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let (drift_plain, drift_held) = (drift(&dp, &plain, e0), drift(&dp, &held, e0));
        let mut apart = 0.0f64;
        for k in 0..=50 {
            let t = 0.01 * k as f64;
            let (a, b) = (held.at(t).expect("in"), plain.at(t).expect("in"));
            apart = apart.max(
                a.iter()
                    .zip(&b)
                    .map(|(x, y)| (x - y).abs())
                    .fold(0.0, f64::max),
            );
        }
        eprintln!(
            "{name}: energy drift {drift_plain:.1e} → {drift_held:.1e} over 20 s; \
             apart by {apart:.1e} over the first 0.5 s"
        );
        assert!(drift_held <= 1e-13, "{name}: {drift_held:e}");
        assert!(apart <= 1e-6, "{name}: {apart:e}");
    }
}

/// What dissipates energy is refused, named: dampers with their coefficients, the
/// non-smooth elements; a start of the wrong length.
#[test]
fn conservative_refuses_what_dissipates() {
    let arm = PlanarArm3::default();
    let y0 = [0.0; 6];
    match Conservative::new(&arm, &y0) {
        Err(ErrorKind::InvalidInput(msg)) => {
            for joint in ["`j1`", "`j2`", "`j3`"] {
                assert!(msg.contains(joint), "{msg}");
            }
            assert!(msg.contains("dampers"), "{msg}");
        }
        other => panic!("damped arm accepted: {:?}", other.map(|s| s.energy())),
    }
    let undamped = PlanarArm3 { c: 0.0, ..arm };
    assert!(Conservative::new(&undamped, &y0).is_ok());
    let sc = SliderCrank::default();
    match Conservative::new(&sc, &[0.0; 6]) {
        Err(ErrorKind::InvalidInput(msg)) => {
            for element in SliderCrank::NON_SMOOTH_ELEMENTS {
                assert!(msg.contains(element), "{msg}");
            }
        }
        other => panic!(
            "slider-crank with friction accepted: {:?}",
            other.map(|s| s.energy())
        ),
    }
    match Conservative::new(&undamped, &[0.0; 5]) {
        Err(ErrorKind::InvalidInput(msg)) => assert!(msg.contains("6 finite"), "{msg}"),
        other => panic!("short start accepted: {:?}", other.map(|s| s.energy())),
    }
    let mut nan = y0;
    nan[4] = f64::NAN;
    assert!(matches!(
        Conservative::new(&undamped, &nan),
        Err(ErrorKind::InvalidInput(_))
    ));
    // The system integrates like its mechanism: same dimension and names.
    let system = Conservative::new(&undamped, &y0).expect("undamped");
    assert_eq!(system.dim(), 6);
    assert_eq!(
        system.names(),
        MechanicalSystem::unforced(&undamped).names()
    );
}
