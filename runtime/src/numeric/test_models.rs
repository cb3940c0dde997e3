//! Small models shared by the unit tests.

use nalgebra::{DMatrix, DVector, Matrix3, Vector3};

use super::{JointKind, Link, Model};

pub const G: f64 = 9.81;

/// A uniform rod along the link's x axis: com at l/2, inertia diag(0, m l²/12, m l²/12).
pub fn rod(
    name: &str,
    parent: Option<usize>,
    coordinate: usize,
    origin_x: f64,
    m: f64,
    l: f64,
) -> Link {
    Link {
        name: name.into(),
        parent,
        joint: JointKind::Revolute { axis: Vector3::z() },
        coordinate: Some(coordinate),
        origin_xyz: Vector3::new(origin_x, 0.0, 0.0),
        origin_rpy: Vector3::zeros(),
        mass: m,
        com: Vector3::new(l / 2.0, 0.0, 0.0),
        inertia: Matrix3::from_diagonal(&Vector3::new(0.0, m * l * l / 12.0, m * l * l / 12.0)),
    }
}

/// Two revolute-z rods in the x–y plane, gravity (0, −9.81, 0); q are relative angles.
pub fn double_pendulum(m1: f64, l1: f64, m2: f64, l2: f64) -> Model {
    Model {
        gravity: Vector3::new(0.0, -G, 0.0),
        links: vec![
            rod("upper", None, 0, 0.0, m1, l1),
            rod("lower", Some(0), 1, l1, m2, l2),
        ],
        springs: vec![],
        dampers: vec![],
        point_springs: vec![],
    }
}

/// Closed-form `M(q)` and `g(q)` of [`double_pendulum`].
pub fn double_pendulum_closed_form(
    m1: f64,
    l1: f64,
    m2: f64,
    l2: f64,
    t1: f64,
    t2: f64,
) -> (DMatrix<f64>, DVector<f64>) {
    let (i1, i2) = (m1 * l1 * l1 / 12.0, m2 * l2 * l2 / 12.0);
    let m22 = m2 * l2 * l2 / 4.0 + i2;
    let m12 = m22 + m2 * l1 * l2 / 2.0 * t2.cos();
    let m11 = m1 * l1 * l1 / 4.0 + i1 + m2 * (l1 * l1 + l1 * l2 * t2.cos()) + m22;
    let mass = DMatrix::from_row_slice(2, 2, &[m11, m12, m12, m22]);
    let g2 = G * m2 * l2 / 2.0 * (t1 + t2).cos();
    let g1 = G * (m1 * l1 / 2.0 + m2 * l1) * t1.cos() + g2;
    (mass, DVector::from_vec(vec![g1, g2]))
}

/// A cart on a prismatic x joint carrying a rod on a revolute z joint, gravity −y.
pub fn cart_pole(mc: f64, mp: f64, l: f64) -> Model {
    let cart = Link {
        name: "cart".into(),
        parent: None,
        joint: JointKind::Prismatic { axis: Vector3::x() },
        coordinate: Some(0),
        origin_xyz: Vector3::zeros(),
        origin_rpy: Vector3::zeros(),
        mass: mc,
        com: Vector3::zeros(),
        inertia: Matrix3::identity() * 0.1,
    };
    Model {
        gravity: Vector3::new(0.0, -G, 0.0),
        links: vec![cart, rod("pole", Some(0), 1, 0.0, mp, l)],
        springs: vec![],
        dampers: vec![],
        point_springs: vec![],
    }
}

