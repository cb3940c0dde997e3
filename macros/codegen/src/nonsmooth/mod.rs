//! Non-smooth elements (`#[friction]`, `#[bingham]`, `#[stop]`) → validated
//! [`Element`]s, one `check_*` per rule; and their lowering for emission.
//!
//! ```text
//! #[friction(joint, f_crit = …)]                                 Coulomb
//! #[friction(joint, f_static = …, f_kinetic = …)]                static/kinetic
//! #[friction(joint, mu = …, radius = …, f_crit = …)]             bearing (limit from the load)
//! #[bingham(joint, f_crit = …, eta = …)]                         linear Bingham
//! #[bingham(joint, f_crit = …, law = <φ in f>)]                  monotone user law v = φ(f)
//! #[bingham(joint, f_crit = …, law = …, select = no_jumps | max_dissipation)]  non-monotone
//! #[stop(joint, max = L | min = L, restitution = e)]            rigid stop
//! #[stop(joint, max = L | min = L, k_support = k)]              spring-backed stop
//! #[stop(joint, min = L1, max = L2, restitution = e | k_support = k)]  both limits
//! ```
//!
//! A joint may have one stop per side, from one attribute with `min` and `max` or from
//! two (each with its own restitution or support). A joint with one stop names it
//! `stop_<joint>`; with two, `stop_<joint>_min` and `stop_<joint>_max`.

pub(crate) mod bearing;
mod static_kinetic;

use syn::Expr;

use crate::diag::Diagnostics;
use crate::model::{Bearing, Element, ElementKind, Law, Link, PExpr, Selection, StopKind};
use crate::parse::{Family, RawAttr, expr::lower, ident_of};

/// The name of the law variable in `law = …` expressions.
const LAW_VAR: &str = "f";

pub fn read(
    raws: Vec<RawAttr>,
    links: &[Link],
    names: &[String],
    diag: &mut Diagnostics,
) -> Vec<Element> {
    let mut out: Vec<Element> = Vec::new();
    let mut reported: Vec<String> = Vec::new();
    for mut raw in raws {
        let Some(joint) = raw.name.clone() else {
            continue;
        };
        let coordinate =
            crate::coordinate::coordinate_of(&joint, links, "non-smooth elements", diag);
        let link = links.iter().rev().find(|l| joint == l.joint_name);
        let unloaded = |k: Vec<ElementKind>| k.into_iter().map(|k| (k, None)).collect();
        let (family, kinds): (_, Vec<(ElementKind, Option<Bearing>)>) = match raw.family {
            Family::Friction if raw.args.iter().any(|(k, _)| k == "mu") => (
                "friction",
                bearing::read(&mut raw, &joint, link, names, diag)
                    .into_iter()
                    .collect(),
            ),
            Family::Friction => (
                "friction",
                unloaded(
                    read_friction(&mut raw, &joint, names, diag)
                        .into_iter()
                        .collect(),
                ),
            ),
            Family::Bingham => (
                "bingham",
                unloaded(
                    read_bingham(&mut raw, &joint, names, diag)
                        .into_iter()
                        .collect(),
                ),
            ),
            _ => ("stop", unloaded(read_stop(&mut raw, &joint, names, diag))),
        };
        for (kind, bearing) in kinds {
            let side = match &kind {
                ElementKind::Stop { upper: true, .. } => "_max",
                ElementKind::Stop { upper: false, .. } => "_min",
                _ => "",
            };
            // Provisional: stops carry their side until the joint's stops are counted.
            let name = format!("{family}_{joint}{side}");
            if out.iter().any(|e| e.name == name) {
                // One message per duplicated element, however many copies follow.
                if reported.contains(&name) {
                    continue;
                }
                reported.push(name.clone());
                let what = match side {
                    "_max" => "an upper (`max`) stop".to_string(),
                    "_min" => "a lower (`min`) stop".to_string(),
                    _ => format!("a `{family}` element"),
                };
                diag.error_at(
                    &joint,
                    format_args!("joint `{joint}` already has {what}; one per joint and kind (stops: one per side)"),
                );
                continue;
            }
            if let Some(coordinate) = coordinate {
                let element = Element {
                    name,
                    coordinate,
                    kind,
                    bearing,
                };
                check_stop_order(&out, &element, &joint, diag);
                out.push(element);
            }
        }
    }
    // A joint with one stop names it `stop_<joint>`.
    let stops_on = |c: usize, out: &[Element]| {
        out.iter()
            .filter(|e| e.coordinate == c && matches!(e.kind, ElementKind::Stop { .. }))
            .count()
    };
    for i in 0..out.len() {
        if matches!(out[i].kind, ElementKind::Stop { .. }) && stops_on(out[i].coordinate, &out) == 1
        {
            let name = &out[i].name;
            out[i].name = name[..name.len() - 4].to_string();
        }
    }
    out
}

