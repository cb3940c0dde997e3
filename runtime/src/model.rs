//! A runtime description of a rigid multibody tree (what a scene *is*, not what one
//! evaluation computes). Built by the generated `Mechanism::model`, or by hand.

use nalgebra::{DVector, Matrix3, Vector3};

use crate::geometry::UnitQuat;

/// How a link moves relative to its parent.
///
/// | kind | velocity coordinates | configuration slots |
/// |---|---|---|
/// | `Revolute`, `Prismatic` | 1: `q̇` | 1: `q` |
/// | `Spherical` | 3: body angular velocity `ω` (link frame) | 4: unit quaternion `(w, x, y, z)` |
/// | `Translation` | 3: `ṗ` (joint-frame axes) | 3: `p` (joint-frame axes) |
/// | `Fixed` | 0 | 0 |
///
/// A free joint is a massless `Translation` link followed by a `Spherical` link
/// (SO(3) × ℝ³; see [`crate::liegroup::LieMechanism`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum JointKind {
    /// Rotation by `q` about a unit axis given in the joint frame.
    Revolute { axis: Vector3<f64> },
    /// Translation by `q` along a unit axis given in the joint frame.
    Prismatic { axis: Vector3<f64> },
    /// Rigidly attached: no coordinate.
    Fixed,
    /// Ball joint: link frame = joint frame · Rot(R), `R` the rotation of the unit
    /// quaternion in the configuration; the velocity is the link's angular velocity
    /// relative to the joint frame, in link-frame axes (`Ṙ = R ω̂`).
    Spherical,
    /// Three-dimensional translation: link frame = joint frame · Trans(p), no rotation;
    /// the velocity is `ṗ` in joint-frame (= link-frame) axes.
    Translation,
}

impl JointKind {
    /// Number of velocity coordinates of the joint: 1, 1, 0, 3, 3.
    pub fn dof(&self) -> usize {
        match self {
            JointKind::Revolute { .. } | JointKind::Prismatic { .. } => 1,
            JointKind::Fixed => 0,
            JointKind::Spherical | JointKind::Translation => 3,
        }
    }

    /// Number of configuration slots of the joint: 1, 1, 0, 4, 3.
    pub fn config_dim(&self) -> usize {
        match self {
            JointKind::Spherical => 4,
            other => other.dof(),
        }
    }
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
    /// Index of the joint's (first) velocity coordinate in `v`, `None` for fixed
    /// joints. A spherical or translation joint owns the three consecutive velocity
    /// coordinates from here. For revolute and prismatic joints of a model without
    /// spherical or translation joints it is also the index in `q`; in general the
    /// configuration slot is [`Model::config_slot`].
    pub coordinate: Option<usize>,
    pub origin_xyz: Vector3<f64>,
    pub origin_rpy: Vector3<f64>,
    pub mass: f64,
    /// Centre of mass in the link frame.
    pub com: Vector3<f64>,
    /// Rotational inertia about the centre of mass, in the link frame.
    pub inertia: Matrix3<f64>,
}

/// A linear spring `τ = −k (q_i − rest)` on a Euclidean coordinate (revolute,
/// prismatic, or a component of a translation joint); `coordinate` is the velocity
/// index, `q_i` the configuration slot of that coordinate ([`Model::euclid_slot`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spring {
    pub coordinate: usize,
    pub stiffness: f64,
    pub rest: f64,
}

/// A viscous damper `τ = −c v_i` on a velocity coordinate (on a spherical joint's
/// component it damps that component of the body angular velocity).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Damper {
    pub coordinate: usize,
    pub damping: f64,
}

/// A rigid multibody tree. Links are in topological order (a parent before its
/// children) and coordinates are numbered in that same order, so the parent of
/// coordinate `i` always has a smaller index.
///
/// # Coordinates
///
/// The configuration `q` has [`config_dim`](Self::config_dim) slots and the velocity
/// `v` (and acceleration, forces) [`dof`](Self::dof) components; both are assigned in
/// link order, per joint as in the table on [`JointKind`]. Without spherical and
/// translation joints the two layouts coincide. The numeric functions take `q` in the
/// configuration layout and `v`, `a`, `τ` in the velocity layout; the equations are in
/// the quasi-velocities `v`: `M(q) v̇ + C(q, v) v + g(q) = τ + τ_p`, the quaternions in
/// `q` being unit.
#[derive(Clone, Debug, PartialEq)]
pub struct Model {
    pub gravity: Vector3<f64>,
    pub links: Vec<Link>,
    pub springs: Vec<Spring>,
    pub dampers: Vec<Damper>,
    /// Linear springs between two points (`#[spring(name: between(a, b), …)]`).
    pub point_springs: Vec<PointSpring>,
}

/// A linear spring between point `a` (on link `a.0`, `None` the world, at `a.1` in
/// that link's frame) and point `b`: potential `½ k (ℓ − rest)²`, `ℓ` their distance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointSpring {
    pub a: (Option<usize>, Vector3<f64>),
    pub b: (Option<usize>, Vector3<f64>),
    pub stiffness: f64,
    pub rest: f64,
}

impl Model {
    /// Number of velocity coordinates (degrees of freedom): the sum of
    /// [`JointKind::dof`] over the links that have a coordinate.
    pub fn dof(&self) -> usize {
        self.links
            .iter()
            .filter(|l| l.coordinate.is_some())
            .map(|l| l.joint.dof())
            .sum()
    }

