//! Scenes read from URDF files of real robots (`robots/`): the derive's expansion
//! against the numeric model `Model::from_urdf` reads from the same file — two readers
//! written apart — at random states, and every identity of `common::check`.

mod common;

#[path = "../examples/support/urdf_arm.rs"]
mod urdf_arm;
use filippov::nalgebra::{DVector, SVector, Vector3};
use filippov::prelude::*;
use filippov::runtime::numeric::{self, Model};
use urdf_arm::Arm;

#[derive(Mechanism)]
#[mechanism(
    urdf = "robots/panda.urdf",
    lock = [panda_finger_joint1, panda_finger_joint2],
    gravity = [0.0, 0.0, -9.81],
    emit = all
)]
struct PandaUrdf;

#[derive(Mechanism)]
#[mechanism(urdf = "robots/ur5.urdf", gravity = [0.0, 0.0, -9.81], emit = all)]
struct Ur5;

/// M, C v + g and forward dynamics of `sys` against the numeric model, relative to the
/// size of each quantity, at 20 random states.
fn against_numeric<S: common::AllKernels<N>, const N: usize>(sys: &S, model: &Model, seed: u64) {
    assert_eq!(model.dof(), N, "the two readers find the same coordinates");
    let mut rng = common::Rng::new(seed);
    let d = |x: &SVector<f64, N>| DVector::from_column_slice(x.as_slice());
    let rel = |a: &[f64], b: &[f64]| {
        let scale = b.iter().fold(1.0f64, |m, x| m.max(x.abs()));
        a.iter()
            .zip(b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max)
            / scale
    };
    for _ in 0..20 {
        let q = SVector::<f64, N>::from_fn(|_, _| rng.uniform(-3.0, 3.0));
        let v = SVector::<f64, N>::from_fn(|_, _| rng.uniform(-2.0, 2.0));
        let tau = SVector::<f64, N>::from_fn(|_, _| rng.uniform(-10.0, 10.0));
        let m = sys.mass_matrix(&q);
        let m_ref = numeric::crba(model, &d(&q));
        assert!(rel(m.as_slice(), m_ref.as_slice()) < 1e-12, "M");
        let bias = sys.bias(&q, &v);
        let bias_ref = numeric::bias(model, &d(&q), &d(&v));
        assert!(rel(bias.as_slice(), bias_ref.as_slice()) < 1e-12, "C v + g");
        let fd = sys.forward_dynamics(&q, &v, &tau);
        let fd_ref = numeric::forward_dynamics(model, &d(&q), &d(&v), &d(&tau));
        assert!(
            rel(fd.as_slice(), fd_ref.as_slice()) < 1e-10,
            "forward dynamics"
        );
    }
}

#[test]
fn panda_from_urdf_matches_the_numeric_reader() {
    let text = include_str!("../robots/panda.urdf");
    let g = Vector3::new(0.0, 0.0, -9.81);
    let model = Model::from_urdf(
        text,
        g,
        false,
        &["panda_finger_joint1", "panda_finger_joint2"],
    )
    .expect("the file reads");
    assert_eq!(
        PandaUrdf::JOINTS,
        [
            "panda_joint1",
            "panda_joint2",
            "panda_joint3",
            "panda_joint4",
            "panda_joint5",
            "panda_joint6",
            "panda_joint7"
        ]
    );
    against_numeric(&PandaUrdf, &model, 11);
    common::check(&PandaUrdf, 12);
    // The file's massless tool frame is left out of the dynamics but, with kinematics
    // asked for, is a frame: 0.1034 along the hand's z.
    let (hand, tcp) = (
        PandaUrdf::frame("panda_hand").expect("a body"),
        PandaUrdf::frame("panda_hand_tcp").expect("the URDF's tool frame"),
    );
    let mut rng = common::Rng::new(13);
    for _ in 0..5 {
        let q: SVector<f64, 7> = rng.vector(2.0);
        let expected = PandaUrdf.frame_pose(hand, &q)
            * filippov::nalgebra::Translation3::new(0.0, 0.0, 0.1034);
        let got = PandaUrdf.frame_pose(tcp, &q);
        assert!((got.translation.vector - expected.translation.vector).norm() < 1e-14);
        assert!(got.rotation.angle_to(&expected.rotation) < 1e-14);
    }
}

