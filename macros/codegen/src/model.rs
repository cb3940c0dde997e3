//! The validated, syn-free model of a scene: what the mechanics passes consume.
//!
//! Links are in topological order (a parent before its children) and coordinates are
//! numbered in that order, so the parent of coordinate `i` has a smaller index — the
//! property the sparse LTDL factorisation relies on.

use proc_macro2::Ident;

use crate::sym::{Graph, Id, Unary};

/// Elementary functions an attribute expression may call.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Func {
    Sqrt,
    Sin,
    Cos,
    Exp,
    Ln,
}

/// An expression over the struct's parameter fields.
#[derive(Clone, Debug, PartialEq)]
pub enum PExpr {
    Const(f64),
    Param(u16),
    /// The free variable of a constitutive law (the force `f` in `v = φ(f)`).
    Var,
    Neg(Box<PExpr>),
    Bin(char, Box<PExpr>, Box<PExpr>),
    Call(Func, Box<PExpr>),
}

impl PExpr {
    pub fn zero() -> PExpr {
        PExpr::Const(0.0)
    }

    /// The value when it does not depend on parameters.
    pub fn as_const(&self) -> Option<f64> {
        match self {
            PExpr::Const(c) => Some(*c),
            PExpr::Param(_) | PExpr::Var => None,
            PExpr::Neg(x) => x.as_const().map(|x| -x),
            PExpr::Bin(op, a, b) => {
                let (a, b) = (a.as_const()?, b.as_const()?);
                Some(match op {
                    '+' => a + b,
                    '-' => a - b,
                    '*' => a * b,
                    _ => a / b,
                })
            }
            PExpr::Call(f, x) => {
                let x = x.as_const()?;
                Some(match f {
                    Func::Sqrt => x.sqrt(),
                    Func::Sin => x.sin(),
                    Func::Cos => x.cos(),
                    Func::Exp => x.exp(),
                    Func::Ln => x.ln(),
                })
            }
        }
    }

    /// The expression as the user would read it (fields by name).
    pub fn display(&self, params: &[Ident]) -> String {
        match self {
            PExpr::Const(c) => format!("{c}"),
            PExpr::Param(i) => params[*i as usize].to_string(),
            PExpr::Var => "f".into(),
            PExpr::Neg(x) => format!("-{}", x.display_atom(params)),
            PExpr::Bin(op, a, b) => {
                format!("{} {op} {}", a.display_atom(params), b.display_atom(params))
            }
            PExpr::Call(f, x) => {
                format!("{}({})", format!("{f:?}").to_lowercase(), x.display(params))
            }
        }
    }

    fn display_atom(&self, params: &[Ident]) -> String {
        match self {
            PExpr::Bin(..) | PExpr::Neg(_) => format!("({})", self.display(params)),
            _ => self.display(params),
        }
    }

    /// Adds the expression to the graph with [`PExpr::Var`] standing for `var`.
    pub fn lower_var(&self, g: &mut Graph, var: Id) -> Id {
        let mut memo = crate::sym::FastMap::default();
        let x0 = g.input(crate::sym::InputKind::Q, 0);
        let e = self.lower(g);
        if x0 == var {
            return e;
        }
        let map: crate::sym::FastMap<_, _> = [(x0, var)].into_iter().collect();
        g.substitute(e, &map, &mut memo)
    }

    /// Adds the expression to the graph.
    pub fn lower(&self, g: &mut Graph) -> Id {
        match self {
            PExpr::Const(c) => g.constant(*c),
            PExpr::Param(i) => g.param(*i),
            // A law is lowered into a graph of its own, with `f` as the one input.
            PExpr::Var => g.input(crate::sym::InputKind::Q, 0),
            PExpr::Neg(x) => {
                let x = x.lower(g);
                g.neg(x)
            }
            PExpr::Bin(op, a, b) => {
                let (a, b) = (a.lower(g), b.lower(g));
                match op {
                    '+' => g.add(a, b),
                    '-' => g.sub(a, b),
                    '*' => g.mul(a, b),
                    _ => g.div(a, b),
                }
            }
            PExpr::Call(f, x) => {
                let x = x.lower(g);
                let op = match f {
                    Func::Sqrt => Unary::Sqrt,
                    Func::Sin => Unary::Sin,
                    Func::Cos => Unary::Cos,
                    Func::Exp => Unary::Exp,
                    Func::Ln => Unary::Ln,
                };
                g.unary(op, x)
            }
        }
    }
}

