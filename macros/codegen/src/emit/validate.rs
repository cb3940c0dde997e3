//! `Mechanism::validate()`: the run-time twin of the compile-time checks, for
//! parameters that are fields (values unknown at expansion). Each violated condition is
//! reported with the parameter's role and the expression that gave it.

use proc_macro2::TokenStream;
use quote::quote;

use super::describe::expr;
use crate::model::{ElementKind, JointKind, Law, Model, PExpr, StopKind};

pub fn validate_fn(model: &Model) -> TokenStream {
    let p = &model.params;
    let ck = quote!(::filippov::runtime::system::check);
    let mut checks = Vec::new();
    // Checks between two expressions, pushed after the single-value ones.
    let mut kinetic_checks = Vec::new();
    // One run-time check of an expression; none when it is a constant that passes
    // (constants are checked at expansion, a check that cannot fail is dead code).
    let mut scalar = |what: String, e: &PExpr, check: Check| {
        if e.as_const().is_some_and(|c| check.passes(c)) {
            return;
        }
        let f = check.function();
        let value = expr(e, p);
        let what = format!("{what} (`{}`)", e.display(p));
        checks.push(quote! {
            if let Some(why) = #ck::#f(#value) { problems.push((#what.to_string(), why)); }
        });
    };
    for field in p {
        let name = format!("field `{field}`");
        scalar(
            name,
            &PExpr::Param(p.iter().position(|f| f == field).unwrap_or(0) as u16),
            Check::Finite,
        );
    }
    for l in &model.links {
        // Translation links (first halves of free joints) and massless intermediate
        // frames (allowed at expansion only when they carry other bodies) have no
        // mass to check.
        if l.kind == JointKind::Translation || l.mass.as_const() == Some(0.0) {
            continue;
        }
        scalar(
            format!("mass of body `{}`", l.name),
            &l.mass,
            Check::Positive,
        );
        for (k, c) in l.com.iter().enumerate() {
            scalar(
                format!("centre of mass [{k}] of body `{}`", l.name),
                c,
                Check::Finite,
            );
        }
    }
    if let Some(g) = &model.gravity {
        for (k, c) in g.iter().enumerate() {
            scalar(format!("gravity [{k}]"), c, Check::Finite);
        }
    }
    for l in &model.links {
        for (k, c) in l.origin.iter().enumerate() {
            scalar(
                format!("origin [{k}] of joint `{}`", l.joint_name),
                c,
                Check::Finite,
            );
        }
        for (k, c) in l.rpy.iter().enumerate() {
            scalar(
                format!("rpy [{k}] of joint `{}`", l.joint_name),
                c,
                Check::Finite,
            );
        }
    }
    for s in &model.springs {
        scalar(
            format!("rest position of the spring on coordinate {}", s.coordinate),
            &s.rest,
            Check::Finite,
        );
        scalar(
            format!("stiffness of the spring on coordinate {}", s.coordinate),
            &s.k,
            Check::Finite,
        );
    }
    for d in &model.dampers {
        scalar(
            format!("damping of the damper on coordinate {}", d.coordinate),
            &d.c,
            Check::NonNegative,
        );
    }
    for c in &model.contacts {
        scalar(
            format!("friction coefficient `mu` of contact `{}`", c.name),
            &c.mu,
            Check::NonNegative,
        );
        if let Some(ms) = &c.mu_static {
            if ms.as_const().is_none() || c.mu.as_const().is_none() {
                let (k, st) = (expr(&c.mu, p), expr(ms, p));
                let what = format!(
                    "friction coefficient `mu` of contact `{}` (`{}`), above its `mu_static`",
                    c.name,
                    c.mu.display(p)
                );
                kinetic_checks.push(quote! {
                    if let Some(why) = #ck::at_most(#k, #st) { problems.push((#what.to_string(), why)); }
                });
            }
        }
        scalar(
            format!("restitution of contact `{}`", c.name),
            &c.restitution,
            Check::UnitInterval,
        );
        scalar(
            format!("radius of contact `{}`", c.name),
            &c.radius,
            Check::NonNegative,
        );
        for (what, v) in [("at", &c.at), ("origin", &c.origin), ("rpy", &c.rpy)] {
            for (k, x) in v.iter().enumerate() {
                scalar(
                    format!("{what} [{k}] of contact `{}`", c.name),
                    x,
                    Check::Finite,
                );
            }
        }
    }
    for e in &model.elements {
        match &e.kind {
            ElementKind::DashPot { law, f_crit } => {
                let limit = match law {
                    Law::StaticKinetic { .. } => "f_static",
                    _ => "f_crit",
                };
                scalar(
                    format!("{limit} of `{}`", e.name),
                    f_crit,
                    Check::NonNegative,
                );
                if let Law::BinghamLinear { eta } = law {
                    scalar(format!("eta of `{}`", e.name), eta, Check::Positive);
                }
                if let Law::StaticKinetic { f_kinetic } = law {
                    scalar(
                        format!("f_kinetic of `{}`", e.name),
                        f_kinetic,
                        Check::NonNegative,
                    );
                    if f_kinetic.as_const().is_none() || f_crit.as_const().is_none() {
                        let (k, s) = (expr(f_kinetic, p), expr(f_crit, p));
                        let what =
                            format!("f_kinetic of `{}` (`{}`)", e.name, f_kinetic.display(p));
                        kinetic_checks.push(quote! {
                            if let Some(why) = #ck::at_most(#k, #s) { problems.push((#what.to_string(), why)); }
                        });
                    }
                }
            }
            ElementKind::Stop { position, kind, .. } => {
                scalar(format!("position of `{}`", e.name), position, Check::Finite);
                match kind {
                    StopKind::Rigid { restitution } => scalar(
                        format!("restitution of `{}`", e.name),
                        restitution,
                        Check::UnitInterval,
                    ),
                    StopKind::SpringBacked { stiffness } => scalar(
                        format!("k_support of `{}`", e.name),
                        stiffness,
                        Check::Positive,
                    ),
                }
            }
        }
    }
    checks.extend(kinetic_checks);
    // Two stops on one coordinate leave room between them.
    for lo in &model.elements {
        let ElementKind::Stop {
            upper: false,
            position: min,
            ..
        } = &lo.kind
        else {
            continue;
        };
        for hi in model
            .elements
            .iter()
            .filter(|e| e.coordinate == lo.coordinate)
        {
            if let ElementKind::Stop {
                upper: true,
                position: max,
                ..
            } = &hi.kind
                && (min.as_const().is_none() || max.as_const().is_none())
            {
                let (a, b) = (expr(min, p), expr(max, p));
                let what = format!("position of `{}` (`{}`)", lo.name, min.display(p));
                checks.push(quote! {
                    if let Some(why) = #ck::below(#a, #b) { problems.push((#what.to_string(), why)); }
                });
            }
        }
    }
    for l in model
        .links
        .iter()
        .filter(|l| l.kind != JointKind::Translation)
        // A constant inertia was checked at expansion.
        .filter(|l| l.inertia.iter().flatten().any(|e| e.as_const().is_none()))
    {
        let entries: Vec<TokenStream> = l.inertia.iter().flatten().map(|e| expr(e, p)).collect();
        let what = format!("inertia of body `{}`", l.name);
        checks.push(quote! {
            if let Some(why) = #ck::inertia(&::filippov::nalgebra::Matrix3::new(#(#entries),*)) {
                problems.push((#what.to_string(), why));
            }
        });
    }
    quote! {
        #[allow(clippy::all)]
        fn validate(&self) -> ::core::result::Result<(), ::filippov::runtime::system::ParameterError> {
            let mut problems: ::std::vec::Vec<(::std::string::String, ::std::string::String)> = ::std::vec::Vec::new();
            #(#checks)*
            if problems.is_empty() {
                Ok(())
            } else {
                Err(::filippov::runtime::system::ParameterError { problems })
            }
        }
    }
}

/// The run-time checks of `filippov::runtime::system::check`.
#[derive(Clone, Copy)]
enum Check {
    Finite,
    Positive,
    NonNegative,
    UnitInterval,
}

impl Check {
    fn function(self) -> proc_macro2::Ident {
        let name = match self {
            Check::Finite => "finite",
            Check::Positive => "positive",
            Check::NonNegative => "non_negative",
            Check::UnitInterval => "unit_interval",
        };
        proc_macro2::Ident::new(name, proc_macro2::Span::call_site())
    }

    /// The same condition, evaluated at expansion.
    fn passes(self, x: f64) -> bool {
        match self {
            Check::Finite => x.is_finite(),
            Check::Positive => x.is_finite() && x > 0.0,
            Check::NonNegative => x.is_finite() && x >= 0.0,
            Check::UnitInterval => (0.0..=1.0).contains(&x),
        }
    }
}
