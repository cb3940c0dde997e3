//! On a declaration error: the `compile_error!`s, and stand-in impls of the traits a
//! scene is used through (`Mechanism`, `Energy`, `NonSmooth`, for every `N`), so that
//! the program's uses of the scene — `scene.mass_matrix(&q)`, `solve_nonsmooth(&scene,
//! …)` — add no follow-on errors (E0599 "no method named `mass_matrix`") to the one
//! that says what is wrong. The program does not compile, so the stand-ins never run.

use proc_macro2::TokenStream;
use quote::quote;

/// The errors of `e`, with stand-in impls for `input`'s type where it was parsed.
pub fn errors(e: syn::Error, input: Option<&syn::DeriveInput>) -> TokenStream {
    let mut out = e.to_compile_error();
    if let Some(input) = input.filter(|i| i.generics.params.is_empty()) {
        let stubs = stand_ins(&input.ident, dof(input));
        out.extend(match renamed_crate(input) {
            Some(path) => super::rename_crate(stubs, &path),
            None => stubs,
        });
    }
    out
}

/// The stand-ins, for `N = dof` where the attributes tell it (so that `N` is inferred
/// at the uses as with the real impl), else for every `N`.
fn stand_ins(ident: &syn::Ident, dof: Option<usize>) -> TokenStream {
    let (generics, n, fixed) = match dof {
        Some(n) => (quote!(), quote!(N), quote!(const N: usize = #n;)),
        None => (quote!(<const N: usize>), quote!(N), quote!()),
    };
    quote! {
        #[allow(unused_variables, unreachable_code)]
        const _: () = {
            use ::filippov::nalgebra::{SMatrix, SVector};
            #fixed
            impl #generics ::filippov::runtime::system::Mechanism<#n> for #ident {
                const JOINTS: [&'static str; N] = [""; N];
                fn mass_matrix(&self, q: &SVector<f64, N>) -> SMatrix<f64, N, N> {
                    unreachable!()
                }
                fn forward_dynamics(
                    &self,
                    q: &SVector<f64, N>,
                    v: &SVector<f64, N>,
                    tau: &SVector<f64, N>,
                ) -> SVector<f64, N> {
                    unreachable!()
                }
                fn forward_dynamics_jacobian(
                    &self,
                    q: &SVector<f64, N>,
                    v: &SVector<f64, N>,
                    tau: &SVector<f64, N>,
                ) -> ::filippov::runtime::system::ForwardJacobian<N> {
                    unreachable!()
                }
                fn model(&self) -> ::filippov::runtime::numeric::Model {
                    unreachable!()
                }
            }
            impl #generics ::filippov::runtime::kernels::Energy<#n> for #ident {
                fn kinetic_energy(&self, q: &SVector<f64, N>, v: &SVector<f64, N>) -> f64 {
                    unreachable!()
                }
                fn potential_energy(&self, q: &SVector<f64, N>) -> f64 {
                    unreachable!()
                }
            }
            impl #generics ::filippov::runtime::nonsmooth::NonSmooth<#n> for #ident {
                const ELEMENTS: usize = 0;
                fn element(&self, e: usize) -> ::filippov::runtime::nonsmooth::Element {
                    unreachable!()
                }
                fn law(&self, e: usize, f: f64) -> (f64, f64) {
                    unreachable!()
                }
                fn inverse_mass_matrix(&self, q: &SVector<f64, N>) -> SMatrix<f64, N, N> {
                    unreachable!()
                }
            }
        };
    }
}

/// `#[mechanism(crate = path)]`, read without the rest of the attribute (which may be
/// what is wrong).
fn renamed_crate(input: &syn::DeriveInput) -> Option<syn::Path> {
    input
        .attrs
        .iter()
        .filter(|a| a.path().is_ident("mechanism"))
        .find_map(|a| {
            let list = a.meta.require_list().ok()?;
            let items = list
                .parse_args_with(
                    syn::punctuated::Punctuated::<syn::Meta, syn::Token![,]>::parse_terminated,
                )
                .ok()?;
            items.into_iter().find_map(|m| match m {
                syn::Meta::NameValue(nv) if nv.path.is_ident("crate") => match nv.value {
                    syn::Expr::Path(p) => Some(p.path),
                    _ => None,
                },
                _ => None,
            })
        })
}

/// The number of coordinates the joint attributes declare, where they tell it: one per
/// revolute or prismatic joint, none per fixed one (`None` for a scene read from a URDF
/// file, with spherical or free joints, or a kind not recognised).
fn dof(input: &syn::DeriveInput) -> Option<usize> {
    use proc_macro2::TokenTree;
    let mut n = 0;
    for a in &input.attrs {
        let path = a.path();
        if path.is_ident("mechanism") {
            let urdf = a.meta.require_list().ok().is_some_and(|l| {
                l.tokens
                    .clone()
                    .into_iter()
                    .any(|t| matches!(t, TokenTree::Ident(i) if i == "urdf"))
            });
            if urdf {
                return None;
            }
        }
        if !(path.is_ident("joint") || path.is_ident("body")) {
            continue;
        }
        let tokens: Vec<TokenTree> = a
            .meta
            .require_list()
            .ok()?
            .tokens
            .clone()
            .into_iter()
            .collect();
        match tokens.as_slice() {
            [
                TokenTree::Ident(_),
                TokenTree::Punct(p),
                TokenTree::Ident(kind),
                ..,
            ] if p.as_char() == ':' => {
                n += match kind.to_string().as_str() {
                    "revolute" | "prismatic" => 1,
                    "fixed" => 0,
                    _ => return None,
                };
            }
            // `#[body(name, …)]` without a joint; a joint without a kind is an error of
            // its own, and the count is not known.
            [TokenTree::Ident(_), ..] if path.is_ident("body") => {}
            _ => return None,
        }
    }
    (n > 0).then_some(n)
}