pub type Vec3 = [PExpr; 3];
pub type Mat3 = [[PExpr; 3]; 3];

/// How a link moves relative to its parent; axes are unit vectors known at expansion.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum JointKind {
    Revolute([f64; 3]),
    Prismatic([f64; 3]),
    Fixed,
    /// A ball joint (SO(3)): configuration a unit quaternion `(w, x, y, z)`, velocity the
    /// body angular velocity in the link frame.
    Spherical,
    /// Translation along the joint frame's three axes (ℝ³): the first half of a free
    /// joint, on a massless link of its own.
    Translation,
    /// As declared: `free` becomes a [`JointKind::Translation`] link followed by a
    /// [`JointKind::Spherical`] one (SO(3) × ℝ³), so no link has this kind.
    Free,
}

impl JointKind {
    /// Velocity coordinates of the joint.
    pub fn dof(self) -> usize {
        match self {
            JointKind::Revolute(_) | JointKind::Prismatic(_) => 1,
            JointKind::Fixed => 0,
            JointKind::Spherical | JointKind::Translation => 3,
            JointKind::Free => 6,
        }
    }

    /// Configuration slots of the joint.
    pub fn config_len(self) -> usize {
        match self {
            JointKind::Spherical => 4,
            JointKind::Free => 7,
            k => k.dof(),
        }
    }

    /// Whether the configuration lives on a Lie group other than ℝⁿ.
    pub fn is_lie(self) -> bool {
        matches!(
            self,
            JointKind::Spherical | JointKind::Translation | JointKind::Free
        )
    }
}

/// A link and the joint attaching it to its parent (URDF frame convention: the link
/// frame is `parent · Trans(origin) · Rot(rpy) · motion(q)`, `Rot = Rz(yaw) Ry(pitch) Rx(roll)`).
#[derive(Clone, Debug)]
pub struct Link {
    pub name: String,
    pub joint_name: String,
    pub parent: Option<usize>,
    pub kind: JointKind,
    /// The first velocity coordinate of the joint (`kind.dof()` consecutive ones).
    pub coordinate: Option<usize>,
    /// The first configuration slot of the joint (`kind.config_len()` consecutive ones);
    /// equal to `coordinate` in scenes without Lie-group joints.
    pub config: Option<usize>,
    pub origin: Vec3,
    pub rpy: Vec3,
    pub mass: PExpr,
    pub com: Vec3,
    /// Rotational inertia about the centre of mass, in the link frame.
    pub inertia: Mat3,
}

/// A linear spring on a joint coordinate: `τ = −k (q − rest)`.
#[derive(Clone, Debug)]
pub struct Spring {
    pub coordinate: usize,
    pub k: PExpr,
    pub rest: PExpr,
}

/// A non-linear spring given by its potential energy `U(x)` in the coordinate `x`
/// ([`PExpr::Var`]); its force is `−dU/dx`.
#[derive(Clone, Debug)]
pub struct Potential {
    pub coordinate: usize,
    pub u: PExpr,
}

/// A linear spring between two points, each fixed to a link (`None`: the world) at a
/// point of the link's frame: potential `½ k (ℓ − rest)²`, `ℓ` their distance.
#[derive(Clone, Debug)]
pub struct PointSpring {
    pub name: String,
    pub a: (Option<usize>, Vec3),
    pub b: (Option<usize>, Vec3),
    pub k: PExpr,
    pub rest: PExpr,
}

/// A viscous damper on a joint coordinate: `τ = −c q̇`.
#[derive(Clone, Debug)]
pub struct Damper {
    pub coordinate: usize,
    pub c: PExpr,
}

