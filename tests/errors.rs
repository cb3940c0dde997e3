//! Run-time failures are typed errors that keep the trajectory computed so far: bad
//! parameters, non-finite initial data and forcing, step-size underflow, inconsistent
//! initial data and ill-posed modes — on generated mechanisms, for every integrator.

use filippov::Mechanism;
use filippov::nalgebra::SVector;
use filippov::runtime::{
    ErrorKind, MechanicalSystem, Method, NonSmoothMethod, NonSmoothProblem, Options, Problem,
    solve, solve_nonsmooth,
};
use filippov_scenes::{BouncingBall, CoulombOscillator, DoublePendulum};

type V1 = SVector<f64, 1>;

fn smooth_methods() -> [Method; 3] {
    [
        Method::Rk4 { h: 1e-2 },
        Method::Dopri5(Options::default()),
        Method::Sdirk4(Options::default()),
    ]
}

fn nonsmooth_methods() -> [NonSmoothMethod; 2] {
    [
        NonSmoothMethod::default(),
        NonSmoothMethod::TimeStepping {
            h: 1e-3,
            theta: 1.0,
        },
    ]
}

#[test]
fn bad_parameters_are_invalid_input_naming_the_parameter() {
    let p = DoublePendulum {
        m2: -0.5,
        g: f64::INFINITY,
        ..DoublePendulum::default()
    };
    let problem = Problem::new(0.0, 1.0, [0.1, 0.2, 0.0, 0.0]);
    for m in smooth_methods() {
        let err = solve(&MechanicalSystem::unforced(&p), &problem, &m).expect_err("bad parameters");
        match &err.kind {
            ErrorKind::InvalidInput(msg) => {
                assert!(
                    msg.contains("mass of body `lower` (`m2`)") && msg.contains("field `g`"),
                    "{msg}"
                )
            }
            other => panic!("expected InvalidInput, got {other:?}"),
        }
        assert!(err.solution.is_empty(), "nothing integrated");
    }
}

#[test]
fn non_finite_initial_state_is_invalid_input() {
    let p = DoublePendulum::default();
    let problem = Problem::new(0.0, 1.0, [0.1, f64::NAN, 0.0, 0.0]);
    for m in smooth_methods() {
        let err = solve(&MechanicalSystem::unforced(&p), &problem, &m).expect_err("NaN state");
        assert!(
            matches!(err.kind, ErrorKind::InvalidInput(_)),
            "{:?}",
            err.kind
        );
    }
    let s = CoulombOscillator {
        m: 1.0,
        k: 1.0,
        f_crit: 0.1,
    };
    let problem = NonSmoothProblem::new(0.0, 1.0, V1::new(f64::INFINITY), V1::new(0.0));
    for m in nonsmooth_methods() {
        let err = solve_nonsmooth(&s, &|_t, _q: &V1, _v: &V1| V1::zeros(), &problem, &m)
            .expect_err("infinite state");
        // Named by its column, as the scene declares the joint.
        assert!(
            matches!(&err.kind, ErrorKind::InvalidInput(m) if m.contains("initial state `q_x` is not finite")),
            "{:?}",
            err.kind
        );
    }
}