    /// Number of configuration slots, `NQ`: the sum of [`JointKind::config_dim`] over
    /// the links that have a coordinate.
    pub fn config_dim(&self) -> usize {
        self.links
            .iter()
            .filter(|l| l.coordinate.is_some())
            .map(|l| l.joint.config_dim())
            .sum()
    }

    /// The first configuration slot of every link (`None` for links without a
    /// coordinate), assigned in link order: one slot per revolute or prismatic joint,
    /// four per spherical joint (`w, x, y, z`), three per translation joint.
    pub fn config_slots(&self) -> Vec<Option<usize>> {
        let mut next = 0;
        self.links
            .iter()
            .map(|l| {
                l.coordinate.map(|_| {
                    let slot = next;
                    next += l.joint.config_dim();
                    slot
                })
            })
            .collect()
    }

    /// The first configuration slot of link `link` (see [`config_slots`](Self::config_slots)).
    pub fn config_slot(&self, link: usize) -> Option<usize> {
        self.config_slots()[link]
    }

    /// The configuration slot of velocity coordinate `k` when it is Euclidean (revolute,
    /// prismatic, a translation component: then `q[slot]` is its position), `None` for
    /// a component of a spherical joint or an index out of range.
    pub fn euclid_slot(&self, k: usize) -> Option<usize> {
        self.links
            .iter()
            .zip(self.config_slots())
            .find_map(|(l, slot)| {
                let c = l.coordinate?;
                let offset = k.checked_sub(c).filter(|&o| o < l.joint.dof())?;
                match l.joint {
                    JointKind::Spherical => None,
                    _ => Some(slot? + offset),
                }
            })
    }

    /// `(slot of w in q, index of ω_x in v)` of every spherical joint, in link order:
    /// the layout of [`crate::liegroup::LieMechanism::ROTATIONS`].
    pub fn rotation_slots(&self) -> Vec<(usize, usize)> {
        self.links
            .iter()
            .zip(self.config_slots())
            .filter_map(|(l, slot)| match (l.joint, slot, l.coordinate) {
                (JointKind::Spherical, Some(s), Some(k)) => Some((s, k)),
                _ => None,
            })
            .collect()
    }

    /// `(slot in q, index in v)` of every Euclidean coordinate, in link order: the
    /// layout of [`crate::liegroup::LieMechanism::EUCLID`].
    pub fn euclid_slots(&self) -> Vec<(usize, usize)> {
        let mut out = Vec::new();
        for (l, slot) in self.links.iter().zip(self.config_slots()) {
            if let (Some(s), Some(k)) = (slot, l.coordinate)
                && l.joint != JointKind::Spherical
            {
                out.extend((0..l.joint.dof()).map(|o| (s + o, k + o)));
            }
        }
        out
    }

    /// The configuration with every Euclidean coordinate zero and every rotation the
    /// identity quaternion `(1, 0, 0, 0)`.
    pub fn identity_configuration(&self) -> DVector<f64> {
        let mut q = DVector::zeros(self.config_dim());
        for (s, _) in self.rotation_slots() {
            q[s] = 1.0;
        }
        q
    }

    /// `q ⊕ φ`: the configuration reached from `q` along the local exponential
    /// coordinates `φ` (length [`dof`](Self::dof)): `R ← R · exp(φ_rot)` for every
    /// spherical joint (quaternion product, renormalised), `x ← x + φ` on Euclidean
    /// coordinates. `∂/∂φ_k` at `φ = 0` is the derivative along the velocity
    /// coordinate `k` (see [`crate::numeric::mass_matrix_derivatives`]).
    pub fn retract(&self, q: &DVector<f64>, phi: &DVector<f64>) -> DVector<f64> {
        let mut out = q.clone();
        for (s, k) in self.euclid_slots() {
            out[s] += phi[k];
        }
        for (s, k) in self.rotation_slots() {
            let r = UnitQuat::try_new(q[s], q[s + 1], q[s + 2], q[s + 3])
                .expect("retract: a quaternion in q is zero or not finite");
            let step = UnitQuat::exp(&Vector3::new(phi[k], phi[k + 1], phi[k + 2]));
            let c = (r * step).normalised().coords();
            out.rows_mut(s, 4).copy_from_slice(&c);
        }
        out
    }

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
                    JointKind::Spherical => ("spherical", "null".into()),
                    JointKind::Translation => ("translation", "null".into()),
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
        let point = |p: &(Option<usize>, Vector3<f64>)| {
            let link = p.0.map_or("null".to_string(), |l| l.to_string());
            format!("{{\"link\": {link}, \"point\": {}}}", v3(&p.1))
        };
        let point_springs: Vec<String> = self
            .point_springs
            .iter()
            .map(|s| {
                format!(
                    "{{\"a\": {}, \"b\": {}, \"stiffness\": {:e}, \"rest\": {:e}}}",
                    point(&s.a),
                    point(&s.b),
                    s.stiffness,
                    s.rest
                )
            })
            .collect();
        format!(
            "{{\n  \"gravity\": {},\n  \"links\": [\n    {}\n  ],\n  \"springs\": [{}],\n  \"dampers\": [{}],\n  \"point_springs\": [{}]\n}}\n",
            v3(&self.gravity),
            links.join(",\n    "),
            springs.join(", "),
            dampers.join(", "),
            point_springs.join(", ")
        )
    }
}
