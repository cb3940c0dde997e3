//! `#[spring(name: between(a, b), k = …, rest = …, from = […], to = […])]`: a linear
//! spring between a point of body `a` (or the world) and a point of body `b`, such as
//! the spring of Andrews' squeezer from a fixed point to a lever. Its potential
//! `½ k (ℓ − rest)²` in their distance `ℓ` joins the potential energy, and its
//! generalised forces `−∂U/∂q` the passive forces ([`crate::mech`]). The points are
//! given in the bodies' frames (`from` on `a`, `to` on `b`; each the frame's origin when
//! left out).

use syn::{Expr, Ident};

use crate::attr_values::{link_list, vec3};
use crate::diag::Diagnostics;
use crate::model::{Link, PExpr, PointSpring, Vec3};
use crate::parse::expr::lower;
use crate::parse::{RawAttr, ident_of, strip};

const KEYS: [&str; 4] = ["k", "rest", "from", "to"];

pub fn read(
    raws: Vec<RawAttr>,
    links: &[Link],
    names: &[String],
    diag: &mut Diagnostics,
) -> Vec<PointSpring> {
    let mut out = Vec::new();
    let bodies = || link_list(links);
    for mut raw in raws {
        let Some(name) = raw.name.clone() else {
            continue;
        };
        let Some(head) = raw.head.clone() else {
            continue;
        };
        let ends = between(&head, &name, diag).map(|[a, b]| {
            let end = |i: &Ident, diag: &mut Diagnostics| -> Option<Option<usize>> {
                if i == "world" {
                    return Some(None);
                }
                match links.iter().position(|l| i == &l.name) {
                    Some(l) => Some(Some(l)),
                    None => {
                        diag.error_at(
                            i,
                            format_args!("no body named `{i}`; a spring's end is `world` or a body ({})", bodies()),
                        );
                        None
                    }
                }
            };
            let (ea, eb) = (end(&a, diag), end(&b, diag));
            if ea.is_some() && ea == eb {
                diag.error_at(
                    &b,
                    "both ends of the spring are on the same body, so it never stretches; connect two different bodies (or a body and `world`)",
                );
                return None;
            }
            Some((ea?, eb?))
        });
        let mut value = |key: &str, raw: &mut RawAttr, required: bool| -> Option<PExpr> {
            match raw.take(key, diag) {
                Some((_, e)) => lower(&e, names, diag),
                None if required => {
                    diag.error_at(
                        &name,
                        format_args!("missing `{key} = <expression>` (the spring's stiffness)"),
                    );
                    None
                }
                None => Some(PExpr::zero()),
            }
        };
        let k = value("k", &mut raw, true);
        let rest = value("rest", &mut raw, false);
        let mut point = |key: &str, raw: &mut RawAttr| -> Option<Vec3> {
            match raw.take(key, diag) {
                Some((_, e)) => vec3(&e, key, names, diag),
                None => Some([PExpr::zero(), PExpr::zero(), PExpr::zero()]),
            }
        };
        let (from, to) = (point("from", &mut raw), point("to", &mut raw));
        raw.reject_rest(&KEYS, diag);
        if let (Some(Some((a, b))), Some(k), Some(rest), Some(from), Some(to)) =
            (ends, k, rest, from, to)
        {
            out.push(PointSpring {
                name: name.to_string(),
                a: (a, from),
                b: (b, to),
                k,
                rest,
            });
        }
    }
    out
}

/// The two ends of `between(a, b)`.
fn between(head: &Expr, name: &Ident, diag: &mut Diagnostics) -> Option<[Ident; 2]> {
    let help = format!(
        "a spring between two points is `#[spring({name}: between(<body or world>, <body>), k = …, rest = …)]`; \
         a spring on a joint is `#[spring(<joint>, k = …, rest = …)]`"
    );
    let Expr::Call(c) = strip(head) else {
        diag.error_at(head, help);
        return None;
    };
    if !ident_of(&c.func).is_some_and(|f| f == "between") || c.args.len() != 2 {
        diag.error_at(head, help);
        return None;
    }
    let a = ident_of(&c.args[0]).cloned();
    let b = ident_of(&c.args[1]).cloned();
    match (a, b) {
        (Some(a), Some(b)) => Some([a, b]),
        _ => {
            diag.error_at(&c.args, help);
            None
        }
    }
}
