//! Spherical and translation joints against closed forms (Newton–Euler of one rigid
//! body), an equivalent revolute description, finite differences along `q · exp(h e_k)`
//! and the structural identities of the Coriolis matrix.

use nalgebra::{DMatrix, DVector, Matrix3, Vector3};

use super::test_models::*;
use super::*;
use crate::liegroup::UnitQuat;

/// `[x, y, z]` as a column.
fn v3(x: [f64; 3]) -> Vector3<f64> {
    Vector3::from(x)
}

/// A quaternion's components.
fn quat(theta: [f64; 3]) -> [f64; 4] {
    UnitQuat::exp(&v3(theta)).coords()
}

/// A configuration of `model` away from the identity: every rotation `exp(φ)` with a
/// different `φ`, Euclidean coordinates spread out.
fn some_configuration(model: &Model) -> DVector<f64> {
    let q0 = model.identity_configuration();
    let phi = DVector::from_fn(model.dof(), |k, _| 0.7 * (1.3 * k as f64 + 0.4).sin());
    model.retract(&q0, &phi)
}

fn some_velocity(model: &Model) -> DVector<f64> {
    DVector::from_fn(model.dof(), |k, _| 1.1 * (0.9 * k as f64 - 0.3).cos())
}

fn lie_models() -> Vec<Model> {
    vec![
        spherical_body(),
        ball_chain(),
        free_body(
            2.5,
            v3([0.1, -0.2, 0.05]),
            full_inertia(0.4, 0.3, 0.5),
            v3([0.0, 0.0, -G]),
        ),
        satellite(v3([0.2, 0.1, -G])),
    ]
}

fn e(n: usize, k: usize, h: f64) -> DVector<f64> {
    DVector::from_fn(n, |i, _| if i == k { h } else { 0.0 })
}

/// `Σ_k D_k M v_k`.
fn mass_matrix_rate(model: &Model, q: &DVector<f64>, v: &DVector<f64>) -> DMatrix<f64> {
    let n = model.dof();
    mass_matrix_derivatives(model, q)
        .iter()
        .zip(v.iter())
        .fold(DMatrix::zeros(n, n), |acc, (d, vk)| acc + d * *vk)
}

