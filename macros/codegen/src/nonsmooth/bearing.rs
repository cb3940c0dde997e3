//! `#[friction(joint, mu = …, radius = …, f_crit = …)]`: bearing friction, Coulomb
//! friction whose limit grows with the load the joint carries,
//! `f_crit + μ r |F_⊥|`, where `F_⊥` is the joint's reaction force (the force it
//! transmits to its child across the joint, less its component along the axis) and `r`
//! the journal's radius on a revolute joint (`1` on a prismatic one: a slider on a rail).
//! The reaction comes from the generated recursive Newton–Euler algorithm
//! (`mech::bearing`); it is the joint's load only where nothing outside the joint's
//! subtree pushes on a body inside it, which [`check_subtrees`] makes sure of.

use super::{check_f_crit, required};
use crate::diag::Diagnostics;
use crate::model::{
    Bearing, Contact, Element, ElementKind, JointKind, Law, Link, LoopJoint, PExpr, PointSpring,
};
use crate::parse::RawAttr;
use crate::parse::expr::lower;

/// The keys of the attribute.
const KEYS: [&str; 3] = ["mu", "radius", "f_crit"];

/// Reads bearing friction on `joint` (a revolute or prismatic joint of `link`): a
/// Coulomb element with the constant part of its limit, and its load coefficient.
pub(super) fn read(
    raw: &mut RawAttr,
    joint: &syn::Ident,
    link: Option<&Link>,
    names: &[String],
    diag: &mut Diagnostics,
) -> Option<(ElementKind, Option<Bearing>)> {
    if let Some((k, _)) = raw
        .args
        .iter()
        .find(|(k, _)| k == "f_static" || k == "f_kinetic")
    {
        diag.error_at(
            k,
            "bearing friction (`mu = …`) is Coulomb friction with one coefficient; static and kinetic forces (`f_static`, `f_kinetic`) do not combine with it",
        );
        return None;
    }
    let mu = required(raw, "mu", joint, names, diag);
    let radius = raw.take("radius", diag);
    let f_crit = raw.take("f_crit", diag);
    raw.reject_rest(&KEYS, diag);
    let (mu_expr, mu) = mu?;
    let mut ok = true;
    if let Some(v) = mu.as_const()
        && !(v >= 0.0 && v.is_finite())
    {
        diag.error_at(
            &mu_expr,
            format_args!("the bearing's friction coefficient `mu` must be ≥ 0, found {v}"),
        );
        ok = false;
    }
    let revolute = matches!(link.map(|l| l.kind), Some(JointKind::Revolute(_)));
    let coefficient = match (revolute, radius) {
        (true, None) => {
            diag.error_at(
                joint,
                format_args!(
                    "bearing friction on revolute joint `{joint}` needs the journal's `radius = …`: the friction torque is μ r |F_⊥|"
                ),
            );
            return None;
        }
        (true, Some((_, e))) => {
            let r = lower(&e, names, diag)?;
            if let Some(v) = r.as_const()
                && !(v > 0.0 && v.is_finite())
            {
                diag.error_at(
                    &e,
                    format_args!("the journal's `radius` must be > 0, found {v}"),
                );
                ok = false;
            }
            PExpr::Bin('*', Box::new(mu), Box::new(r))
        }
        (false, Some((k, _))) => {
            diag.error_at(
                &k,
                format_args!(
                    "`radius` belongs to bearing friction on a revolute joint; on prismatic joint `{joint}` the friction force is μ |F_⊥|: drop it"
                ),
            );
            return None;
        }
        (false, None) => mu,
    };
    let f_crit = match f_crit {
        Some((_, e)) => {
            let p = lower(&e, names, diag)?;
            check_f_crit(&e, &p, diag);
            p
        }
        None => PExpr::zero(),
    };
    ok.then_some((
        ElementKind::DashPot {
            law: Law::Coulomb,
            f_crit,
        },
        Some(Bearing {
            coefficient,
            span: joint.span(),
        }),
    ))
}

/// A bearing's load is the force its joint transmits only if every force on the bodies
/// of its subtree that comes from outside the subtree is gravity: no contact, loop joint
/// or point spring may join a body inside to one outside (or to the world).
pub(crate) fn check_subtrees(
    elements: &[Element],
    links: &[Link],
    loops: &[LoopJoint],
    point_springs: &[PointSpring],
    contacts: &[Contact],
    diag: &mut Diagnostics,
) {
    for el in elements {
        let Some(bearing) = &el.bearing else {
            continue;
        };
        let Some(top) = links
            .iter()
            .position(|l| l.coordinate == Some(el.coordinate))
        else {
            continue;
        };
        let inside = |body: Option<usize>| -> bool {
            let mut b = body;
            while let Some(i) = b {
                if i == top {
                    return true;
                }
                b = links[i].parent;
            }
            false
        };
        let crosses = |a: Option<usize>, b: Option<usize>| inside(a) != inside(b);
        let joint = &links[top].joint_name;
        let mut outside = |what: String| {
            diag.error_span(
                bearing.span,
                format_args!(
                    "bearing friction on `{joint}` takes its load from the force the joint transmits, but {what} pushes on the bodies it carries from outside them; put the friction on a joint whose subtree has no such force, or use `f_crit = …`"
                ),
            );
        };
        if let Some(c) = contacts.iter().find(|c| crosses(Some(c.body), c.plane)) {
            outside(format!("contact `{}`", c.name));
        } else if let Some(l) = loops.iter().find(|l| crosses(l.parent, Some(l.child))) {
            outside(format!("loop joint `{}`", l.name));
        } else if let Some(s) = point_springs.iter().find(|s| crosses(s.a.0, s.b.0)) {
            outside(format!("point spring `{}`", s.name));
        }
    }
}