/// A branched spatial tree: non-trivial origins (rpy), general axes, a prismatic joint
/// and a fixed link, full inertias.
pub fn spatial_chain() -> Model {
    let inertia =
        |a: f64, b: f64, c: f64| Matrix3::new(a, 0.01, -0.02, 0.01, b, 0.03, -0.02, 0.03, c);
    let link = |name: &str,
                parent,
                joint,
                coordinate,
                xyz: [f64; 3],
                rpy: [f64; 3],
                mass,
                com: [f64; 3],
                i| Link {
        name: String::from(name),
        parent,
        joint,
        coordinate,
        origin_xyz: Vector3::from(xyz),
        origin_rpy: Vector3::from(rpy),
        mass,
        com: Vector3::from(com),
        inertia: i,
    };
    let axis = |x: f64, y: f64, z: f64| Vector3::new(x, y, z).normalize();
    Model {
        gravity: Vector3::new(0.3, -0.2, -G),
        links: vec![
            link(
                "a",
                None,
                JointKind::Revolute { axis: Vector3::z() },
                Some(0),
                [0.0, 0.0, 0.1],
                [0.0, 0.0, 0.4],
                2.0,
                [0.05, 0.0, 0.2],
                inertia(0.3, 0.25, 0.1),
            ),
            link(
                "b",
                Some(0),
                JointKind::Revolute {
                    axis: axis(0.0, 1.0, 0.2),
                },
                Some(1),
                [0.0, 0.1, 0.4],
                [0.3, -0.5, 0.2],
                1.5,
                [0.3, 0.02, -0.01],
                inertia(0.1, 0.2, 0.2),
            ),
            link(
                "c",
                Some(1),
                JointKind::Prismatic {
                    axis: axis(1.0, 0.3, 0.0),
                },
                Some(2),
                [0.5, 0.0, 0.0],
                [0.0, 0.2, 0.0],
                0.8,
                [0.1, 0.0, 0.05],
                inertia(0.05, 0.06, 0.07),
            ),
            link(
                "tool",
                Some(2),
                JointKind::Fixed,
                None,
                [0.1, 0.0, 0.0],
                [1.0, 0.0, -0.3],
                0.3,
                [0.0, 0.05, 0.0],
                inertia(0.02, 0.02, 0.03),
            ),
            link(
                "d",
                Some(3),
                JointKind::Revolute {
                    axis: axis(1.0, 0.0, 1.0),
                },
                Some(3),
                [0.0, 0.2, 0.0],
                [-0.4, 0.1, 0.9],
                0.6,
                [0.0, 0.0, 0.1],
                inertia(0.04, 0.05, 0.02),
            ),
            link(
                "e",
                Some(0),
                JointKind::Revolute { axis: Vector3::x() },
                Some(4),
                [0.0, -0.2, 0.3],
                [0.0, 0.5, 0.0],
                0.9,
                [0.0, -0.1, 0.0],
                inertia(0.06, 0.04, 0.05),
            ),
        ],
        springs: vec![],
        dampers: vec![],
        point_springs: vec![],
    }
}

/// A symmetric positive definite inertia with off-diagonal terms.
pub fn full_inertia(a: f64, b: f64, c: f64) -> Matrix3<f64> {
    Matrix3::new(a, 0.01, -0.02, 0.01, b, 0.03, -0.02, 0.03, c)
}

/// A link with all fields given (the generated code's literal, in short).
#[allow(clippy::too_many_arguments)]
pub fn link(
    name: &str,
    parent: Option<usize>,
    joint: JointKind,
    coordinate: Option<usize>,
    xyz: [f64; 3],
    rpy: [f64; 3],
    mass: f64,
    com: [f64; 3],
    inertia: Matrix3<f64>,
) -> Link {
    Link {
        name: name.into(),
        parent,
        joint,
        coordinate,
        origin_xyz: Vector3::from(xyz),
        origin_rpy: Vector3::from(rpy),
        mass,
        com: Vector3::from(com),
        inertia,
    }
}

/// A massless translation link at the world origin (coordinates 0–2): the first half
/// of a free joint.
fn free_base() -> Link {
    link(
        "base",
        None,
        JointKind::Translation,
        Some(0),
        [0.0; 3],
        [0.0; 3],
        0.0,
        [0.0; 3],
        Matrix3::zeros(),
    )
}

