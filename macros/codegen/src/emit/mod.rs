//! Emission: the `Mechanism` impl from the kernels, one generated function per method
//! ([`function`]), the numeric model description ([`describe`]) and, on error, a stub
//! impl that keeps secondary errors away ([`fallback`]).

pub mod compact;
pub mod contacts;
pub mod describe;
pub mod fallback;
pub mod function;
pub mod loops;
pub mod nonsmooth;
pub mod validate;

use proc_macro2::{Literal, TokenStream};
use quote::{format_ident, quote};

use crate::mech::Kernels;
use crate::model::Model;
use crate::sym::{Id, InputKind, OpCount};
use function::{Signature, emit};

/// What was emitted for one method, for tests and the report.
#[derive(Clone, Debug)]
pub struct FnStats {
    pub name: &'static str,
    pub ops: OpCount,
    pub lets: usize,
}

pub(crate) fn vector(outs: Vec<TokenStream>, n: usize) -> TokenStream {
    quote!(::filippov::nalgebra::SVector::<f64, #n>::from([#(#outs),*]))
}

/// Column-major assembly of a row-major `rows × cols` list of entries.
pub(crate) fn rect_matrix(outs: Vec<TokenStream>, rows: usize, cols: usize) -> TokenStream {
    let columns: Vec<TokenStream> = (0..cols)
        .map(|j| {
            let col: Vec<&TokenStream> = (0..rows).map(|i| &outs[i * cols + j]).collect();
            quote!([#(#col),*])
        })
        .collect();
    quote!(::filippov::nalgebra::SMatrix::<f64, #rows, #cols>::from([#(#columns),*]))
}

/// The methods of one emitted impl, each a straight-line function of the scene's
/// graph: their code, the helpers they share, and their statistics.
pub(crate) struct Methods<'a> {
    pub graph: &'a crate::sym::Graph,
    pub params: &'a [proc_macro2::Ident],
    /// `(n, nq)`: velocity and configuration dimensions.
    pub dims: (usize, usize),
    pub stats: &'a mut Vec<FnStats>,
    pub helpers: TokenStream,
    /// The methods [`add`](Self::add)ed so far.
    pub methods: TokenStream,
    /// `Some(P)`: associated functions generic over their scalar, the `P` parameters an
    /// input (see [`Signature::generic`]).
    pub generic: Option<usize>,
}

impl<'a> Methods<'a> {
    /// No methods yet, for `graph` over `params`, with `n` coordinates (`q` and `v`
    /// alike: the trees these impls are emitted for).
    pub fn new(
        graph: &'a crate::sym::Graph,
        params: &'a [proc_macro2::Ident],
        n: usize,
        stats: &'a mut Vec<FnStats>,
    ) -> Self {
        Self::with_dims(graph, params, (n, n), stats)
    }

    /// No methods yet, with `(n, nq)` velocity and configuration dimensions.
    pub fn with_dims(
        graph: &'a crate::sym::Graph,
        params: &'a [proc_macro2::Ident],
        dims: (usize, usize),
        stats: &'a mut Vec<FnStats>,
    ) -> Self {
        Methods {
            graph,
            params,
            dims,
            stats,
            helpers: TokenStream::new(),
            methods: TokenStream::new(),
            generic: None,
        }
    }

    /// As [`emit`](Self::emit), the method kept in [`methods`](Self::methods).
    pub fn add(
        &mut self,
        name: &'static str,
        inputs: Vec<InputKind>,
        ret: TokenStream,
        outs: &[Id],
        asm: &dyn Fn(Vec<TokenStream>) -> TokenStream,
        doc: &str,
    ) {
        let method = self.emit(name, inputs, ret, outs, asm, doc);
        self.methods.extend(method);
    }

    /// Emits method `name` with `inputs`, returning `ret` assembled from `outs` by `asm`;
    /// returns its code.
    pub fn emit(
        &mut self,
        name: &'static str,
        inputs: Vec<InputKind>,
        ret: TokenStream,
        outs: &[Id],
        asm: &dyn Fn(Vec<TokenStream>) -> TokenStream,
        doc: &str,
    ) -> TokenStream {
        let sig = Signature {
            generic: self.generic,
            // The kernels an explicit integrator calls at every stage.
            fused: matches!(
                name,
                "forward_dynamics"
                    | "mass_matrix"
                    | "forward_dynamics_generic"
                    | "mass_matrix_generic"
            ),
            vis: quote!(),
            elements: 0,
            name: format_ident!("{}", name),
            inputs,
            ret,
            doc: doc.to_string(),
        };
        let e = emit(self.graph, self.params, self.dims, &sig, outs, asm);
        self.stats.push(FnStats {
            name,
            ops: self.graph.count_ops(outs),
            lets: e.lets,
        });
        self.helpers.extend(e.helpers);
        e.method
    }
}

/// Column-major assembly of a row-major `n × n` list of entries.
pub(crate) fn matrix(outs: Vec<TokenStream>, n: usize) -> TokenStream {
    rect_matrix(outs, n, n)
}

pub fn mechanism_impl(model: &Model, k: &Kernels) -> (TokenStream, Vec<FnStats>) {
    use InputKind::*;
    let n = k.dof;
    let nq = model.config_dim();
    let lie = model.is_lie();
    let g = &k.graph;
    let params = &model.params;
    let ident = &model.ident;
    let vec_t = quote!(::filippov::nalgebra::SVector<f64, #n>);
    let mat_t = quote!(::filippov::nalgebra::SMatrix<f64, #n, #n>);
    let flat = |m: &[Vec<Id>]| m.iter().flatten().copied().collect::<Vec<Id>>();
    let mut helpers = TokenStream::new();
    let mut stats = Vec::new();
    // Large trees: forward dynamics and its Jacobian as loops over a table.
    let compact = k
        .compact
        .as_ref()
        .map(|ck| compact::compact_impl(model, k, ck, &mut stats));
    let mut core = Methods::with_dims(g, params, (n, nq), &mut stats);
    let mut add = |name: &'static str,
                   inputs: Vec<InputKind>,
                   ret: TokenStream,
                   outs: Vec<Id>,
                   asm: &dyn Fn(Vec<TokenStream>) -> TokenStream,
                   doc: &str|
     -> TokenStream { core.emit(name, inputs, ret, &outs, asm, doc) };
    let vasm = |o: Vec<TokenStream>| vector(o, n);
    let masm = |o: Vec<TokenStream>| matrix(o, n);
    let emits = model.emit;
    // What every integrator calls: in the core trait.
    let mut methods = match &compact {
        Some(c) => c.mass.clone(),
        None => add(
            "mass_matrix",
            vec![Q],
            mat_t.clone(),
            flat(&k.mass),
            &masm,
            " Mass matrix `M(q)` (composite-rigid-body algorithm, unrolled).",
        ),
    };
    if let Some(c) = &compact {
        methods.extend(c.core.clone());
        helpers.extend(c.helpers.clone());
    } else {
        methods.extend(add(
            "forward_dynamics",
            vec![Q, V, Tau],
            vec_t.clone(),
            k.forward.clone(),
            &vasm,
            &format!(
                " Forward dynamics `M⁻¹ (τ + τ_p − C v − g)` {}.",
                algorithm_doc(k.algorithms[0])
            ),
        ));
        let mut jac_outs = k.jacobian_forward.clone();
        jac_outs.extend(flat(&k.jac_q));
        jac_outs.extend(flat(&k.jac_v));
        methods.extend(add(
        "forward_dynamics_jacobian",
        vec![Q, V, Tau],
        quote!(::filippov::runtime::system::ForwardJacobian<#n>),
        jac_outs,
        &|o: Vec<TokenStream>| {
            let acc = vector(o[..n].to_vec(), n);
            let dq = matrix(o[n..n + n * n].to_vec(), n);
            let dv = matrix(o[n + n * n..].to_vec(), n);
            quote!(::filippov::runtime::system::ForwardJacobian { acceleration: #acc, d_dq: #dq, d_dv: #dv })
        },
        &format!(
            " Forward dynamics and its symbolic Jacobian with respect to `(q, v)`, \
             `∂v̇/∂x = −M⁻¹ ∂ID/∂x`, {}.",
            algorithm_doc(k.algorithms[1])
        ),
    ));
    }

    // Asked for by name (`emit = [...]`): one trait each, so that a kernel the scene
    // did not ask for is a compile error naming the option, not dead code in every build.
    let generics = if lie { quote!(<#n, #nq>) } else { quote!(<#n>) };
    let mut optional = TokenStream::new();
    let mut kernel = |tr: &str, body: TokenStream| {
        let tr = format_ident!("{}", tr);
        optional.extend(quote! {
            impl ::filippov::runtime::kernels::#tr #generics for #ident { #body }
        });
    };
    if emits.christoffel && !lie {
        let chris: Vec<Id> = k
            .christoffel
            .iter()
            .flat_map(|ci| ci.iter().flatten().copied())
            .collect();
        kernel(
            "Christoffel",
            add(
                "christoffel_symbols",
                vec![Q],
                quote!([#mat_t; #n]),
                chris,
                &|o: Vec<TokenStream>| {
                    let per: Vec<TokenStream> =
                        o.chunks(n * n).map(|c| matrix(c.to_vec(), n)).collect();
                    quote!([#(#per),*])
                },
                " Christoffel symbols of the first kind, `out[i][(j, k)] = c_ijk`.",
            ),
        );
    }
    if emits.coriolis {
        kernel(
            "Coriolis",
            add(
                "coriolis_matrix",
                vec![Q, V],
                mat_t.clone(),
                flat(&k.coriolis),
                &masm,
                if lie {
                    " Coriolis matrix `C_ij = Σ_k c_ijk v_k + (M v)·[e_i, e_j]`, `c_ijk` the \
                     Christoffel symbols in local exponential coordinates."
                } else {
                    " Coriolis matrix `C_ij = Σ_k c_ijk v_k`."
                },
            ),
        );
    }
    if emits.gravity {
        kernel(
            "Gravity",
            add(
                "gravity",
                vec![Q],
                vec_t.clone(),
                k.gravity.clone(),
                &vasm,
                " Generalised gravity force `g(q)`.",
            ),
        );
    }
    if emits.bias {
        kernel(
            "Bias",
            add(
                "bias",
                vec![Q, V],
                vec_t.clone(),
                k.bias.clone(),
                &vasm,
                " Bias force `C(q, v) v + g(q)` (recursive Newton–Euler with zero acceleration).",
            ),
        );
    }
    if emits.passive_forces {
        kernel(
            "PassiveForces",
            add(
                "passive_forces",
                vec![Q, V],
                vec_t.clone(),
                k.passive.clone(),
                &vasm,
                " Spring and damper forces on the joint coordinates.",
            ),
        );
    }
    if emits.inverse_dynamics {
        kernel(
            "InverseDynamics",
            add(
                "inverse_dynamics",
                vec![Q, V, A],
                vec_t.clone(),
                k.inverse.clone(),
                &vasm,
                " Inverse dynamics `M a + C v + g − τ_p` (recursive Newton–Euler).",
            ),
        );
    }
    if let Some((kinetic, potential)) = k.energy {
        let mut body = add(
            "kinetic_energy",
            vec![Q, V],
            quote!(f64),
            vec![kinetic],
            &|mut o| o.remove(0),
            " Kinetic energy `½ vᵀ M v`.",
        );
        body.extend(add(
            "potential_energy",
            vec![Q],
            quote!(f64),
            vec![potential],
            &|mut o| o.remove(0),
            " Potential energy of gravity and springs.",
        ));
        kernel("Energy", body);
    }

    helpers.extend(core.helpers);
    if !k.frames.is_empty() {
        let (body, frame_helpers) = frames_impl(model, k, &mut stats);
        helpers.extend(frame_helpers);
        kernel("Kinematics", body);
    }

    if emits.generic {
        let np = params.len();
        let mut gm = Methods::with_dims(g, params, (n, nq), &mut stats);
        gm.generic = Some(np);
        let rows = |o: Vec<TokenStream>| -> TokenStream {
            let rows: Vec<TokenStream> = o.chunks(n).map(|r| quote!([#(#r),*])).collect();
            quote!([#(#rows),*])
        };
        let array = |o: Vec<TokenStream>| quote!([#(#o),*]);
        let mut methods = match &compact {
            Some(c) => c.generic.clone(),
            None => gm.emit(
                "forward_dynamics_generic",
                vec![Q, V, Tau],
                quote!([T; #n]),
                &k.forward,
                &array,
                " `v̇ = M⁻¹ (τ + τ_p − C v − g)` on any scalar, the parameters `p` in \
                 declaration order.",
            ),
        };
        methods.extend(match &compact {
            Some(c) => c.generic_mass.clone(),
            None => gm.emit(
                "mass_matrix_generic",
                vec![Q],
                quote!([[T; #n]; #n]),
                &flat(&k.mass),
                &rows,
                " `M(q)` on any scalar, an array of rows.",
            ),
        });
        methods.extend(gm.emit(
            "inverse_dynamics_generic",
            vec![Q, V, A],
            quote!([T; #n]),
            &k.inverse,
            &array,
            " `τ = M a + C v + g − τ_p` on any scalar.",
        ));
        let mut jac_outs = k.jacobian_forward.clone();
        jac_outs.extend(flat(&k.jac_q));
        jac_outs.extend(flat(&k.jac_v));
        if let Some(c) = &compact {
            methods.extend(c.generic_jacobian.clone());
        } else {
            methods.extend(gm.emit(
                "forward_dynamics_jacobian_generic",
                vec![Q, V, Tau],
                quote!(::filippov::runtime::kernels::GenericJacobian<T, #n>),
                &jac_outs,
                &|o: Vec<TokenStream>| {
                    let acc = &o[..n];
                    let dq = rows(o[n..n + n * n].to_vec());
                    let dv = rows(o[n + n * n..].to_vec());
                    quote!(::filippov::runtime::kernels::GenericJacobian {
                        acceleration: [#(#acc),*], d_dq: #dq, d_dv: #dv
                    })
                },
                " Forward dynamics and its symbolic Jacobian with respect to `(q, v)` on any \
             scalar, the matrices arrays of rows.",
            ));
        }
        helpers.extend(gm.helpers);
        let names: Vec<String> = params.iter().map(|p| p.to_string()).collect();
        optional.extend(quote! {
            impl ::filippov::runtime::kernels::GenericDynamics<#n, #nq, #np> for #ident {
                const PARAMETERS: [&'static str; #np] = [#(#names),*];
                fn parameters(&self) -> [f64; #np] {
                    [#(self.#params),*]
                }
                #methods
            }
        });
    }
    let names: Vec<Literal> = model
        .joint_names()
        .iter()
        .map(|s| Literal::string(s))
        .collect();
    let describe = describe::model_fn(model);
    let validate = validate::validate_fn(model);
    let inputs = inputs_items(model, n);
    let (nonsmooth, ns_helpers) = nonsmooth::nonsmooth_impl(model, k, &mut stats);
    helpers.extend(ns_helpers);
    let (loop_constraints, loop_helpers) = loops::loops_impl(model, k, &mut stats);
    helpers.extend(loop_helpers);
    let (contact_kernels, contact_helpers) = contacts::contacts_impl(model, k, &mut stats);
    helpers.extend(contact_helpers);
    let head = if lie {
        let rot: Vec<TokenStream> = model
            .links
            .iter()
            .filter(|l| l.kind == crate::model::JointKind::Spherical)
            .filter_map(|l| Some((l.config?, l.coordinate?)))
            .map(|(s, c)| quote!((#s, #c)))
            .collect();
        let euclid: Vec<TokenStream> = model
            .links
            .iter()
            .filter(|l| l.kind != crate::model::JointKind::Spherical)
            .filter_map(|l| Some((l.config?, l.coordinate?, l.kind.dof())))
            .flat_map(|(s, c, d)| (0..d).map(move |k| (s + k, c + k)))
            .map(|(s, c)| quote!((#s, #c)))
            .collect();
        quote! {
            impl ::filippov::runtime::liegroup::LieMechanism<#n, #nq> for #ident {
                const COORDINATES: [&'static str; #n] = [#(#names),*];
                const ROTATIONS: &'static [(usize, usize)] = &[#(#rot),*];
                const EUCLID: &'static [(usize, usize)] = &[#(#euclid),*];
                #methods
                #validate
                #describe
            }
        }
    } else {
        // Named so that the smooth path can refuse a scene it would silently misread.
        let elements = if model.elements.is_empty() {
            quote!()
        } else {
            let e = model.elements.iter().map(|e| e.name.as_str());
            quote!(const NON_SMOOTH_ELEMENTS: &'static [&'static str] = &[#(#e),*];)
        };
        let loops = match &k.loops {
            None => quote!(),
            Some(lo) => {
                let m = lo.constraints.rows();
                let rows = lo.constraints.names.iter().map(|s| s.as_str());
                quote! {
                    const LOOP_CONSTRAINTS: &'static [&'static str] = &[#(#rows),*];
                    fn project_onto_loops(
                        &self,
                        q: &mut ::filippov::nalgebra::SVector<f64, #n>,
                        v: &mut ::filippov::nalgebra::SVector<f64, #n>,
                        held: &[bool],
                    ) -> ::core::result::Result<bool, ::filippov::runtime::loops::LoopError> {
                        ::filippov::runtime::loops::project::<Self, #n, #m>(self, q, v, held)
                    }
                    fn loop_conditioning(&self, q: &::filippov::nalgebra::SVector<f64, #n>) -> f64 {
                        ::filippov::runtime::loops::conditioning::<Self, #n, #m>(self, q)
                    }
                    fn loop_forces(
                        &self,
                        q: &::filippov::nalgebra::SVector<f64, #n>,
                        v: &::filippov::nalgebra::SVector<f64, #n>,
                        tau: &::filippov::nalgebra::SVector<f64, #n>,
                        out: &mut [f64],
                    ) {
                        let (_, lambda) =
                            <Self as ::filippov::runtime::loops::LoopConstraints<#n, #m>>::constrained_forward_dynamics(
                                self, q, v, tau,
                            );
                        out.copy_from_slice(lambda.as_slice());
                    }
                }
            }
        };
        quote! {
            impl ::filippov::runtime::system::Mechanism<#n> for #ident {
                const JOINTS: [&'static str; #n] = [#(#names),*];
                #elements
                #loops
                #methods
                #validate
                #describe
            }
        }
    };
    let config = if lie {
        quote! {
            /// Number of configuration slots (quaternions take four).
            pub const CONFIG: usize = #nq;
        }
    } else {
        quote!()
    };
    let parameters = parameters_impl(model);
    let code = quote! {
        #head
        #parameters
        #optional
        #nonsmooth
        #loop_constraints
        #contact_kernels
        impl #ident {
            /// Number of degrees of freedom.
            pub const DOF: usize = #n;
            #config
            #inputs
            #helpers
        }
    };
    (code, stats)
}

/// `Parameters`: the fields by name, and the scene from their values.
fn parameters_impl(model: &Model) -> TokenStream {
    let ident = &model.ident;
    let params = &model.params;
    let names: Vec<String> = params.iter().map(|p| p.to_string()).collect();
    let np = params.len();
    let index = 0..np;
    // Braces build unit structs too (`Arm {}`).
    let build = quote!(#ident { #(#params: values[#index]),* });
    quote! {
        impl ::filippov::runtime::system::Parameters for #ident {
            const NAMES: &'static [&'static str] = &[#(#names),*];
            fn values(&self) -> ::std::vec::Vec<f64> {
                ::std::vec![#(self.#params),*]
            }
            fn from_values(values: &[f64]) -> ::core::option::Option<Self> {
                (values.len() == #np).then(|| #build)
            }
        }
    }
}

/// The `Kinematics` kernel: one private method per frame for its pose and one for its
/// Jacobian (each straight-line code for that frame alone), and the trait methods that
/// dispatch on the frame id.
fn frames_impl(model: &Model, k: &Kernels, stats: &mut Vec<FnStats>) -> (TokenStream, TokenStream) {
    let (n, nq) = (k.dof, model.config_dim());
    let g = &k.graph;
    let mut helpers = TokenStream::new();
    let mut pose_arms = Vec::new();
    let mut jac_arms = Vec::new();
    let (mut pose_lets, mut jac_lets) = (0, 0);
    let last = k.frames.len() - 1;
    for (i, f) in k.frames.iter().enumerate() {
        let doc = format!(" World pose of frame `{}`.", f.name);
        let sig = Signature {
            generic: None,
            fused: false,
            vis: quote!(),
            elements: 0,
            name: format_ident!("__filippov_frame_pose_{}", i),
            inputs: vec![InputKind::Q],
            ret: quote!(::filippov::nalgebra::Isometry3<f64>),
            doc,
        };
        let e = emit(g, &model.params, (n, nq), &sig, &f.pose, &|o: Vec<
            TokenStream,
        >| {
            let (r, p) = o.split_at(9);
            quote!(::filippov::runtime::kernels::isometry([#(#r),*], [#(#p),*]))
        });
        pose_lets += e.lets;
        helpers.extend(e.method);
        helpers.extend(e.helpers);
        let doc = format!(
            " Jacobian of frame `{}`: rows `ṗ` then `ω`, world axes.",
            f.name
        );
        let sig = Signature {
            generic: None,
            fused: false,
            vis: quote!(),
            elements: 0,
            name: format_ident!("__filippov_frame_jacobian_{}", i),
            inputs: vec![InputKind::Q],
            ret: quote!(::filippov::nalgebra::SMatrix<f64, 6, #n>),
            doc,
        };
        let e = emit(g, &model.params, (n, nq), &sig, &f.jacobian, &|o: Vec<
            TokenStream,
        >| {
            let cols: Vec<TokenStream> = (0..n)
                .map(|j| {
                    let col = (0..6).map(|r| &o[r * n + j]);
                    quote!([#(#col),*])
                })
                .collect();
            quote!(::filippov::nalgebra::SMatrix::<f64, 6, #n>::from([#(#cols),*]))
        });
        jac_lets += e.lets;
        helpers.extend(e.method);
        helpers.extend(e.helpers);
        let (pose, jac) = (
            format_ident!("__filippov_frame_pose_{}", i),
            format_ident!("__filippov_frame_jacobian_{}", i),
        );
        // The last frame takes every other index too: ids come only from `frame` and
        // `frame_at`, which check the range, so no arm can panic.
        let pat = if i == last { quote!(_) } else { quote!(#i) };
        pose_arms.push(quote!(#pat => self.#pose(q)));
        jac_arms.push(quote!(#pat => self.#jac(q)));
    }
    let poses: Vec<Id> = k
        .frames
        .iter()
        .flat_map(|f| f.pose.iter().copied())
        .collect();
    let jacs: Vec<Id> = k
        .frames
        .iter()
        .flat_map(|f| f.jacobian.iter().copied())
        .collect();
    stats.push(FnStats {
        name: "frame_pose",
        ops: g.count_ops(&poses),
        lets: pose_lets,
    });
    stats.push(FnStats {
        name: "frame_jacobian",
        ops: g.count_ops(&jacs),
        lets: jac_lets,
    });
    let names = k.frames.iter().map(|f| f.name.as_str());
    let body = quote! {
        const FRAMES: &'static [&'static str] = &[#(#names),*];
        #[inline]
        fn frame_pose(
            &self,
            frame: ::filippov::runtime::kernels::FrameId<Self>,
            q: &::filippov::nalgebra::SVector<f64, #nq>,
        ) -> ::filippov::nalgebra::Isometry3<f64> {
            match frame.index() { #(#pose_arms,)* }
        }
        #[inline]
        fn frame_jacobian(
            &self,
            frame: ::filippov::runtime::kernels::FrameId<Self>,
            q: &::filippov::nalgebra::SVector<f64, #nq>,
        ) -> ::filippov::nalgebra::SMatrix<f64, 6, #n> {
            match frame.index() { #(#jac_arms,)* }
        }
    };
    (body, helpers)
}

/// The actuated coordinates and the map `u ↦ τ` (zero on passive joints); nothing when
/// the scene declares no inputs.
fn inputs_items(model: &Model, n: usize) -> TokenStream {
    if model.inputs.is_empty() {
        return TokenStream::new();
    }
    let k = model.inputs.len();
    let idx = &model.inputs;
    let entries: Vec<TokenStream> = (0..n)
        .map(|c| match model.inputs.iter().position(|&i| i == c) {
            Some(j) => quote!(u[#j]),
            None => quote!(0.0),
        })
        .collect();
    quote! {
        /// The actuated coordinates, in the order of the input vector `u`.
        pub const INPUTS: [usize; #k] = [#(#idx),*];
        /// Generalised forces `τ = B u` of an input vector (zero on passive joints).
        #[inline]
        pub fn input_forces(u: &::filippov::nalgebra::SVector<f64, #k>) -> ::filippov::nalgebra::SVector<f64, #n> {
            ::filippov::nalgebra::SVector::<f64, #n>::from([#(#entries),*])
        }
    }
}

/// Replaces every `::filippov` the emitter wrote by `path` (the `crate = …` option), in
/// one pass over the finished tokens so that no emitter needs to know.
pub fn rename_crate(tokens: TokenStream, path: &syn::Path) -> TokenStream {
    use proc_macro2::{Group, Spacing, TokenTree};
    let replacement = quote!(#path);
    let trees: Vec<TokenTree> = tokens.into_iter().collect();
    let mut out = Vec::with_capacity(trees.len());
    let mut i = 0;
    while i < trees.len() {
        if let (Some(TokenTree::Punct(a)), Some(TokenTree::Punct(b)), Some(TokenTree::Ident(id))) =
            (trees.get(i), trees.get(i + 1), trees.get(i + 2))
            && a.as_char() == ':'
            && a.spacing() == Spacing::Joint
            && b.as_char() == ':'
            && id == "filippov"
            // A leading `::filippov`, not `a::filippov`: the token before is not a path
            // segment (an identifier that is not a keyword such as `impl` or `for`).
            && !matches!(
                i.checked_sub(1).and_then(|j| trees.get(j)),
                Some(TokenTree::Ident(prev)) if syn::parse_str::<syn::Ident>(&prev.to_string()).is_ok()
            )
        {
            out.extend(replacement.clone());
            i += 3;
            continue;
        }
        match &trees[i] {
            TokenTree::Group(g) => {
                let mut inner = Group::new(g.delimiter(), rename_crate(g.stream(), path));
                inner.set_span(g.span());
                out.push(TokenTree::Group(inner));
            }
            t => out.push(t.clone()),
        }
        i += 1;
    }
    out.into_iter().collect()
}

/// How a kernel that solves with `M` was built, for its doc comment.
fn algorithm_doc(a: crate::model::Algorithm) -> &'static str {
    match a {
        crate::model::Algorithm::Aba => "by the articulated-body algorithm, unrolled per link",
        _ => "by a sparse `LᵀDL` of the CRBA mass matrix",
    }
}