/// The hand-written Panda scenes (`filippov_scenes::Panda`, and `PandaS9` with friction
/// and stops) type in the file's kinematics by hand and take their inertial data from
/// Gaz et al.'s identification, not from the file. Their link frames must be the file's
/// at random configurations, S9's mass matrix must be the plain scene's (the same data,
/// typed twice), and S9's two stops must sit at the file's upper limits.
#[test]
fn hand_written_pandas_have_the_urdf_kinematics() {
    use filippov_scenes::{Panda, PandaS9};
    let (p, s9) = (Panda::default(), PandaS9::default());
    let mut rng = common::Rng::new(17);
    for _ in 0..10 {
        let q: SVector<f64, 7> = rng.vector(2.5);
        for i in 1..=7 {
            let from_file = PandaUrdf.frame_pose(
                PandaUrdf::frame(&format!("panda_link{i}")).expect("a body of the file"),
                &q,
            );
            let mine = p.frame_pose(Panda::frame(&format!("link{i}")).expect("a body"), &q);
            let s9_pose = s9.frame_pose(PandaS9::frame(&format!("link{i}")).expect("a body"), &q);
            for pose in [mine, s9_pose] {
                let dp = (pose.translation.vector - from_file.translation.vector).norm();
                let dr = pose.rotation.angle_to(&from_file.rotation);
                assert!(dp < 1e-14 && dr < 1e-14, "link {i}: {dp:e} m, {dr:e} rad");
            }
        }
        let (m, m9) = (p.mass_matrix(&q), s9.mass_matrix(&q));
        assert!((m - m9).norm() <= 1e-14 * m.norm(), "S9's inertial data");
    }
    // S9's stops: upper limits of j2 and j4 (`#[stop(j2, max = 1.7628)]`, `#[stop(j4,
    // max = -0.0698)]`), against the file's `<limit upper>`.
    let text = include_str!("../robots/panda.urdf");
    let upper = |joint: &str| -> f64 {
        let at = text
            .find(&format!("<joint name=\"{joint}\""))
            .expect("the joint");
        let limit = &text[at..][text[at..].find("<limit").expect("a limit")..];
        let u = &limit[limit.find("upper=\"").expect("an upper limit") + 7..];
        u[..u.find('"').expect("quoted")].parse().expect("a number")
    };
    use filippov::runtime::nonsmooth::{ElementKind, NonSmooth};
    let stops: Vec<(usize, f64)> = (0..PandaS9::ELEMENTS)
        .map(|e| s9.element(e))
        .filter_map(|el| match el.kind {
            ElementKind::Stop { position, .. } => Some((el.coordinate, position)),
            _ => None,
        })
        .collect();
    assert_eq!(
        stops,
        [(1, upper("panda_joint2")), (3, upper("panda_joint4"))]
    );
}

#[test]
fn ur5_from_urdf_matches_the_numeric_reader() {
    let text = include_str!("../robots/ur5.urdf");
    let model = Model::from_urdf(text, Vector3::new(0.0, 0.0, -9.81), false, &[]).expect("reads");
    assert_eq!(Ur5::DOF, 6);
    against_numeric(&Ur5, &model, 21);
    common::check(&Ur5, 22);
}

