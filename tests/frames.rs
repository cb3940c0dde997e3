//! Generated forward kinematics (`#[frame]`, `emit = [kinematics]`): declared frames —
//! on a body, on another frame, on the world — against poses composed here with
//! nalgebra from the numeric model's link poses, and every frame's Jacobian against
//! central differences of its pose (`common::check_kinematics`), at random states.

mod common;

use filippov::nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use filippov::prelude::*;
use filippov::runtime::numeric;

#[derive(Mechanism)]
#[mechanism(gravity = [0.0, 0.0, -9.81])]
#[body(upper, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[joint(shoulder: revolute(z), parent = world, child = upper, origin = [0.1, 0.0, 0.2])]
#[body(fore, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[joint(elbow: revolute([0.0, 0.6, 0.8]), parent = upper, child = fore, origin = [l, 0.0, 0.0], rpy = [0.3, -0.2, 0.1])]
#[body(slider, mass = m / 2.0, com = [0.0, 0.0, 0.0], inertia = sphere(m / 2.0, 0.05))]
#[joint(rail: prismatic([1.0, 2.0, 2.0]), parent = fore, child = slider, origin = [l / 2.0, 0.0, 0.0])]
#[frame(wrist, parent = fore, origin = [l, 0.0, 0.0], rpy = [0.0, 0.5, 0.0])]
#[frame(tool, parent = wrist, origin = [0.0, 0.0, d], rpy = [0.1, 0.2, 0.3])]
#[frame(camera, parent = world, origin = [1.0, 2.0, 3.0], rpy = [0.0, 0.0, 1.0])]
struct Arm {
    m: f64,
    l: f64,
    d: f64,
}

fn offset(xyz: [f64; 3], rpy: [f64; 3]) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::new(xyz[0], xyz[1], xyz[2]),
        UnitQuaternion::from_euler_angles(rpy[0], rpy[1], rpy[2]),
    )
}

#[test]
fn declared_frames_compose_their_offsets() {
    let arm = Arm {
        m: 1.3,
        l: 0.7,
        d: 0.15,
    };
    assert_eq!(
        Arm::FRAMES,
        ["upper", "fore", "slider", "wrist", "tool", "camera"]
    );
    let model = arm.model();
    let (tool, camera) = (Arm::frame("tool").unwrap(), Arm::frame("camera").unwrap());
    let mut rng = common::Rng::new(7);
    for _ in 0..20 {
        let q: SVector<f64, 3> = rng.vector(3.0);
        let v: SVector<f64, 3> = rng.vector(2.0);
        let poses = numeric::link_poses(&model, &common::dvec(&q));
        let fore: Isometry3<f64> = poses[1].into();
        let expected = fore
            * offset([0.7, 0.0, 0.0], [0.0, 0.5, 0.0])
            * offset([0.0, 0.0, 0.15], [0.1, 0.2, 0.3]);
        let got = arm.frame_pose(tool, &q);
        assert!(
            (got.translation.vector - expected.translation.vector).norm() < 1e-14
                && got.rotation.angle_to(&expected.rotation) < 1e-14,
            "tool: {got} vs {expected}"
        );
        // A frame on the world does not move: its pose is the offset, its Jacobian zero.
        let cam = arm.frame_pose(camera, &q);
        let cam_ref = offset([1.0, 2.0, 3.0], [0.0, 0.0, 1.0]);
        assert!((cam.translation.vector - cam_ref.translation.vector).norm() < 1e-15);
        assert!(cam.rotation.angle_to(&cam_ref.rotation) < 1e-15);
        assert_eq!(
            arm.frame_jacobian(camera, &q),
            SMatrix::<f64, 6, 3>::zeros()
        );
        // The slider is not on the tool's path: its column is an exact zero.
        let j = arm.frame_jacobian(tool, &q);
        assert_eq!(j.column(2).norm(), 0.0, "rail is off the tool's path");
        // The tool's angular velocity is the shoulder's and elbow's axes (world) times
        // their rates.
        let upper: Isometry3<f64> = poses[0].into();
        let w = Vector3::z() * v[0]
            + upper.rotation
                * (offset([0.0; 3], [0.3, -0.2, 0.1]).rotation * Vector3::new(0.0, 0.6, 0.8))
                * v[1];
        assert!((j.fixed_rows::<3>(3) * v - w).norm() < 1e-13);
        common::check_kinematics(&arm, &model, &q, &v, |s| q + v * s);
    }
}