/// Two stops on one joint must leave room between them: `min < max` when both are
/// constants (a field-valued pair is checked by `validate()` at run time).
fn check_stop_order(
    elements: &[Element],
    new: &Element,
    joint: &syn::Ident,
    diag: &mut Diagnostics,
) {
    let ElementKind::Stop {
        upper, position, ..
    } = &new.kind
    else {
        return;
    };
    for other in elements.iter().filter(|e| e.coordinate == new.coordinate) {
        if let ElementKind::Stop {
            upper: other_upper,
            position: other_position,
            ..
        } = &other.kind
            && other_upper != upper
        {
            let (min, max) = if *upper {
                (other_position, position)
            } else {
                (position, other_position)
            };
            if let (Some(a), Some(b)) = (min.as_const(), max.as_const())
                && a >= b
            {
                diag.error_at(
                    joint,
                    format_args!(
                        "the stops on `{joint}` leave no room: min = {a} must be below max = {b}"
                    ),
                );
            }
        }
    }
}

pub(crate) fn required(
    raw: &mut RawAttr,
    key: &str,
    joint: &syn::Ident,
    names: &[String],
    diag: &mut Diagnostics,
) -> Option<(Expr, PExpr)> {
    match raw.take(key, diag) {
        Some((_, e)) => lower(&e, names, diag).map(|p| (e, p)),
        None => {
            diag.error_at(joint, format_args!("missing `{key} = <expression>`"));
            None
        }
    }
}

/// A literal critical force must be non-negative: it is the half-width of the dead zone.
pub(crate) fn check_f_crit(e: &Expr, p: &PExpr, diag: &mut Diagnostics) {
    if let Some(v) = p.as_const()
        && !(v >= 0.0 && v.is_finite())
    {
        diag.error_at(
            e,
            format_args!("`f_crit` is the half-width of the dead zone and must be ≥ 0, found {v}"),
        );
    }
}

fn read_friction(
    raw: &mut RawAttr,
    joint: &syn::Ident,
    names: &[String],
    diag: &mut Diagnostics,
) -> Option<ElementKind> {
    if raw
        .args
        .iter()
        .any(|(k, _)| k == "f_static" || k == "f_kinetic")
    {
        return static_kinetic::read(raw, joint, names, diag);
    }
    let f_crit = required(raw, "f_crit", joint, names, diag);
    raw.reject_rest(&["f_crit", "f_static", "f_kinetic"], diag);
    let (e, f_crit) = f_crit?;
    check_f_crit(&e, &f_crit, diag);
    Some(ElementKind::DashPot {
        law: Law::Coulomb,
        f_crit,
    })
}

