//! Contacts' kinematics (`#[contact(…)]`): the generated gaps, normal and tangential
//! Jacobians and `γ` terms against references that do not use the generator — the
//! numeric model's link poses composed here with the contact's declaration, central
//! differences of those poses for the material points' velocities — on an oblique
//! spatial tree at random states; and closed forms on planar scenes (a box's corners, a
//! rolling ball).

mod common;
#[path = "../examples/support/contact_closed_forms.rs"]
mod contact_closed_forms;

use filippov::nalgebra::{DVector, Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use filippov::prelude::*;
use filippov::runtime::contacts::Contacts;
use filippov::runtime::numeric;

/// An oblique spatial tree (nothing axis-aligned to fold): a sphere on the last body
/// against a tilted world plane, and a point on the second against a plane the first
/// body carries.
#[derive(Mechanism, Clone, Copy)]
#[mechanism(gravity = [0.0, 0.0, -9.81])]
#[body(base, mass = 1.0, com = [0.1, 0.0, 0.05], inertia = sphere(1.0, 0.2))]
#[joint(slide: prismatic([0.6, 0.0, 0.8]), parent = world, child = base, origin = [0.0, 0.0, 1.0], rpy = [0.1, 0.2, 0.3])]
#[body(arm, mass = 0.5, com = [0.2, 0.05, 0.0], inertia = sphere(0.5, 0.1))]
#[joint(shoulder: revolute([0.0, 0.6, 0.8]), parent = base, child = arm, origin = [0.1, 0.2, 0.0], rpy = [0.3, -0.2, 0.5])]
#[body(hand, mass = 0.3, com = [0.05, 0.0, 0.02], inertia = sphere(0.3, 0.05))]
#[joint(wrist: revolute([1.0, 1.0, 0.0]), parent = arm, child = hand, origin = [0.4, 0.0, 0.1], rpy = [-0.2, 0.1, 0.0])]
#[contact(ball: sphere(r), body = hand, at = [0.1, 0.05, -0.02], plane = world,
          origin = [0.0, 0.1, 0.1], rpy = [0.2, -0.1, 0.3], normal = z, mu = mu, restitution = e)]
#[contact(tip: point, body = arm, at = [0.4, -0.1, 0.05], plane = base,
          origin = [0.0, 0.1, 0.2], rpy = [0.0, 0.4, -0.3], normal = -x, mu = 0.3)]
struct Oblique {
    r: f64,
    mu: f64,
    e: f64,
}

const OBLIQUE: Oblique = Oblique {
    r: 0.07,
    mu: 0.4,
    e: 0.5,
};

fn offset(xyz: [f64; 3], rpy: [f64; 3]) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::new(xyz[0], xyz[1], xyz[2]),
        UnitQuaternion::from_euler_angles(rpy[0], rpy[1], rpy[2]),
    )
}

/// One contact as declared, for the reference: the sphere's body and centre, its radius,
/// the plane's body (`None`: world), frame offset and normal axis.
struct Declared {
    body: &'static str,
    at: [f64; 3],
    radius: f64,
    plane: Option<&'static str>,
    origin: [f64; 3],
    rpy: [f64; 3],
    normal: [f64; 3],
}

const DECLARED: [Declared; 2] = [
    Declared {
        body: "hand",
        at: [0.1, 0.05, -0.02],
        radius: 0.07,
        plane: None,
        origin: [0.0, 0.1, 0.1],
        rpy: [0.2, -0.1, 0.3],
        normal: [0.0, 0.0, 1.0],
    },
    Declared {
        body: "arm",
        at: [0.4, -0.1, 0.05],
        radius: 0.0,
        plane: Some("base"),
        origin: [0.0, 0.1, 0.2],
        rpy: [0.0, 0.4, -0.3],
        normal: [-1.0, 0.0, 0.0],
    },
];

/// The reference at `q`: per contact, the gap, the contact point, the plane's frame.
fn reference(model: &numeric::Model, q: &DVector<f64>) -> Vec<(f64, Point3<f64>, Isometry3<f64>)> {
    let poses: Vec<Isometry3<f64>> = numeric::link_poses(model, q)
        .into_iter()
        .map(Into::into)
        .collect();
    let link = |name: &str| {
        let i = model
            .links
            .iter()
            .position(|l| l.name == name)
            .expect("a link");
        poses[i]
    };
    DECLARED
        .iter()
        .map(|c| {
            let plane = c.plane.map_or(Isometry3::identity(), link) * offset(c.origin, c.rpy);
            let n = plane.rotation * Vector3::from(c.normal);
            let centre = link(c.body) * Point3::from(c.at);
            let gap = n.dot(&(centre - Point3::from(plane.translation.vector))) - c.radius;
            (gap, centre - n * c.radius, plane)
        })
        .collect()
}

/// The velocity, along `v`, of the material point of link `name` (or of the world: 0)
/// that is at `point` at `q`: central differences of its body-fixed position.
fn material_velocity(
    model: &numeric::Model,
    q: &DVector<f64>,
    v: &DVector<f64>,
    name: Option<&str>,
    point: Point3<f64>,
) -> Vector3<f64> {
    let Some(name) = name else {
        return Vector3::zeros();
    };
    let i = model
        .links
        .iter()
        .position(|l| l.name == name)
        .expect("a link");
    let pose = |q: &DVector<f64>| -> Isometry3<f64> { numeric::link_poses(model, q)[i].into() };
    let local = pose(q).inverse() * point;
    let h = 1e-6;
    ((pose(&(q + v * h)) * local) - (pose(&(q - v * h)) * local)) / (2.0 * h)
}

#[test]
fn oblique_contacts_match_the_numeric_model() {
    let s = OBLIQUE;
    assert_eq!(Oblique::CONTACTS, ["ball", "tip"]);
    // Spatial: both tangents of each contact survive.
    assert_eq!(Oblique::TANGENTS, ["ball.x", "ball.y", "tip.y", "tip.z"]);
    assert_eq!(Oblique::TANGENT_OF, [0, 0, 1, 1]);
    assert_eq!(s.contact_friction(), [0.4, 0.3]);
    assert_eq!(s.contact_restitution(), [0.5, 0.0]);
    let model = s.model();
    let mut rng = common::Rng::new(71);
    let mut worst = [0.0f64; 5];
    for _ in 0..20 {
        let q: SVector<f64, 3> = rng.vector(1.0);
        let v: SVector<f64, 3> = rng.vector(2.0);
        let (qd, vd) = (common::dvec(&q), common::dvec(&v));
        let refs = reference(&model, &qd);
        let gaps = s.contact_gaps(&q);
        let w_n = s.contact_normal_jacobian(&q);
        let w_t = s.contact_tangent_jacobian(&q);
        let h = 1e-6;
        for (k, (gap, point, plane)) in refs.iter().enumerate() {
            worst[0] = worst[0].max((gaps[k] - gap).abs());
            // W_N against central differences of the reference gap, column by column.
            for j in 0..3 {
                let mut e = DVector::zeros(3);
                e[j] = h;
                let d = (reference(&model, &(&qd + &e))[k].0 - reference(&model, &(&qd - &e))[k].0)
                    / (2.0 * h);
                worst[1] = worst[1].max((w_n[(k, j)] - d).abs());
            }
            // W_T v against the material points' relative velocity along the tangents.
            let c = &DECLARED[k];
            let u = material_velocity(&model, &qd, &vd, Some(c.body), *point)
                - material_velocity(&model, &qd, &vd, c.plane, *point);
            let rows: Vec<usize> = (0..4).filter(|&t| Oblique::TANGENT_OF[t] == k).collect();
            let axes: Vec<usize> = (0..3).filter(|&a| c.normal[a] == 0.0).collect();
            for (&row, &axis) in rows.iter().zip(&axes) {
                let t = plane.rotation * Vector3::ith(axis, 1.0);
                worst[2] = worst[2].max(((w_t.row(row) * v)[0] - t.dot(&u)).abs());
            }
            // The normal velocity is the gap's rate.
            let n = plane.rotation * Vector3::from(c.normal);
            worst[3] = worst[3].max(((w_n.row(k) * v)[0] - n.dot(&u)).abs());
        }
        // γ = −Ẇ v against central differences of W v along v.
        let e = 1e-6;
        let (qp, qm) = (q + v * e, q - v * e);
        let gn = -(s.contact_normal_jacobian(&qp) - s.contact_normal_jacobian(&qm)) * v / (2.0 * e);
        let gt =
            -(s.contact_tangent_jacobian(&qp) - s.contact_tangent_jacobian(&qm)) * v / (2.0 * e);
        worst[4] = worst[4]
            .max((s.contact_normal_gamma(&q, &v) - gn).amax())
            .max((s.contact_tangent_gamma(&q, &v) - gt).amax());
    }
    eprintln!(
        "gap {:.1e}, W_N {:.1e}, W_T v {:.1e}, W_N v = n·u {:.1e}, γ {:.1e}",
        worst[0], worst[1], worst[2], worst[3], worst[4]
    );
    assert!(worst[0] < 1e-14, "gap {:e}", worst[0]);
    assert!(
        worst[1] < 1e-8 && worst[2] < 1e-8 && worst[3] < 1e-8,
        "{worst:?}"
    );
    assert!(worst[4] < 1e-6, "γ {:e}", worst[4]);
}

