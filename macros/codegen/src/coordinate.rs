//! Which joint coordinate an element (spring, damper, friction, stop) names: shared by
//! the validation of springs and dampers and the reading of non-smooth elements.

use syn::Ident;

use crate::diag::Diagnostics;
use crate::model::{JointKind, Link};

/// The coordinate of the joint an element names: the joint must exist and move (a
/// fixed joint has no coordinate to act on). `what` names the elements in messages.
pub(crate) fn coordinate_of(
    joint: &Ident,
    links: &[Link],
    what: &str,
    diag: &mut Diagnostics,
) -> Option<usize> {
    // The joint was declared with an error (or twice), and that is reported already.
    if diag.is_excused(joint) {
        return None;
    }
    match links.iter().rev().find(|l| *joint == l.joint_name) {
        Some(l) if l.kind.is_lie() => {
            diag.error_at(
                joint,
                format_args!(
                    "joint `{joint}` is {}: {what} act on the one coordinate of a revolute or prismatic joint",
                    if links.iter().any(|m| m.kind == JointKind::Translation && *joint == m.joint_name) { "free" } else { "spherical" }
                ),
            );
            None
        }
        Some(Link {
            coordinate: Some(c),
            ..
        }) => Some(*c),
        Some(_) => {
            diag.error_at(
                joint,
                format_args!("joint `{joint}` is fixed and has no coordinate for {what} to act on"),
            );
            None
        }
        None => {
            diag.error_at(
                joint,
                format_args!(
                    "no joint named `{joint}`; {what} act on a joint's coordinate: one of {}",
                    moving_joints(links)
                ),
            );
            None
        }
    }
}

/// The joints that have a coordinate, as a list for messages: `` `a`, `b` ``.
pub(crate) fn moving_joints(links: &[Link]) -> String {
    let known: Vec<String> = links
        .iter()
        .filter(|l| l.coordinate.is_some())
        .map(|l| format!("`{}`", l.joint_name))
        .collect();
    known.join(", ")
}