/// The arm of `examples/urdf_arm.rs`: its URDF limits as stops, its friction and
/// damping as elements. Released under gravity, it falls onto the shoulder's upper
/// limit and comes to rest there; time-stepping ends in the same state (first order in
/// h). Three elements on one coordinate (two stops and friction) share its force while
/// it rests: the time-stepping solve (also used inside the event-driven run, for the
/// impacts' accumulation) must converge on the coordinate's force, not on its split.
#[test]
fn urdf_arm_comes_to_rest_on_its_limit() {
    use filippov::runtime::{NonSmoothMethod, NonSmoothProblem, solve_nonsmooth};
    type V3 = SVector<f64, 3>;
    assert_eq!(Arm::NON_SMOOTH_ELEMENTS.len(), 9);
    let p = NonSmoothProblem::new(0.0, 4.0, V3::new(0.0, 0.2, -0.3), V3::zeros());
    let zero = |_t: f64, _q: &V3, _v: &V3| V3::zeros();
    let sol = solve_nonsmooth(&Arm, &zero, &p, &NonSmoothMethod::default()).expect("completes");
    let (_, y) = sol.last().unwrap();
    assert_eq!(y[0], 0.6, "on the shoulder's upper limit");
    assert!(y[3..6].iter().all(|v| *v == 0.0), "at rest: {y:?}");
    let end = |h: f64| {
        let ts = solve_nonsmooth(
            &Arm,
            &zero,
            &p,
            &NonSmoothMethod::TimeStepping { h, theta: 1.0 },
        )
        .expect("time-stepping completes");
        let z = ts.last().unwrap().1.to_vec();
        (0..3).map(|i| (z[i] - y[i]).abs()).fold(0.0, f64::max)
    };
    let (d3, d4) = (end(1e-3), end(1e-4));
    eprintln!("end-state distance to time-stepping: h = 1e-3 {d3:.2e}, 1e-4 {d4:.2e}");
    assert!(d4 < 2e-2 && d4 < 0.5 * d3, "{d3:e} → {d4:e}");
    // Resting on the limit, the stop carries the shoulder's load and its friction none
    // (the split the time-stepping solve settles on where a stop and a stuck friction
    // hold one coordinate); the held forces are solved, not swept towards.
    let ts = solve_nonsmooth(
        &Arm,
        &zero,
        &p,
        &NonSmoothMethod::TimeStepping {
            h: 1e-3,
            theta: 1.0,
        },
    )
    .expect("time-stepping completes");
    let names = ts.names().to_vec();
    let column = |prefix: &str| {
        let name = names
            .iter()
            .find(|n| n.starts_with(prefix) && n.contains("shoulder"))
            .unwrap_or_else(|| panic!("a column {prefix}…shoulder… in {names:?}"));
        ts.column(name).expect("the column")
    };
    let (friction, times) = (column("f_friction"), ts.times().to_vec());
    let q = ts.column("q_shoulder").expect("q_shoulder");
    let resting: Vec<usize> = (0..times.len()).filter(|&i| times[i] > 3.0).collect();
    assert!(
        resting.iter().all(|&i| q[i] == 0.6),
        "on the limit after 3 s"
    );
    // The stops' columns: the shoulder's load is theirs (to rounding).
    let stops: Vec<Vec<f64>> = (names.iter())
        .filter(|n| n.starts_with("f_") && n.contains("shoulder") && !n.contains("friction"))
        .map(|n| ts.column(n).expect("the column"))
        .collect();
    assert!(!stops.is_empty(), "the shoulder's stops in {names:?}");
    for &i in &resting {
        let load: f64 = stops.iter().map(|s| s[i].abs()).sum();
        assert!(load > 0.1, "the stop carries the load at t = {}", times[i]);
        assert!(
            friction[i].abs() <= 1e-12 * load,
            "the shoulder's friction carries nothing on its limit: {} against {load} at t = {}",
            friction[i],
            times[i]
        );
    }
    let sweeps = ts.stats.newton_iterations as f64 / ts.stats.steps as f64;
    assert!(sweeps < 4.0, "{sweeps:.1} sweeps per step");
}

#[derive(Mechanism)]
#[mechanism(urdf = "robots/solo12.urdf", base = free, gravity = [0.0, 0.0, -9.81], emit = all)]
struct Solo12;

#[derive(Mechanism)]
#[mechanism(
    urdf = "robots/simple_humanoid.urdf",
    base = free,
    gravity = [0.0, 0.0, -9.81],
    emit = [bias]
)]
struct Humanoid;

/// `max |a − b| / max(1, max |b|)`.
fn rel(a: &[f64], b: &[f64]) -> f64 {
    let scale = b.iter().fold(1.0f64, |m, x| m.max(x.abs()));
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
        / scale
}

