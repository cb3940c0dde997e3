//! `#[contact(…)]`: a point or sphere on a body touching a plane, fixed in the world or
//! carried by another body (theory §8).
//!
//! ```text
//! #[contact(left_foot: sphere(r), body = shin, at = [0.0, -l, 0.0],
//!           plane = world, normal = y, mu = mu, restitution = e)]
//! #[contact(corner: point, body = block, at = [a, -b, 0.0],
//!           plane = world, rpy = [0.0, 0.0, phi], normal = y, mu = 0.5)]
//! ```
//!
//! The plane's frame is `plane · Trans(origin) · Rot(rpy)` (`plane = world` by default);
//! `normal` is the plane's normal in that frame, a coordinate axis (`x`, `-y`, …), and
//! the other two axes of the frame are its tangent directions. The sphere's centre (the
//! point, for `point`) is `at` in the body's frame. `mu` (Coulomb friction coefficient,
//! default 0: frictionless; the kinetic one where `mu_static` is given), `mu_static`
//! (the static coefficient, at least `mu`; default `mu`) and `restitution` (Newton's
//! coefficient `e`, default 0) are expressions in the fields like any parameter.

use syn::{Expr, Ident};

use crate::attr_values::{axis, link_list, placement, refuse_on_lie_tree, vec3, zero3};
use crate::diag::Diagnostics;
use crate::model::{Contact, Link, PExpr};
use crate::parse::expr::lower;
use crate::parse::{RawAttr, ident_of, strip};

/// The keys a contact takes.
const KEYS: [&str; 9] = [
    "body",
    "at",
    "plane",
    "origin",
    "rpy",
    "normal",
    "mu",
    "mu_static",
    "restitution",
];

