//! Values that several attribute families are read with: vectors, placements
//! (`origin`/`rpy`), joint kinds and axes, a joint's `parent` and `child`. Below
//! [`crate::validate`], [`crate::loops`], [`crate::point_springs`] and [`crate::contacts`],
//! which all use them; and the refusal of a family on trees with spherical or free joints.

use syn::{Expr, Ident};

use crate::diag::Diagnostics;
use crate::model::{JointKind, Link, PExpr, Vec3};
use crate::parse::expr::lower;
use crate::parse::{RawAttr, array, ident_of, strip};

pub(crate) fn vec3(e: &Expr, what: &str, names: &[String], diag: &mut Diagnostics) -> Option<Vec3> {
    let items = array(e, 3, what, diag)?;
    let v: Vec<Option<PExpr>> = items.into_iter().map(|x| lower(x, names, diag)).collect();
    let [a, b, c] = <[Option<PExpr>; 3]>::try_from(v).ok()?;
    Some([a?, b?, c?])
}

/// `origin = [x, y, z]` and `rpy = [r, p, y]` of a joint or frame (zero when absent).
pub(crate) fn placement(
    raw: &mut RawAttr,
    names: &[String],
    diag: &mut Diagnostics,
) -> (Vec3, Vec3) {
    placement_at(raw, ["origin", "rpy"], names, diag)
}

/// The translation and roll-pitch-yaw under the keys `[origin, rpy]` (zero where
/// absent).
pub(crate) fn placement_at(
    raw: &mut RawAttr,
    keys: [&str; 2],
    names: &[String],
    diag: &mut Diagnostics,
) -> (Vec3, Vec3) {
    let mut take = |key: &str| {
        raw.take(key, diag)
            .and_then(|(_, e)| vec3(&e, key, names, diag))
            .unwrap_or_else(zero3)
    };
    (take(keys[0]), take(keys[1]))
}

pub(crate) fn zero3() -> Vec3 {
    [PExpr::zero(), PExpr::zero(), PExpr::zero()]
}

/// `parent = world | <body>` of a joint (`what`: "joint", "loop joint"): `Some(None)`
/// for the world, `None` after an error.
pub(crate) fn take_parent(
    raw: &mut RawAttr,
    name: &Ident,
    what: &str,
    diag: &mut Diagnostics,
) -> Option<Option<Ident>> {
    match raw.take("parent", diag) {
        Some((_, e)) => match ident_of(&e) {
            Some(i) if i == "world" => Some(None),
            Some(i) => Some(Some(i.clone())),
            None => {
                diag.error_at(&e, "`parent` must be a body name or `world`");
                None
            }
        },
        None => {
            diag.error_at(
                name,
                format_args!(
                    "{what} `{name}` has no parent; add `parent = world` or `parent = <body>`"
                ),
            );
            None
        }
    }
}

/// `child = <body>` of a joint (`what`: "joint", "loop joint"), `None` after an error.
pub(crate) fn take_child(
    raw: &mut RawAttr,
    name: &Ident,
    what: &str,
    diag: &mut Diagnostics,
) -> Option<Ident> {
    match raw.take("child", diag) {
        Some((_, e)) => match ident_of(&e) {
            Some(i) if i == "world" => {
                diag.error_at(
                    &e,
                    "`world` cannot be a child; a joint's child is one of the bodies (the world goes on the parent side)",
                );
                None
            }
            Some(i) => Some(i.clone()),
            None => {
                diag.error_at(&e, "`child` must be a body name");
                None
            }
        },
        None => {
            diag.error_at(
                name,
                format_args!("{what} `{name}` has no child; add `child = <body>`"),
            );
            None
        }
    }
}

/// The links' names, for messages: "`a`, `b`, …".
pub(crate) fn link_list(links: &[Link]) -> String {
    links
        .iter()
        .map(|l| format!("`{}`", l.name))
        .collect::<Vec<_>>()
        .join(", ")
}