/// Forcing that turns NaN at t = 0.5: the error names the time and component, and the
/// trajectory up to there is kept.
#[test]
fn non_finite_forcing_is_reported_with_the_trajectory_so_far() {
    let p = DoublePendulum::default();
    let input = |t: f64, _q: &SVector<f64, 2>, _v: &SVector<f64, 2>| {
        if t < 0.5 {
            SVector::<f64, 2>::new(0.1, 0.0)
        } else {
            SVector::<f64, 2>::new(f64::NAN, 0.0)
        }
    };
    let problem = Problem::new(0.0, 1.0, [0.1, 0.2, 0.0, 0.0]);
    for m in smooth_methods() {
        let err = solve(&MechanicalSystem::new(&p, input), &problem, &m).expect_err("NaN forcing");
        match err.kind {
            ErrorKind::NonFinite { t, .. } => assert!((0.45..=0.55).contains(&t), "at t = {t}"),
            other => panic!("expected NonFinite, got {other:?}"),
        }
        let kept = err.solution.last().map_or(0.0, |(t, _)| t);
        assert!(
            kept > 0.4 && err.solution.len() > 2,
            "trajectory kept up to {kept}"
        );
        assert!(
            (0..err.solution.len()).all(|i| err.solution.state(i).iter().all(|x| x.is_finite()))
        );
    }
    let s = CoulombOscillator {
        m: 1.0,
        k: 1.0,
        f_crit: 0.1,
    };
    let input = |t: f64, _q: &V1, _v: &V1| V1::new(if t < 0.5 { 0.3 } else { f64::NAN });
    let problem = NonSmoothProblem::new(0.0, 1.0, V1::new(0.0), V1::new(0.0));
    for m in nonsmooth_methods() {
        let err = solve_nonsmooth(&s, &input, &problem, &m).expect_err("NaN forcing");
        assert!(
            matches!(err.kind, ErrorKind::NonFinite { .. }),
            "{:?}",
            err.kind
        );
        // The message names the column the NaN appeared in.
        let message = err.to_string();
        assert!(
            message.contains("non-finite value in `v_x`") || message.contains("in `f_"),
            "{message}"
        );
        assert!(
            err.solution.len() > 1,
            "{m:?}: rows before the failure are kept ({} rows, {:?})",
            err.solution.len(),
            err.kind
        );
    }
}

/// A force that blows up in finite time: x' = x² through the input; the adaptive
/// methods report a step-size underflow (or a non-finite state) near the blow-up time
/// rather than returning garbage.
#[test]
fn blow_up_is_step_size_underflow_or_non_finite() {
    let p = DoublePendulum {
        g: 0.0,
        ..DoublePendulum::default()
    };
    let input = |_t: f64, _q: &SVector<f64, 2>, v: &SVector<f64, 2>| {
        SVector::<f64, 2>::new(10.0 * v[0] * v[0], 0.0)
    };
    let problem = Problem::new(0.0, 10.0, [0.0, 0.0, 1.0, 0.0]);
    for m in [
        Method::Dopri5(Options::default()),
        Method::Sdirk4(Options::default()),
    ] {
        let err = solve(&MechanicalSystem::new(&p, input), &problem, &m).expect_err("blow-up");
        assert!(
            matches!(
                err.kind,
                ErrorKind::StepSizeUnderflow { .. }
                    | ErrorKind::NonFinite { .. }
                    | ErrorKind::NewtonDivergence { .. }
            ),
            "{:?}",
            err.kind
        );
        assert!(err.solution.len() > 1);
    }
}

/// Starting below a rigid floor cannot be repaired.
#[test]
fn penetrating_initial_state_is_inconsistent_initial_data() {
    let b = BouncingBall {
        m: 1.0,
        g: 9.81,
        e: 0.5,
    };
    let problem = NonSmoothProblem::new(0.0, 1.0, V1::new(-0.1), V1::new(0.0));
    // Both integrators refuse it (time-stepping used to hold the violation all run).
    for method in [
        NonSmoothMethod::default(),
        NonSmoothMethod::TimeStepping {
            h: 1e-3,
            theta: 1.0,
        },
    ] {
        let err = solve_nonsmooth(&b, &|_t, _q: &V1, _v: &V1| V1::zeros(), &problem, &method)
            .expect_err("penetration");
        assert!(
            matches!(&err.kind, ErrorKind::InconsistentInitialData(m)
                if m.contains("joint `x` starts at -0.1, inside the rigid stop `stop_x` at 0; start it at or above 0")),
            "{method:?}: {:?}",
            err.kind
        );
        assert!(err.solution.is_empty());
    }
    // A given stuck force beyond f_crit.
    let s = CoulombOscillator {
        m: 1.0,
        k: 1.0,
        f_crit: 0.1,
    };
    let problem =
        NonSmoothProblem::new(0.0, 1.0, V1::new(0.05), V1::new(0.0)).with_forces(vec![Some(0.3)]);
    let err = solve_nonsmooth(
        &s,
        &|_t, _q: &V1, _v: &V1| V1::zeros(),
        &problem,
        &NonSmoothMethod::default(),
    )
    .expect_err("force beyond f_crit");
    assert!(
        matches!(err.kind, ErrorKind::InconsistentInitialData(_)),
        "{:?}",
        err.kind
    );
}