/// A box free in the plane (`x`, `y`, angle `θ`), two bottom corners on the ground
/// (normal `y`), a ball of radius `r` rolling beside it; in the plane each contact keeps
/// one tangent (`x`), the out-of-plane one folding away.
#[derive(Mechanism, Clone, Copy)]
#[mechanism(gravity = [0.0, -9.81, 0.0])]
#[body(slider_x, mass = 0.0)]
#[joint(x: prismatic(x), parent = world, child = slider_x)]
#[body(slider_y, mass = 0.0)]
#[joint(y: prismatic(y), parent = slider_x, child = slider_y)]
#[body(block, mass = m, inertia = cuboid(m, 2.0 * a, 2.0 * b, 0.1))]
#[joint(angle: revolute(z), parent = slider_y, child = block)]
#[contact(left: point, body = block, at = [-a, -b, 0.0], plane = world, normal = y, mu = mu)]
#[contact(right: point, body = block, at = [a, -b, 0.0], plane = world, normal = y, mu = mu)]
#[contact(rim: sphere(r), body = block, plane = world, origin = [0.0, -h, 0.0], normal = y)]
struct PlanarBox {
    m: f64,
    a: f64,
    b: f64,
    r: f64,
    h: f64,
    mu: f64,
}

#[test]
fn planar_contacts_keep_one_tangent_and_match_closed_forms() {
    let s = PlanarBox {
        m: 2.0,
        a: 0.3,
        b: 0.2,
        r: 0.25,
        h: 0.1,
        mu: 0.6,
    };
    assert_eq!(PlanarBox::TANGENTS, ["left.x", "right.x", "rim.x"]);
    let mut rng = common::Rng::new(5);
    let mut worst = 0.0f64;
    for _ in 0..20 {
        let q: SVector<f64, 3> = rng.vector(1.0);
        let v: SVector<f64, 3> = rng.vector(2.0);
        let (y, th) = (q[1], q[2]);
        let (c, sn) = (th.cos(), th.sin());
        let gaps = s.contact_gaps(&q);
        // A corner (±a, −b) of the box: height y ± a sin θ − b cos θ.
        let corner = |sx: f64| y + sx * s.a * sn - s.b * c;
        let expected = [corner(-1.0), corner(1.0), y - s.r + s.h];
        let w_t = s.contact_tangent_jacobian(&q);
        let w_n = s.contact_normal_jacobian(&q);
        // A corner's horizontal velocity: ẋ − θ̇ (±a sin θ − b cos θ)… as d/dt of
        // x ± a cos θ + b sin θ; the rolling rim's slip: ẋ + r θ̇.
        let slide = |sx: f64| v[0] + v[2] * (-sx * s.a * sn + s.b * c);
        let lift = |sx: f64| v[1] + v[2] * (sx * s.a * c + s.b * sn);
        let slips = [slide(-1.0), slide(1.0), v[0] + s.r * v[2]];
        let normals = [lift(-1.0), lift(1.0), v[1]];
        for k in 0..3 {
            worst = worst
                .max((gaps[k] - expected[k]).abs())
                .max(((w_t.row(k) * v)[0] - slips[k]).abs())
                .max(((w_n.row(k) * v)[0] - normals[k]).abs());
        }
        // A corner's normal acceleration term: −d/dt(W_N v) at fixed v̇, the corner's
        // centripetal part: θ̇² (± a sin θ − b cos θ)… of y's second derivative.
        let gamma = s.contact_normal_gamma(&q, &v);
        for (k, sx) in [(0, -1.0), (1, 1.0)] {
            let centripetal = v[2] * v[2] * (sx * s.a * sn - s.b * c);
            worst = worst.max((gamma[k] - centripetal).abs());
        }
        assert_eq!(
            s.contact_tangent_gamma(&q, &v)[2],
            0.0,
            "rolling on a plane: no γ_T"
        );
    }
    eprintln!("planar closed forms within {worst:.1e}");
    assert!(worst < 1e-13, "{worst:e}");
}

#[test]
fn contact_coefficients_are_validated() {
    let bad = PlanarBox {
        m: 2.0,
        a: 0.3,
        b: 0.2,
        r: -0.1,
        h: 0.1,
        mu: -0.5,
    };
    let err = bad
        .validate()
        .expect_err("a negative friction coefficient and radius");
    let text = err.to_string();
    assert!(text.contains("`mu` of contact `left`"), "{text}");
    assert!(text.contains("radius of contact `rim`"), "{text}");
    let bouncy = Oblique { e: 1.5, ..OBLIQUE };
    let text = bouncy.validate().expect_err("e > 1").to_string();
    assert!(text.contains("restitution of contact `ball`"), "{text}");
}

/// The planar scenes' start and input, shared by the integrators' tests.
mod planar {
    use filippov::prelude::*;
    use filippov::scenes::SlidingBox;

    pub type V3 = SVector<f64, 3>;

    pub fn no_input(_: f64, _: &V3, _: &V3) -> V3 {
        V3::zeros()
    }

    /// The box resting on its ground (tilted by φ): angle φ, centre at `b` along the
    /// normal from the origin.
    pub fn resting(s: &SlidingBox) -> V3 {
        V3::from([-s.b * s.phi.sin(), s.b * s.phi.cos(), s.phi])
    }
}

mod stepping {
    use super::planar::{V3, no_input, resting};
    use filippov::runtime::contacts::Contacts;
    use filippov::runtime::{NonSmoothProblem, contact_time_stepping};
    use filippov::scenes::{SlidingBox, SpinningBall};

    /// Level ground, launched at `v0`: it slides to rest at `t = v0 / (μ g)` after
    /// `v0² / (2 μ g)`, without turning or lifting, its leading corner carrying
    /// `μ b m g / a` more than the trailing one; first order in `h`.
    #[test]
    fn box_slides_to_rest_in_its_closed_form_time_and_distance() {
        let s = SlidingBox::default();
        let v0 = 2.0;
        let (t_stop, distance) = (v0 / (s.mu * s.g), v0 * v0 / (2.0 * s.mu * s.g));
        let mut errors = Vec::new();
        for h in [1e-3, 1e-4] {
            let p = NonSmoothProblem::new(0.0, 1.0, resting(&s), V3::from([v0, 0.0, 0.0]));
            let sol = contact_time_stepping(&s, &no_input, &p, h).unwrap_or_else(|e| panic!("{e}"));
            let stopped = sol
                .rows()
                .find(|(_, y)| y[3] == 0.0)
                .map(|(t, _)| t)
                .expect("it stops");
            let (_, last) = sol.last().unwrap();
            let (rear, front) = (
                sol.column_index("λ_rear.n").unwrap(),
                sol.column_index("λ_front.n").unwrap(),
            );
            // While sliding: the load split and the friction at the cone's edge.
            let (_, mid) = sol.rows().nth(10).unwrap();
            let split = mid[front] - mid[rear];
            assert!(
                (split - s.mu * s.b * s.m * s.g / s.a).abs() < 1e-9,
                "{split}"
            );
            assert!((mid[front] + mid[rear] - s.m * s.g).abs() < 1e-9);
            let worst_turn = sol
                .rows()
                .map(|(_, y)| y[2].abs().max((y[1] - s.b).abs()))
                .fold(0.0, f64::max);
            eprintln!(
                "h = {h}: stopped at {stopped:.6} (closed form {t_stop:.6}), slid {:.6} ({distance:.6}); \
                 turned or lifted ≤ {worst_turn:.1e}",
                last[0]
            );
            assert!(
                (stopped - t_stop).abs() <= 1.01 * h,
                "{stopped} against {t_stop}"
            );
            assert!(
                (last[0] - distance).abs() <= 1.01 * v0 * h,
                "{} against {distance}",
                last[0]
            );
            assert!(worst_turn < 1e-12, "{worst_turn:e}");
            // At rest it does not move by a rounding.
            assert!(
                sol.rows()
                    .filter(|(t, _)| *t >= stopped)
                    .all(|(_, y)| y[0] == last[0] && y[3] == 0.0)
            );
            errors.push((last[0] - distance).abs());
        }
        assert!(
            errors[1] < 0.2 * errors[0] + 1e-12,
            "first order: {errors:?}"
        );
    }

    /// Below its friction angle the box on the incline stays where it was put: its
    /// coordinates are the start's, bit for bit, over 10⁴ s.
    #[test]
    fn box_on_an_incline_below_its_friction_angle_does_not_move() {
        let s = SlidingBox {
            phi: 0.3,
            ..SlidingBox::default()
        };
        assert!(s.phi.tan() < s.mu);
        let q0 = resting(&s);
        let p = NonSmoothProblem::new(0.0, 1e4, q0, V3::zeros());
        let sol = contact_time_stepping(&s, &no_input, &p, 0.1).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(sol.len(), 100_001);
        for (t, y) in sol.rows() {
            assert_eq!(&y[..6], &[q0[0], q0[1], q0[2], 0.0, 0.0, 0.0], "t = {t}");
        }
        let (_, last) = sol.last().unwrap();
        let tangential = last[sol.column_index("λ_rear.x").unwrap()]
            + last[sol.column_index("λ_front.x").unwrap()];
        assert!(
            (tangential - s.m * s.g * s.phi.sin()).abs() < 1e-9,
            "{tangential}"
        );
    }