pub(crate) fn joint_kind(h: &Expr, diag: &mut Diagnostics) -> Option<JointKind> {
    const KINDS: &str = "`revolute(<axis>)`, `prismatic(<axis>)`, `spherical`, `free` or `fixed`";
    match ident_of(h).map(|i| i.to_string()).as_deref() {
        Some("fixed") => return Some(JointKind::Fixed),
        Some("spherical") => return Some(JointKind::Spherical),
        Some("free") => return Some(JointKind::Free),
        _ => {}
    }
    if let Expr::Call(c) = strip(h)
        && let Some(name) = ident_of(&c.func).map(|i| i.to_string())
        && matches!(name.as_str(), "spherical" | "free" | "fixed")
    {
        let (what, kind) = match name.as_str() {
            "spherical" => ("a ball joint turns about every axis", JointKind::Spherical),
            "free" => (
                "a free joint moves along and about every axis",
                JointKind::Free,
            ),
            _ => ("a fixed joint does not move", JointKind::Fixed),
        };
        diag.error_at(
            &c.args,
            format_args!("`{name}` takes no axis: {what}; write `<joint>: {name}`"),
        );
        // Recover with the kind, so the tree is still checked without follow-on errors.
        return Some(kind);
    }
    let Expr::Call(c) = strip(h) else {
        diag.error_at(h, format_args!("unknown joint kind; expected {KINDS}"));
        return None;
    };
    let name = ident_of(&c.func).map(|i| i.to_string()).unwrap_or_default();
    if name != "revolute" && name != "prismatic" {
        diag.error_at(
            &c.func,
            format_args!("unknown joint kind `{name}`; expected {KINDS}"),
        );
        return None;
    }
    if c.args.len() != 1 {
        diag.error_at(
            h,
            format_args!("`{name}` takes one axis, e.g. `{name}(z)` or `{name}([0.0, 0.0, 1.0])`"),
        );
        return None;
    }
    let axis = axis(&c.args[0], diag)?;
    Some(if name == "revolute" {
        JointKind::Revolute(axis)
    } else {
        JointKind::Prismatic(axis)
    })
}

/// An axis is `x`, `y`, `z` (optionally negated) or three numeric literals, normalised
/// here; it must be known at expansion so the kernels fold its zeros away.
pub(crate) fn axis(e: &Expr, diag: &mut Diagnostics) -> Option<[f64; 3]> {
    const HELP: &str =
        "an axis is `x`, `y`, `z`, `-z`, … or three numbers `[0.0, 0.6, 0.8]`, not all zero";
    let (neg, inner) = match strip(e) {
        Expr::Unary(u) if matches!(u.op, syn::UnOp::Neg(_)) => (-1.0, &*u.expr),
        _ => (1.0, e),
    };
    if let Some(i) = ident_of(inner) {
        let a = match i.to_string().as_str() {
            "x" => [1.0, 0.0, 0.0],
            "y" => [0.0, 1.0, 0.0],
            "z" => [0.0, 0.0, 1.0],
            _ => {
                diag.error_at(e, format_args!("unknown axis `{i}`; {HELP}"));
                return None;
            }
        };
        return Some(a.map(|c| c * neg));
    }
    let items = array(e, 3, "an axis", diag)?;
    let v: Vec<f64> = items
        .iter()
        .map(|x| lower(x, &[], &mut Diagnostics::new()).and_then(|p| p.as_const()))
        .collect::<Option<_>>()
        .or_else(|| {
            diag.error_at(e, format_args!("axis entries must be numbers; {HELP}"));
            None
        })?;
    let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    if !(n > 0.0 && n.is_finite()) {
        diag.error_at(e, format_args!("this axis has zero length; {HELP}"));
        return None;
    }
    Some([v[0] / n, v[1] / n, v[2] / n])
}

/// Refuses every attribute of `raws`, a family not supported yet on trees with
/// spherical or free joints, when `links` has one: one error per attribute at its name,
/// `message(name, joint)` naming the first such joint. Returns whether it refused.
pub(crate) fn refuse_on_lie_tree(
    raws: &[RawAttr],
    links: &[Link],
    message: impl Fn(&Ident, &str) -> String,
    diag: &mut Diagnostics,
) -> bool {
    let Some(l) = links.iter().find(|l| l.kind.is_lie()) else {
        return false;
    };
    for name in raws.iter().filter_map(|r| r.name.as_ref()) {
        diag.error_at(name, message(name, &l.joint_name.to_string()));
    }
    !raws.is_empty()
}
