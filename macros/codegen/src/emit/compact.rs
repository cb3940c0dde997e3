//! The compact kernels' code (`forward_dynamics = compact`, or `auto` on a large tree):
//! the tree's table as constants, or where parameters enter it a function that fills
//! it; the generalised forces as one generic function; forward dynamics and its
//! Jacobian as calls into `runtime::compact`.

use proc_macro2::{Literal, TokenStream};
use quote::{format_ident, quote};

use super::FnStats;
use super::function::{Signature, emit};
use crate::mech::compact::{ENTRIES, Joint};
use crate::mech::{CompactKernels, Kernels};
use crate::model::Model;
use crate::sym::{Id, InputKind};

/// What the compact scene's impls take from here.
pub struct Compact {
    /// `forward_dynamics` and `forward_dynamics_jacobian` (trait `Mechanism`).
    pub core: TokenStream,
    /// `forward_dynamics_generic` (trait `GenericDynamics`).
    pub generic: TokenStream,
    /// `forward_dynamics_jacobian_generic` (trait `GenericDynamics`).
    pub generic_jacobian: TokenStream,
    /// `mass_matrix` (trait `Mechanism`).
    pub mass: TokenStream,
    /// `mass_matrix_generic` (trait `GenericDynamics`).
    pub generic_mass: TokenStream,
    /// The table, the forces and their helper chunks (inherent items).
    pub helpers: TokenStream,
}