    /// Above it the box slides down at `g (sin φ − μ cos φ)`: time-stepping's velocity is
    /// that, step after step.
    #[test]
    fn box_on_an_incline_above_its_friction_angle_accelerates() {
        let s = SlidingBox {
            phi: 0.6,
            ..SlidingBox::default()
        };
        let a = s.g * (s.phi.sin() - s.mu * s.phi.cos());
        let p = NonSmoothProblem::new(0.0, 2.0, resting(&s), V3::zeros());
        let sol = contact_time_stepping(&s, &no_input, &p, 1e-3).unwrap_or_else(|e| panic!("{e}"));
        let mut worst = 0.0f64;
        for (t, y) in sol.rows() {
            let speed = -(y[3] * s.phi.cos() + y[4] * s.phi.sin());
            worst = worst.max((speed - a * t).abs());
            assert!(y[5].abs() < 1e-12, "no rotation");
        }
        eprintln!("down the slope at g (sin φ − μ cos φ) within {worst:.1e} m/s");
        assert!(worst < 1e-9 * a * 2.0, "{worst:e}");
    }

    /// A solid ball set spinning at `ω₀` on the ground without moving: it slips, the
    /// friction `μ m g` slowing the slip `ẋ + r θ̇` at `(7/2) μ g`, until it rolls at
    /// `t = 2 r ω₀ / (7 μ g)` with `ẋ = −(2/7) r ω₀` (the angular momentum about the
    /// contact point kept), and rolls on at that speed.
    #[test]
    fn spinning_ball_slips_until_it_rolls() {
        let s = SpinningBall::default();
        let omega = 20.0;
        let (t_roll, v_roll) = (
            2.0 * s.r * omega / (7.0 * s.mu * s.g),
            -2.0 / 7.0 * s.r * omega,
        );
        for h in [1e-3, 1e-4] {
            let p = NonSmoothProblem::new(
                0.0,
                1.0,
                V3::from([0.0, s.r, 0.0]),
                V3::from([0.0, 0.0, omega]),
            );
            let sol = contact_time_stepping(&s, &no_input, &p, h).unwrap_or_else(|e| panic!("{e}"));
            let rolls = sol
                .rows()
                .find(|(_, y)| (y[3] + s.r * y[5]).abs() < 1e-12)
                .map(|(t, _)| t)
                .expect("it rolls");
            let (_, last) = sol.last().unwrap();
            eprintln!(
                "h = {h}: rolls from {rolls:.5} (closed form {t_roll:.5}) at {:.6} m/s ({v_roll:.6})",
                last[3]
            );
            assert!(
                (rolls - t_roll).abs() <= 1.01 * h,
                "{rolls} against {t_roll}"
            );
            assert!(
                (last[3] - v_roll).abs() <= 1.01 * s.mu * s.g * h,
                "{} against {v_roll}",
                last[3]
            );
            assert!((last[3] + s.r * last[5]).abs() < 1e-12, "rolling");
            assert!(
                last[4].abs() < 1e-12 && (last[1] - s.r).abs() < 1e-12,
                "on the ground"
            );
        }
    }

    /// A ball dropped from height H onto the ground with restitution e: the first impact
    /// at √(2H/g), rebounding at e √(2 g H); it comes to rest pressing with `m g`.
    #[test]
    fn dropped_ball_bounces_then_rests_with_its_weight() {
        let s = SpinningBall::default();
        assert_eq!(SpinningBall::TANGENTS, ["bottom.x"]);
        let height = 0.2;
        let q0 = V3::from([0.0, s.r + height, 0.0]);
        let p = NonSmoothProblem::new(0.0, 3.0, q0, V3::zeros());
        let h = 1e-4;
        let sol = contact_time_stepping(&s, &no_input, &p, h).unwrap_or_else(|e| panic!("{e}"));
        let impacts: Vec<_> = sol
            .switches
            .iter()
            .filter(|sw| sw.kind == filippov::runtime::SwitchKind::Impact)
            .collect();
        let first = impacts.first().expect("an impact");
        let (t1, v1) = ((2.0 * height / s.g).sqrt(), (2.0 * s.g * height).sqrt());
        assert!((first.t - t1).abs() <= 2.0 * h, "{} against {t1}", first.t);
        let rebound = first.after[4];
        assert!(
            (rebound - s.e * v1).abs() < 2.0 * s.g * h,
            "{rebound} against {}",
            s.e * v1
        );
        let (_, last) = sol.last().unwrap();
        let normal = last[sol.column_index("λ_bottom.n").unwrap()];
        eprintln!(
            "{} impacts, first at {:.5} (closed form {t1:.5}) rebounding at {rebound:.4} ({:.4}); at rest pressing {normal:.9} N",
            impacts.len(),
            first.t,
            s.e * v1
        );
        assert!((normal - s.m * s.g).abs() < 1e-9, "{normal}");
        assert!(last[3].abs() < 1e-12 && last[4].abs() < 1e-12, "{last:?}");
        assert!(
            s.contact_gaps(&V3::from_column_slice(&last[..3]))[0] > -1e-3 * h,
            "penetration"
        );
    }
}

/// A uniform rod of half-length `l` free in the plane, its end `(−l, 0)` touching the
/// ground: Painlevé's example.
#[derive(Mechanism, Clone, Copy)]
#[mechanism(gravity = [0.0, -9.81, 0.0])]
#[body(rod_x, mass = 0.0)]
#[joint(x: prismatic(x), parent = world, child = rod_x)]
#[body(rod_y, mass = 0.0)]
#[joint(y: prismatic(y), parent = rod_x, child = rod_y)]
#[body(rod, mass = 1.0, inertia = rod(1.0, 2.0 * l))]
#[joint(tilt: revolute(z), parent = rod_y, child = rod)]
#[contact(end: point, body = rod, at = [-l, 0.0, 0.0], plane = world, normal = y, mu = mu)]
struct PainleveRod {
    l: f64,
    mu: f64,
}

mod event_driven {
    use super::PainleveRod;
    use super::planar::{V3, no_input, resting};
    use filippov::runtime::{
        ErrorKind, Method, NonSmoothProblem, Options, SwitchKind, contact_event_driven,
    };
    use filippov::scenes::{SlidingBox, SpinningBall};

    /// DOPRI5 at rtol 1e-12 (the closed forms' tolerance), also the static–kinetic tests'.
    pub(super) fn tight() -> Method {
        Method::Dopri5(Options {
            max_steps: 1_000_000,
            ..Options::tolerances(1e-12, 1e-14)
        })
    }

    #[test]
    fn box_slides_to_rest_at_its_closed_form_time_and_place() {
        let s = SlidingBox::default();
        let v0 = 2.0;
        let (t_stop, distance) = (v0 / (s.mu * s.g), v0 * v0 / (2.0 * s.mu * s.g));
        let p = NonSmoothProblem::new(0.0, 1.0, resting(&s), V3::from([v0, 0.0, 0.0]));
        let sol =
            contact_event_driven(&s, &no_input, &p, &tight()).unwrap_or_else(|e| panic!("{e}"));
        let stick = sol
            .switches
            .iter()
            .find(|sw| sw.to == Some(filippov::runtime::Mode::Stick))
            .expect("it sticks");
        let (_, last) = sol.last().unwrap();
        let (rear, front) = (
            sol.column_index("λ_rear.n").unwrap(),
            sol.column_index("λ_front.n").unwrap(),
        );
        let mut worst_split = 0.0f64;
        // The rows after the start's mode selection (the first row is the state as
        // given, before its contacts were closed).
        for (t, y) in sol.rows().skip(1) {
            if t < stick.t && y[3] > 0.0 {
                worst_split =
                    worst_split.max((y[front] - y[rear] - s.mu * s.b * s.m * s.g / s.a).abs());
            }
        }
        eprintln!(
            "event-driven: sticks at {:.15} (closed form {t_stop:.15}), at x = {:.15} ({distance:.15}); split within {worst_split:.1e}; {}",
            stick.t, last[0], sol.stats
        );
        assert!(
            (stick.t - t_stop).abs() < 1e-9,
            "{} against {t_stop}",
            stick.t
        );
        assert!(
            (last[0] - distance).abs() < 1e-9,
            "{} against {distance}",
            last[0]
        );
        assert!(worst_split < 1e-9, "{worst_split:e}");
        assert!(
            sol.rows()
                .filter(|(t, _)| *t > stick.t)
                .all(|(_, y)| y[0] == last[0] && y[3] == 0.0)
        );
    }

    #[test]
    fn box_on_an_incline_below_its_friction_angle_does_not_move() {
        let s = SlidingBox {
            phi: 0.3,
            ..SlidingBox::default()
        };
        let q0 = resting(&s);
        let p = NonSmoothProblem::new(0.0, 1e4, q0, V3::zeros());
        let sol =
            contact_event_driven(&s, &no_input, &p, &tight()).unwrap_or_else(|e| panic!("{e}"));
        for (t, y) in sol.rows() {
            assert_eq!(&y[..6], &[q0[0], q0[1], q0[2], 0.0, 0.0, 0.0], "t = {t}");
        }
        assert_eq!(sol.last().unwrap().0, 1e4);
    }

    #[test]
    fn box_on_an_incline_above_its_friction_angle_slides_at_its_closed_form() {
        let s = SlidingBox {
            phi: 0.6,
            ..SlidingBox::default()
        };
        let a = s.g * (s.phi.sin() - s.mu * s.phi.cos());
        let q0 = resting(&s);
        let p = NonSmoothProblem::new(0.0, 2.0, q0, V3::zeros());
        let sol =
            contact_event_driven(&s, &no_input, &p, &tight()).unwrap_or_else(|e| panic!("{e}"));
        let mut worst = 0.0f64;
        for (t, y) in sol.rows() {
            let along = -((y[0] - q0[0]) * s.phi.cos() + (y[1] - q0[1]) * s.phi.sin());
            let speed = -(y[3] * s.phi.cos() + y[4] * s.phi.sin());
            worst = worst
                .max((along - 0.5 * a * t * t).abs())
                .max((speed - a * t).abs());
        }
        eprintln!("down the incline: position and speed within {worst:.1e} of the closed form");
        assert!(worst < 1e-9, "{worst:e}");
    }

