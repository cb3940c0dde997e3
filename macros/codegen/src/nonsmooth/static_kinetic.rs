//! `#[friction(joint, f_static = …, f_kinetic = …)]`: static and kinetic friction. At
//! rest the joint holds any force up to `f_static`; slipping it resists with
//! `f_kinetic ≤ f_static` (the runtime's `nonsmooth/kind/static_kinetic.rs` says what the
//! law does). Read here into a dash-pot whose dead zone is `f_static` and whose law is
//! [`Law::StaticKinetic`].

use syn::Expr;

use super::required;
use crate::diag::Diagnostics;
use crate::model::{ElementKind, Law, PExpr};
use crate::parse::RawAttr;

/// The keys of the attribute.
const KEYS: [&str; 2] = ["f_static", "f_kinetic"];

pub(super) fn read(
    raw: &mut RawAttr,
    joint: &syn::Ident,
    names: &[String],
    diag: &mut Diagnostics,
) -> Option<ElementKind> {
    if let Some((k, _)) = raw.take("f_crit", diag) {
        diag.error_at(
            &k,
            "give either `f_crit = …` (Coulomb friction) or `f_static = …, f_kinetic = …` (static and kinetic friction), not both",
        );
        raw.take("f_static", diag);
        raw.take("f_kinetic", diag);
        return None;
    }
    let f_static = required(raw, "f_static", joint, names, diag);
    let f_kinetic = required(raw, "f_kinetic", joint, names, diag);
    raw.reject_rest(&KEYS, diag);
    let ((es, f_static), (ek, f_kinetic)) = (f_static?, f_kinetic?);
    let static_ok = non_negative(&es, &f_static, "f_static", diag);
    let kinetic_ok = non_negative(&ek, &f_kinetic, "f_kinetic", diag);
    if static_ok
        && kinetic_ok
        && let (Some(s), Some(k)) = (f_static.as_const(), f_kinetic.as_const())
        && k > s
    {
        diag.error_at(
            &ek,
            format_args!(
                "kinetic friction f_kinetic = {k} exceeds static friction f_static = {s}; the force held at rest is at least the force while slipping (equal forces are Coulomb friction, `f_crit = …`)"
            ),
        );
        return None;
    }
    (static_ok && kinetic_ok).then_some(ElementKind::DashPot {
        law: Law::StaticKinetic { f_kinetic },
        f_crit: f_static,
    })
}

/// A literal friction force must be finite and `≥ 0`.
fn non_negative(e: &Expr, p: &PExpr, key: &str, diag: &mut Diagnostics) -> bool {
    match p.as_const() {
        Some(v) if !(v >= 0.0 && v.is_finite()) => {
            diag.error_at(
                e,
                format_args!("`{key}` is a friction force and must be finite and ≥ 0, found {v}"),
            );
            false
        }
        _ => true,
    }
}