/// Reads the contacts against the tree's `links`; their names must differ from the
/// joints', loop joints' and elements' (`taken`).
pub fn read(
    raws: Vec<RawAttr>,
    links: &[Link],
    taken: &[String],
    names: &[String],
    diag: &mut Diagnostics,
) -> Vec<Contact> {
    let mut out: Vec<Contact> = Vec::new();
    let lie = |_: &Ident, joint: &str| {
        format!(
            "contacts are not supported yet in scenes with spherical or free joints (joint `{joint}`); \
             build the tree from revolute and prismatic joints (a planar body free in the plane is \
             `x: prismatic(x)`, `y: prismatic(y)`, `angle: revolute(z)`)"
        )
    };
    if refuse_on_lie_tree(&raws, links, lie, diag) {
        return out;
    }
    let body_of = |i: &Ident| links.iter().position(|l| i == &l.name);
    for mut raw in raws {
        let Some(name) = raw.name.clone() else {
            continue;
        };
        let mut ok = true;
        if taken.iter().any(|t| name == t) || out.iter().any(|c| name == c.name) {
            diag.error_at(
                &name,
                format_args!(
                    "`{name}` already names a joint, an element or a contact; give each contact its own name"
                ),
            );
            ok = false;
        }
        let radius = match &raw.head {
            Some(h) => shape(h, &name, names, diag),
            None => {
                diag.error_at(
                    &name,
                    format_args!(
                        "contact `{name}` needs a shape: `{name}: point` or `{name}: sphere(<radius>)`"
                    ),
                );
                None
            }
        };
        let body = match raw.take("body", diag) {
            Some((_, e)) => match ident_of(&e) {
                Some(i) if i == "world" => {
                    diag.error_at(
                        &e,
                        "the contact's point must be on a body that moves; `world` carries planes (`plane = world`)",
                    );
                    None
                }
                Some(i) => body_of(i).or_else(|| {
                    diag.error_at(
                        i,
                        format_args!(
                            "no body named `{i}`; a contact's point is on a declared body ({})",
                            link_list(links)
                        ),
                    );
                    None
                }),
                None => {
                    diag.error_at(
                        &e,
                        "`body` is the name of the body that carries the point or sphere",
                    );
                    None
                }
            },
            None => {
                diag.error_at(
                    &name,
                    format_args!("contact `{name}` needs `body = <body>`, the body that carries the point or sphere"),
                );
                None
            }
        };
        let at = match raw.take("at", diag) {
            Some((_, e)) => vec3(&e, "at", names, diag),
            None => Some(zero3()),
        };
        let plane = match raw.take("plane", diag) {
            Some((_, e)) => {
                match ident_of(&e) {
                    Some(i) if i == "world" => Some(None),
                    Some(i) => match body_of(i) {
                        Some(l) if Some(l) == body => {
                            diag.error_at(
                            i,
                            "a body cannot touch a plane it carries itself; the plane is `world` or another body",
                        );
                            None
                        }
                        Some(l) => Some(Some(l)),
                        None => {
                            diag.error_at(
                            i,
                            format_args!("no body named `{i}`; a plane is `world` or a declared body ({})", link_list(links)),
                        );
                            None
                        }
                    },
                    None => {
                        diag.error_at(
                            &e,
                            "`plane` is `world` or the name of the body that carries the plane",
                        );
                        None
                    }
                }
            }
            None => Some(None),
        };
        let (origin, rpy) = placement(&mut raw, names, diag);
        let normal = match raw.take("normal", diag) {
            Some((_, e)) => normal(&e, diag),
            None => {
                diag.error_at(
                    &name,
                    format_args!(
                        "contact `{name}` needs the plane's normal in its frame: `normal = y` (or `x`, `z`, `-y`, …)"
                    ),
                );
                None
            }
        };
        let mut coefficient = |key: &str, what: &str, upper: Option<f64>, raw: &mut RawAttr| {
            let Some((k, e)) = raw.take(key, diag) else {
                return Some(PExpr::zero());
            };
            let value = lower(&e, names, diag)?;
            if let Some(c) = value.as_const() {
                let bad = !(c >= 0.0) || upper.is_some_and(|u| c > u) || !c.is_finite();
                if bad {
                    let range = match upper {
                        Some(u) => format!("between 0 and {u}"),
                        None => "0 or more".to_string(),
                    };
                    diag.error_at(&e, format_args!("{what} `{k}` is {c}; it must be {range}"));
                    return None;
                }
            }
            Some(value)
        };
        let mu = coefficient("mu", "the friction coefficient", None, &mut raw);
        let static_key = raw.args.iter().any(|(k, _)| k == "mu_static");
        let mu_static = if static_key {
            coefficient(
                "mu_static",
                "the static friction coefficient",
                None,
                &mut raw,
            )
        } else {
            Some(PExpr::zero())
        };
        let restitution = coefficient(
            "restitution",
            "the coefficient of restitution",
            Some(1.0),
            &mut raw,
        );
        // The static coefficient holds at least what the kinetic one does.
        let mu_static = match (static_key, &mu, mu_static) {
            (false, _, Some(_)) => Some(None),
            (true, Some(m), Some(ms)) => match (m.as_const(), ms.as_const()) {
                (Some(k), Some(st)) if st < k => {
                    diag.error_at(
                        &name,
                        format_args!(
                            "contact `{name}`: `mu_static` = {st} is below `mu` = {k}; the static \
                             friction coefficient must be at least the kinetic one (`mu`)"
                        ),
                    );
                    None
                }
                _ => Some(Some(ms)),
            },
            _ => None,
        };
        raw.reject_rest(&KEYS, diag);
        if let (
            true,
            Some(radius),
            Some(body),
            Some(at),
            Some(plane),
            Some(normal),
            Some(mu),
            Some(mu_static),
            Some(restitution),
        ) = (
            ok,
            radius,
            body,
            at,
            plane,
            normal,
            mu,
            mu_static,
            restitution,
        ) {
            out.push(Contact {
                name: name.to_string(),
                body,
                at,
                radius,
                plane,
                origin,
                rpy,
                normal,
                mu,
                mu_static,
                restitution,
            });
        }
    }
    out
}

/// `point` (radius 0) or `sphere(<radius>)`.
fn shape(head: &Expr, name: &Ident, names: &[String], diag: &mut Diagnostics) -> Option<PExpr> {
    let help = format!("a contact's shape is `{name}: point` or `{name}: sphere(<radius>)`");
    if ident_of(head).is_some_and(|i| i == "point") {
        return Some(PExpr::zero());
    }
    let Expr::Call(c) = strip(head) else {
        diag.error_at(head, help);
        return None;
    };
    if !ident_of(&c.func).is_some_and(|f| f == "sphere") || c.args.len() != 1 {
        diag.error_at(head, help);
        return None;
    }
    let r = lower(&c.args[0], names, diag)?;
    if let Some(v) = r.as_const()
        && !(v >= 0.0 && v.is_finite())
    {
        diag.error_at(
            &c.args[0],
            format_args!("the sphere's radius is {v}; it must be 0 or more"),
        );
        return None;
    }
    Some(r)
}

/// A coordinate axis of the plane's frame, with its sign.
fn normal(e: &Expr, diag: &mut Diagnostics) -> Option<[f64; 3]> {
    let a = axis(e, diag)?;
    if a.iter().filter(|c| **c != 0.0).count() != 1 {
        diag.error_at(
            e,
            "the normal is one axis of the plane's frame (`x`, `y`, `z`, `-y`, …); turn the frame with `rpy = […]` for an incline",
        );
        return None;
    }
    Some(a)
}