/// A validated scene.
#[derive(Clone, Debug)]
pub struct Model {
    /// The path of the `filippov` crate in the user's crate (`None`: `::filippov`).
    pub krate: Option<syn::Path>,
    pub ident: Ident,
    /// Parameter fields, in declaration order.
    pub params: Vec<Ident>,
    /// `None` when there is no gravity (no gravity code is emitted then).
    pub gravity: Option<Vec3>,
    pub links: Vec<Link>,
    pub springs: Vec<Spring>,
    pub dampers: Vec<Damper>,
    /// Actuated coordinates, in the order of the input vector `u`.
    pub inputs: Vec<usize>,
    /// Non-smooth elements (dash-pots, friction, stops).
    pub elements: Vec<Element>,
    /// Non-linear springs by their potentials.
    pub potentials: Vec<Potential>,
    /// The optional kernels asked for with `emit = [...]`.
    pub emit: Emit,
    /// The URDF file the scene was read from (absolute), so that the expansion can make
    /// cargo rebuild when it changes.
    pub urdf_file: Option<std::path::PathBuf>,
    /// Frames declared with `#[frame(…)]` (tool points, sensors), each fixed to a link.
    pub frames: Vec<Frame>,
    /// How forward dynamics, its Jacobian and `M⁻¹` solve with the mass matrix
    /// (`#[mechanism(forward_dynamics = …)]`).
    pub algorithm: Algorithm,
    /// Joints that close kinematic loops (`#[loop_joint(…)]`), in declaration order.
    pub loops: Vec<LoopJoint>,
    /// Springs between two points (`#[spring(name: between(a, b), …)]`).
    pub point_springs: Vec<PointSpring>,
    /// Contacts of points and spheres with planes (`#[contact(…)]`), in declaration order.
    pub contacts: Vec<Contact>,
}

/// The linear solve behind forward dynamics, its Jacobian and `M⁻¹`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Algorithm {
    /// Per kernel, whichever of the two emits fewer operations for this scene: forward
    /// dynamics is built and counted both ways; for the column kernels (its Jacobian,
    /// `M⁻¹`) a sample of columns is, and the rest extrapolated.
    #[default]
    Auto,
    /// Mass matrix by the composite-rigid-body algorithm, then its sparse `LᵀDL`.
    Crba,
    /// The articulated-body algorithm, unrolled per link.
    Aba,
    /// The articulated-body algorithm as one loop over a table of the bodies' constants
    /// (`runtime::compact`): code whose size does not grow with the tree. Trees of
    /// revolute, prismatic and fixed joints without loop joints.
    Compact,
}

impl Algorithm {
    pub const NAMES: [(&'static str, Algorithm); 4] = [
        ("auto", Algorithm::Auto),
        ("crba", Algorithm::Crba),
        ("aba", Algorithm::Aba),
        ("compact", Algorithm::Compact),
    ];
}

impl Model {
    /// Why the compact kernels cannot take this scene (`None`: they can): they run on
    /// trees of one-dof and fixed joints, each link after its parent.
    pub fn compact_unsupported(&self) -> Option<String> {
        if let Some(l) = self.links.iter().find(|l| l.kind.is_lie()) {
            return Some(format!(
                "joint `{}` is a ball, translation or free joint; the compact kernels take \
                 revolute, prismatic and fixed joints",
                l.joint_name
            ));
        }
        if let Some(l) = self.loops.first() {
            return Some(format!(
                "loop joint `{}` closes a loop; the compact kernels take trees",
                l.name
            ));
        }
        if let Some((i, l)) = self
            .links
            .iter()
            .enumerate()
            .find(|(i, l)| l.parent.is_some_and(|p| p >= *i))
        {
            return Some(format!(
                "link `{}` (number {i}) comes before its parent; the compact kernels need \
                 parents first",
                l.name
            ));
        }
        None
    }
}

/// A frame fixed to a link: `link · Trans(origin) · Rot(rpy)` (URDF convention), a
/// frame declared on another frame already composed onto that frame's link.
#[derive(Clone, Debug)]
pub struct Frame {
    pub name: String,
    /// The link it is fixed to; `None`: the world.
    pub link: Option<usize>,
    /// Offsets from the link frame outwards, applied in order (one per frame in the
    /// chain from the link to this frame).
    pub offsets: Vec<(Vec3, Vec3)>,
}

/// A joint that closes a kinematic loop between two links already connected through
/// the tree (the spanning tree's cut joint): it adds constraints, not coordinates. Its
/// frame on the parent side is `parent · Trans(origin) · Rot(rpy)`, on the child side
/// `child · Trans(child_origin) · Rot(child_rpy)`; the joint holds the two frames
/// together as its kind allows (a revolute one lets them turn about its axis, given in
/// the parent-side frame).
#[derive(Clone, Debug)]
pub struct LoopJoint {
    pub name: String,
    /// [`JointKind::Revolute`], [`JointKind::Prismatic`], [`JointKind::Spherical`] or
    /// [`JointKind::Fixed`].
    pub kind: JointKind,
    /// The parent-side link; `None`: the world.
    pub parent: Option<usize>,
    pub child: usize,
    pub origin: Vec3,
    pub rpy: Vec3,
    pub child_origin: Vec3,
    pub child_rpy: Vec3,
}

/// A point or sphere on a body touching a plane (`#[contact(…)]`, theory §8): the
/// sphere's centre `at` (body frame) and its radius; the plane's frame
/// `plane · Trans(origin) · Rot(rpy)` (`plane`: its link, `None` for the world) and its
/// normal there, a signed coordinate axis, the frame's other two axes its tangents.
#[derive(Clone, Debug)]
pub struct Contact {
    pub name: String,
    pub body: usize,
    pub at: Vec3,
    pub radius: PExpr,
    pub plane: Option<usize>,
    pub origin: Vec3,
    pub rpy: Vec3,
    pub normal: [f64; 3],
    /// Coulomb friction coefficient (`0`: frictionless); the kinetic one where
    /// `mu_static` is given.
    pub mu: PExpr,
    /// The static friction coefficient (`≥ mu`), where it differs from `mu`.
    pub mu_static: Option<PExpr>,
    /// Newton's coefficient of restitution.
    pub restitution: PExpr,
}

/// Kernels the integrators do not call, emitted only when the scene asks for them by
/// name (`#[mechanism(emit = [coriolis, energy])]` or `emit = all`). The mass matrix,
/// forward dynamics and its Jacobian (and, with non-smooth elements, `M⁻¹` and the
/// element laws) are always emitted: every integrator needs them.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Emit {
    pub christoffel: bool,
    pub coriolis: bool,
    pub gravity: bool,
    pub bias: bool,
    pub passive_forces: bool,
    pub inverse_dynamics: bool,
    pub energy: bool,
    pub delassus: bool,
    pub dae_residuals: bool,
    pub switching_functions: bool,
    pub kinematics: bool,
    pub generic: bool,
}