    #[test]
    fn spinning_ball_rolls_at_its_closed_form_time_and_speed() {
        let s = SpinningBall::default();
        let omega = 20.0;
        let (t_roll, v_roll) = (
            2.0 * s.r * omega / (7.0 * s.mu * s.g),
            -2.0 / 7.0 * s.r * omega,
        );
        let p = NonSmoothProblem::new(
            0.0,
            1.0,
            V3::from([0.0, s.r, 0.0]),
            V3::from([0.0, 0.0, omega]),
        );
        let sol =
            contact_event_driven(&s, &no_input, &p, &tight()).unwrap_or_else(|e| panic!("{e}"));
        let stick = sol
            .switches
            .iter()
            .find(|sw| sw.to == Some(filippov::runtime::Mode::Stick))
            .expect("it rolls");
        let (_, last) = sol.last().unwrap();
        eprintln!(
            "rolls from {:.15} ({t_roll:.15}) at {:.15} ({v_roll:.15})",
            stick.t, last[3]
        );
        assert!((stick.t - t_roll).abs() < 1e-9);
        assert!((last[3] - v_roll).abs() < 1e-9);
        assert!(
            (last[3] + s.r * last[5]).abs() < 1e-12,
            "rolling without slip"
        );
    }

    /// Dropped from H with restitution e: impacts at t₁ = √(2H/g), then every
    /// 2 eᵏ v₁ / g, accumulating at t₁ + 2 e v₁ / (g (1 − e)); at rest it presses with m g.
    #[test]
    fn dropped_ball_bounces_to_its_accumulation_point_and_rests() {
        let s = SpinningBall::default();
        let height = 0.2;
        let p = NonSmoothProblem::new(0.0, 1.5, V3::from([0.0, s.r + height, 0.0]), V3::zeros());
        let sol =
            contact_event_driven(&s, &no_input, &p, &tight()).unwrap_or_else(|e| panic!("{e}"));
        let (t1, v1) = ((2.0 * height / s.g).sqrt(), (2.0 * s.g * height).sqrt());
        let impacts: Vec<f64> = sol
            .switches
            .iter()
            .filter(|sw| sw.kind == SwitchKind::Impact)
            .map(|sw| sw.t)
            .collect();
        let settled = sol
            .switches
            .iter()
            .find(|sw| sw.kind == SwitchKind::Settled)
            .unwrap_or_else(|| {
                panic!(
                    "it settles: {:?}",
                    sol.switches
                        .iter()
                        .map(|sw| (sw.t, sw.kind, sw.to))
                        .collect::<Vec<_>>()
                )
            });
        let t_inf = t1 + 2.0 * s.e * v1 / (s.g * (1.0 - s.e));
        let mut worst = 0.0f64;
        let mut expected = t1;
        for (k, &t) in impacts.iter().enumerate() {
            worst = worst.max((t - expected).abs());
            expected += 2.0 * s.e.powi(k as i32 + 1) * v1 / s.g;
        }
        let (_, last) = sol.last().unwrap();
        let normal = last[sol.column_index("λ_bottom.n").unwrap()];
        // The settled entry carries the Zeno limit of the rebounds it ends.
        let limit = settled.accumulation.expect("the accumulation point");
        eprintln!(
            "{} impacts within {worst:.1e} of their closed-form times; settled at {:.9}, its Zeno limit {limit:.15} (accumulation {t_inf:.15}); pressing {normal}",
            impacts.len(),
            settled.t
        );
        assert!(worst < 1e-9, "{worst:e}");
        assert!(
            (settled.t - t_inf).abs() < 1e-5,
            "{} against {t_inf}",
            settled.t
        );
        assert!((limit - t_inf).abs() < 1e-9, "{limit} against {t_inf}");
        assert!((normal - s.m * s.g).abs() < 1e-9, "{normal}");
    }

    /// Housner's rocking block: released tilted on one corner (rough enough not to slip,
    /// `e = 0`), it rocks from corner to corner, each impact multiplying its angular
    /// velocity by `1 − (3/2) sin²α` (`α = atan(a/b)`: the momentum about the new corner
    /// kept, the old corner lifting), Newton's law and the contact problem at both
    /// corners deciding it; between impacts the energy of a pendulum about the corner.
    #[test]
    fn housner_block_rocks_with_its_closed_form_ratio() {
        let s = SlidingBox {
            a: 0.2,
            b: 0.4,
            mu: 1.0,
            e: 0.0,
            ..SlidingBox::default()
        };
        let alpha = (s.a / s.b).atan();
        let ratio = 1.0 - 1.5 * alpha.sin().powi(2);
        let theta0: f64 = 0.1;
        // On the rear corner at the origin, turned by θ0.
        let (st, ct) = theta0.sin_cos();
        let q0 = V3::from([s.a * ct - s.b * st, s.a * st + s.b * ct, theta0]);
        let p = NonSmoothProblem::new(0.0, 3.0, q0, V3::zeros());
        let sol =
            contact_event_driven(&s, &no_input, &p, &tight()).unwrap_or_else(|e| panic!("{e}"));
        // The landings that keep it rocking (with e = 0 each is plastic, `Settled` at its
        // corner); the last entries are the Zeno limit, where it comes to rest.
        let impacts: Vec<_> = sol
            .switches
            .iter()
            .filter(|sw| {
                matches!(sw.kind, SwitchKind::Impact | SwitchKind::Settled)
                    && sw.after[5].abs() > 1e-9
            })
            .collect();
        assert!(
            impacts.len() >= 4,
            "{:?}",
            sol.switches
                .iter()
                .map(|sw| (sw.t, sw.kind, sw.element.clone()))
                .collect::<Vec<_>>()
        );
        let mut worst = 0.0f64;
        for sw in &impacts {
            // The angle is zero at every impact; the angular velocity drops by the ratio.
            worst = worst.max((sw.after[5] / sw.before[5] - ratio).abs());
        }
        eprintln!(
            "{} impacts, θ̇⁺/θ̇⁻ within {worst:.1e} of 1 − (3/2) sin²α = {ratio:.12}",
            impacts.len()
        );
        assert!(worst < 1e-12, "{worst:e}");
        assert!(impacts.len() >= 10, "{} rocking impacts", impacts.len());
        // At rest, flat on both corners: still, bit for bit, to the end.
        let (_, last) = sol.last().unwrap();
        assert_eq!(&last[3..6], &[0.0, 0.0, 0.0]);
        assert!(last[2].abs() < 1e-12, "flat: {}", last[2]);
    }

    /// Housner's block released at θ₀ rocks with impact times, speeds before impact and
    /// amplitudes after it as the energy equation gives them by quadrature (the
    /// closed-form module), to 1e-9 at rtol 1e-12.
    #[test]
    fn housner_block_rocks_at_its_closed_form_times_and_amplitudes() {
        let s = SlidingBox {
            a: 0.2,
            b: 0.4,
            mu: 1.0,
            e: 0.0,
            ..SlidingBox::default()
        };
        let theta0: f64 = 0.1;
        let (st, ct) = theta0.sin_cos();
        let q0 = V3::from([s.a * ct - s.b * st, s.a * st + s.b * ct, theta0]);
        let p = NonSmoothProblem::new(0.0, 3.0, q0, V3::zeros());
        let sol =
            contact_event_driven(&s, &no_input, &p, &tight()).unwrap_or_else(|e| panic!("{e}"));
        let mut times: Vec<(f64, f64)> = Vec::new();
        for sw in &sol.switches {
            let rocking = matches!(sw.kind, SwitchKind::Impact | SwitchKind::Settled)
                && sw.after[5].abs() > 1e-9;
            if rocking && times.last().is_none_or(|&(t, _)| sw.t > t) {
                times.push((sw.t, sw.before[5].abs()));
            }
        }
        let housner = super::contact_closed_forms::Housner::new(s.a, s.b, s.g);
        let n = times.len().min(8);
        assert!(n >= 8, "{times:?}");
        let reference = housner.impacts(theta0, n);
        let (mut dt, mut dv, mut da) = (0.0f64, 0.0f64, 0.0f64);
        for (&(t, speed), imp) in times.iter().zip(&reference) {
            dt = dt.max((t - imp.t).abs());
            dv = dv.max((speed - imp.speed).abs());
            let apex = sol.at(imp.apex).expect("inside the run");
            da = da.max((apex[2].abs() - imp.amplitude).abs());
        }
        eprintln!(
            "{n} impacts: times within {dt:.1e} s, speeds {dv:.1e} rad/s, amplitudes {da:.1e} rad \
             of the quadrature's (first at {:.6} s, amplitude after it {:.6})",
            reference[0].t, reference[0].amplitude
        );
        assert!(dt < 1e-9 && dv < 1e-9 && da < 1e-9, "{dt:e} {dv:e} {da:e}");
    }

