//! The `Contacts` impl of a scene with contacts: gaps, normal and tangential Jacobians
//! and their `γ` terms ([`crate::mech::contacts`]), each one straight-line method, and
//! the contacts' coefficients.

use proc_macro2::{Literal, TokenStream};
use quote::quote;

use super::describe::expr;
use super::{FnStats, Methods, rect_matrix};
use crate::mech::Kernels;
use crate::model::Model;
use crate::sym::InputKind;

/// `impl Contacts<N, K, T>`, or nothing for a scene without contacts.
pub fn contacts_impl(
    model: &Model,
    k: &Kernels,
    stats: &mut Vec<FnStats>,
) -> (TokenStream, TokenStream) {
    let Some(ck) = &k.contacts else {
        return (TokenStream::new(), TokenStream::new());
    };
    let (n, kc, t) = (k.dof, ck.contacts(), ck.tangents());
    let g = &k.graph;
    let ident = &model.ident;
    let mut out = Methods::new(g, &model.params, n, stats);
    let vector = |m: usize| move |o: Vec<TokenStream>| quote!(::filippov::nalgebra::SVector::<f64, #m>::from([#(#o),*]));
    let matrix = |m: usize| move |o: Vec<TokenStream>| rect_matrix(o, m, n);
    out.add(
        "contact_gaps",
        vec![InputKind::Q],
        quote!(::filippov::nalgebra::SVector<f64, #kc>),
        &ck.gaps,
        &vector(kc),
        " The contacts' gaps `g_N(q)` (positive apart, negative in penetration).",
    );
    out.add(
        "contact_normal_jacobian",
        vec![InputKind::Q],
        quote!(::filippov::nalgebra::SMatrix<f64, #kc, #n>),
        &ck.normal,
        &matrix(kc),
        " `W_N(q) = ∂g_N/∂q`: the normal velocities are `W_N v`.",
    );
    out.add(
        "contact_normal_gamma",
        vec![InputKind::Q, InputKind::V],
        quote!(::filippov::nalgebra::SVector<f64, #kc>),
        &ck.normal_gamma,
        &vector(kc),
        " `γ_N = −Ẇ_N v`: the normal accelerations are `W_N v̇ − γ_N`.",
    );
    out.add(
        "contact_tangent_jacobian",
        vec![InputKind::Q],
        quote!(::filippov::nalgebra::SMatrix<f64, #t, #n>),
        &ck.tangent,
        &matrix(t),
        " `W_T(q)`: the contact points' relative velocities along the planes' tangents are `W_T v`.",
    );
    out.add(
        "contact_tangent_gamma",
        vec![InputKind::Q, InputKind::V],
        quote!(::filippov::nalgebra::SVector<f64, #t>),
        &ck.tangent_gamma,
        &vector(t),
        " `γ_T = −Ẇ_T v`: the tangential accelerations are `W_T v̇ − γ_T`.",
    );
    let p = &model.params;
    let mu: Vec<TokenStream> = model.contacts.iter().map(|c| expr(&c.mu, p)).collect();
    // Static coefficients, where a contact gives one.
    let static_friction = if model.contacts.iter().any(|c| c.mu_static.is_some()) {
        let ms = model
            .contacts
            .iter()
            .map(|c| expr(c.mu_static.as_ref().unwrap_or(&c.mu), p));
        quote! {
            fn contact_static_friction(&self) -> [f64; #kc] {
                [#(#ms),*]
            }
        }
    } else {
        TokenStream::new()
    };
    let e: Vec<TokenStream> = model
        .contacts
        .iter()
        .map(|c| expr(&c.restitution, p))
        .collect();
    let names: Vec<Literal> = ck.names.iter().map(|s| Literal::string(s)).collect();
    let tangents: Vec<Literal> = ck
        .tangent_names
        .iter()
        .map(|s| Literal::string(s))
        .collect();
    let of = &ck.tangent_of;
    let methods = &out.methods;
    // Beside joint elements: they are the NonSmooth impl's, listed for the contact
    // time-stepper.
    let elements = if model.elements.is_empty() {
        TokenStream::new()
    } else {
        quote! {
            fn joint_elements(&self) -> ::std::vec::Vec<::filippov::runtime::nonsmooth::Element> {
                let count = <Self as ::filippov::runtime::nonsmooth::NonSmooth<#n>>::ELEMENTS;
                (0..count)
                    .map(|e| <Self as ::filippov::runtime::nonsmooth::NonSmooth<#n>>::element(self, e))
                    .collect()
            }
            const JOINT_BEARINGS: &'static [usize] =
                <Self as ::filippov::runtime::nonsmooth::NonSmooth<#n>>::BEARINGS;
            fn joint_bearing_limits(
                &self,
                q: &::filippov::nalgebra::SVector<f64, #n>,
                v: &::filippov::nalgebra::SVector<f64, #n>,
                a: &::filippov::nalgebra::SVector<f64, #n>,
                limits: &mut [f64],
            ) {
                <Self as ::filippov::runtime::nonsmooth::NonSmooth<#n>>::bearing_limits(self, q, v, a, limits)
            }
        }
    };
    let code = quote! {
        impl ::filippov::runtime::contacts::Contacts<#n, #kc, #t> for #ident {
            const CONTACTS: [&'static str; #kc] = [#(#names),*];
            const TANGENTS: [&'static str; #t] = [#(#tangents),*];
            const TANGENT_OF: [usize; #t] = [#(#of),*];
            fn contact_friction(&self) -> [f64; #kc] {
                [#(#mu),*]
            }
            fn contact_restitution(&self) -> [f64; #kc] {
                [#(#e),*]
            }
            #static_friction
            #methods
            #elements
        }
    };
    (code, out.helpers)
}