#[test]
fn configuration_layout() {
    let sat = satellite(Vector3::zeros());
    assert_eq!((sat.dof(), sat.config_dim()), (8, 9));
    assert_eq!(sat.config_slots(), [Some(0), Some(3), Some(7), Some(8)]);
    assert_eq!(sat.config_slot(2), Some(7));
    assert_eq!(sat.rotation_slots(), [(3, 3)]);
    assert_eq!(sat.euclid_slots(), [(0, 0), (1, 1), (2, 2), (7, 6), (8, 7)]);
    assert_eq!(
        (0..8).map(|k| sat.euclid_slot(k)).collect::<Vec<_>>(),
        [
            Some(0),
            Some(1),
            Some(2),
            None,
            None,
            None,
            Some(7),
            Some(8)
        ]
    );
    let q0 = sat.identity_configuration();
    assert_eq!(q0.as_slice(), [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
    // Without Lie-group joints the layouts coincide.
    let chain = spatial_chain();
    assert_eq!(chain.config_dim(), chain.dof());
    for (i, link) in chain.links.iter().enumerate() {
        assert_eq!(chain.config_slot(i), link.coordinate);
    }
    assert!(chain.rotation_slots().is_empty());
    let json = sat.to_json();
    assert!(json.contains("\"joint\": \"translation\", \"axis\": null"));
    assert!(json.contains("\"joint\": \"spherical\", \"axis\": null"));
}

/// `retract` moves a quaternion by a right product with `exp(φ)`, and a Euclidean slot
/// by addition; the pose of a spherical link is the joint frame times `R(q)`.
#[test]
fn retract_and_poses_of_lie_joints() {
    let model = ball_chain();
    let q = some_configuration(&model);
    let phi = DVector::from_vec(vec![0.1, 0.2, -0.3, 0.4, 0.5]);
    let moved = model.retract(&q, &phi);
    let r0 = UnitQuat::try_new(q[1], q[2], q[3], q[4]).unwrap();
    let r1 = UnitQuat::try_new(moved[1], moved[2], moved[3], moved[4]).unwrap();
    let expected = r0.to_matrix() * crate::liegroup::so3::exp(&v3([0.2, -0.3, 0.4]));
    assert!((r1.to_matrix() - expected).norm() < 1e-14);
    assert!((moved[0] - q[0] - 0.1).abs() < 1e-15 && (moved[5] - q[5] - 0.5).abs() < 1e-15);
    let poses = link_poses(&model, &q);
    let ball = &model.links[1];
    let joint = poses[0].rotation * rpy_matrix(&ball.origin_rpy);
    assert!((poses[1].rotation - joint * r0.to_matrix()).norm() < 1e-14);
    assert!((poses[1].translation - poses[0].transform_point(&ball.origin_xyz)).norm() < 1e-15);
    // Translation: the link keeps the joint frame's orientation, offset by p.
    let body = free_body(1.0, Vector3::zeros(), Matrix3::identity(), Vector3::zeros());
    let mut qb = body.identity_configuration();
    qb.rows_mut(0, 3).copy_from_slice(&[0.3, -0.4, 2.0]);
    qb.rows_mut(3, 4).copy_from_slice(&quat([0.5, 0.1, -0.2]));
    let poses = link_poses(&body, &qb);
    assert_eq!(poses[0].rotation, Matrix3::identity());
    assert_eq!(poses[0].translation, v3([0.3, -0.4, 2.0]));
    assert_eq!(poses[1].translation, v3([0.3, -0.4, 2.0]));
}

/// A free body: RNEA against Newton–Euler written at the body's frame origin `p` with
/// the centre of mass at `c` (body frame). With `R` the body rotation, `ω`, `ω̇` body
/// angular velocity and acceleration, `p̈` the world acceleration of the origin:
/// `a_c = p̈ + R (ω̇ × c + ω × (ω × c))`, `f = m (a_c − g)` (world, the force on the
/// translation coordinates), and the moment about `p` in body axes
/// `n = I_c ω̇ + ω × I_c ω + c × (Rᵀ f)` (on the rotation coordinates).
#[test]
fn free_body_rnea_is_newton_euler() {
    let (m, c, ic) = (2.5, v3([0.1, -0.2, 0.05]), full_inertia(0.4, 0.3, 0.5));
    for g in [Vector3::zeros(), v3([0.4, -1.0, -G])] {
        let model = free_body(m, c, ic, g);
        let mut q = DVector::zeros(7);
        q.rows_mut(0, 3).copy_from_slice(&[0.3, -0.5, 1.2]);
        q.rows_mut(3, 4).copy_from_slice(&quat([0.4, -1.1, 0.8]));
        let r = UnitQuat::try_new(q[3], q[4], q[5], q[6])
            .unwrap()
            .to_matrix();
        let (pd, w) = (v3([0.7, 0.1, -0.4]), v3([1.3, -0.6, 2.1]));
        let (pdd, wd) = (v3([-0.2, 0.9, 0.3]), v3([0.5, 1.7, -0.8]));
        let v = DVector::from_iterator(6, pd.iter().chain(w.iter()).copied());
        let a = DVector::from_iterator(6, pdd.iter().chain(wd.iter()).copied());
        let a_c = pdd + r * (wd.cross(&c) + w.cross(&w.cross(&c)));
        let f = (a_c - g) * m;
        let n = ic * wd + w.cross(&(ic * w)) + c.cross(&(r.transpose() * f));
        let expected = DVector::from_iterator(6, f.iter().chain(n.iter()).copied());
        let tau = rnea(&model, &q, &v, &a);
        assert!((&tau - &expected).norm() < 1e-12, "{tau} vs {expected}");
        // The same through M and the bias.
        let via_m = crba(&model, &q) * &a + bias(&model, &q, &v);
        assert!((via_m - expected).norm() < 1e-12);
    }
}

/// One body on a spherical joint: `M = I_O = I_c + m (|c|² 𝟙 − c cᵀ)` (about the joint,
/// body axes) at every orientation, the velocity part of the bias is `ω × I_O ω`, and
/// gravity is `N = ∂U/∂φ = m (Rᵀ g) × c` (`U = −m g·(p + R c)` changes along
/// `R exp(t ê_a)` by `−m g·R (e_a × c)`), `R` the world rotation of the body.
#[test]
fn spherical_body_is_euler_equations_about_the_joint() {
    let model = spherical_body();
    let link = &model.links[0];
    let (m, c) = (link.mass, link.com);
    let i_o = link.inertia + (Matrix3::identity() * c.norm_squared() - c * c.transpose()) * m;
    for theta in [[0.0; 3], [0.3, -1.2, 2.0], [2.5, 0.4, 0.1]] {
        let q = DVector::from_column_slice(&quat(theta));
        let r = rpy_matrix(&link.origin_rpy) * UnitQuat::exp(&v3(theta)).to_matrix();
        let w = v3([0.8, -1.7, 0.6]);
        let v = DVector::from_column_slice(w.as_slice());
        let mass = crba(&model, &q);
        assert!((&mass - DMatrix::from_column_slice(3, 3, i_o.as_slice())).norm() < 1e-13);
        let n = (r.transpose() * model.gravity).cross(&c) * m;
        let g = gravity(&model, &q);
        assert!((&g - DVector::from_column_slice(n.as_slice())).norm() < 1e-12);
        let gyro = w.cross(&(i_o * w));
        let b = bias(&model, &q, &v) - g;
        assert!((b - DVector::from_column_slice(gyro.as_slice())).norm() < 1e-12);
    }
}

/// A spherical joint at the identity against revolute x, y, z joints (coincident,
/// massless intermediate links) at zero angles: the motion subspaces coincide, so `M`
/// and gravity agree. The biases differ by the revolute stack's `Ṡ` terms: its body
/// angular acceleration with zero joint accelerations is `ω_x e_x × ω_y e_y +
/// (ω_x e_x + ω_y e_y) × ω_z e_z = (ω_y ω_z, −ω_x ω_z, ω_x ω_y)`, a rotation about the
/// fixed joint point, so `bias_rev = bias_sph + M (ω_y ω_z, −ω_x ω_z, ω_x ω_y)`.
#[test]
fn spherical_equals_three_revolutes_at_identity() {
    let ball = spherical_body();
    let l = &ball.links[0];
    let massless = |name: &str, parent, axis, coordinate, xyz, rpy| {
        link(
            name,
            parent,
            JointKind::Revolute { axis },
            Some(coordinate),
            xyz,
            rpy,
            0.0,
            [0.0; 3],
            Matrix3::zeros(),
        )
    };
    let stack = Model {
        links: vec![
            massless(
                "rx",
                None,
                Vector3::x(),
                0,
                l.origin_xyz.into(),
                l.origin_rpy.into(),
            ),
            massless("ry", Some(0), Vector3::y(), 1, [0.0; 3], [0.0; 3]),
            Link {
                parent: Some(1),
                joint: JointKind::Revolute { axis: Vector3::z() },
                coordinate: Some(2),
                origin_xyz: Vector3::zeros(),
                origin_rpy: Vector3::zeros(),
                ..l.clone()
            },
        ],
        ..ball.clone()
    };
    let (qs, qr) = (ball.identity_configuration(), DVector::zeros(3));
    let mass = crba(&ball, &qs);
    assert!((crba(&stack, &qr) - &mass).norm() < 1e-14);
    assert!((gravity(&stack, &qr) - gravity(&ball, &qs)).norm() < 1e-13);
    let w = DVector::from_vec(vec![0.9, -1.4, 0.5]);
    let extra = DVector::from_vec(vec![w[1] * w[2], -w[0] * w[2], w[0] * w[1]]);
    let expected = bias(&ball, &qs, &w) + &mass * extra;
    assert!((bias(&stack, &qr, &w) - expected).norm() < 1e-13);
}

/// `D_k M` against central differences of CRBA along `q ⊕ (±h e_k)`: `q · exp(±h e_a)`
/// on a rotation, `q_k ± h` on a Euclidean coordinate.
#[test]
fn mass_matrix_derivatives_match_differences_along_exp() {
    for model in lie_models() {
        let n = model.dof();
        let q = some_configuration(&model);
        let dm = mass_matrix_derivatives(&model, &q);
        let h = 1e-6;
        for (k, dmk) in dm.iter().enumerate() {
            let qp = model.retract(&q, &e(n, k, h));
            let qm = model.retract(&q, &e(n, k, -h));
            let fd = (crba(&model, &qp) - crba(&model, &qm)) / (2.0 * h);
            assert!((dmk - &fd).norm() < 1e-8, "k = {k}: {dmk} vs {fd}");
        }
        // One body on a ball joint has a constant M (the inertia about the joint, in body
        // axes); in the others the rotation components do change M.
        let rotations = model.rotation_slots();
        let max_rot = rotations
            .iter()
            .flat_map(|&(_, k)| (k..k + 3).map(|i| dm[i].norm()))
            .fold(0.0, f64::max);
        if model.links.len() == 1 {
            assert!(max_rot < 1e-13);
        } else {
            assert!(max_rot > 1e-2, "{max_rot}");
        }
    }
}

/// Gravity and springs are the derivative of the potential energy along `q ⊕ (h e_k)`.
#[test]
fn gravity_and_springs_are_potential_gradient_along_exp() {
    let mut models = lie_models();
    models[1].springs.push(Spring {
        coordinate: 4,
        stiffness: 3.0,
        rest: 0.2,
    });
    models[3].springs.push(Spring {
        coordinate: 1,
        stiffness: 2.0,
        rest: -0.3,
    });
    for model in models {
        let n = model.dof();
        let q = some_configuration(&model);
        let zero = DVector::zeros(n);
        let force = gravity(&model, &q) - passive_forces(&model, &q, &zero);
        let h = 1e-6;
        for k in 0..n {
            let up = potential_energy(&model, &model.retract(&q, &e(n, k, h)));
            let um = potential_energy(&model, &model.retract(&q, &e(n, k, -h)));
            let du = (up - um) / (2.0 * h);
            assert!(
                (du - force[k]).abs() < 1e-7,
                "k = {k}: {du} vs {}",
                force[k]
            );
        }
    }
}

/// `lie_coriolis_matrix · v = bias − gravity` (RNEA with `a = 0`), `Ṁ − 2C` is
/// skew-symmetric with `Ṁ = Σ_k D_k M v_k`, and without spherical joints it is the
/// Christoffel `coriolis_matrix`.
#[test]
fn lie_coriolis_is_the_bias_and_keeps_passivity() {
    for model in lie_models() {
        let q = some_configuration(&model);
        let v = some_velocity(&model);
        let c = lie_coriolis_matrix(&model, &q, &v);
        let cv = bias(&model, &q, &v) - gravity(&model, &q);
        assert!((&c * &v - &cv).norm() < 1e-11, "{} vs {cv}", &c * &v);
        let s = mass_matrix_rate(&model, &q, &v) - 2.0 * &c;
        assert!((&s + s.transpose()).norm() < 1e-11);
        // The symmetric (Christoffel) part alone misses the ad term.
        assert!((coriolis_matrix(&model, &q, &v) * &v - &cv).norm() > 1e-3);
    }
    for model in [spatial_chain(), cart_pole(2.0, 0.5, 1.0)] {
        let n = model.dof();
        let q = DVector::from_fn(n, |i, _| 0.5 + 0.3 * i as f64);
        let v = DVector::from_fn(n, |i, _| 1.1 - 0.8 * i as f64);
        assert_eq!(
            lie_coriolis_matrix(&model, &q, &v),
            coriolis_matrix(&model, &q, &v)
        );
    }
    // A translation joint alone is Euclidean: no ad term, and the Christoffel form is
    // exact for it too.
    let mut point = free_body(1.0, Vector3::zeros(), Matrix3::identity(), Vector3::zeros());
    point.links.truncate(1);
    point.links[0].mass = 2.0;
    point.links[0].com = v3([0.1, 0.2, 0.3]);
    point.links[0].inertia = full_inertia(0.2, 0.3, 0.4);
    let q = DVector::from_vec(vec![0.5, -0.2, 0.1]);
    let v = DVector::from_vec(vec![1.0, 2.0, -1.0]);
    assert_eq!(crba(&point, &q), DMatrix::identity(3, 3) * 2.0);
    assert!(bias(&point, &q, &v).norm() < 1e-15);
}

/// Column `j` of `M` is `RNEA(q, 0, e_j) − RNEA(q, 0, 0)` with Lie-group joints too.
#[test]
fn mass_matrix_columns_equal_rnea_differences() {
    for model in lie_models() {
        let n = model.dof();
        let q = some_configuration(&model);
        let zero = DVector::zeros(n);
        let mass = crba(&model, &q);
        let g = rnea(&model, &q, &zero, &zero);
        for j in 0..n {
            let col = rnea(&model, &q, &zero, &e(n, j, 1.0)) - &g;
            assert!((mass.column(j) - col).norm() < 1e-12, "column {j}");
        }
        assert!((&mass - mass.transpose()).norm() < 1e-12);
        assert!(mass.clone().cholesky().is_some());
    }
}

/// Forward and inverse dynamics are inverse, with a spring on the wrist (configuration
/// slot 5, velocity index 4) and a damper on an angular-velocity component.
#[test]
fn forward_and_inverse_dynamics_are_inverse_with_lie_joints() {
    let mut model = ball_chain();
    model.springs.push(Spring {
        coordinate: 4,
        stiffness: 3.0,
        rest: 0.2,
    });
    model.dampers.push(Damper {
        coordinate: 2,
        damping: 0.7,
    });
    let q = some_configuration(&model);
    let v = some_velocity(&model);
    let passive = passive_forces(&model, &q, &v);
    assert!((passive[4] + 3.0 * (q[5] - 0.2)).abs() < 1e-15);
    assert!((passive[2] + 0.7 * v[2]).abs() < 1e-15);
    let tau = DVector::from_fn(5, |i, _| (i as f64).sin());
    let a = forward_dynamics(&model, &q, &v, &tau);
    assert!((inverse_dynamics(&model, &q, &v, &a) - tau).norm() < 1e-11);
}

/// Energy balance `dE/dt = vᵀ (τ + τ_damper)` along `q(t) = q ⊕ (t v + t²/2 a)`,
/// `v(t) = v + t a` (the body velocity of that curve is `v + t a + O(t²)` with an even
/// `t²` term, which the central difference cancels).
#[test]
fn energy_rate_equals_power_with_lie_joints() {
    for mut model in lie_models() {
        let n = model.dof();
        model.dampers.push(Damper {
            coordinate: n - 1,
            damping: 0.4,
        });
        let q = some_configuration(&model);
        let v = some_velocity(&model);
        let tau = DVector::from_fn(n, |i, _| 0.3 * i as f64 - 0.2);
        let a = forward_dynamics(&model, &q, &v, &tau);
        let energy = |t: f64| {
            let qt = model.retract(&q, &(&v * t + &a * (0.5 * t * t)));
            let vt = &v + &a * t;
            kinetic_energy(&model, &qt, &vt) + potential_energy(&model, &qt)
        };
        // The truncation error is O(h²) with a large constant here (the accelerations
        // of the light spherical body are large): 1e-3 at h = 1e-2, 1e-9 at 1e-5.
        let h = 1e-5;
        let rate = (energy(h) - energy(-h)) / (2.0 * h);
        let power = v.dot(&(tau + passive_forces(&model, &q, &v)));
        assert!((rate - power).abs() < 1e-7, "{rate} vs {power}");
    }
}

/// A free body's spatial momentum: `L = m (ṗ + R (ω × c))` and, about the world origin,
/// `x_c × L + R I_c ω` with `x_c = p + R c`.
#[test]
fn free_body_spatial_momentum_closed_form() {
    let (m, c, ic) = (2.5, v3([0.1, -0.2, 0.05]), full_inertia(0.4, 0.3, 0.5));
    let model = free_body(m, c, ic, Vector3::zeros());
    let mut q = DVector::zeros(7);
    q.rows_mut(0, 3).copy_from_slice(&[0.3, -0.5, 1.2]);
    q.rows_mut(3, 4).copy_from_slice(&quat([-0.7, 0.2, 1.5]));
    let r = UnitQuat::try_new(q[3], q[4], q[5], q[6])
        .unwrap()
        .to_matrix();
    let (pd, w) = (v3([0.7, 0.1, -0.4]), v3([1.3, -0.6, 2.1]));
    let v = DVector::from_iterator(6, pd.iter().chain(w.iter()).copied());
    let (lin, ang) = spatial_momentum(&model, &q, &v);
    let l = (pd + r * w.cross(&c)) * m;
    let x_c = q.fixed_rows::<3>(0) + r * c;
    assert!((lin - l).norm() < 1e-14);
    assert!((ang - (x_c.cross(&l) + r * ic * w)).norm() < 1e-13);
}

/// Newton's and Euler's laws for the whole satellite: with gravity and internal arm
/// torques, the spatial momentum changes at the rate of the external wrench,
/// `(Σ m_i g, Σ m_i x_i × g)` (central differences along the motion, as in the energy
/// balance).
#[test]
fn satellite_momentum_rate_is_the_gravity_wrench() {
    let g = v3([0.2, 0.1, -G]);
    let model = satellite(g);
    let q = some_configuration(&model);
    let v = some_velocity(&model);
    let mut tau = DVector::zeros(8);
    tau[6] = 1.5;
    tau[7] = -0.8;
    let a = forward_dynamics(&model, &q, &v, &tau);
    let momentum = |t: f64| {
        let qt = model.retract(&q, &(&v * t + &a * (0.5 * t * t)));
        spatial_momentum(&model, &qt, &(&v + &a * t))
    };
    let h = 1e-4;
    let ((lp, ap), (lm, am)) = (momentum(h), momentum(-h));
    let poses = link_poses(&model, &q);
    let total: f64 = model.links.iter().map(|l| l.mass).sum();
    let first_moment = model
        .links
        .iter()
        .zip(&poses)
        .fold(Vector3::zeros(), |acc, (l, p)| {
            acc + p.transform_point(&l.com) * l.mass
        });
    assert!(((lp - lm) / (2.0 * h) - g * total).norm() < 1e-6);
    assert!(((ap - am) / (2.0 * h) - first_moment.cross(&g)).norm() < 1e-6);
}