    /// A rod stood on its foot at θ₀ off the vertical pivots on it, stuck, until the
    /// friction it needs reaches `μ N` at the closed-form angle; then its foot slips,
    /// against the lean where the ground pushed it towards the lean. At rtol 1e-12 the
    /// angle is met to 1e-9; at the default tolerance to 100·rtol.
    #[test]
    fn falling_rod_slips_at_its_closed_form_angle() {
        use filippov::runtime::Mode;
        use filippov::scenes::FallingRod;
        let theta0: f64 = 0.05;
        for (mu, method, tol) in [
            (0.3, tight(), 1e-9),
            (0.5, tight(), 1e-9),
            (
                0.3,
                Method::Dopri5(Options::default()),
                100.0 * Options::default().rtol,
            ),
        ] {
            let s = FallingRod {
                mu,
                ..FallingRod::default()
            };
            let (angle, push) =
                super::contact_closed_forms::rod_slip_angle(mu, theta0).expect("slips");
            let l = s.l;
            let q0 = V3::from([-l * theta0.sin(), l * theta0.cos(), theta0]);
            let p = NonSmoothProblem::new(0.0, 2.0, q0, V3::zeros());
            let sol =
                contact_event_driven(&s, &no_input, &p, &method).unwrap_or_else(|e| panic!("{e}"));
            let slip = sol
                .switches
                .iter()
                .find(|sw| {
                    sw.element.as_deref() == Some("foot")
                        && matches!(sw.to, Some(Mode::SlipPos(_) | Mode::SlipNeg(_)))
                })
                .unwrap_or_else(|| {
                    panic!(
                        "the foot slips: {:?}",
                        sol.switches
                            .iter()
                            .map(|sw| (
                                sw.t,
                                sw.kind,
                                sw.element.clone(),
                                sw.from,
                                sw.to,
                                sw.after[2]
                            ))
                            .collect::<Vec<_>>()
                    )
                });
            let lean = slip.after[2];
            eprintln!(
                "μ = {mu}: slips at {lean:.12} rad (closed form {angle:.12}), {:?}",
                slip.to
            );
            assert!((lean - angle).abs() < tol, "{lean} against {angle}");
            // Pushed towards the lean (−x), the foot gives way towards +x.
            let expected = if push > 0.0 {
                Mode::SlipPos(0)
            } else {
                Mode::SlipNeg(0)
            };
            assert_eq!(slip.to, Some(expected), "μ = {mu}");
            // Stuck before: the foot where it was put (to a thousandth of the angle's
            // tolerance, the contact's projection tolerance).
            for (t, y) in sol.rows().take_while(|(t, _)| *t < slip.t) {
                let foot = [y[0] + l * y[2].sin(), y[1] - l * y[2].cos()];
                let pinned = 1e-3 * tol;
                assert!(
                    foot[0].abs() < pinned && foot[1].abs() < pinned,
                    "t = {t}: {foot:?}"
                );
            }
        }
    }

    /// A cart on a rail with a pendulum swinging below it: the rail's friction is μ
    /// times the skids' load, and that load is not the weight — it carries the
    /// pendulum's swing. Checked by Newton's law for the whole system (no kernel writes
    /// it): the skids' normal forces less the weight are the vertical momentum's rate
    /// (cart and bob accelerations from the solution's own derivative rows), their
    /// friction the horizontal one's; sliding, the friction is μ times the load.
    #[test]
    fn cart_on_a_rail_carries_its_pendulum_load_into_its_friction() {
        use filippov::scenes::CartOnRail;
        type V4 = filippov::nalgebra::SVector<f64, 4>;
        let s = CartOnRail::default();
        let q0 = V4::from([0.0, s.b, 0.0, 1.2]);
        let p = NonSmoothProblem::new(0.0, 3.0, q0, V4::zeros());
        let free = |_: f64, _: &V4, _: &V4| V4::zeros();
        let sol = contact_event_driven(&s, &free, &p, &tight()).unwrap_or_else(|e| panic!("{e}"));
        let col = |name: &str| sol.column_index(name).unwrap();
        let (nr, nf, tr, tf) = (
            col("λ_rear.n"),
            col("λ_front.n"),
            col("λ_rear.x"),
            col("λ_front.x"),
        );
        let weight = (s.mc + s.mp) * s.g;
        let (mut worst, mut load_range, mut sliding_rows) = (0.0f64, (f64::MAX, f64::MIN), 0);
        for i in 1..sol.len() {
            let y = sol.state(i);
            let a = &sol.derivative(i)[4..8];
            let phi = y[2] + y[3];
            let (dphi, ddphi) = (y[6] + y[7], a[2] + a[3]);
            let bob = [
                a[0] + s.l * (ddphi * phi.cos() - dphi * dphi * phi.sin()),
                a[1] + s.l * (ddphi * phi.sin() + dphi * dphi * phi.cos()),
            ];
            let load = y[nr] + y[nf];
            let friction = y[tr] + y[tf];
            worst = worst
                .max((load - weight - s.mc * a[1] - s.mp * bob[1]).abs())
                .max((friction - s.mc * a[0] - s.mp * bob[0]).abs());
            load_range = (load_range.0.min(load), load_range.1.max(load));
            if y[4].abs() > 1e-9 {
                sliding_rows += 1;
                assert!(
                    (friction.abs() - s.mu * load).abs() < 1e-9 * weight,
                    "t = {}",
                    sol.times()[i]
                );
            }
        }
        let switches = sol
            .switches
            .iter()
            .filter(|sw| sw.kind == SwitchKind::Mode)
            .count();
        eprintln!(
            "Newton's law within {worst:.1e} N; the skids' load between {:.3} and {:.3} N (weight {weight:.3}); \
             {sliding_rows} sliding rows, {switches} mode switches",
            load_range.0, load_range.1
        );
        assert!(worst < 1e-8 * weight, "{worst:e}");
        assert!(sliding_rows > 0 && switches >= 2);
        assert!(load_range.1 - load_range.0 > 0.2 * weight, "{load_range:?}");
    }

    /// Painlevé's rod sliding on its end at angle θ: above μ_P = (1 + 3 cos²θ) /
    /// (3 sin θ cos θ) the event-driven integrator says the contact problem has no
    /// unique solution; below it, it integrates.
    #[test]
    fn painleve_rod_is_refused_above_its_threshold_and_not_below() {
        let (l, theta) = (0.5f64, 0.5f64);
        let (s, c) = theta.sin_cos();
        let threshold = (1.0 + 3.0 * c * c) / (3.0 * s * c);
        let q0 = V3::from([0.0, l * s, theta]);
        // The end slides towards −x.
        let v0 = V3::from([-1.0, 0.0, 0.0]);
        let p = NonSmoothProblem::new(0.0, 0.01, q0, v0);
        let below = contact_event_driven(
            &PainleveRod {
                l,
                mu: 0.99 * threshold,
            },
            &no_input,
            &p,
            &tight(),
        );
        assert!(below.is_ok(), "{:?}", below.err().map(|e| e.to_string()));
        match contact_event_driven(
            &PainleveRod {
                l,
                mu: 1.01 * threshold,
            },
            &no_input,
            &p,
            &tight(),
        ) {
            Err(e) => match &e.kind {
                ErrorKind::IllPosedMode { detail, .. } => assert!(
                    detail.contains("Painlevé") && detail.contains("`end`"),
                    "{detail}"
                ),
                other => panic!("{other}"),
            },
            Ok(_) => panic!("accepted above the threshold"),
        }
    }
}

/// Spatial contacts (two tangent rows each) by time-stepping on the isotropic cone, and
/// event-driven.
mod spatial {
    use filippov::prelude::*;
    use filippov::runtime::contacts::Contacts;
    use filippov::runtime::{
        Method, NonSmoothProblem, Options, contact_event_driven, contact_time_stepping,
    };
    use filippov::scenes::{Puck, Table};

    type V3 = SVector<f64, 3>;
    type V6 = SVector<f64, 6>;

    fn free3(_: f64, _: &V3, _: &V3) -> V3 {
        V3::zeros()
    }

    fn free6(_: f64, _: &V6, _: &V6) -> V6 {
        V6::zeros()
    }

    /// The puck on a 0.3 rad incline at its friction angle (`μ = tan φ`), the angle, its
    /// launch speed across the slope and the downhill direction.
    fn at_friction_angle() -> (Puck, f64, f64, V3) {
        let phi: f64 = 0.3;
        let s = Puck {
            phi,
            mu: phi.tan(),
            ..Puck::default()
        };
        (s, phi, 2.0, V3::from([0.0, -phi.cos(), -phi.sin()]))
    }

    /// The table standing on its ground (tilted by φ about x): centre `d` along the
    /// plane's normal, rolled by φ.
    fn standing(s: &Table) -> V6 {
        V6::from([0.0, -s.d * s.phi.sin(), s.d * s.phi.cos(), 0.0, 0.0, s.phi])
    }

    /// On level ground a puck launched at `v0` in any direction slides straight to rest:
    /// the friction impulse opposes the velocity whatever its direction (a pyramid would
    /// bend the path off the diagonals), each step taking `μ g h` off the speed, so it
    /// stops at `v0 / (μ g)` after `v0² / (2 μ g)`.
    #[test]
    fn puck_slides_straight_to_rest_in_every_direction() {
        let s = Puck::default();
        let (v0, h) = (1.5, 1e-3);
        let (t_stop, distance) = (v0 / (s.mu * s.g), v0 * v0 / (2.0 * s.mu * s.g));
        for k in 0..12 {
            let theta = 0.37 + k as f64 * std::f64::consts::TAU / 12.0;
            let (c, sn) = (theta.cos(), theta.sin());
            let p = NonSmoothProblem::new(0.0, 1.0, V3::zeros(), V3::from([v0 * c, v0 * sn, 0.0]));
            let sol = contact_time_stepping(&s, &free3, &p, h).unwrap_or_else(|e| panic!("{e}"));
            let stopped = sol
                .rows()
                .find(|(_, y)| y[3] == 0.0 && y[4] == 0.0)
                .map(|(t, _)| t)
                .expect("it stops");
            let (_, last) = sol.last().unwrap();
            let along = last[0] * c + last[1] * sn;
            let across = -last[0] * sn + last[1] * c;
            assert!((stopped - t_stop).abs() <= 1.01 * h, "{theta}: {stopped}");
            assert!(
                (along - distance).abs() <= 1.01 * v0 * h,
                "{theta}: {along}"
            );
            assert!(across.abs() < 1e-12, "{theta}: off the line by {across:e}");
            assert!(sol.rows().all(|(_, y)| y[2] == 0.0 && y[5] == 0.0));
            assert!(sol.stats.contact_residual <= 1e-12, "{}", sol.stats);
        }
    }