fn float(c: f64) -> TokenStream {
    if c.is_nan() {
        return quote!(f64::NAN);
    }
    if c.is_infinite() {
        return if c > 0.0 {
            quote!(f64::INFINITY)
        } else {
            quote!(f64::NEG_INFINITY)
        };
    }
    let l = Literal::f64_unsuffixed(c.abs());
    if c.is_sign_negative() {
        quote!(-#l)
    } else {
        quote!(#l)
    }
}

/// `([Body<_>; B], [_; 3])` from the table's entries in order.
fn table_value(outs: &[TokenStream], b: usize) -> TokenStream {
    let bodies: Vec<TokenStream> = (0..b)
        .map(|i| {
            let e = &outs[i * ENTRIES..(i + 1) * ENTRIES];
            let (r0, r1, r2) = (&e[0..3], &e[3..6], &e[6..9]);
            let (t, m, h, inertia) = (&e[9..12], &e[12], &e[13..16], &e[16..22]);
            quote!(::filippov::runtime::compact::Body {
                rotation: [[#(#r0),*], [#(#r1),*], [#(#r2),*]],
                translation: [#(#t),*],
                mass: #m,
                first_moment: [#(#h),*],
                inertia: [#(#inertia),*],
            })
        })
        .collect();
    let g = &outs[b * ENTRIES..];
    quote!(([#(#bodies),*], [#(#g),*]))
}

pub fn compact_impl(
    model: &Model,
    k: &Kernels,
    ck: &CompactKernels,
    stats: &mut Vec<FnStats>,
) -> Compact {
    let g = &k.graph;
    let n = k.dof;
    let params = &model.params;
    let np = params.len();
    let b = ck.tree.bodies.len();
    let mut helpers = TokenStream::new();

    let nodes: Vec<TokenStream> = ck
        .tree
        .nodes
        .iter()
        .map(|(parent, joint)| {
            let parent = match parent {
                Some(p) => quote!(::core::option::Option::Some(#p)),
                None => quote!(::core::option::Option::None),
            };
            let joint = match joint {
                Joint::Revolute(c) => quote!(::filippov::runtime::compact::Joint::Revolute(#c)),
                Joint::Prismatic(c) => quote!(::filippov::runtime::compact::Joint::Prismatic(#c)),
                Joint::Fixed => quote!(::filippov::runtime::compact::Joint::Fixed),
            };
            quote!(::filippov::runtime::compact::Node { parent: #parent, joint: #joint })
        })
        .collect();
    helpers.extend(quote! {
        /// The tree of the compact kernels: each body's parent and joint.
        const __FILIPPOV_NODES: [::filippov::runtime::compact::Node; #b] = [#(#nodes),*];
        /// The mass matrix's entries off the diagonal that the tree can make nonzero.
        /// (The length repeats the tree: an array's length may not name `Self`.)
        const __FILIPPOV_PAIRS: [
            ::filippov::runtime::compact::Pair;
            ::filippov::runtime::compact::pair_count(&[#(#nodes),*])
        ] = ::filippov::runtime::compact::pairs(&Self::__FILIPPOV_NODES);
    });

    // The table: constants when no parameter enters it.
    let mut entries: Vec<Id> = ck.tree.bodies.iter().flat_map(|b| b.entries()).collect();
    entries.extend(ck.tree.gravity);
    let constant: Option<Vec<f64>> = entries.iter().map(|&e| g.as_const(e)).collect();
    let table_t = |t: TokenStream| quote!(([::filippov::runtime::compact::Body<#t>; #b], [#t; 3]));
    let (table_f64, table_generic) = match &constant {
        Some(values) => {
            let lits: Vec<TokenStream> = values.iter().map(|&c| float(c)).collect();
            let value = table_value(&lits, b);
            let ty = table_t(quote!(f64));
            helpers.extend(quote! {
                /// The bodies of the compact kernels in their joint-aligned frames, and gravity.
                #[allow(clippy::all)]
                const __FILIPPOV_TABLE: #ty = #value;
                /// The bodies with each constant in four lanes, for the lanes twins of the
                /// forward dynamics and mass matrix (spread here, at compile time, not in
                /// each call).
                const __FILIPPOV_TABLE_LANES: [::filippov::runtime::compact::Body<
                    ::filippov::runtime::numerics::fused_lanes::F64x4,
                >; #b] = ::filippov::runtime::compact::fused::lanes_table(&Self::__FILIPPOV_TABLE.0);
            });
            (
                quote!(Self::__FILIPPOV_TABLE),
                quote!({
                    let (b, g) = &Self::__FILIPPOV_TABLE;
                    (
                        (*b).map(|b| b.lift::<T>()),
                        (*g).map(<T as ::filippov::runtime::Real>::cst),
                    )
                }),
            )
        }
        None => {
            let sig = Signature {
                name: format_ident!("__filippov_table"),
                inputs: vec![],
                ret: table_t(quote!(T)),
                doc: " The bodies of the compact kernels in their joint-aligned frames, and \
                      gravity, at parameters `p`."
                    .to_string(),
                vis: quote!(),
                elements: 0,
                generic: Some(np),
                fused: false,
            };
            let e = emit(g, params, (n, n), &sig, &entries, &|o| table_value(&o, b));
            helpers.extend(e.method);
            helpers.extend(e.helpers);
            (
                quote!(Self::__filippov_table::<f64>(&[#(self.#params),*])),
                quote!(Self::__filippov_table::<T>(p)),
            )
        }
    };

    // The generalised forces τ + τ_p on any scalar (τ itself without springs or dampers).
    let forces = ck.forces.as_ref().map(|f| {
        let sig = Signature {
            name: format_ident!("__filippov_forces"),
            inputs: vec![InputKind::Q, InputKind::V, InputKind::Tau],
            ret: quote!([T; #n]),
            doc: " `τ + τ_p`: the applied and passive generalised forces, at parameters `p`."
                .to_string(),
            vis: quote!(),
            elements: 0,
            generic: Some(np),
            fused: false,
        };
        let e = emit(g, params, (n, n), &sig, f, &|o| quote!([#(#o),*]));
        helpers.extend(e.method);
        helpers.extend(e.helpers);
        stats.push(FnStats {
            name: "compact_forces",
            ops: g.count_ops(f),
            lets: e.lets,
        });
    });
    let forces_f64 = match forces {
        Some(()) => quote!(Self::__filippov_forces::<f64>(&[#(self.#params),*], &q, &v, &tau)),
        None => quote!(tau),
    };
    let forces_generic = match forces {
        Some(()) => quote!(Self::__filippov_forces::<T>(p, q, v, tau)),
        None => quote!(*tau),
    };
    let forces_dual = match forces {
        Some(()) => quote!(|q, v| Self::__filippov_forces(&pd, q, v, &td)),
        None => quote!(|_, _| td),
    };
    let dual_params = match forces {
        Some(()) => quote!(let pd = [#(self.#params),*].map(::filippov::runtime::Dual::constant);),
        None => quote!(),
    };
    let dual_params_generic = match forces {
        Some(()) => quote!(let pd = p.map(::filippov::runtime::Dual::constant);),
        None => quote!(let _ = p;),
    };
    stats.push(FnStats {
        name: "compact_table",
        ops: g.count_ops(&entries),
        lets: 0,
    });

    let vec_t = quote!(::filippov::nalgebra::SVector<f64, #n>);
    let arrays = quote! {
        let q: [f64; #n] = (*q).into();
        let v: [f64; #n] = (*v).into();
        let tau: [f64; #n] = (*tau).into();
    };
    let core = quote! {
        /// Forward dynamics `M⁻¹ (τ + τ_p − C v − g)` by the articulated-body algorithm,
        /// one loop over a table of the bodies (`runtime::compact`).
        #[inline]
        fn forward_dynamics(&self, q: &#vec_t, v: &#vec_t, tau: &#vec_t) -> #vec_t {
            #arrays
            let tau = #forces_f64;
            let (bodies, gravity) = &#table_f64;
            #[cfg(target_arch = "x86_64")]
            if ::filippov::runtime::numerics::fused::enabled() {
                // SAFETY: `enabled` holds only where the processor has AVX2 and FMA.
                return ::filippov::nalgebra::SVector::<f64, #n>::from(unsafe {
                    ::filippov::runtime::compact::fused::forward_dynamics(
                        &Self::__FILIPPOV_NODES, bodies, *gravity, &q, &v, &tau,
                    )
                });
            }
            ::filippov::nalgebra::SVector::<f64, #n>::from(
                ::filippov::runtime::compact::aba::forward_dynamics(
                    &Self::__FILIPPOV_NODES, bodies, *gravity, &q, &v, &tau,
                ),
            )
        }
        /// Forward dynamics and its Jacobian with respect to `(q, v)`, by dual numbers
        /// through the compact articulated-body algorithm (exact to rounding).
        fn forward_dynamics_jacobian(
            &self,
            q: &#vec_t,
            v: &#vec_t,
            tau: &#vec_t,
        ) -> ::filippov::runtime::system::ForwardJacobian<#n> {
            #arrays
            #dual_params
            let td = tau.map(::filippov::runtime::Dual::constant);
            let (bodies, gravity) = &#table_f64;
            let (acc, dq, dv) = ::filippov::runtime::compact::jacobian::forward_dynamics_jacobian(
                &Self::__FILIPPOV_NODES, bodies, *gravity, &q, &v, #forces_dual,
            );
            ::filippov::runtime::system::ForwardJacobian {
                acceleration: ::filippov::nalgebra::SVector::<f64, #n>::from(acc),
                d_dq: ::filippov::nalgebra::SMatrix::<f64, #n, #n>::from_fn(|i, j| dq[i][j]),
                d_dv: ::filippov::nalgebra::SMatrix::<f64, #n, #n>::from_fn(|i, j| dv[i][j]),
            }
        }
    };
    // Four states in `f64x4` run the fused lanes twin, where the table is constant (a
    // table of parameters would be lanes too).
    let lanes = quote!(::filippov::runtime::numerics::fused_lanes);
    let lanes_twin = match &constant {
        Some(_) => quote! {
            #[cfg(target_arch = "x86_64")]
            if ::filippov::runtime::numerics::fused::enabled() {
                // (No `let` chain: the user's crate may be of an edition before 2024.)
                if let (Some(q4), Some(v4), Some(t4)) =
                    (#lanes::to_fused(q), #lanes::to_fused(v), #lanes::to_fused(&tau))
                {
                    // SAFETY: `enabled` holds only where the processor has AVX2 and FMA.
                    let r = unsafe {
                        ::filippov::runtime::compact::fused::forward_dynamics_lanes(
                            &Self::__FILIPPOV_NODES,
                            &Self::__FILIPPOV_TABLE_LANES,
                            Self::__FILIPPOV_TABLE.1,
                            q4,
                            v4,
                            t4,
                        )
                    };
                    return #lanes::from_fused::<[T; #n], _>(r);
                }
            }
        },
        None => quote!(),
    };
    let generic = quote! {
        #[doc = " `v̇ = M⁻¹ (τ + τ_p − C v − g)` on any scalar, the parameters `p` in \
                 declaration order, by the compact articulated-body algorithm."]
        #[inline]
        fn forward_dynamics_generic<T: ::filippov::runtime::Real>(
            p: &[T; #np],
            q: &[T; #n],
            v: &[T; #n],
            tau: &[T; #n],
        ) -> [T; #n] {
            let _ = p;
            let tau = #forces_generic;
            #lanes_twin
            let (bodies, gravity) = #table_generic;
            ::filippov::runtime::compact::aba::forward_dynamics(
                &Self::__FILIPPOV_NODES, &bodies, gravity, q, v, &tau,
            )
        }
    };
    let generic_jacobian = quote! {
        #[doc = " Forward dynamics and its Jacobian with respect to `(q, v)` on any scalar, by \
                 dual numbers of that scalar through the compact articulated-body algorithm, \
                 the matrices arrays of rows."]
        fn forward_dynamics_jacobian_generic<T: ::filippov::runtime::Real>(
            p: &[T; #np],
            q: &[T; #n],
            v: &[T; #n],
            tau: &[T; #n],
        ) -> ::filippov::runtime::kernels::GenericJacobian<T, #n> {
            #dual_params_generic
            let td = tau.map(::filippov::runtime::Dual::constant);
            let (bodies, gravity) = #table_generic;
            let (acceleration, d_dq, d_dv) =
                ::filippov::runtime::compact::jacobian::forward_dynamics_jacobian(
                    &Self::__FILIPPOV_NODES, &bodies, gravity, q, v, #forces_dual,
                );
            ::filippov::runtime::kernels::GenericJacobian { acceleration, d_dq, d_dv }
        }
    };
    let mat_t = quote!(::filippov::nalgebra::SMatrix<f64, #n, #n>);
    let mass = quote! {
        /// Mass matrix `M(q)` by the composite-rigid-body algorithm, one loop over a
        /// table of the bodies (`runtime::compact`).
        #[inline]
        fn mass_matrix(&self, q: &#vec_t) -> #mat_t {
            let q: [f64; #n] = (*q).into();
            let (bodies, _) = &#table_f64;
            // Symmetric: its rows are its columns. Each branch returns the kernel's
            // result directly, so that it is built in the caller's place (one `let` for
            // both would be a copy of its N² entries).
            #[cfg(target_arch = "x86_64")]
            if ::filippov::runtime::numerics::fused::enabled() {
                // SAFETY: `enabled` holds only where the processor has AVX2 and FMA.
                return ::filippov::nalgebra::SMatrix::<f64, #n, #n>::from_data(
                    ::filippov::nalgebra::ArrayStorage(unsafe {
                        ::filippov::runtime::compact::fused::mass_matrix(
                            &Self::__FILIPPOV_NODES, &Self::__FILIPPOV_PAIRS, bodies, &q,
                        )
                    }),
                );
            }
            ::filippov::nalgebra::SMatrix::<f64, #n, #n>::from_data(::filippov::nalgebra::ArrayStorage(
                ::filippov::runtime::compact::crba::mass_matrix(
                    &Self::__FILIPPOV_NODES, &Self::__FILIPPOV_PAIRS, bodies, &q,
                ),
            ))
        }
    };
    let mass_lanes_twin = match &constant {
        Some(_) => quote! {
            #[cfg(target_arch = "x86_64")]
            if ::filippov::runtime::numerics::fused::enabled() {
                if let Some(q4) = #lanes::to_fused(q) {
                    // SAFETY: `enabled` holds only where the processor has AVX2 and FMA.
                    let m = unsafe {
                        ::filippov::runtime::compact::fused::mass_matrix_lanes(
                            &Self::__FILIPPOV_NODES,
                            &Self::__FILIPPOV_PAIRS,
                            &Self::__FILIPPOV_TABLE_LANES,
                            q4,
                        )
                    };
                    return #lanes::from_fused::<[[T; #n]; #n], _>(m);
                }
            }
        },
        None => quote!(),
    };
    let generic_mass = quote! {
        #[doc = " `M(q)` on any scalar, an array of rows, by the compact composite-rigid-body \
                 algorithm."]
        #[inline]
        fn mass_matrix_generic<T: ::filippov::runtime::Real>(p: &[T; #np], q: &[T; #n]) -> [[T; #n]; #n] {
            let _ = p;
            #mass_lanes_twin
            let (bodies, _) = #table_generic;
            ::filippov::runtime::compact::crba::mass_matrix(
                &Self::__FILIPPOV_NODES, &Self::__FILIPPOV_PAIRS, &bodies, q,
            )
        }
    };
    Compact {
        core,
        generic,
        generic_jacobian,
        mass,
        generic_mass,
        helpers,
    }
}
