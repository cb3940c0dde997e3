//! [`Model::from_urdf`]: a URDF file as a numeric model, for the cross-check of scenes
//! the derive reads from the same file and for users without the derive. Written apart
//! from the derive's reader (`macros/codegen/src/urdf.rs`) on purpose: the two agree
//! only if both map the file right.

use std::collections::HashMap;

use nalgebra::{Matrix3, Rotation3, Vector3};

use crate::model::{JointKind, Link, Model};

impl Model {
    /// The rigid-body tree of a URDF document (the file's text), with `gravity`.
    ///
    /// The root link is the world (`free_base = false`) or hangs from it by a free joint
    /// (a massless translation link `<root>_base_translation`, then the root on a
    /// spherical joint). Revolute and continuous joints are revolute, prismatic joints
    /// prismatic, fixed joints fixed; links without `<inertial>` are massless, and
    /// massless leaves on fixed joints are left out. Coordinates follow a depth-first
    /// walk from the root, children in file order — the order the derive uses for the
    /// same file. Joints named in `lock` are held at zero (fixed). Limits, friction and
    /// damping are not part of this model.
    pub fn from_urdf(
        text: &str,
        gravity: Vector3<f64>,
        free_base: bool,
        lock: &[&str],
    ) -> Result<Model, String> {
        let robot = urdf_rs::read_from_string(text).map_err(|e| format!("malformed URDF: {e}"))?;
        let by_name: HashMap<&str, &urdf_rs::Link> =
            robot.links.iter().map(|l| (l.name.as_str(), l)).collect();
        let mut is_child = HashMap::new();
        let mut children: HashMap<&str, Vec<&urdf_rs::Joint>> = HashMap::new();
        for j in &robot.joints {
            if is_child.insert(j.child.link.as_str(), ()).is_some() {
                return Err(format!(
                    "link `{}` is the child of two joints",
                    j.child.link
                ));
            }
            children.entry(j.parent.link.as_str()).or_default().push(j);
        }
        let roots: Vec<&str> = robot
            .links
            .iter()
            .map(|l| l.name.as_str())
            .filter(|n| !is_child.contains_key(n))
            .collect();
        let [root] = roots[..] else {
            return Err(format!("a URDF has one root link, found {}", roots.len()));
        };
        let mass = |l: &str| by_name.get(l).map_or(0.0, |l| l.inertial.mass.value);
        // Depth-first order of joints.
        // Depth-first preorder, children in file order.
        let mut order: Vec<&urdf_rs::Joint> = Vec::new();
        let mut stack: Vec<&urdf_rs::Joint> = children
            .get(root)
            .map(|cs| cs.iter().rev().copied().collect())
            .unwrap_or_default();
        while let Some(j) = stack.pop() {
            order.push(j);
            if order.len() > robot.joints.len() {
                break;
            }
            if let Some(cs) = children.get(j.child.link.as_str()) {
                stack.extend(cs.iter().rev().copied());
            }
        }
        if order.len() != robot.joints.len() {
            return Err("the joints do not form one tree".into());
        }
        let mut carries: HashMap<&str, bool> = HashMap::new();
        for j in order.iter().rev() {
            let c = j.child.link.as_str();
            let below = children
                .get(c)
                .is_some_and(|cs| cs.iter().any(|k| carries[k.child.link.as_str()]));
            let fixed =
                j.joint_type == urdf_rs::JointType::Fixed || lock.contains(&j.name.as_str());
            carries.insert(c, mass(c) > 0.0 || below || !fixed);
        }

        let mut links: Vec<Link> = Vec::new();
        let mut index: HashMap<&str, usize> = HashMap::new();
        let mut coordinate = 0usize;
        let v3 = |v: [f64; 3]| Vector3::new(v[0], v[1], v[2]);
        let inertial = |name: &str| -> (f64, Vector3<f64>, Matrix3<f64>) {
            let Some(l) = by_name.get(name) else {
                return (0.0, Vector3::zeros(), Matrix3::zeros());
            };
            let i = &l.inertial.inertia;
            let i0 = Matrix3::new(
                i.ixx, i.ixy, i.ixz, i.ixy, i.iyy, i.iyz, i.ixz, i.iyz, i.izz,
            );
            let r = l.inertial.origin.rpy.0;
            let rot = Rotation3::from_euler_angles(r[0], r[1], r[2]);
            let inertia = rot.matrix() * i0 * rot.matrix().transpose();
            (l.inertial.mass.value, v3(l.inertial.origin.xyz.0), inertia)
        };
        if free_base {
            links.push(Link {
                name: format!("{root}_base_translation"),
                parent: None,
                joint: JointKind::Translation,
                coordinate: Some(0),
                origin_xyz: Vector3::zeros(),
                origin_rpy: Vector3::zeros(),
                mass: 0.0,
                com: Vector3::zeros(),
                inertia: Matrix3::zeros(),
            });
            let (m, com, inertia) = inertial(root);
            links.push(Link {
                name: root.to_string(),
                parent: Some(0),
                joint: JointKind::Spherical,
                coordinate: Some(3),
                origin_xyz: Vector3::zeros(),
                origin_rpy: Vector3::zeros(),
                mass: m,
                com,
                inertia,
            });
            index.insert(root, 1);
            coordinate = 6;
        }
        for j in order {
            let child = j.child.link.as_str();
            if !carries[child] {
                continue;
            }
            let axis = v3(j.axis.xyz.0);
            let unit = || {
                let n = axis.norm();
                if n > 0.0 && n.is_finite() {
                    Ok(axis / n)
                } else {
                    Err(format!("joint `{}` has a zero axis", j.name))
                }
            };
            let joint = match j.joint_type {
                _ if lock.contains(&j.name.as_str()) => JointKind::Fixed,
                urdf_rs::JointType::Revolute | urdf_rs::JointType::Continuous => {
                    JointKind::Revolute { axis: unit()? }
                }
                urdf_rs::JointType::Prismatic => JointKind::Prismatic { axis: unit()? },
                urdf_rs::JointType::Fixed => JointKind::Fixed,
                ref other => {
                    return Err(format!(
                        "joint `{}` of type {other:?} is not supported",
                        j.name
                    ));
                }
            };
            let (m, com, inertia) = inertial(child);
            let parent = index.get(j.parent.link.as_str()).copied();
            let dof = joint.dof();
            links.push(Link {
                name: child.to_string(),
                parent,
                joint,
                coordinate: (dof > 0).then_some(coordinate),
                origin_xyz: v3(j.origin.xyz.0),
                origin_rpy: v3(j.origin.rpy.0),
                mass: m,
                com,
                inertia,
            });
            coordinate += dof;
            index.insert(child, links.len() - 1);
        }
        Ok(Model {
            gravity,
            links,
            springs: Vec::new(),
            dampers: Vec::new(),
            point_springs: Vec::new(),
        })
    }
}