impl Emit {
    /// Every name `emit = [...]` accepts, with what it adds.
    pub const NAMES: [(&'static str, &'static str); 12] = [
        ("christoffel", "`christoffel_symbols` (trait `Christoffel`)"),
        ("coriolis", "`coriolis_matrix` (trait `Coriolis`)"),
        ("gravity", "`gravity` (trait `Gravity`)"),
        ("bias", "`bias` = C v + g (trait `Bias`)"),
        ("passive_forces", "`passive_forces` (trait `PassiveForces`)"),
        (
            "inverse_dynamics",
            "`inverse_dynamics` (trait `InverseDynamics`)",
        ),
        (
            "energy",
            "`kinetic_energy` and `potential_energy` (trait `Energy`)",
        ),
        ("delassus", "`delassus` (scenes with non-smooth elements)"),
        (
            "dae_residuals",
            "`momentum_residual` and `constitutive_residual` (scenes with non-smooth elements)",
        ),
        (
            "switching_functions",
            "`switching_functions` (scenes with non-smooth elements)",
        ),
        (
            "kinematics",
            "`frame_pose` and `frame_jacobian` of every body and `#[frame]` (trait `Kinematics`)",
        ),
        (
            "generic",
            "`forward_dynamics_generic` on any scalar: f32, dual numbers (trait `GenericDynamics`)",
        ),
    ];

    pub fn all() -> Emit {
        let mut e = Emit::default();
        for (name, _) in Emit::NAMES {
            e.set(name);
        }
        e
    }

    /// Sets the flag of `name`; `false` for an unknown name.
    pub fn set(&mut self, name: &str) -> bool {
        let flag = match name {
            "christoffel" => &mut self.christoffel,
            "coriolis" => &mut self.coriolis,
            "gravity" => &mut self.gravity,
            "bias" => &mut self.bias,
            "passive_forces" => &mut self.passive_forces,
            "inverse_dynamics" => &mut self.inverse_dynamics,
            "energy" => &mut self.energy,
            "delassus" => &mut self.delassus,
            "dae_residuals" => &mut self.dae_residuals,
            "switching_functions" => &mut self.switching_functions,
            "kinematics" => &mut self.kinematics,
            "generic" => &mut self.generic,
            _ => return false,
        };
        *flag = true;
        true
    }
}

/// Which velocity a non-monotone law's branch takes where several forces fit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Selection {
    NoVelocityJumps,
    MaximalDissipation,
}

