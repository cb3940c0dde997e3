//! The `LoopConstraints` impl of a scene with loop joints: `Φ`, `G` and `γ`
//! ([`crate::mech::loops`]), each one straight-line method.

use proc_macro2::{Literal, TokenStream};
use quote::quote;

use super::{FnStats, Methods, rect_matrix};
use crate::mech::Kernels;
use crate::model::Model;
use crate::sym::InputKind;

/// `impl LoopConstraints<N, M>`, or nothing for a scene without loop joints.
pub fn loops_impl(
    model: &Model,
    k: &Kernels,
    stats: &mut Vec<FnStats>,
) -> (TokenStream, TokenStream) {
    let Some(lo) = &k.loops else {
        return (TokenStream::new(), TokenStream::new());
    };
    let lk = &lo.constraints;
    let (n, m) = (k.dof, lk.rows());
    let g = &k.graph;
    let ident = &model.ident;
    let mut out = Methods::new(g, &model.params, n, stats);
    let vec_m =
        |o: Vec<TokenStream>| quote!(::filippov::nalgebra::SVector::<f64, #m>::from([#(#o),*]));
    out.add(
        "constraint_residual",
        vec![InputKind::Q],
        quote!(::filippov::nalgebra::SVector<f64, #m>),
        &lk.residual,
        &vec_m,
        " The loop joints' constraint residual `Φ(q)`.",
    );
    out.add(
        "constraint_jacobian",
        vec![InputKind::Q],
        quote!(::filippov::nalgebra::SMatrix<f64, #m, #n>),
        &lk.jacobian,
        &|o: Vec<TokenStream>| rect_matrix(o, m, n),
        " The constraint Jacobian `G(q) = ∂Φ/∂q`.",
    );
    out.add(
        "constraint_gamma",
        vec![InputKind::Q, InputKind::V],
        quote!(::filippov::nalgebra::SVector<f64, #m>),
        &lk.gamma,
        &vec_m,
        " The constraint acceleration term `γ = −Ġ v` (`G v̇ = γ`).",
    );
    let mut outs = k.forward.clone();
    outs.extend(lo.lambda.iter().copied());
    out.add(
        "constrained_forward_dynamics",
        vec![InputKind::Q, InputKind::V, InputKind::Tau],
        quote!((::filippov::nalgebra::SVector<f64, #n>, ::filippov::nalgebra::SVector<f64, #m>)),
        &outs,
        &|o: Vec<TokenStream>| {
            let (a, l) = o.split_at(n);
            quote!((
                ::filippov::nalgebra::SVector::<f64, #n>::from([#(#a),*]),
                ::filippov::nalgebra::SVector::<f64, #m>::from([#(#l),*])
            ))
        },
        " Forward dynamics of the closed mechanism and its constraint forces `λ`: \
         `M v̇ = τ + τ_p − C v − g + Gᵀ λ` with `G v̇ = γ`.",
    );
    let names: Vec<Literal> = lk.names.iter().map(|s| Literal::string(s)).collect();
    let methods = &out.methods;
    let code = quote! {
        impl ::filippov::runtime::loops::LoopConstraints<#n, #m> for #ident {
            const CONSTRAINTS: [&'static str; #m] = [#(#names),*];
            #methods
        }
    };
    (code, out.helpers)
}
