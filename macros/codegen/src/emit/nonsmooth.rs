//! `impl NonSmooth<N>`: the elements with their parameters, the user laws `v = φ(f)`
//! with their symbolic derivatives, and `M⁻¹` — emitted only for scenes that declare
//! elements, and for each element only what its kind needs.

use proc_macro2::{Literal, TokenStream};
use quote::{format_ident, quote};

use super::describe::expr;
use super::function::{Signature, emit};
use super::{FnStats, matrix};
use crate::mech::Kernels;
use crate::model::{ElementKind, Law, Model, Selection, StopKind};
use crate::sym::{Graph, Input, InputKind};

const RT: &str = "::filippov::runtime::nonsmooth";

pub fn nonsmooth_impl(
    model: &Model,
    k: &Kernels,
    stats: &mut Vec<FnStats>,
) -> (TokenStream, TokenStream) {
    let Some(inv) = &k.inverse_mass else {
        return (TokenStream::new(), TokenStream::new());
    };
    let rt: TokenStream = RT.parse().expect("path");
    let n = k.dof;
    let ident = &model.ident;
    let p = &model.params;
    let mut helpers = TokenStream::new();
    let mut arms = Vec::new();
    let mut law_arms = Vec::new();
    for (i, el) in model.elements.iter().enumerate() {
        let name = Literal::string(&el.name);
        let c = el.coordinate;
        let kind = match &el.kind {
            ElementKind::DashPot { law, f_crit } => {
                let fc = expr(f_crit, p);
                let law = match law {
                    Law::Coulomb => quote!(#rt::Law::Coulomb),
                    Law::StaticKinetic { f_kinetic } => {
                        let fk = expr(f_kinetic, p);
                        quote!(#rt::Law::StaticKinetic { f_kinetic: #fk })
                    }
                    Law::BinghamLinear { eta } => {
                        let eta = expr(eta, p);
                        quote!(#rt::Law::BinghamLinear { eta: #eta })
                    }
                    Law::User { phi, selection } => {
                        // φ and dφ/df on f ≥ 0 as straight-line code; odd extension below.
                        let mut g = Graph::new();
                        let v = phi.lower(&mut g);
                        let dv = g.diff(
                            v,
                            Input {
                                kind: InputKind::Q,
                                index: 0,
                            },
                        );
                        let hname = format_ident!("__law_{}", i);
                        let sig = Signature {
                            generic: None,
                            fused: false,
                            vis: quote!(),
                            elements: 0,
                            name: hname.clone(),
                            inputs: vec![InputKind::Q],
                            ret: quote!((f64, f64)),
                            doc: format!(
                                " `(φ(f), dφ/df)` of element `{}` for `f = q[0] ≥ 0`.",
                                el.name
                            ),
                        };
                        let e = emit(&g, p, (1, 1), &sig, &[v, dv], &|o: Vec<TokenStream>| {
                            let (a, b) = (&o[0], &o[1]);
                            quote!((#a, #b))
                        });
                        stats.push(FnStats {
                            name: "law",
                            ops: g.count_ops(&[v, dv]),
                            lets: e.lets,
                        });
                        let method = e.method;
                        helpers.extend(quote!(#[doc(hidden)] #method));
                        helpers.extend(e.helpers);
                        law_arms.push(quote! {
                            #i => {
                                let (phi, dphi) = self.#hname(&::filippov::nalgebra::SVector::<f64, 1>::new(f.abs()));
                                (phi.copysign(f), dphi)
                            }
                        });
                        match selection {
                            None => quote!(#rt::Law::BinghamMonotone),
                            Some(Selection::NoVelocityJumps) => {
                                quote!(#rt::Law::BinghamNonMonotone { selection: #rt::Selection::NoVelocityJumps })
                            }
                            Some(Selection::MaximalDissipation) => {
                                quote!(#rt::Law::BinghamNonMonotone { selection: #rt::Selection::MaximalDissipation })
                            }
                        }
                    }
                };
                quote!(#rt::ElementKind::DashPot { law: #law, f_crit: #fc })
            }
            ElementKind::Stop {
                upper,
                position,
                kind,
            } => {
                let side = if *upper {
                    quote!(#rt::Side::Upper)
                } else {
                    quote!(#rt::Side::Lower)
                };
                let pos = expr(position, p);
                let kind = match kind {
                    StopKind::Rigid { restitution } => {
                        let r = expr(restitution, p);
                        quote!(#rt::StopKind::Rigid { restitution: #r })
                    }
                    StopKind::SpringBacked { stiffness } => {
                        let k = expr(stiffness, p);
                        quote!(#rt::StopKind::SpringBacked { stiffness: #k })
                    }
                };
                quote!(#rt::ElementKind::Stop { side: #side, position: #pos, kind: #kind })
            }
        };
        arms.push(quote!(#i => #rt::Element { name: #name, coordinate: #c, kind: #kind },));
    }
    let count = model.elements.len();
    let inv_flat: Vec<_> = inv.iter().flatten().copied().collect();
    let sig = Signature {
            generic: None,
            fused: false,
        vis: quote!(),
        elements: 0,
        name: format_ident!("inverse_mass_matrix"),
        inputs: vec![InputKind::Q],
        ret: quote!(::filippov::nalgebra::SMatrix<f64, #n, #n>),
        doc: " `M(q)⁻¹` by the sparse `LᵀDL` factorisation (its submatrix at the elements' coordinates is their Delassus operator).".into(),
    };
    let e = emit(&k.graph, p, (n, n), &sig, &inv_flat, &|o| matrix(o, n));
    stats.push(FnStats {
        name: "inverse_mass_matrix",
        ops: k.graph.count_ops(&inv_flat),
        lets: e.lets,
    });
    helpers.extend(e.helpers);
    let inv_method = e.method;
    helpers.extend(element_kernels(model, k, stats));
    if model.emit.dae_residuals {
        helpers.extend(constitutive_residual(model, n));
    }
    let law_fn = if law_arms.is_empty() {
        quote! {
            #[inline]
            fn law(&self, element: usize, f: f64) -> (f64, f64) {
                (0.0, 0.0)
            }
        }
    } else {
        quote! {
            #[inline]
            fn law(&self, element: usize, f: f64) -> (f64, f64) {
                match element {
                    #(#law_arms)*
                    _ => (0.0, 0.0),
                }
            }
        }
    };
    let bearings = bearing_limits(model, k, stats, &mut helpers);
    let declared = if model.contacts.is_empty() {
        TokenStream::new()
    } else {
        let names = model.contacts.iter().map(|c| Literal::string(&c.name));
        quote!(const DECLARED_CONTACTS: &'static [&'static str] = &[#(#names),*];)
    };
    let imp = quote! {
        impl #rt::NonSmooth<#n> for #ident {
            const ELEMENTS: usize = #count;
            #declared
            #[allow(clippy::all)]
            fn element(&self, element: usize) -> #rt::Element {
                match element {
                    #(#arms)*
                    _ => panic!("element index {} out of range: this mechanism has {} elements", element, #count),
                }
            }
            #[allow(unused_variables)]
            #law_fn
            #inv_method
            #bearings
        }
    };
    (imp, helpers)
}

/// For scenes with bearing friction: the hidden kernel `__bearing_limits(q, v, a)` (into
/// `helpers`) and the trait's `BEARINGS` and `bearing_limits`, which call it.
fn bearing_limits(
    model: &Model,
    k: &Kernels,
    stats: &mut Vec<FnStats>,
    helpers: &mut TokenStream,
) -> TokenStream {
    if k.bearings.is_empty() {
        return TokenStream::new();
    }
    let (n, b) = (k.dof, k.bearings.len());
    let which: Vec<usize> = (model.elements.iter().enumerate())
        .filter(|(_, e)| e.bearing.is_some())
        .map(|(i, _)| i)
        .collect();
    let names: Vec<String> = which
        .iter()
        .map(|&i| format!("`{}`", model.elements[i].name))
        .collect();
    let sig = Signature {
        generic: None,
        fused: false,
        vis: quote!(),
        elements: 0,
        name: format_ident!("__bearing_limits"),
        inputs: vec![InputKind::Q, InputKind::V, InputKind::A],
        ret: quote!([f64; #b]),
        doc: format!(
            " The load-dependent limits `μ r |F_⊥|` of the bearing frictions ({}), from the forces their joints transmit at `(q, v, a)`.",
            names.join(", ")
        ),
    };
    let e = emit(
        &k.graph,
        &model.params,
        (n, n),
        &sig,
        &k.bearings,
        &|o| quote!([#(#o),*]),
    );
    stats.push(FnStats {
        name: "bearing_limits",
        ops: k.graph.count_ops(&k.bearings),
        lets: e.lets,
    });
    let method = e.method;
    helpers.extend(quote!(#[doc(hidden)] #method));
    helpers.extend(e.helpers);
    quote! {
        const BEARINGS: &'static [usize] = &[#(#which),*];
        fn bearing_limits(
            &self,
            q: &::filippov::nalgebra::SVector<f64, #n>,
            v: &::filippov::nalgebra::SVector<f64, #n>,
            a: &::filippov::nalgebra::SVector<f64, #n>,
            limits: &mut [f64],
        ) {
            limits.copy_from_slice(&self.__bearing_limits(q, v, a));
        }
    }
}

/// Inherent methods: the Delassus operator, the momentum balance's DAE residual and the
/// switching functions of every element.
fn element_kernels(model: &Model, k: &Kernels, stats: &mut Vec<FnStats>) -> TokenStream {
    let Some(ek) = &k.elements else {
        return TokenStream::new();
    };
    let (n, m) = (k.dof, model.elements.len());
    let p = &model.params;
    let mut out = TokenStream::new();
    let mut add = |name: &'static str,
                   inputs: Vec<InputKind>,
                   ret: TokenStream,
                   outs: Vec<crate::sym::Id>,
                   asm: &dyn Fn(Vec<TokenStream>) -> TokenStream,
                   doc: String| {
        let sig = Signature {
            generic: None,
            fused: false,
            vis: quote!(pub),
            elements: m,
            name: format_ident!("{}", name),
            inputs,
            ret,
            doc,
        };
        let e = emit(&k.graph, p, (n, n), &sig, &outs, asm);
        stats.push(FnStats {
            name,
            ops: k.graph.count_ops(&outs),
            lets: e.lets,
        });
        out.extend(e.method);
        out.extend(e.helpers);
    };
    let names: Vec<String> = model
        .elements
        .iter()
        .map(|e| format!("`{}`", e.name))
        .collect();
    let emits = model.emit;
    let flat: Vec<_> = ek.delassus.iter().flatten().copied().collect();
    if emits.delassus {
        add(
            "delassus",
            vec![InputKind::Q],
            quote!(::filippov::nalgebra::SMatrix<f64, #m, #m>),
            flat,
            &|o| matrix(o, m),
            format!(
                " Delassus operator `W = J M⁻¹ Jᵀ` of the elements ({}), in that order.",
                names.join(", ")
            ),
        );
    }
    if emits.dae_residuals {
        add(
        "momentum_residual",
        vec![InputKind::Q, InputKind::V, InputKind::A, InputKind::Tau, InputKind::F],
        quote!(::filippov::nalgebra::SVector<f64, #n>),
        ek.momentum_residual.clone(),
        &|o| super::vector(o, n),
        " DAE residual of the momentum balance, `M a + C v + g − τ − τ_p + Σ_e f_e e_c`, with `a = v̇` and the element forces `f` (zero on a solution).".into(),
    );
    }
    let s = ek.switching.len();
    if emits.switching_functions {
        add(
            "switching_functions",
            vec![InputKind::Q, InputKind::V, InputKind::F],
            quote!(::filippov::nalgebra::SVector<f64, #s>),
            ek.switching.clone(),
            &|o| super::vector(o, s),
            format!(
                " Switching functions, two per element ({}): a dash-pot gives `[v_c, f_crit² − f²]` (slip→stick, stick→slip), a stop `[gap, f]` (contact, release; the gap is positive on the admissible side).",
                names.join(", ")
            ),
        );
    }
    out
}

/// `constitutive_residual(element, relation, q, v, a, f) -> (r, [∂r/∂q_c, ∂r/∂v_c,
/// ∂r/∂a_c, ∂r/∂f_e])`: the residual of one element's constitutive relation in the given
/// relation, with its derivatives. The residuals of all elements together with
/// `momentum_residual` are the DAE of a mode. The reduced equations of a mode (which
/// elements hold their coordinates) are assembled at run time from these and the
/// Delassus operator: there are 3^K modes, and for elements on coordinates each costs a
/// few operations given `W`.
fn constitutive_residual(model: &Model, n: usize) -> TokenStream {
    let p = &model.params;
    let rt: TokenStream = RT.parse().expect("path");
    let mut arms = Vec::new();
    for (i, el) in model.elements.iter().enumerate() {
        let c = el.coordinate;
        let hold = quote!(#rt::Relation::Hold => (a[#c], [0.0, 0.0, 1.0, 0.0]),);
        let body = match &el.kind {
            ElementKind::DashPot { law, f_crit } => {
                let fc = expr(f_crit, p);
                let slip = match law {
                    Law::Coulomb => quote! {
                        #rt::Relation::Slip => (f - #fc * v[#c].signum(), [0.0, 0.0, 0.0, 1.0]),
                    },
                    Law::StaticKinetic { f_kinetic } => {
                        let fk = expr(f_kinetic, p);
                        quote! {
                            #rt::Relation::Slip => (f - #fk * v[#c].signum(), [0.0, 0.0, 0.0, 1.0]),
                        }
                    }
                    Law::BinghamLinear { eta } => {
                        let eta = expr(eta, p);
                        quote! {
                            #rt::Relation::Slip => {
                                let eta = #eta;
                                (v[#c] - (f - f.signum() * #fc) / eta, [0.0, 1.0, 0.0, -1.0 / eta])
                            }
                        }
                    }
                    Law::User { .. } => quote! {
                        #rt::Relation::Slip => {
                            let (phi, dphi) = <Self as #rt::NonSmooth<#n>>::law(self, #i, f);
                            (v[#c] - phi, [0.0, 1.0, 0.0, -dphi])
                        }
                    },
                };
                quote! {
                    match relation {
                        #hold
                        #slip
                        _ => (f64::NAN, [f64::NAN; 4]),
                    }
                }
            }
            ElementKind::Stop {
                upper,
                position,
                kind,
            } => {
                let pos = expr(position, p);
                let compressed = match kind {
                    StopKind::SpringBacked { stiffness } => {
                        let ks = expr(stiffness, p);
                        // penetration = ±(q − L); f = k_s · penetration
                        let (pen, dpen) = if *upper {
                            (quote!(q[#c] - #pos), quote!(1.0))
                        } else {
                            (quote!(#pos - q[#c]), quote!(-1.0))
                        };
                        quote! {
                            #rt::Relation::Compressed => {
                                let ks = #ks;
                                (f - ks * (#pen), [-ks * #dpen, 0.0, 0.0, 1.0])
                            }
                        }
                    }
                    StopKind::Rigid { .. } => quote!(),
                };
                quote! {
                    match relation {
                        #hold
                        #rt::Relation::Free => (f, [0.0, 0.0, 0.0, 1.0]),
                        #compressed
                        _ => (f64::NAN, [f64::NAN; 4]),
                    }
                }
            }
        };
        arms.push(quote!(#i => { #body }));
    }
    quote! {
        /// Residual of element `element`'s constitutive relation `relation` at the
        /// coordinate values `q`, `v`, acceleration `a` and its force `f`, with the
        /// derivatives `[∂r/∂q_c, ∂r/∂v_c, ∂r/∂a_c, ∂r/∂f]`; NaN for a relation the
        /// element does not have (a dash-pot is never `Free`).
        #[allow(clippy::all, unused_variables)]
        pub fn constitutive_residual(
            &self,
            element: usize,
            relation: #rt::Relation,
            q: &::filippov::nalgebra::SVector<f64, #n>,
            v: &::filippov::nalgebra::SVector<f64, #n>,
            a: &::filippov::nalgebra::SVector<f64, #n>,
            f: f64,
        ) -> (f64, [f64; 4]) {
            match element {
                #(#arms)*
                _ => (f64::NAN, [f64::NAN; 4]),
            }
        }
    }
}