    /// On an incline with `μ = tan φ`, launched horizontally across it at `v0`: gravity
    /// along the slope and friction balance, so the acceleration is
    /// `g sin φ (d − v/|v|)` (`d` downhill) and `v·d + |v|` keeps its start `v0` — the
    /// speed tends to `v0/2`, the path turning downhill. Time-stepping keeps the
    /// invariant to first order in `h`.
    #[test]
    fn puck_across_an_incline_at_its_friction_angle_keeps_its_invariant() {
        let (s, phi, v0, downhill) = at_friction_angle();
        let mut worst = Vec::new();
        for h in [1e-3, 1e-4] {
            let p = NonSmoothProblem::new(0.0, 3.0, V3::zeros(), V3::from([v0, 0.0, 0.0]));
            let sol = contact_time_stepping(&s, &free3, &p, h).unwrap_or_else(|e| panic!("{e}"));
            let mut w = 0.0f64;
            for (_, y) in sol.rows() {
                let v = V3::from([y[3], y[4], y[5]]);
                let q = V3::from([y[0], y[1], y[2]]);
                w = w.max((v.dot(&downhill) + v.norm() - v0).abs());
                // On the plane, moving along it.
                let normal = V3::from([0.0, -phi.sin(), phi.cos()]);
                assert!(q.dot(&normal).abs() < 1e-12 && v.dot(&normal).abs() < 1e-12);
            }
            let (_, last) = sol.last().unwrap();
            let speed = V3::from([last[3], last[4], last[5]]).norm();
            eprintln!(
                "h = {h}: v·d + |v| within {w:.2e} of v0; speed at 3 s {speed:.4} (→ {})",
                v0 / 2.0
            );
            assert!(speed > 0.5 * v0 - w && speed < 0.6 * v0, "{speed}");
            worst.push(w);
        }
        assert!(worst[1] < 0.15 * worst[0], "first order: {worst:?}");
        assert!(worst[1] < 1e-3 * v0, "{worst:?}");
    }

    /// Below its friction angle the table stands still, bit for bit, for 10⁴ s, its legs
    /// carrying its weight: normal forces summing to `m g cos φ`, friction to
    /// `m g sin φ`, each inside its cone.
    #[test]
    fn table_on_an_incline_below_its_friction_angle_does_not_move() {
        let s = Table {
            phi: 0.3,
            ..Table::default()
        };
        assert!(s.phi.tan() < s.mu);
        let q0 = standing(&s);
        assert!(s.contact_gaps(&q0).amax() < 1e-15);
        let p = NonSmoothProblem::new(0.0, 1e4, q0, V6::zeros());
        let sol = contact_time_stepping(&s, &free6, &p, 0.1).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(sol.len(), 100_001);
        for (t, y) in sol.rows() {
            assert_eq!(&y[..6], q0.as_slice(), "t = {t}");
            assert!(y[6..12].iter().all(|&x| x == 0.0), "t = {t}");
        }
        let (_, last) = sol.last().unwrap();
        let col = |name: &str| last[sol.column_index(name).unwrap()];
        let (mut normal, mut along) = (0.0, [0.0; 2]);
        for leg in Table::CONTACTS {
            let n = col(&format!("λ_{leg}.n"));
            let t = [col(&format!("λ_{leg}.x")), col(&format!("λ_{leg}.y"))];
            assert!(n > 0.0 && t[0].hypot(t[1]) < s.mu * n, "{leg}: {n} {t:?}");
            normal += n;
            along[0] += t[0];
            along[1] += t[1];
        }
        let weight = s.m * s.g;
        assert!((normal - weight * s.phi.cos()).abs() < 1e-9, "{normal}");
        assert!(along[0].abs() < 1e-9 && (along[1] - weight * s.phi.sin()).abs() < 1e-9);
    }

    /// Launched sliding and spinning on level ground, the table loses energy at every
    /// step, never sinks into the ground, keeps each leg's friction on its cone's edge
    /// while it slides, comes to rest exactly, and its resting place converges to first
    /// order in `h`.
    #[test]
    fn sliding_spinning_table_is_passive_and_stops() {
        let s = Table::default();
        let v0 = V6::from([1.2, -0.7, 0.0, 4.0, 0.0, 0.0]);
        let weight = s.m * s.g;
        let mut rests = Vec::new();
        for h in [1e-3, 1e-4, 1e-5] {
            let p = NonSmoothProblem::new(0.0, 1.0, standing(&s), v0);
            let sol = contact_time_stepping(&s, &free6, &p, h).unwrap_or_else(|e| panic!("{e}"));
            assert!(sol.stats.contact_residual <= 1e-12, "{}", sol.stats);
            let mut energy = f64::INFINITY;
            // The step's rows are taken at its start (Moreau–Jean).
            let mut q_before = standing(&s);
            for (t, y) in sol.rows() {
                let q = V6::from_column_slice(&y[..6]);
                let v = V6::from_column_slice(&y[6..12]);
                let e = 0.5 * v.dot(&(s.mass_matrix(&q) * v)) + weight * q[2];
                assert!(
                    e <= energy * (1.0 + 1e-14),
                    "t = {t}: energy rose {energy} → {e}"
                );
                energy = e;
                assert!(s.contact_gaps(&q).min() > -1e-12, "t = {t}: sank");
                let (n, f) = (y[12..15].iter().sum::<f64>(), y[15..21].chunks(2));
                // Forces are impulses over h: the solver's relative tolerance on the
                // velocities (1e-12) over h bounds their error.
                let tol = 1e-12 * weight / h;
                if t > 0.0 && v.amax() > 0.0 {
                    assert!((n - weight).abs() < tol, "t = {t}: {n}");
                    for (k, leg) in f.enumerate() {
                        let slip = s.contact_tangent_jacobian(&q_before).rows(2 * k, 2) * v;
                        if slip.norm() > 1e-9 {
                            let fk = leg[0].hypot(leg[1]);
                            assert!((fk - s.mu * y[12 + k]).abs() < tol, "t = {t}: {fk}");
                        }
                    }
                }
                q_before = q;
            }
            let (_, last) = sol.last().unwrap();
            assert!(last[6..12].iter().all(|&x| x == 0.0), "at rest: {last:?}");
            eprintln!("h = {h}: rests at {:?}; {}", &last[..6], sol.stats);
            rests.push(V6::from_column_slice(&last[..6]));
        }
        let e1 = (rests[0] - rests[2]).amax();
        let e2 = (rests[1] - rests[2]).amax();
        assert!(e2 < 0.2 * e1, "first order: {e1:e}, {e2:e}");
    }

    fn tight() -> Method {
        Method::Dopri5(Options {
            max_steps: 1_000_000,
            ..Options::tolerances(1e-12, 1e-14)
        })
    }

    /// Event-driven, a puck launched on level ground in any direction slides straight
    /// (its friction opposing its velocity on the isotropic cone) and sticks at its
    /// closed-form time `v0 / (μ g)` and place `v0² / (2 μ g)` along its launch.
    #[test]
    fn event_driven_puck_stops_at_its_closed_form_time_and_place() {
        let s = Puck::default();
        let v0 = 1.5;
        let (t_stop, distance) = (v0 / (s.mu * s.g), v0 * v0 / (2.0 * s.mu * s.g));
        for k in 0..6 {
            let theta = 0.37 + k as f64 * std::f64::consts::TAU / 6.0;
            let (c, sn) = (theta.cos(), theta.sin());
            let p = NonSmoothProblem::new(0.0, 1.0, V3::zeros(), V3::from([v0 * c, v0 * sn, 0.0]));
            let sol =
                contact_event_driven(&s, &free3, &p, &tight()).unwrap_or_else(|e| panic!("{e}"));
            let stick = sol
                .switches
                .iter()
                .find(|w| w.to == Some(filippov::runtime::Mode::Stick))
                .expect("it sticks");
            assert!(
                (stick.t - t_stop).abs() < 1e-9,
                "θ = {theta}: stops at {}",
                stick.t
            );
            let (_, last) = sol.last().unwrap();
            assert!(
                (last[0] - distance * c).abs() < 1e-9 && (last[1] - distance * sn).abs() < 1e-9
            );
            assert_eq!(last[2], 0.0);
            assert!(last[3..6].iter().all(|&x| x == 0.0), "at rest: {last:?}");
            // Sliding, its friction is μ m g against the motion.
            let f = |name: &str| last[sol.column_index(name).unwrap()];
            assert!((f("λ_bottom.n") - s.m * s.g).abs() < 1e-9);
        }
    }

