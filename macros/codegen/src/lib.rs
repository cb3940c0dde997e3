//! The engine behind `#[derive(Mechanism)]`, as a plain library so that tests, build
//! scripts and the report can call it.
//!
//! Pipeline (one module each): [`parse`] attributes → [`validate`] into a [`model`]
//! (errors accumulated in [`diag`]) → [`mech`]anics on the symbolic DAG of [`sym`] →
//! [`emit`] straight-line Rust.

// Index loops read like the formulas they implement (M_ij, c_ijk, …).
#![allow(clippy::needless_range_loop)]

pub mod attr_values;
pub mod contacts;
pub mod coordinate;
pub mod diag;
pub mod emit;
pub mod loops;
pub mod mech;
pub mod model;
pub mod nonsmooth;
pub mod parse;
pub mod point_springs;
pub mod sym;
pub mod urdf;
pub mod validate;

use proc_macro2::TokenStream;

pub use emit::FnStats;

/// The expansion and what it took.
pub struct Expansion {
    pub tokens: TokenStream,
    pub dof: usize,
    /// Nodes in the shared expression graph.
    pub graph_nodes: usize,
    /// Per generated method: operation counts and number of `let`s.
    pub functions: Vec<FnStats>,
    /// The forward dynamics' operations per part (kinematics, mass matrix or
    /// articulated inertias, bias forces, factorisation, solves), in the order the
    /// kernel computes them; they sum to its count. Empty for compact and
    /// loop-constrained forward dynamics.
    pub forward_parts: Vec<(&'static str, sym::OpCount)>,
}

/// The derive: the expansion, or on a mistake its spanned errors with stand-in impls
/// that keep the program's uses of the scene from adding follow-on errors
/// ([`emit::fallback`]).
pub fn derive(input: TokenStream) -> TokenStream {
    let parsed = syn::parse2::<syn::DeriveInput>(input.clone()).ok();
    match expand(input) {
        Ok(tokens) => tokens,
        Err(e) => emit::fallback::errors(e, parsed.as_ref()),
    }
}

/// Expands `#[derive(Mechanism)]` on `input` (the struct's tokens).
pub fn expand(input: TokenStream) -> Result<TokenStream, syn::Error> {
    expand_with_stats(input).map(|e| e.tokens)
}

/// [`expand`], also returning operation counts.
pub fn expand_with_stats(input: TokenStream) -> Result<Expansion, syn::Error> {
    let input: syn::DeriveInput = syn::parse2(input)?;
    let mut diag = diag::Diagnostics::new();
    let model = validate::validate(&input, &mut diag);
    diag.finish()?;
    let model = model.expect("a model when there are no errors");
    let kernels = mech::Kernels::build(&model);
    let (mut tokens, functions) = emit::mechanism_impl(&model, &kernels);
    let parts: Vec<&[sym::Id]> = kernels.forward_parts.iter().map(|(_, p)| &p[..]).collect();
    let forward_parts = kernels
        .forward_parts
        .iter()
        .map(|(name, _)| *name)
        .zip(kernels.graph.count_parts(&kernels.forward, &parts))
        .collect();
    if let Some(path) = model.urdf_file.as_ref().and_then(|p| p.to_str()) {
        // Cargo tracks files a crate includes: a changed URDF rebuilds the scene.
        tokens.extend(quote::quote! {
            const _: &[u8] = include_bytes!(#path);
        });
    }
    let tokens = match &model.krate {
        Some(path) => emit::rename_crate(tokens, path),
        None => tokens,
    };
    Ok(Expansion {
        tokens,
        dof: kernels.dof,
        graph_nodes: kernels.graph.len(),
        functions,
        forward_parts,
    })
}