/// A free rigid body (translation + spherical, velocity `(ṗ, ω)`, configuration
/// `(p, quaternion)`), mass `m`, centre of mass `com` in the body frame and inertia
/// `inertia` about it; gravity as given.
pub fn free_body(m: f64, com: Vector3<f64>, inertia: Matrix3<f64>, gravity: Vector3<f64>) -> Model {
    Model {
        gravity,
        links: vec![
            free_base(),
            link(
                "body",
                Some(0),
                JointKind::Spherical,
                Some(3),
                [0.0; 3],
                [0.0; 3],
                m,
                [com.x, com.y, com.z],
                inertia,
            ),
        ],
        springs: vec![],
        dampers: vec![],
        point_springs: vec![],
    }
}

/// One body on a spherical joint with an offset, rotated origin, offset centre of mass
/// and full inertia.
pub fn spherical_body() -> Model {
    Model {
        gravity: Vector3::new(0.5, -1.0, -G),
        links: vec![link(
            "ball",
            None,
            JointKind::Spherical,
            Some(0),
            [0.1, -0.2, 0.3],
            [0.2, 0.4, -0.3],
            1.7,
            [0.12, -0.05, 0.3],
            full_inertia(0.2, 0.15, 0.1),
        )],
        springs: vec![],
        dampers: vec![],
        point_springs: vec![],
    }
}

/// Revolute – spherical – revolute with offsets, rotated origins, centre-of-mass offsets
/// and full inertias. `v = (q̇₀, ω₁, ω₂, ω₃, q̇₄)`, `q = (q₀, w, x, y, z, q₅)`.
pub fn ball_chain() -> Model {
    let axis = |x: f64, y: f64, z: f64| Vector3::new(x, y, z).normalize();
    Model {
        gravity: Vector3::new(0.3, -0.2, -G),
        links: vec![
            link(
                "shoulder",
                None,
                JointKind::Revolute {
                    axis: axis(0.1, 0.2, 1.0),
                },
                Some(0),
                [0.0, 0.0, 0.2],
                [0.1, 0.0, 0.4],
                2.0,
                [0.05, 0.02, 0.2],
                full_inertia(0.3, 0.25, 0.1),
            ),
            link(
                "ball",
                Some(0),
                JointKind::Spherical,
                Some(1),
                [0.1, 0.3, 0.4],
                [0.3, -0.5, 0.2],
                1.5,
                [0.3, 0.02, -0.1],
                full_inertia(0.1, 0.2, 0.2),
            ),
            link(
                "wrist",
                Some(1),
                JointKind::Revolute {
                    axis: axis(1.0, 0.0, 0.5),
                },
                Some(4),
                [0.5, 0.1, 0.0],
                [0.0, 0.2, -0.6],
                0.8,
                [0.1, -0.04, 0.05],
                full_inertia(0.05, 0.06, 0.07),
            ),
        ],
        springs: vec![],
        dampers: vec![],
        point_springs: vec![],
    }
}

/// A satellite: a free bus (translation + spherical, coordinates 0–5) carrying a
/// two-link revolute arm (coordinates 6, 7); `q = (p, quaternion, q₇, q₈)`. Gravity as
/// given.
pub fn satellite(gravity: Vector3<f64>) -> Model {
    Model {
        gravity,
        links: vec![
            free_base(),
            link(
                "bus",
                Some(0),
                JointKind::Spherical,
                Some(3),
                [0.0; 3],
                [0.0; 3],
                10.0,
                [0.05, -0.02, 0.1],
                full_inertia(1.0, 1.4, 1.9),
            ),
            link(
                "arm1",
                Some(1),
                JointKind::Revolute {
                    axis: Vector3::new(0.0, 0.3, 1.0).normalize(),
                },
                Some(6),
                [0.6, 0.1, 0.2],
                [0.2, 0.0, 0.5],
                1.2,
                [0.4, 0.0, 0.02],
                full_inertia(0.08, 0.2, 0.22),
            ),
            link(
                "arm2",
                Some(2),
                JointKind::Revolute { axis: Vector3::y() },
                Some(7),
                [0.8, 0.0, 0.0],
                [0.0, -0.3, 0.1],
                0.7,
                [0.3, 0.05, 0.0],
                full_inertia(0.05, 0.1, 0.12),
            ),
        ],
        springs: vec![],
        dampers: vec![],
        point_springs: vec![],
    }
}