/// Two friction elements on one coordinate, both stuck: any split of the holding force
/// between them fits, so the stuck forces are not unique — an ill-posed mode.
#[derive(Mechanism)]
#[body(block, mass = m)]
#[joint(x: prismatic(x), parent = world, child = block)]
#[spring(x, k = 1.0)]
#[friction(x, f_crit = 0.5)]
#[bingham(x, f_crit = 0.3, eta = 1.0)]
struct DoubleFriction {
    m: f64,
}

#[test]
fn non_unique_stuck_forces_are_an_ill_posed_mode() {
    let s = DoubleFriction { m: 1.0 };
    let method = NonSmoothMethod::EventDriven(Method::Dopri5(Options::default()));
    let none = |_t: f64, _q: &V1, _v: &V1| V1::zeros();
    // At rest from the start: no initial mode with unique forces.
    let problem = NonSmoothProblem::new(0.0, 2.0, V1::new(0.1), V1::new(0.0));
    let err = solve_nonsmooth(&s, &none, &problem, &method).expect_err("non-unique forces at t0");
    match &err.kind {
        ErrorKind::InconsistentInitialData(detail) => {
            assert!(detail.contains("not unique"), "{detail}")
        }
        other => panic!("expected InconsistentInitialData, got {other:?}"),
    }
    // Moving, then coming to rest inside the combined dead zone: reported when it sticks,
    // with the motion before kept.
    let problem = NonSmoothProblem::new(0.0, 5.0, V1::new(0.0), V1::new(0.5));
    let err =
        solve_nonsmooth(&s, &none, &problem, &method).expect_err("non-unique forces when sticking");
    match &err.kind {
        ErrorKind::IllPosedMode { t, detail } => {
            assert!(*t > 0.1, "at t = {t}");
            assert!(detail.contains("not unique"), "{detail}");
        }
        other => panic!("expected IllPosedMode, got {other:?}"),
    }
    assert!(err.solution.len() > 2, "the motion before is kept");
}

/// A user law that is not finite on its domain (`(f − f_c)/f` with `f_c = 0` is `0/0` at
/// `f = 0 = f_crit`) is an invalid input naming the element, for both integrators —
/// never an `Ok` trajectory that breaks the law.
#[test]
fn law_not_finite_on_its_domain_is_refused() {
    #[derive(Mechanism)]
    #[body(block, mass = m)]
    #[joint(x: prismatic(x), parent = world, child = block)]
    #[spring(x, k = k)]
    #[bingham(x, f_crit = fc, law = (f - fc) / f)]
    struct Degenerate {
        m: f64,
        k: f64,
        fc: f64,
    }
    let s = Degenerate {
        m: 1.0,
        k: 1.0,
        fc: 0.0,
    };
    let problem = NonSmoothProblem::new(0.0, 1.0, V1::new(1.0), V1::new(0.0));
    for method in [
        NonSmoothMethod::default(),
        NonSmoothMethod::TimeStepping {
            h: 1e-3,
            theta: 1.0,
        },
    ] {
        let err = solve_nonsmooth(&s, &|_t, _q: &V1, _v: &V1| V1::zeros(), &problem, &method)
            .expect_err("a law with 0/0 at f_crit");
        assert!(
            matches!(&err.kind, ErrorKind::InvalidInput(m) if m.contains("bingham_x") && m.contains("not finite")),
            "{method:?}: {:?}",
            err.kind
        );
    }
}