/// A robot on a free base against the numeric reader of the same file at `states` random
/// states (unit quaternions in the rotation slots): M, C v + g and forward dynamics;
/// `more` checks anything else at the same state.
fn free_base_against_reader<S, const N: usize, const NQ: usize>(
    sys: &S,
    model: &Model,
    seed: u64,
    states: usize,
    mut more: impl FnMut(&SVector<f64, NQ>, &SVector<f64, N>, &SVector<f64, N>),
) where
    S: filippov::runtime::liegroup::LieMechanism<N, NQ> + Bias<N, NQ>,
{
    use filippov::runtime::UnitQuat;
    let mut rng = common::Rng::new(seed);
    for _ in 0..states {
        let mut q = SVector::<f64, NQ>::from_fn(|_, _| rng.uniform(-2.0, 2.0));
        for &(s, _) in S::ROTATIONS {
            let r = UnitQuat::try_new(q[s], q[s + 1], q[s + 2], q[s + 3])
                .unwrap_or_default()
                .coords();
            q.fixed_rows_mut::<4>(s).copy_from_slice(&r);
        }
        let v = SVector::<f64, N>::from_fn(|_, _| rng.uniform(-2.0, 2.0));
        let tau = SVector::<f64, N>::from_fn(|_, _| rng.uniform(-5.0, 5.0));
        let (qd, vd) = (
            DVector::from_column_slice(q.as_slice()),
            DVector::from_column_slice(v.as_slice()),
        );
        let m = sys.mass_matrix(&q);
        let m_ref = numeric::crba(model, &qd);
        assert!(rel(m.as_slice(), m_ref.as_slice()) < 1e-12, "M");
        let b = sys.bias(&q, &v);
        let b_ref = numeric::bias(model, &qd, &vd);
        assert!(rel(b.as_slice(), b_ref.as_slice()) < 1e-12, "C v + g");
        let fd = sys.forward_dynamics(&q, &v, &tau);
        let tau_d = DVector::from_column_slice(tau.as_slice());
        let fd_ref = numeric::forward_dynamics(model, &qd, &vd, &tau_d);
        assert!(
            rel(fd.as_slice(), fd_ref.as_slice()) < 1e-10,
            "forward dynamics"
        );
        more(&q, &v, &tau);
    }
}

/// A humanoid of 29 revolute joints on a floating base (35 dof), large enough that
/// `forward_dynamics = auto` takes the articulated-body algorithm for forward dynamics:
/// M, C v + g and forward dynamics against the numeric reader at random configurations,
/// and the Jacobian against central differences along the group's retraction (over the
/// whole matrix, as rounding in a difference scales with the largest acceleration).
#[test]
fn humanoid_with_a_free_base_matches_the_numeric_reader() {
    use filippov::runtime::liegroup::LieMechanism;
    let text = include_str!("../robots/simple_humanoid.urdf");
    let model = Model::from_urdf(text, Vector3::new(0.0, 0.0, -9.81), true, &[]).expect("reads");
    assert_eq!((Humanoid::DOF, Humanoid::CONFIG, model.dof()), (35, 36, 35));
    free_base_against_reader(&Humanoid, &model, 37, 10, |q, v, tau| {
        let jac = Humanoid.forward_dynamics_jacobian(q, v, tau);
        let h = 1e-6;
        let mut dq = filippov::nalgebra::SMatrix::<f64, 35, 35>::zeros();
        for k in 0..35 {
            let e = SVector::<f64, 35>::from_fn(|i, _| f64::from(i == k));
            let plus = Humanoid.forward_dynamics(&Humanoid::retract(q, &(e * h)), v, tau);
            let minus = Humanoid.forward_dynamics(&Humanoid::retract(q, &(e * -h)), v, tau);
            dq.set_column(k, &((plus - minus) / (2.0 * h)));
        }
        assert!(rel(jac.d_dq.as_slice(), dq.as_slice()) < 1e-6, "∂v̇/∂φ");
    });
}

