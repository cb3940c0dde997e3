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
    let mut scalar = |what: String, e: &PExpr, f: TokenStream| {
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
            quote!(finite),
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
            quote!(positive),
        );
        for (k, c) in l.com.iter().enumerate() {
            scalar(
                format!("centre of mass [{k}] of body `{}`", l.name),
                c,
                quote!(finite),
            );
        }
    }
    for s in &model.springs {
        scalar(
            format!("stiffness of the spring on coordinate {}", s.coordinate),
            &s.k,
            quote!(finite),
        );
    }
    for d in &model.dampers {
        scalar(
            format!("damping of the damper on coordinate {}", d.coordinate),
            &d.c,
            quote!(non_negative),
        );
    }
    for e in &model.elements {
        match &e.kind {
            ElementKind::DashPot { law, f_crit } => {
                scalar(
                    format!("f_crit of `{}`", e.name),
                    f_crit,
                    quote!(non_negative),
                );
                if let Law::BinghamLinear { eta } = law {
                    scalar(format!("eta of `{}`", e.name), eta, quote!(positive));
                }
            }
            ElementKind::Stop { position, kind, .. } => {
                scalar(
                    format!("position of `{}`", e.name),
                    position,
                    quote!(finite),
                );
                match kind {
                    StopKind::Rigid { restitution } => scalar(
                        format!("restitution of `{}`", e.name),
                        restitution,
                        quote!(unit_interval),
                    ),
                    StopKind::SpringBacked { stiffness } => scalar(
                        format!("k_support of `{}`", e.name),
                        stiffness,
                        quote!(positive),
                    ),
                }
            }
        }
    }
    for l in model
        .links
        .iter()
        .filter(|l| l.kind != JointKind::Translation)
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