/// `validate()` covers every parameter expression, origins, rpy, gravity and spring rest
/// positions included: one that overflows names its role, before anything runs.
#[test]
fn validate_names_every_non_finite_parameter_expression() {
    #[derive(Mechanism)]
    #[mechanism(gravity = [0.0, -g * s * s, 0.0])]
    #[body(link, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
    #[joint(hinge: revolute(z), parent = world, child = link, origin = [l * s * s, 0.0, 0.0], rpy = [0.0, 0.0, s * s])]
    #[spring(hinge, k = 1.0, rest = s * s)]
    struct Scaled {
        m: f64,
        l: f64,
        g: f64,
        s: f64,
    }
    let ok = Scaled {
        m: 1.0,
        l: 1.0,
        g: 9.81,
        s: 1.0,
    };
    assert!(ok.validate().is_ok());
    let huge = Scaled { s: 1e200, ..ok };
    let err = huge.validate().unwrap_err().to_string();
    for role in [
        "gravity [1]",
        "origin [0] of joint `hinge`",
        "rpy [2] of joint `hinge`",
        "rest position of the spring",
    ] {
        assert!(err.contains(role), "{role} missing in: {err}");
    }
}

/// When the event-driven integrator must give up because one element keeps switching
/// (Coulomb friction under a force flipping 1e5 times a second, with a small step
/// budget), the error names the element and its modes and points to time-stepping,
/// which integrates the same run.
#[test]
fn an_element_that_keeps_switching_is_named() {
    let s = CoulombOscillator {
        m: 1.0,
        k: 1.0,
        f_crit: 0.1,
    };
    let shake = |t: f64, _q: &V1, _v: &V1| V1::new(0.2 * (1e5 * t).sin());
    let p = NonSmoothProblem::new(0.0, 1.0, V1::new(0.0), V1::new(0.0));
    let method = NonSmoothMethod::EventDriven(Method::Dopri5(Options {
        max_steps: 2000,
        ..Options::tolerances(1e-8, 1e-10)
    }));
    let err = solve_nonsmooth(&s, &shake, &p, &method).expect_err("budget");
    match &err.kind {
        ErrorKind::KeepsSwitching { element, cycle, .. } => {
            assert_eq!(element, "friction_x");
            assert!(cycle.contains("Stick") || cycle.contains("Slip"), "{cycle}");
            assert!(err.to_string().contains("TimeStepping"), "{err}");
        }
        other => panic!(
            "{other:?}; {} switches, last {:?}",
            err.solution.switches.len(),
            err.solution
                .switches
                .iter()
                .rev()
                .take(3)
                .collect::<Vec<_>>()
        ),
    }
    assert!(err.solution.len() > 1, "what was computed is kept");
    // Time-stepping integrates the whole run. A free mass under F sin(ωt) from rest moves
    // by F t/(mω) − F sin(ωt)/(mω²); friction only takes motion away, so
    // |q| ≤ F/(mω) + F/(mω²) over [0, 1] (F = 0.2, ω = 1e5, m = 1, the spring's force
    // at that displacement is negligible).
    let ts = NonSmoothMethod::TimeStepping {
        h: 1e-6,
        theta: 1.0,
    };
    let every = p
        .clone()
        .with_output(filippov::runtime::Output::Every(1000));
    let sol = solve_nonsmooth(&s, &shake, &every, &ts).expect("time-stepping integrates it");
    assert_eq!(sol.last().map(|(t, _)| t), Some(1.0));
    let bound = 0.2 / 1e5 + 0.2 / 1e10;
    for (t, y) in sol.rows() {
        assert!(y[0].abs() <= bound * 1.01, "q = {:e} at t = {t}", y[0]);
    }
}

/// A run that uses up its step budget says where its steps ended and what to try.
#[test]
fn max_steps_says_what_to_try() {
    let p = DoublePendulum::default();
    let problem = Problem::new(0.0, 10.0, [1.0, 0.5, 0.0, 0.0]);
    let options = Options {
        max_steps: 20,
        ..Options::default()
    };
    for m in [
        Method::Dopri5(options),
        Method::Sdirk4(options),
        Method::Bdf(options),
    ] {
        let err = solve(&MechanicalSystem::unforced(&p), &problem, &m).expect_err("budget");
        assert!(matches!(err.kind, ErrorKind::MaxSteps { .. }), "{err}");
        let message = err.to_string();
        for part in ["the last step", "raise `Options::max_steps`", "Method::Bdf"] {
            assert!(message.contains(part), "{m:?}: {message}");
        }
    }
}