/// A quadruped with a floating base (SO(3) × ℝ³ and 12 revolute joints): the derive's
/// expansion against the numeric reader at random configurations (unit quaternion for
/// the base), frame kinematics included.
#[test]
fn solo12_with_a_free_base_matches_the_numeric_reader() {
    let text = include_str!("../robots/solo12.urdf");
    let model = Model::from_urdf(text, Vector3::new(0.0, 0.0, -9.81), true, &[]).expect("reads");
    assert_eq!((Solo12::DOF, Solo12::CONFIG, model.dof()), (18, 19, 18));
    free_base_against_reader(&Solo12, &model, 31, 20, |q, v, _| {
        common::check_kinematics_lie(&Solo12, &model, q, v);
    });
}

#[derive(Mechanism)]
#[mechanism(
    urdf = "robots/three_link_arm.urdf",
    limits = stops(restitution = e),
    joint_friction = true,
    joint_damping = true,
    gravity = [0.0, 0.0, -9.81]
)]
#[urdf_param(upper.mass = m_upper, elbow.friction = fc, shoulder.upper = lim)]
struct ParamArm {
    m_upper: f64,
    fc: f64,
    lim: f64,
    e: f64,
}

/// Values bound to struct fields with `#[urdf_param]`: at the file's values the scene is
/// the file's; another mass changes M as the numeric model with that mass says; the
/// bound friction and limit are the elements' parameters.
#[test]
fn urdf_params_bind_struct_fields() {
    use filippov::runtime::nonsmooth::{ElementKind, NonSmooth};
    type V3 = SVector<f64, 3>;
    let file = ParamArm {
        m_upper: 2.0,
        fc: 1.5,
        lim: 0.6,
        e: 0.3,
    };
    let q = V3::new(0.3, -0.4, 0.5);
    assert_eq!(file.mass_matrix(&q), Arm.mass_matrix(&q));
    assert_eq!(ParamArm::NON_SMOOTH_ELEMENTS, Arm::NON_SMOOTH_ELEMENTS);

    let heavier = ParamArm {
        m_upper: 3.5,
        fc: 0.7,
        lim: 0.4,
        e: 0.3,
    };
    let text = include_str!("../robots/three_link_arm.urdf");
    let mut model = Model::from_urdf(text, Vector3::new(0.0, 0.0, -9.81), false, &[]).unwrap();
    let upper = model.links.iter().position(|l| l.name == "upper").unwrap();
    model.links[upper].mass = 3.5;
    let m_ref = numeric::crba(&model, &DVector::from_column_slice(q.as_slice()));
    let m = heavier.mass_matrix(&q);
    for i in 0..3 {
        for j in 0..3 {
            assert!(
                (m[(i, j)] - m_ref[(i, j)]).abs() < 1e-12 * m_ref.amax(),
                "M[{i}][{j}]"
            );
        }
    }
    let names = ParamArm::NON_SMOOTH_ELEMENTS;
    let at = |n: &str| names.iter().position(|x| *x == n).unwrap();
    match heavier.element(at("friction_elbow")).kind {
        ElementKind::DashPot { f_crit, .. } => assert_eq!(f_crit, 0.7),
        other => panic!("{other:?}"),
    }
    match heavier.element(at("stop_shoulder_max")).kind {
        ElementKind::Stop { position, .. } => assert_eq!(position, 0.4),
        other => panic!("{other:?}"),
    }
}

/// Names that are not identifiers beside ones they map onto (`j-1` and `j_1`, links
/// `arm-1` and `arm_1`): two joints and two links, each under its own identifier, the
/// file's valid names kept as they are.
#[derive(Mechanism)]
#[mechanism(urdf = "macros/tests/ui/urdf/dashed_names.urdf", gravity = [0.0, -9.81, 0.0], emit = all)]
struct DashedNames;

#[test]
fn urdf_names_stay_distinct() {
    assert_eq!(DashedNames::DOF, 2);
    assert_eq!(DashedNames::JOINTS, ["j_1_2", "j_1"]);
    let text = include_str!("../macros/tests/ui/urdf/dashed_names.urdf");
    let model = Model::from_urdf(text, Vector3::new(0.0, -9.81, 0.0), false, &[]).expect("reads");
    against_numeric(&DashedNames, &model, 23);
}
