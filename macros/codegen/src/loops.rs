//! `#[loop_joint(…)]`: joints that close kinematic loops.
//!
//! The bodies and `#[joint]`s form the spanning tree; a loop joint connects two bodies
//! the tree already connects (or a body and the world) and becomes constraints on the
//! tree's coordinates instead of coordinates of its own (theory §7). It is written like
//! a tree joint, with the frame on the child side given too:
//!
//! ```text
//! #[loop_joint(close: revolute(z), parent = crank, child = rocker,
//!              origin = [l1, 0.0, 0.0], child_origin = [l3, 0.0, 0.0])]
//! ```
//!
//! The parent-side frame is `parent · Trans(origin) · Rot(rpy)`, the child-side frame
//! `child · Trans(child_origin) · Rot(child_rpy)`; the joint's axis is in the
//! parent-side frame. Revolute, prismatic, spherical and fixed loop joints.

use syn::Ident;

use crate::attr_values::{
    joint_kind, link_list, placement, placement_at, refuse_on_lie_tree, take_child, take_parent,
};
use crate::diag::Diagnostics;
use crate::model::{JointKind, Link, LoopJoint};
use crate::parse::RawAttr;

/// The keys a loop joint takes.
const KEYS: [&str; 6] = [
    "parent",
    "child",
    "origin",
    "rpy",
    "child_origin",
    "child_rpy",
];

/// Reads the loop joints against the tree's `links` (named by their bodies) and the
/// tree joints' names (a loop joint's name must differ from them).
pub fn read(
    raws: Vec<RawAttr>,
    links: &[Link],
    tree_joints: &[&Ident],
    names: &[String],
    diag: &mut Diagnostics,
) -> Vec<LoopJoint> {
    let mut out: Vec<LoopJoint> = Vec::new();
    let lie = |name: &Ident, joint: &str| {
        format!(
            "loop joints are not supported yet in scenes with spherical or free tree joints (joint `{joint}`); \
             build the tree from revolute and prismatic joints (a ball joint that closes the loop is fine: \
             `{name}: spherical`)"
        )
    };
    if refuse_on_lie_tree(&raws, links, lie, diag) {
        return out;
    }
    // Bodies by link index.
    let body = |name: &Ident| links.iter().position(|l| name == &l.name);
    let bodies = || link_list(links);
    for mut raw in raws {
        let Some(name) = raw.name.clone() else {
            continue;
        };
        let mut ok = true;
        if tree_joints.iter().any(|j| **j == name) || out.iter().any(|l| name == l.name) {
            diag.error_at(
                &name,
                format_args!(
                    "a joint named `{name}` is already declared; give each joint its own name"
                ),
            );
            ok = false;
        }
        let kind = match &raw.head {
            Some(h) => match joint_kind(h, diag) {
                Some(JointKind::Free) => {
                    diag.error_at(
                        h,
                        "a free loop joint would constrain nothing; drop it, or choose `revolute(<axis>)`, `prismatic(<axis>)`, `spherical` or `fixed`",
                    );
                    None
                }
                k => k,
            },
            None => {
                diag.error_at(
                    &name,
                    format_args!("loop joint `{name}` needs a kind: `{name}: revolute(z)`, `{name}: prismatic(x)`, `{name}: spherical` or `{name}: fixed`"),
                );
                None
            }
        };
        let body = |i: &Ident, role: &str, diag: &mut Diagnostics| match body(i) {
            Some(l) => Some(l),
            None => {
                diag.error_at(
                    i,
                    format_args!(
                        "no body named `{i}`; the {role} must be a declared body ({})",
                        bodies()
                    ),
                );
                None
            }
        };
        let parent = match take_parent(&mut raw, &name, "loop joint", diag) {
            Some(Some(p)) => body(&p, "parent", diag).map(Some),
            Some(None) => Some(None),
            None => None,
        };
        let child = take_child(&mut raw, &name, "loop joint", diag)
            .and_then(|c| body(&c, "child", diag).map(|l| (l, c)));
        let (origin, rpy) = placement(&mut raw, names, diag);
        let (child_origin, child_rpy) =
            placement_at(&mut raw, ["child_origin", "child_rpy"], names, diag);
        raw.reject_rest(&KEYS, diag);
        let (Some(kind), Some(parent), Some((child, child_name)), true) = (kind, parent, child, ok)
        else {
            continue;
        };
        if parent == Some(child) {
            diag.error_at(
                &child_name,
                "a loop joint cannot connect a body to itself; its parent and child must differ",
            );
            continue;
        }
        out.push(LoopJoint {
            name: name.to_string(),
            kind,
            parent,
            child,
            origin,
            rpy,
            child_origin,
            child_rpy,
        });
    }
    out
}