fn read_bingham(
    raw: &mut RawAttr,
    joint: &syn::Ident,
    names: &[String],
    diag: &mut Diagnostics,
) -> Option<ElementKind> {
    let f_crit = required(raw, "f_crit", joint, names, diag);
    let eta = raw.take("eta", diag);
    let law = raw.take("law", diag);
    let select = raw.take("select", diag);
    raw.reject_rest(&["f_crit", "eta", "law", "select"], diag);
    let (fe, f_crit) = f_crit?;
    check_f_crit(&fe, &f_crit, diag);
    let mut select_ok = true;
    let selection = match &select {
        None => None,
        Some((_, e)) => match ident_of(e).map(|i| i.to_string()).as_deref() {
            Some("no_jumps") => Some(Selection::NoVelocityJumps),
            Some("max_dissipation") => Some(Selection::MaximalDissipation),
            _ => {
                diag.error_at(e, "`select` is `no_jumps` (approach 1: stay on the branch) or `max_dissipation` (approach 2: outer branch)");
                select_ok = false;
                None
            }
        },
    };
    let law = match (eta, law) {
        (Some((_, e)), None) => {
            if let Some((k, _)) = &select {
                diag.error_at(k, "`select` applies to a non-monotone `law = …`; a linear Bingham law is monotone");
            }
            Law::BinghamLinear {
                eta: lower(&e, names, diag)?,
            }
        }
        (None, Some((_, e))) => {
            let phi = lower_law(&e, names, diag)?;
            Law::User { phi, selection }
        }
        (Some((k, _)), Some(_)) => {
            diag.error_at(
                k,
                "give either `eta = …` (linear Bingham) or `law = …` (v = φ(f)), not both",
            );
            return None;
        }
        (None, None) => {
            diag.error_at(joint, "a Bingham dash-pot needs `eta = <viscosity>` or `law = <velocity as a function of the force f>`; for Coulomb friction use `#[friction(joint, f_crit = …)]`");
            return None;
        }
    };
    select_ok.then_some(ElementKind::DashPot { law, f_crit })
}

/// `law = …` is an expression in the force `f` (and the fields).
fn lower_law(e: &Expr, names: &[String], diag: &mut Diagnostics) -> Option<PExpr> {
    crate::parse::expr::lower_with_var(e, names, LAW_VAR, diag)
}

/// One stop, or two (`min` and `max` in one attribute) sharing the kind.
fn read_stop(
    raw: &mut RawAttr,
    joint: &syn::Ident,
    names: &[String],
    diag: &mut Diagnostics,
) -> Vec<ElementKind> {
    let max = raw.take("max", diag);
    let min = raw.take("min", diag);
    let restitution = raw.take("restitution", diag);
    let k_support = raw.take("k_support", diag);
    raw.reject_rest(&["max", "min", "restitution", "k_support"], diag);
    let sides: Vec<(bool, Expr)> = [(true, max), (false, min)]
        .into_iter()
        .filter_map(|(upper, e)| e.map(|(_, e)| (upper, e)))
        .collect();
    if sides.is_empty() {
        diag.error_at(
            joint,
            "a stop needs `max = L` (the coordinate stays ≤ L), `min = L` (≥ L), or both",
        );
        return Vec::new();
    }
    let Some(kind) = read_stop_kind(restitution, k_support, joint, names, diag) else {
        return Vec::new();
    };
    sides
        .into_iter()
        .filter_map(|(upper, pos)| {
            Some(ElementKind::Stop {
                upper,
                position: lower(&pos, names, diag)?,
                kind: kind.clone(),
            })
        })
        .collect()
}

/// `restitution = e` (rigid) or `k_support = k` (spring-backed).
fn read_stop_kind(
    restitution: Option<(syn::Ident, Expr)>,
    k_support: Option<(syn::Ident, Expr)>,
    joint: &syn::Ident,
    names: &[String],
    diag: &mut Diagnostics,
) -> Option<StopKind> {
    let kind = match (restitution, k_support) {
        (Some((_, e)), None) => {
            let r = lower(&e, names, diag)?;
            if let Some(v) = r.as_const()
                && !(0.0..=1.0).contains(&v)
            {
                diag.error_at(
                    &e,
                    format_args!(
                        "a restitution coefficient lies in [0, 1] (0 plastic, 1 elastic), found {v}"
                    ),
                );
            }
            StopKind::Rigid { restitution: r }
        }
        (None, Some((_, e))) => {
            let k = lower(&e, names, diag)?;
            if let Some(v) = k.as_const()
                && !(v > 0.0 && v.is_finite())
            {
                diag.error_at(
                    &e,
                    format_args!("`k_support` is a stiffness and must be positive, found {v}"),
                );
            }
            StopKind::SpringBacked { stiffness: k }
        }
        (Some((k, _)), Some(_)) => {
            diag.error_at(k, "give either `restitution = e` (rigid stop) or `k_support = k` (spring-backed stop), not both");
            return None;
        }
        (None, None) => {
            diag.error_at(joint, "a stop needs `restitution = e` (rigid, Newton's impact law) or `k_support = k` (massless support on a spring)");
            return None;
        }
    };
    Some(kind)
}