    /// Event-driven, the puck sent across an incline at its friction angle keeps
    /// `v·d + |v| = v0` (see the time-stepping test above) to the method's tolerance, its
    /// sliding direction turning continuously downhill.
    #[test]
    fn event_driven_puck_across_an_incline_keeps_its_invariant() {
        let (s, _, v0, downhill) = at_friction_angle();
        let p = NonSmoothProblem::new(0.0, 3.0, V3::zeros(), V3::from([v0, 0.0, 0.0]));
        let sol = contact_event_driven(&s, &free3, &p, &tight()).unwrap_or_else(|e| panic!("{e}"));
        let mut worst = 0.0f64;
        for (_, y) in sol.rows() {
            let v = V3::from([y[3], y[4], y[5]]);
            worst = worst.max((v.dot(&downhill) + v.norm() - v0).abs());
        }
        assert!(worst < 1e-9 * v0, "v·d + |v| off v0 by {worst:e}");
        let (_, last) = sol.last().unwrap();
        let speed = V3::from([last[3], last[4], last[5]]).norm();
        assert!(speed > 0.5 * v0 && speed < 0.6 * v0, "{speed}");
    }

    /// Event-driven, a puck thrown straight up an incline steeper than its friction
    /// angle slows at `g (sin φ + μ cos φ)`, stops at `t₁ = v0 / that` and slides back
    /// at `g (sin φ − μ cos φ)`: its slip reverses through zero along a fixed line.
    #[test]
    fn event_driven_puck_thrown_uphill_slides_back() {
        let (phi, mu): (f64, f64) = (0.5, 0.3);
        let s = Puck {
            phi,
            mu,
            ..Puck::default()
        };
        let v0 = 2.0;
        let up = V3::from([0.0, phi.cos(), phi.sin()]);
        let (a1, a2) = (
            s.g * (phi.sin() + mu * phi.cos()),
            s.g * (phi.sin() - mu * phi.cos()),
        );
        let t1 = v0 / a1;
        let tf = 1.0;
        assert!(t1 < tf);
        let p = NonSmoothProblem::new(0.0, tf, V3::zeros(), up * v0);
        let sol = contact_event_driven(&s, &free3, &p, &tight()).unwrap_or_else(|e| panic!("{e}"));
        let (_, last) = sol.last().unwrap();
        let (q, v) = (
            V3::from_column_slice(&last[..3]),
            V3::from_column_slice(&last[3..6]),
        );
        let along = v0 * t1 - 0.5 * a1 * t1 * t1 - 0.5 * a2 * (tf - t1).powi(2);
        assert!(
            (q - up * along).amax() < 1e-9,
            "at {q:?}, expected {along} up the slope"
        );
        assert!((v + up * (a2 * (tf - t1))).amax() < 1e-9, "moving at {v:?}");
    }

    /// Event-driven, the table below its friction angle stands still bit for bit for
    /// 10⁴ s (its three legs stuck, their redundant frictions in their cones).
    #[test]
    fn event_driven_table_below_its_friction_angle_does_not_move() {
        let s = Table {
            phi: 0.3,
            ..Table::default()
        };
        let q0 = standing(&s);
        let p = NonSmoothProblem::new(0.0, 1e4, q0, V6::zeros());
        let sol = contact_event_driven(&s, &free6, &p, &tight()).unwrap_or_else(|e| panic!("{e}"));
        for (t, y) in sol.rows() {
            assert_eq!(&y[..6], q0.as_slice(), "t = {t}");
            assert!(y[6..12].iter().all(|&x| x == 0.0), "t = {t}");
        }
        let (_, last) = sol.last().unwrap();
        for (k, leg) in Table::CONTACTS.iter().enumerate() {
            let (n, t) = (last[12 + k], [last[15 + 2 * k], last[16 + 2 * k]]);
            assert!(n > 0.0 && t[0].hypot(t[1]) < s.mu * n, "{leg}: {n} {t:?}");
        }
    }

    /// Event-driven, the table pushed along level ground without spin slides straight
    /// (every leg's slip in the push's direction) and stops at the closed-form time
    /// `v0 / (μ g)` and place `v0² / (2 μ g)`, whatever its legs' loads.
    #[test]
    fn event_driven_table_slides_straight_to_rest() {
        let s = Table::default();
        let v0 = 1.2;
        let (t_stop, distance) = (v0 / (s.mu * s.g), v0 * v0 / (2.0 * s.mu * s.g));
        let (c, sn) = (0.6, -0.8);
        let p = NonSmoothProblem::new(
            0.0,
            1.0,
            standing(&s),
            V6::from([v0 * c, v0 * sn, 0.0, 0.0, 0.0, 0.0]),
        );
        let sol = contact_event_driven(&s, &free6, &p, &tight()).unwrap_or_else(|e| panic!("{e}"));
        let stopped = sol
            .switches
            .iter()
            .filter(|w| w.to == Some(filippov::runtime::Mode::Stick))
            .map(|w| w.t)
            .fold(f64::NAN, f64::max);
        assert!((stopped - t_stop).abs() < 1e-9, "stops at {stopped}");
        let (_, last) = sol.last().unwrap();
        assert!((last[0] - distance * c).abs() < 1e-9 && (last[1] - distance * sn).abs() < 1e-9);
        assert!(
            last[2..6]
                .iter()
                .zip(&standing(&s).as_slice()[2..])
                .all(|(a, b)| (a - b).abs() < 1e-12)
        );
        assert!(last[6..12].iter().all(|&x| x == 0.0), "at rest: {last:?}");
    }

    /// A table spinning as it slides: its legs' slips turn as they stop, beyond the
    /// event-driven integrator; the error says so, names the legs and the way through,
    /// and keeps the rows computed.
    #[test]
    fn event_driven_names_a_spinning_slide_and_points_to_time_stepping() {
        let s = Table::default();
        let v0 = V6::from([1.2, -0.7, 0.0, 4.0, 0.0, 0.0]);
        let p = NonSmoothProblem::new(0.0, 1.0, standing(&s), v0);
        let method = Method::Dopri5(Options {
            max_steps: 20_000,
            ..Options::tolerances(1e-10, 1e-12)
        });
        let err = contact_event_driven(&s, &free6, &p, &method).expect_err("a spinning slide");
        let text = err.to_string();
        assert!(
            text.contains("`leg_a`") && text.contains("contact_time_stepping"),
            "{text}"
        );
        assert!(err.solution.len() > 100, "the rows so far are kept");
    }
}

/// Contacts beside joint elements in one scene: a block on the ground (contact `bottom`,
/// friction `μ`) whose rail adds Coulomb friction `fc` on `x` and ends at a rigid stop.
mod beside_elements {
    use filippov::nalgebra::SVector;
    use filippov::prelude::*;
    use filippov::runtime::{
        ErrorKind, Method, Mode, NonSmoothMethod, NonSmoothProblem, Options, Unforced,
        contact_event_driven, contact_time_stepping, solve_nonsmooth,
    };

    type V2 = SVector<f64, 2>;

    #[derive(Mechanism, Clone, Copy)]
    #[mechanism(gravity = [0.0, -g, 0.0])]
    #[body(slider_x, mass = 0.0)]
    #[joint(x: prismatic(x), parent = world, child = slider_x)]
    #[body(block, mass = m)]
    #[joint(y: prismatic(y), parent = slider_x, child = block)]
    #[friction(x, f_crit = fc)]
    #[stop(x, max = wall, restitution = e)]
    #[contact(bottom: point, body = block, plane = world, normal = y, mu = mu)]
    struct BlockOnRail {
        m: f64,
        g: f64,
        fc: f64,
        wall: f64,
        e: f64,
        mu: f64,
    }

    const BLOCK: BlockOnRail = BlockOnRail {
        m: 2.0,
        g: 9.81,
        fc: 3.0,
        wall: 0.5,
        e: 0.5,
        mu: 0.3,
    };

    /// Launched at `V` towards the wall: the ground's μ m g and the rail's `fc` slow it at
    /// `a = (μ m g + fc)/m`; it hits the wall at `v = √(V² − 2 a L)`, rebounds at `e v`
    /// and stops `(e v)²/(2a)` short of the wall, `e v / a` later. Time-stepping meets
    /// these to first order; at rest it does not move by a rounding.
    #[test]
    fn block_slowed_by_ground_and_rail_rebounds_off_the_wall_and_stops() {
        let s = BLOCK;
        let speed = 3.0;
        let a = (s.mu * s.m * s.g + s.fc) / s.m;
        let hit = (speed * speed - 2.0 * a * s.wall).sqrt();
        let t_hit = (speed - hit) / a;
        let (rest_x, rest_t) = (
            s.wall - (s.e * hit).powi(2) / (2.0 * a),
            t_hit + s.e * hit / a,
        );
        let mut errors = Vec::new();
        for h in [1e-3, 1e-4] {
            let p = NonSmoothProblem::new(0.0, 2.0, V2::zeros(), V2::from([speed, 0.0]));
            let sol = contact_time_stepping(&s, &Unforced, &p, h).unwrap_or_else(|e| panic!("{e}"));
            let names = sol.names().to_vec();
            assert!(names.iter().any(|n| n.starts_with("f_")), "{names:?}");
            let impact = sol
                .switches
                .iter()
                .find(|sw| sw.to == Some(Mode::Contact))
                .expect("it hits the wall");
            let stopped = sol
                .rows()
                .find(|(t, y)| *t > impact.t && y[2] == 0.0)
                .map(|(t, _)| t)
                .expect("it stops");
            let (_, last) = sol.last().unwrap();
            eprintln!(
                "h = {h}: hits at {:.5} ({t_hit:.5}), rebounds at {:.5} (−e v = {:.5}), rests at \
                 x = {:.5} ({rest_x:.5}) from {stopped:.5} ({rest_t:.5})",
                impact.t,
                impact.after[2],
                -s.e * hit,
                last[0]
            );
            assert!((impact.t - t_hit).abs() <= 2.0 * h);
            assert!((last[0] - rest_x).abs() <= 2.0 * speed * h, "{}", last[0]);
            assert!((stopped - rest_t).abs() <= 2.0 * h, "{stopped}");
            assert!(
                last[1].abs() < 1e-15 && last[3] == 0.0,
                "on the ground: {last:?}"
            );
            // At rest with nothing pushing, neither friction holds a force.
            assert!(last[5].abs() < 1e-9 && last[6].abs() < 1e-9, "{last:?}");
            let after: Vec<_> = sol.rows().filter(|(t, _)| *t >= stopped).collect();
            assert!(after.iter().all(|(_, y)| y[0] == last[0] && y[2] == 0.0));
            errors.push((last[0] - rest_x).abs() + (impact.t - t_hit).abs());
        }
        assert!(
            errors[1] < 0.2 * errors[0] + 1e-12,
            "first order: {errors:?}"
        );
    }