/// The slip law of a dash-pot element outside its dead zone.
#[derive(Clone, Debug)]
pub enum Law {
    Coulomb,
    /// Static/kinetic friction: the element's `f_crit` is the static force.
    StaticKinetic {
        f_kinetic: PExpr,
    },
    BinghamLinear {
        eta: PExpr,
    },
    /// `v = φ(f)` for `f > f_crit` (odd extension), `φ` an expression in [`PExpr::Var`].
    User {
        phi: PExpr,
        selection: Option<Selection>,
    },
}

/// What a stop is made of.
#[derive(Clone, Debug)]
pub enum StopKind {
    Rigid { restitution: PExpr },
    SpringBacked { stiffness: PExpr },
}

#[derive(Clone, Debug)]
pub enum ElementKind {
    DashPot {
        law: Law,
        f_crit: PExpr,
    },
    /// `upper`: the coordinate stays at or below `position`.
    Stop {
        upper: bool,
        position: PExpr,
        kind: StopKind,
    },
}

/// A non-smooth element on a joint coordinate.
#[derive(Clone, Debug)]
pub struct Element {
    pub name: String,
    pub coordinate: usize,
    pub kind: ElementKind,
    /// Bearing friction: the limit grows with the joint's load (Coulomb only).
    pub bearing: Option<Bearing>,
}

/// The load-dependent part of a friction element's limit, `coefficient · |F_⊥|`
/// (`coefficient = μ` on a prismatic joint, `μ r` on a revolute one), where `F_⊥` is the
/// reaction force the joint transmits (see `nonsmooth::bearing`).
#[derive(Clone, Debug)]
pub struct Bearing {
    pub coefficient: PExpr,
    /// Where the friction names its joint, for messages.
    pub span: proc_macro2::Span,
}

impl Model {
    /// Number of velocity coordinates.
    pub fn dof(&self) -> usize {
        self.links.iter().map(|l| l.kind.dof()).sum()
    }

    /// Number of configuration slots (`dof()` unless there are Lie-group joints).
    pub fn config_dim(&self) -> usize {
        self.links.iter().map(|l| l.kind.config_len()).sum()
    }

    /// Whether the scene has spherical or free joints.
    pub fn is_lie(&self) -> bool {
        self.links.iter().any(|l| l.kind.is_lie())
    }

    /// The links that carry the coordinates, by coordinate index.
    pub fn coordinate_links(&self) -> Vec<usize> {
        let mut out = vec![0; self.dof()];
        for (i, l) in self.links.iter().enumerate() {
            if let Some(c) = l.coordinate {
                for k in 0..l.kind.dof() {
                    out[c + k] = i;
                }
            }
        }
        out
    }

    /// The configuration slot of a coordinate of a one-dof joint (its `q`).
    pub fn slot_of(&self, coordinate: usize) -> usize {
        let l = &self.links[self.coordinate_links()[coordinate]];
        l.config.unwrap_or(0) + (coordinate - l.coordinate.unwrap_or(0))
    }

    /// The nearest ancestor coordinate of each coordinate (`λ(i)` of the LTDL
    /// factorisation), skipping fixed joints; the coordinates of a three-dof joint form
    /// a chain.
    pub fn coordinate_parents(&self) -> Vec<Option<usize>> {
        self.coordinate_links()
            .into_iter()
            .enumerate()
            .map(|(c, li)| {
                if self.links[li].coordinate != Some(c) {
                    return Some(c - 1);
                }
                let mut p = self.links[li].parent;
                while let Some(pi) = p {
                    if let Some(c) = self.links[pi].coordinate {
                        return Some(c + self.links[pi].kind.dof() - 1);
                    }
                    p = self.links[pi].parent;
                }
                None
            })
            .collect()
    }

    /// Names by coordinate: the joint's, suffixed `.x`, `.y`, `.z` (translation) or
    /// `.wx`, `.wy`, `.wz` (rotation) on three-dof joints.
    pub fn joint_names(&self) -> Vec<String> {
        self.coordinate_links()
            .into_iter()
            .enumerate()
            .map(|(c, li)| {
                let l = &self.links[li];
                let k = c - l.coordinate.unwrap_or(c);
                match l.kind {
                    JointKind::Spherical => format!("{}.{}", l.joint_name, ["wx", "wy", "wz"][k]),
                    JointKind::Translation => format!("{}.{}", l.joint_name, ["x", "y", "z"][k]),
                    _ => l.joint_name.clone(),
                }
            })
            .collect()
    }
}
