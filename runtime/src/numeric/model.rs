//! A runtime description of a rigid multibody tree (what a scene *is*, not what one
//! evaluation computes). Built by the generated `Mechanism::model`, or by hand.

use nalgebra::{Matrix3, Vector3};

/// How a link moves relative to its parent.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum JointKind {
    /// Rotation by `q` about a unit axis given in the joint frame.
    Revolute { axis: Vector3<f64> },
    /// Translation by `q` along a unit axis given in the joint frame.
    Prismatic { axis: Vector3<f64> },
    /// Rigidly attached: no coordinate.
    Fixed,
}

/// One rigid link and the joint that attaches it to its parent.
///
/// Frame convention (as URDF): the link frame is
/// `parent frame · Trans(origin_xyz) · Rot(origin_rpy) · joint motion(q)`, where
/// `Rot(rpy) = Rz(yaw) · Ry(pitch) · Rx(roll)`; the axis is expressed in the joint frame
/// (after the origin transform), and so are the centre of mass and the inertia.
#[derive(Clone, Debug, PartialEq)]
pub struct Link {
    pub name: String,
    /// Index of the parent link in [`Model::links`], `None` for the world.
    pub parent: Option<usize>,
    pub joint: JointKind,
    /// Index of the joint coordinate in `q`, `None` for fixed joints.
    pub coordinate: Option<usize>,
    pub origin_xyz: Vector3<f64>,
    pub origin_rpy: Vector3<f64>,
    pub mass: f64,
    /// Centre of mass in the link frame.
    pub com: Vector3<f64>,
    /// Rotational inertia about the centre of mass, in the link frame.
    pub inertia: Matrix3<f64>,
}

/// A linear spring `τ = −k (q_i − rest)` on a joint coordinate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spring {
    pub coordinate: usize,
    pub stiffness: f64,
    pub rest: f64,
}

/// A viscous damper `τ = −c q̇_i` on a joint coordinate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Damper {
    pub coordinate: usize,
    pub damping: f64,
}

/// A rigid multibody tree. Links are in topological order (a parent before its
/// children) and coordinates are numbered in that same order, so the parent of
/// coordinate `i` always has a smaller index.
#[derive(Clone, Debug, PartialEq)]
pub struct Model {
    pub gravity: Vector3<f64>,
    pub links: Vec<Link>,
    pub springs: Vec<Spring>,
    pub dampers: Vec<Damper>,
}

impl Model {
    /// The model as JSON (no dependency: written by hand), for peer tools that build
    /// the same mechanism from a file (the report's Pinocchio comparison). Joint axes,
    /// origins and inertias are in the conventions documented on [`Link`].
    pub fn to_json(&self) -> String {
        fn v3(v: &Vector3<f64>) -> String {
            format!("[{:e}, {:e}, {:e}]", v[0], v[1], v[2])
        }
        fn opt(i: Option<usize>) -> String {
            i.map_or("null".into(), |i| i.to_string())
        }
        let links: Vec<String> = self
            .links
            .iter()
            .map(|l| {
                let (kind, axis) = match l.joint {
                    JointKind::Revolute { axis } => ("revolute", v3(&axis)),
                    JointKind::Prismatic { axis } => ("prismatic", v3(&axis)),
                    JointKind::Fixed => ("fixed", "null".into()),
                };
                let i = &l.inertia;
                format!(
                    "{{\"name\": {:?}, \"parent\": {}, \"joint\": \"{kind}\", \"axis\": {axis}, \"coordinate\": {}, \"origin_xyz\": {}, \"origin_rpy\": {}, \"mass\": {:e}, \"com\": {}, \"inertia\": [[{:e}, {:e}, {:e}], [{:e}, {:e}, {:e}], [{:e}, {:e}, {:e}]]}}",
                    l.name,
                    opt(l.parent),
                    opt(l.coordinate),
                    v3(&l.origin_xyz),
                    v3(&l.origin_rpy),
                    l.mass,
                    v3(&l.com),
                    i[(0, 0)], i[(0, 1)], i[(0, 2)], i[(1, 0)], i[(1, 1)], i[(1, 2)], i[(2, 0)], i[(2, 1)], i[(2, 2)]
                )
            })
            .collect();
        let springs: Vec<String> = self
            .springs
            .iter()
            .map(|s| {
                format!(
                    "{{\"coordinate\": {}, \"stiffness\": {:e}, \"rest\": {:e}}}",
                    s.coordinate, s.stiffness, s.rest
                )
            })
            .collect();
        let dampers: Vec<String> = self
            .dampers
            .iter()
            .map(|d| {
                format!(
                    "{{\"coordinate\": {}, \"damping\": {:e}}}",
                    d.coordinate, d.damping
                )
            })
            .collect();
        format!(
            "{{\n  \"gravity\": {},\n  \"links\": [\n    {}\n  ],\n  \"springs\": [{}],\n  \"dampers\": [{}]\n}}\n",
            v3(&self.gravity),
            links.join(",\n    "),
            springs.join(", "),
            dampers.join(", ")
        )
    }
}