    /// While it slides, the rail's friction column is `fc` against the motion, the
    /// ground's tangential force `μ` times its normal force `m g`.
    #[test]
    fn sliding_forces_are_the_laws() {
        let s = BLOCK;
        let p = NonSmoothProblem::new(0.0, 0.1, V2::zeros(), V2::from([3.0, 0.0]));
        let sol = contact_time_stepping(&s, &Unforced, &p, 1e-3).unwrap_or_else(|e| panic!("{e}"));
        let rail = sol
            .names()
            .iter()
            .position(|n| n.starts_with("f_") && n.contains("friction"))
            .expect("the rail's friction column");
        let (n, t) = (
            sol.column_index("λ_bottom.n").unwrap(),
            sol.column_index("λ_bottom.x").unwrap(),
        );
        for (time, y) in sol.rows().skip(1) {
            assert!((y[rail] - s.fc).abs() < 1e-9, "t = {time}: {}", y[rail]);
            assert!((y[n] - s.m * s.g).abs() < 1e-9, "t = {time}: {}", y[n]);
            assert!(
                (y[t] + s.mu * s.m * s.g).abs() < 1e-9,
                "t = {time}: {}",
                y[t]
            );
        }
    }

    /// The element integrators do not integrate contacts and say so, naming them; the
    /// event-driven contact integrator does not integrate joint elements and says so.
    #[test]
    fn integrators_that_cannot_take_both_say_so() {
        let p = NonSmoothProblem::new(0.0, 1.0, V2::zeros(), V2::from([1.0, 0.0]));
        let err = solve_nonsmooth(
            &BLOCK,
            &|_: f64, _: &V2, _: &V2| V2::zeros(),
            &p,
            &NonSmoothMethod::default(),
        )
        .unwrap_err();
        let text = err.to_string();
        assert!(matches!(err.kind, ErrorKind::InvalidInput(_)), "{text}");
        assert!(
            text.contains("`bottom`") && text.contains("contact_time_stepping"),
            "{text}"
        );
        let err = contact_event_driven(&BLOCK, &Unforced, &p, &Method::Dopri5(Options::default()))
            .unwrap_err();
        let text = err.to_string();
        assert!(
            text.contains("joint elements") && text.contains("contact_time_stepping"),
            "{text}"
        );
    }
}

/// Static and kinetic friction on contacts (`mu_static ≥ mu`): a box on an incline
/// steeper than its kinetic friction angle but not its static one.
mod static_kinetic {
    use filippov::nalgebra::SVector;
    use filippov::prelude::*;
    use filippov::runtime::{
        Mode, NonSmoothProblem, Unforced, contact_event_driven, contact_time_stepping,
    };

    type V3 = SVector<f64, 3>;

    #[derive(Mechanism, Clone, Copy)]
    #[mechanism(gravity = [0.0, -g, 0.0])]
    #[body(slider_x, mass = 0.0)]
    #[joint(x: prismatic(x), parent = world, child = slider_x)]
    #[body(slider_y, mass = 0.0)]
    #[joint(y: prismatic(y), parent = slider_x, child = slider_y)]
    #[body(block, mass = m, inertia = cuboid(m, 2.0 * a, 2.0 * b, 0.1))]
    #[joint(angle: revolute(z), parent = slider_y, child = block)]
    #[contact(rear: point, body = block, at = [-a, -b, 0.0], plane = world,
              rpy = [0.0, 0.0, phi], normal = y, mu = mu_k, mu_static = mu_s)]
    #[contact(front: point, body = block, at = [a, -b, 0.0], plane = world,
              rpy = [0.0, 0.0, phi], normal = y, mu = mu_k, mu_static = mu_s)]
    struct StickyBox {
        m: f64,
        a: f64,
        b: f64,
        mu_k: f64,
        mu_s: f64,
        phi: f64,
        g: f64,
    }

    /// tan φ = 0.309: between μ_k = 0.2 and μ_s = 0.5.
    const BOX: StickyBox = StickyBox {
        m: 1.0,
        a: 0.2,
        b: 0.1,
        mu_k: 0.2,
        mu_s: 0.5,
        phi: 0.3,
        g: 9.81,
    };

    fn resting(s: &StickyBox) -> V3 {
        V3::from([-s.b * s.phi.sin(), s.b * s.phi.cos(), s.phi])
    }

    use super::event_driven::tight;

    /// Put down still, the static friction holds it, bit for bit, by both integrators.
    #[test]
    fn held_by_static_friction_it_does_not_move() {
        let s = BOX;
        let q0 = resting(&s);
        let p = NonSmoothProblem::new(0.0, 100.0, q0, V3::zeros());
        let ed =
            contact_event_driven(&s, &Unforced, &p, &tight()).unwrap_or_else(|e| panic!("{e}"));
        let ts = contact_time_stepping(&s, &Unforced, &p, 1e-2).unwrap_or_else(|e| panic!("{e}"));
        for sol in [&ed, &ts] {
            for (t, y) in sol.rows() {
                assert_eq!(&y[..6], &[q0[0], q0[1], q0[2], 0.0, 0.0, 0.0], "t = {t}");
            }
        }
    }

    /// Launched up the slope at `v0` it slows at `g (sin φ + μ_k cos φ)`, stops after
    /// `v0² / (2 a)` at `v0 / a`, and the static friction holds it there; launched down,
    /// it speeds up at `g (sin φ − μ_k cos φ)` and never stops.
    #[test]
    fn kinetic_friction_while_sliding_static_once_stopped() {
        let s = BOX;
        let (sp, cp) = s.phi.sin_cos();
        let up = s.g * (sp + s.mu_k * cp);
        let down = s.g * (sp - s.mu_k * cp);
        let v0 = 1.5;
        let along = |y: &[f64]| (y[0] - resting(&s)[0]) * cp + (y[1] - resting(&s)[1]) * sp;
        let speed = |y: &[f64]| y[3] * cp + y[4] * sp;
        // Up: stops and stays.
        let p = NonSmoothProblem::new(0.0, 2.0, resting(&s), V3::from([v0 * cp, v0 * sp, 0.0]));
        let sol =
            contact_event_driven(&s, &Unforced, &p, &tight()).unwrap_or_else(|e| panic!("{e}"));
        let stick = sol
            .switches
            .iter()
            .find(|sw| sw.to == Some(Mode::Stick) && sw.t > 0.0)
            .expect("it sticks");
        let (_, last) = sol.last().unwrap();
        eprintln!(
            "up: sticks at {:.12} (closed form {:.12}) after {:.12} m ({:.12})",
            stick.t,
            v0 / up,
            along(last),
            v0 * v0 / (2.0 * up)
        );
        assert!((stick.t - v0 / up).abs() < 1e-9);
        assert!((along(last) - v0 * v0 / (2.0 * up)).abs() < 1e-9);
        assert_eq!(&last[3..6], &[0.0, 0.0, 0.0]);
        // Down: slides on at the kinetic law.
        let p = NonSmoothProblem::new(0.0, 2.0, resting(&s), V3::from([-v0 * cp, -v0 * sp, 0.0]));
        let sol =
            contact_event_driven(&s, &Unforced, &p, &tight()).unwrap_or_else(|e| panic!("{e}"));
        let worst = sol
            .rows()
            .map(|(t, y)| (speed(y) + v0 + down * t).abs())
            .fold(0.0, f64::max);
        eprintln!("down: speed within {worst:.1e} of −(v0 + g (sin φ − μ_k cos φ) t)");
        assert!(worst < 1e-9, "{worst:e}");
        // Time-stepping, up: stops within a step of the closed form and stays.
        let p = NonSmoothProblem::new(0.0, 2.0, resting(&s), V3::from([v0 * cp, v0 * sp, 0.0]));
        let h = 1e-4;
        let sol = contact_time_stepping(&s, &Unforced, &p, h).unwrap_or_else(|e| panic!("{e}"));
        let stopped = sol
            .rows()
            .find(|(t, y)| *t > 0.0 && speed(y) == 0.0)
            .map(|(t, _)| t)
            .expect("it stops");
        assert!((stopped - v0 / up).abs() <= 1.01 * h, "{stopped}");
        let (_, last) = sol.last().unwrap();
        assert_eq!(&last[3..6], &[0.0, 0.0, 0.0]);
    }

    /// `mu_static` below `mu` is refused at run time, naming the contact.
    #[test]
    fn static_below_kinetic_is_refused() {
        let bad = StickyBox { mu_s: 0.1, ..BOX };
        let text = bad.validate().expect_err("μ_s < μ_k").to_string();
        assert!(
            text.contains("`rear`") && text.contains("mu_static"),
            "{text}"
        );
    }
}
