//! Contacts' kinematics (`#[contact(…)]`): the generated gaps, normal and tangential
//! Jacobians and `γ` terms against references that do not use the generator — the
//! numeric model's link poses composed here with the contact's declaration, central
//! differences of those poses for the material points' velocities — on an oblique
//! spatial tree at random states; and closed forms on planar scenes (a box's corners, a
//! rolling ball).

mod common;

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
        let (x, y, th) = (q[0], q[1], q[2]);
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
        let _ = x;
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
