//! One generated function from a set of output nodes.
//!
//! Every reachable node used more than once gets a `let` (common subexpressions, in
//! arena order, which is topological); a node used once is written inline into its only
//! user. Each `sin`/`cos` pair of one argument comes from a single `sin_cos()`, and in a
//! function emitted whole the pairs of inputs come from one batched `sin_cos_n`.
//! Functions beyond [`WHOLE`] lets are split into helper functions of [`CHUNK`] lets that pass the values
//! crossing a split through a stack array: rustc's time grows much faster than linearly
//! in the length of one function, and its debug build overflows its stack beyond a few
//! thousand lets.

use std::collections::BTreeSet;

use proc_macro2::{Ident, Literal, Span, TokenStream};
use quote::{format_ident, quote};

use crate::sym::{Graph, Id, InputKind, Node, Unary};

/// A function with at most this many lets is emitted whole (no call overhead in the
/// kernels of small and mid-sized scenes: the Panda's forward dynamics has 350).
pub const WHOLE: usize = 1200;
/// Lets per helper function when a function is split. Measured on the default kernels of
/// a 50-link planar chain (about 290,000 operations, almost all in the Jacobian), release
/// build of the user's crate: 63 s with chunks of 1,200, 53 s with 400, 46 s with 200
/// and 47 s with 100, the kernels' run time unchanged.
pub const CHUNK: usize = 200;
/// A function with more lets than this gets no fused twin: the twin compiles the
/// function a second time, and beyond this size the compile time it adds weighs more
/// than the run time it saves (the humanoid's forward dynamics, ten chunks of up to 200 lets, has
/// one; the unrolled kernels of large trees, which `auto` makes compact anyway, do not).
pub const TWIN_MAX: usize = 4 * WHOLE;
/// Deepest expression written inline (operators nested), beyond which a `let` is bound.
pub const MAX_INLINE_DEPTH: u32 = 32;

/// What a generated function looks like from outside.
pub struct Signature {
    pub name: Ident,
    /// The inputs the function takes (`q`, `v`, `a`, `tau`), in order.
    pub inputs: Vec<InputKind>,
    pub ret: TokenStream,
    pub doc: String,
    /// `pub` for inherent methods, empty for trait methods.
    pub vis: TokenStream,
    /// Length of the element-force argument `f` (when `inputs` has [`InputKind::F`]).
    pub elements: usize,
    /// `Some(P)`: an associated function generic over its scalar `T: Real`, the `P`
    /// parameters an input `p: &[T; P]` (no `self`); `None`: a method on `f64`.
    pub generic: Option<usize>,
    /// Also emit a twin compiled for AVX2 and FMA, products fused into sums, which the
    /// method calls when the processor has them (`runtime::numerics::fused`): on `f64`
    /// for a method, on `F64x4` lanes (`runtime::numerics::fused_lanes`) for a function
    /// generic over its scalar called on `f64x4`; a function split into chunks has
    /// fused twins of its chunks. For what the integrators call most.
    pub fused: bool,
}

/// A generated method and the helper chunks it calls.
pub struct Emitted {
    pub method: TokenStream,
    pub helpers: TokenStream,
    pub lets: usize,
}

#[derive(Clone, Copy)]
enum Item {
    Let(Id),
    SinCos(Id, Id),
}

fn arg_name(k: InputKind) -> Ident {
    Ident::new(
        match k {
            InputKind::Q => "q",
            InputKind::V => "v",
            InputKind::A => "a",
            InputKind::Tau => "tau",
            InputKind::F => "f",
        },
        Span::call_site(),
    )
}

/// Emits `sig` computing `outputs`; `assemble` builds the return value from the rendered
/// outputs (in order). `dof` is the length of `v`, `a` and `tau`, `config` that of `q`
/// (they differ only with Lie-group joints).
pub fn emit(
    g: &Graph,
    params: &[Ident],
    (dof, config): (usize, usize),
    sig: &Signature,
    outputs: &[Id],
    assemble: &dyn Fn(Vec<TokenStream>) -> TokenStream,
) -> Emitted {
    let reach = g.reachable(outputs);
    let mut uses = vec![0u32; g.len()];
    for (i, _) in reach.iter().enumerate().filter(|(_, r)| **r) {
        match g.node(Id(i as u32)) {
            Node::Add(a, b) | Node::Mul(a, b) => {
                uses[a.index()] += 1;
                uses[b.index()] += 1;
            }
            Node::Unary(_, a) => uses[a.index()] += 1,
            _ => {}
        }
    }
    for o in outputs {
        uses[o.index()] += 1;
    }
    let is_leaf = |id: Id| matches!(g.node(id), Node::Const(_) | Node::Param(_) | Node::Input(_));
    let is_trig = |id: Id| matches!(g.node(id), Node::Unary(Unary::Sin | Unary::Cos, _));
    let mut bound: Vec<bool> = (0..g.len())
        .map(|i| reach[i] && !is_leaf(Id(i as u32)) && (uses[i] >= 2 || is_trig(Id(i as u32))))
        .collect();
    // No inline expression deeper than MAX_INLINE_DEPTH: a node that would be is bound
    // to a `let` instead, so that neither rustc (which recurses over expression depth
    // and overflowed its stack on a 1,000-term sum written inline) nor the renderer
    // below meets a deep tree, whatever the user wrote. Arena order is topological, so
    // one forward pass sees every child before its parent.
    let mut depth = vec![0u32; g.len()];
    for i in 0..g.len() {
        if !reach[i] {
            continue;
        }
        let child = |c: Id| {
            if bound[c.index()] {
                0
            } else {
                depth[c.index()]
            }
        };
        let d = 1 + match g.node(Id(i as u32)) {
            Node::Add(a, b) | Node::Mul(a, b) => child(a).max(child(b)),
            Node::Unary(_, a) => child(a),
            _ => 0,
        };
        if d > MAX_INLINE_DEPTH && !bound[i] {
            bound[i] = true;
        }
        depth[i] = if bound[i] { 0 } else { d };
    }

    // Items in topological order; sin and cos of one argument together.
    let mut items = Vec::new();
    let mut done = vec![false; g.len()];
    for i in 0..g.len() {
        let id = Id(i as u32);
        if !bound[i] || done[i] {
            continue;
        }
        done[i] = true;
        let partner = match g.node(id) {
            Node::Unary(Unary::Sin, x) => g.find(Node::Unary(Unary::Cos, x)).map(|c| (id, c)),
            Node::Unary(Unary::Cos, x) => g.find(Node::Unary(Unary::Sin, x)).map(|s| (s, id)),
            _ => None,
        };
        match partner {
            Some((s, c)) if bound[s.index()] && bound[c.index()] => {
                done[s.index()] = true;
                done[c.index()] = true;
                items.push(Item::SinCos(s, c));
            }
            _ => items.push(Item::Let(id)),
        }
    }

    // Names.
    let mut names: Vec<Option<Ident>> = vec![None; g.len()];
    let mut next = 0usize;
    let mut fresh = |id: Id, names: &mut Vec<Option<Ident>>| {
        let name = match g.node(id) {
            Node::Unary(op @ (Unary::Sin | Unary::Cos), x) => match g.node(x) {
                Node::Input(inp) if inp.kind == InputKind::Q => {
                    format_ident!("{}{}", if op == Unary::Sin { "s" } else { "c" }, inp.index)
                }
                _ => {
                    next += 1;
                    format_ident!("x{}", next - 1)
                }
            },
            _ => {
                next += 1;
                format_ident!("x{}", next - 1)
            }
        };
        names[id.index()] = Some(name);
    };
    for it in &items {
        match *it {
            Item::Let(id) => fresh(id, &mut names),
            Item::SinCos(s, c) => {
                fresh(s, &mut names);
                fresh(c, &mut names);
            }
        }
    }

    // Chunks: the last one lives in the method itself.
    let nchunks = if items.len() <= WHOLE {
        1
    } else {
        items.len().div_ceil(CHUNK)
    };
    let chunk_of_item = |k: usize| (k / CHUNK).min(nchunks - 1);
    let mut def_chunk = vec![usize::MAX; g.len()];
    for (k, it) in items.iter().enumerate() {
        match *it {
            Item::Let(id) => def_chunk[id.index()] = chunk_of_item(k),
            Item::SinCos(s, c) => {
                def_chunk[s.index()] = chunk_of_item(k);
                def_chunk[c.index()] = chunk_of_item(k);
            }
        }
    }
    // Where each node is rendered: a bound node in its chunk, an inline one in its user's.
    let mut home = vec![usize::MAX; g.len()];
    for o in outputs {
        if !bound[o.index()] {
            home[o.index()] = nchunks - 1;
        }
    }
    let mut slot = vec![usize::MAX; g.len()];
    let mut nslots = 0usize;
    let mut need_slot = |c: Id, h: usize, slot: &mut Vec<usize>| {
        if bound[c.index()] && def_chunk[c.index()] != h && slot[c.index()] == usize::MAX {
            slot[c.index()] = nslots;
            nslots += 1;
        }
    };
    for o in outputs {
        need_slot(*o, nchunks - 1, &mut slot);
    }
    for i in (0..g.len()).rev() {
        if !reach[i] {
            continue;
        }
        let h = if bound[i] { def_chunk[i] } else { home[i] };
        let kids: Vec<Id> = match g.node(Id(i as u32)) {
            Node::Add(a, b) | Node::Mul(a, b) => vec![a, b],
            Node::Unary(_, a) => vec![a],
            _ => vec![],
        };
        for c in kids {
            if bound[c.index()] {
                need_slot(c, h, &mut slot);
            } else {
                home[c.index()] = h;
            }
        }
    }

    let generic = sig.generic.is_some();
    let real = quote!(::filippov::runtime::Real);
    let mut r = Renderer {
        g,
        params,
        generic,
        fused: false,
        bound: &bound,
        names: &names,
        def_chunk: &def_chunk,
        slot: &slot,
    };
    let args: Vec<TokenStream> = sig
        .inputs
        .iter()
        .map(|k| {
            let a = arg_name(*k);
            let len = match k {
                InputKind::F => sig.elements,
                InputKind::Q => config,
                _ => dof,
            };
            if generic {
                quote!(#a: &[T; #len])
            } else {
                quote!(#a: &::filippov::nalgebra::SVector<f64, #len>)
            }
        })
        .collect();
    let mut arg_names: Vec<Ident> = sig.inputs.iter().map(|k| arg_name(*k)).collect();
    // A generic function's parameters come first, as an input.
    let (args, scalar, receiver, call) = match sig.generic {
        Some(np) => {
            let np = Literal::usize_unsuffixed(np);
            let mut all = vec![quote!(p: &[T; #np])];
            all.extend(args);
            arg_names.insert(0, Ident::new("p", Span::call_site()));
            (all, quote!(T), quote!(), quote!(Self::))
        }
        None => (args, quote!(f64), quote!(&self,), quote!(self.)),
    };
    let type_params = if generic {
        quote!(<T: #real>)
    } else {
        quote!()
    };
    let nslots_lit = Literal::usize_unsuffixed(nslots);
    let mut helpers = TokenStream::new();
    let mut calls = TokenStream::new();
    let mut chunk_items: Vec<Vec<Item>> = vec![Vec::new(); nchunks];
    for (k, it) in items.iter().enumerate() {
        chunk_items[chunk_of_item(k)].push(*it);
    }
    let mut main_body = TokenStream::new();
    // In a function emitted whole, the sines and cosines of inputs (the joint angles)
    // are taken in one batch at its start (`Real::sin_cos_n`; on `f64` one vectorised
    // evaluation instead of a library call per angle, `runtime::numerics::trig`).
    let batched: Vec<(Id, Id, Id)> = if nchunks == 1 {
        items
            .iter()
            .filter_map(|it| match *it {
                Item::SinCos(s, c) => match g.node(s) {
                    Node::Unary(_, x) if matches!(g.node(x), Node::Input(_)) => Some((s, c, x)),
                    _ => None,
                },
                Item::Let(_) => None,
            })
            .collect()
    } else {
        Vec::new()
    };
    let batched = if batched.len() >= 2 {
        batched
    } else {
        Vec::new()
    };
    // The fused twin (see `Signature::fused`), with fused twins of its helper chunks.
    let twin = sig.fused && items.len() <= TWIN_MAX;
    let mut fused_body = TokenStream::new();
    let mut fused_calls = TokenStream::new();
    // The twins on lanes keep 32-byte values on their stack: they align their frames
    // (`runtime::numerics::fused_lanes::align_frame`).
    let align = if generic {
        quote!(::filippov::runtime::numerics::fused_lanes::align_frame();)
    } else {
        quote!()
    };
    for fused in [false, true] {
        if fused && !twin {
            break;
        }
        r.fused = fused;
        let (main_body, calls) = if fused {
            (&mut fused_body, &mut fused_calls)
        } else {
            (&mut main_body, &mut calls)
        };
        for (c, its) in chunk_items.iter().enumerate() {
            let mut used = BTreeSet::new();
            let mut body = TokenStream::new();
            if c == 0 && !batched.is_empty() {
                let name = |id: Id| names[id.index()].as_ref().expect("named");
                let ss = batched.iter().map(|b| name(b.0));
                let cs = batched.iter().map(|b| name(b.1));
                let xs: Vec<TokenStream> =
                    batched.iter().map(|b| r.expr(b.2, c, &mut used)).collect();
                body.extend(if generic {
                    quote!(let ([#(#ss),*], [#(#cs),*]) = <T as #real>::sin_cos_n([#(#xs),*]);)
                } else {
                    let f = r.trig("sin_cos_n");
                    quote!(let ([#(#ss),*], [#(#cs),*]) = #f([#(#xs),*]);)
                });
            }
            for it in its {
                if let Item::SinCos(s, _) = *it
                    && batched.iter().any(|b| b.0 == s)
                {
                    continue;
                }
                let defs: Vec<Id> = match *it {
                    Item::Let(id) => {
                        let name = names[id.index()].as_ref().expect("named");
                        let e = r.inline(id, c, &mut used);
                        body.extend(quote!(let #name = #e;));
                        vec![id]
                    }
                    Item::SinCos(s, cs) => {
                        let (ns, nc) = (
                            names[s.index()].as_ref().expect("named"),
                            names[cs.index()].as_ref().expect("named"),
                        );
                        let Node::Unary(_, x) = g.node(s) else {
                            unreachable!()
                        };
                        let e = r.atom(x, c, &mut used);
                        body.extend(if generic {
                            quote!(let (#ns, #nc) = #real::sin_cos(#e);)
                        } else {
                            let f = r.trig("sin_cos");
                            quote!(let (#ns, #nc) = #f(#e);)
                        });
                        vec![s, cs]
                    }
                };
                for d in defs {
                    if slot[d.index()] != usize::MAX {
                        let k = Literal::usize_unsuffixed(slot[d.index()]);
                        let name = names[d.index()].as_ref().expect("named");
                        body.extend(quote!(t[#k] = #name;));
                    }
                }
            }
            if c + 1 == nchunks {
                let outs: Vec<TokenStream> =
                    outputs.iter().map(|o| r.expr(*o, c, &mut used)).collect();
                let ret = assemble(outs);
                let binds = bind_inputs(&used);
                *main_body = quote!(#binds #body #ret);
            } else if fused {
                let hname = format_ident!("__{}_fused_part{}", sig.name, c);
                let binds = bind_inputs(&used);
                helpers.extend(quote! {
                    /// A chunk of the fused twin.
                    ///
                    /// # Safety
                    /// Only on a processor with AVX2 and FMA.
                    #[cfg(target_arch = "x86_64")]
                    #[doc(hidden)]
                    #[inline(never)]
                    #[target_feature(enable = "avx2,fma")]
                    #[allow(clippy::all, unused_variables)]
                    unsafe fn #hname #type_params(#receiver #(#args,)* t: &mut [#scalar; #nslots_lit]) {
                        #align
                        #binds
                        #body
                    }
                });
                // SAFETY: called from the twin, which runs only where the processor has
                // AVX2 and FMA.
                calls.extend(quote!(unsafe { #call #hname(#(#arg_names,)* &mut t) };));
            } else {
                let hname = format_ident!("__{}_part{}", sig.name, c);
                let binds = bind_inputs(&used);
                helpers.extend(quote! {
                    #[doc(hidden)]
                    #[inline(never)]
                    #[allow(clippy::all, unused_variables)]
                    fn #hname #type_params(#receiver #(#args,)* t: &mut [#scalar; #nslots_lit]) {
                        #binds
                        #body
                    }
                });
                calls.extend(quote!(#call #hname(#(#arg_names,)* &mut t);));
            }
        }
    }
    let scratch = match (nchunks > 1, generic) {
        (false, _) => quote!(),
        (true, false) => quote!(let mut t = [0.0f64; #nslots_lit];),
        (true, true) => quote!(let mut t = [<T as #real>::cst(0.0); #nslots_lit];),
    };
    let (name, ret, doc, vis) = (&sig.name, &sig.ret, &sig.doc, &sig.vis);
    let dispatch = if twin {
        // The twin: on `f64` a method, on lanes a function the generic kernel calls on
        // `F64x4` (`runtime::numerics::fused_lanes`) when its scalar is `f64x4`.
        let tname = format_ident!("__{}_fused", sig.name);
        helpers.extend(quote! {
            /// The fused multiply–add twin (`runtime::numerics::fused`).
            ///
            /// # Safety
            /// Only on a processor with AVX2 and FMA.
            #[cfg(target_arch = "x86_64")]
            #[doc(hidden)]
            #[target_feature(enable = "avx2,fma")]
            #[allow(unused_variables, clippy::all)]
            pub unsafe fn #tname #type_params(#receiver #(#args),*) -> #ret {
                #align
                #scratch
                #fused_calls
                #fused_body
            }
        });
        if generic {
            let lanes = quote!(::filippov::runtime::numerics::fused_lanes);
            quote! {
                #[cfg(target_arch = "x86_64")]
                if ::filippov::runtime::numerics::fused::enabled() {
                    // (No `let` chain: the user's crate may be of an edition before 2024.)
                    if let (#(Some(#arg_names),)*) = (#(#lanes::to_fused(#arg_names),)*) {
                        // SAFETY: `enabled` holds only where the processor has AVX2 and FMA.
                        #[allow(unused_unsafe)]
                        let r = unsafe { Self::#tname::<#lanes::F64x4>(#(#arg_names),*) };
                        return #lanes::from_fused::<#ret, _>(r);
                    }
                }
            }
        } else {
            quote! {
                #[cfg(target_arch = "x86_64")]
                if ::filippov::runtime::numerics::fused::enabled() {
                    // SAFETY: `enabled` holds only where the processor has AVX2 and FMA.
                    #[allow(unused_unsafe)]
                    return unsafe { self.#tname(#(#arg_names),*) };
                }
            }
        }
    } else {
        quote!()
    };
    let method = quote! {
        #[doc = #doc]
        #[inline]
        #[allow(unused_variables, clippy::all)]
        #vis fn #name #type_params(#receiver #(#args),*) -> #ret {
            #dispatch
            #scratch
            #calls
            #main_body
        }
    };
    Emitted {
        method,
        helpers,
        lets: items.len(),
    }
}

fn bind_inputs(used: &BTreeSet<(InputKind, u16)>) -> TokenStream {
    let mut out = TokenStream::new();
    for (k, i) in used {
        let arg = arg_name(*k);
        let name = format_ident!("{}{}", arg, *i);
        let idx = Literal::usize_unsuffixed(*i as usize);
        out.extend(quote!(let #name = #arg[#idx];));
    }
    out
}

struct Renderer<'a> {
    g: &'a Graph,
    params: &'a [Ident],
    /// Generic over `T: Real`: constants through `T::cst`, parameters from `p`.
    generic: bool,
    /// The fused twin: each inline product feeding a sum as `f64::mul_add` (or
    /// `Real::mul_add` on the twin's lanes), sines and cosines by `trig`'s fused
    /// functions (through the lanes' `Real` in a generic function).
    fused: bool,
    bound: &'a [bool],
    names: &'a [Option<Ident>],
    def_chunk: &'a [usize],
    slot: &'a [usize],
}

/// Precedence levels for parenthesising.
const SUM: u8 = 1;
const PRODUCT: u8 = 2;
const ATOM: u8 = 3;

impl Renderer<'_> {
    /// The path of `runtime::numerics::trig`'s function `name`, or of its fused
    /// variant in the fused twin.
    fn trig(&self, name: &str) -> TokenStream {
        let f = if self.fused {
            format_ident!("{}_fused", name)
        } else {
            format_ident!("{}", name)
        };
        quote!(::filippov::runtime::numerics::trig::#f)
    }

    /// The node as an operand needing at least precedence `min`.
    fn operand(
        &self,
        id: Id,
        chunk: usize,
        min: u8,
        used: &mut BTreeSet<(InputKind, u16)>,
    ) -> TokenStream {
        let (e, p) = self.render(id, chunk, used);
        if p >= min { e } else { quote!((#e)) }
    }

    fn atom(&self, id: Id, chunk: usize, used: &mut BTreeSet<(InputKind, u16)>) -> TokenStream {
        self.operand(id, chunk, ATOM, used)
    }

    fn expr(&self, id: Id, chunk: usize, used: &mut BTreeSet<(InputKind, u16)>) -> TokenStream {
        self.render(id, chunk, used).0
    }

    /// The definition of a bound node (never its name).
    fn inline(&self, id: Id, chunk: usize, used: &mut BTreeSet<(InputKind, u16)>) -> TokenStream {
        self.render_node(id, chunk, used).0
    }

    fn render(
        &self,
        id: Id,
        chunk: usize,
        used: &mut BTreeSet<(InputKind, u16)>,
    ) -> (TokenStream, u8) {
        let i = id.index();
        if self.bound[i] {
            if self.def_chunk[i] == chunk {
                let n = self.names[i].as_ref().expect("named");
                return (quote!(#n), ATOM);
            }
            let k = Literal::usize_unsuffixed(self.slot[i]);
            return (quote!(t[#k]), ATOM);
        }
        self.render_node(id, chunk, used)
    }

    fn render_node(
        &self,
        id: Id,
        chunk: usize,
        used: &mut BTreeSet<(InputKind, u16)>,
    ) -> (TokenStream, u8) {
        let g = self.g;
        match g.node(id) {
            Node::Const(bits) if self.generic => {
                let c = f64::from_bits(bits);
                let lit = if c.is_finite() {
                    let l = Literal::f64_unsuffixed(c.abs());
                    if c < 0.0 { quote!(-#l) } else { quote!(#l) }
                } else if c.is_nan() {
                    quote!(f64::NAN)
                } else if c > 0.0 {
                    quote!(f64::INFINITY)
                } else {
                    quote!(f64::NEG_INFINITY)
                };
                (quote!(<T as ::filippov::runtime::Real>::cst(#lit)), ATOM)
            }
            Node::Const(bits) => {
                let c = f64::from_bits(bits);
                if !c.is_finite() {
                    return (
                        if c.is_nan() {
                            quote!(f64::NAN)
                        } else if c > 0.0 {
                            quote!(f64::INFINITY)
                        } else {
                            quote!(f64::NEG_INFINITY)
                        },
                        ATOM,
                    );
                }
                let lit = Literal::f64_unsuffixed(c.abs());
                if c < 0.0 {
                    (quote!(-#lit), SUM)
                } else {
                    (quote!(#lit), ATOM)
                }
            }
            Node::Param(p) if self.generic => {
                let i = Literal::usize_unsuffixed(p as usize);
                (quote!(p[#i]), ATOM)
            }
            Node::Param(p) => {
                let f = &self.params[p as usize];
                (quote!(self.#f), ATOM)
            }
            Node::Input(inp) => {
                used.insert((inp.kind, inp.index));
                let n = format_ident!("{}{}", arg_name(inp.kind), inp.index);
                (quote!(#n), ATOM)
            }
            Node::Add(a, b) => {
                let neg = |x: Id| match g.node(x) {
                    Node::Unary(Unary::Neg, y) => Some(y),
                    _ => None,
                };
                // Only inline negations are absorbed; a bound `-x` is a value.
                let na = neg(a).filter(|_| !self.bound[a.index()]);
                let nb = neg(b).filter(|_| !self.bound[b.index()]);
                if self.fused {
                    // A product written inline (not a name, no reciprocal in it) and the
                    // other operand: `f64::mul_add(x, y, other)`, or with `−x` for a
                    // subtracted product.
                    let product = |x: Id| match g.node(x) {
                        Node::Mul(p, q) if !self.bound[x.index()] => {
                            let rec = |y: Id| matches!(g.node(y), Node::Unary(Unary::Recip, _));
                            (!rec(p) && !rec(q)).then_some((p, q))
                        }
                        _ => None,
                    };
                    let fusable = [
                        (product(a), b, false),
                        (product(b), a, false),
                        (nb.and_then(product), a, true),
                        (na.and_then(product), b, true),
                    ];
                    if let Some(&(Some((p, q)), other, negate)) =
                        fusable.iter().find(|f| f.0.is_some())
                    {
                        let x = self.atom(p, chunk, used);
                        let y = self.expr(q, chunk, used);
                        let c = self.expr(other, chunk, used);
                        let x = if negate { quote!(-#x) } else { x };
                        return if self.generic {
                            (
                                quote!(<T as ::filippov::runtime::Real>::mul_add(#x, #y, #c)),
                                ATOM,
                            )
                        } else {
                            (quote!(f64::mul_add(#x, #y, #c)), ATOM)
                        };
                    }
                }
                match (na, nb) {
                    (_, Some(y)) => {
                        let l = self.operand(a, chunk, SUM, used);
                        let r = self.operand(y, chunk, PRODUCT, used);
                        (quote!(#l - #r), SUM)
                    }
                    (Some(x), None) => {
                        let l = self.operand(b, chunk, SUM, used);
                        let r = self.operand(x, chunk, PRODUCT, used);
                        (quote!(#l - #r), SUM)
                    }
                    (None, None) => {
                        let l = self.operand(a, chunk, SUM, used);
                        let r = self.operand(b, chunk, PRODUCT, used);
                        (quote!(#l + #r), SUM)
                    }
                }
            }
            Node::Mul(a, b) => {
                let rec = |x: Id| match g.node(x) {
                    Node::Unary(Unary::Recip, y) if !self.bound[x.index()] => Some(y),
                    _ => None,
                };
                if let Some(y) = rec(b) {
                    let l = self.operand(a, chunk, PRODUCT, used);
                    let r = self.atom(y, chunk, used);
                    return (quote!(#l / #r), PRODUCT);
                }
                if let Some(y) = rec(a) {
                    let l = self.operand(b, chunk, PRODUCT, used);
                    let r = self.atom(y, chunk, used);
                    return (quote!(#l / #r), PRODUCT);
                }
                let l = self.operand(a, chunk, PRODUCT, used);
                let r = self.atom(b, chunk, used);
                (quote!(#l * #r), PRODUCT)
            }
            Node::Unary(op, a) if self.generic => {
                let x = self.atom(a, chunk, used);
                let real = quote!(<T as ::filippov::runtime::Real>);
                match op {
                    Unary::Neg => (quote!(-#x), SUM),
                    Unary::Recip => (quote!(#real::cst(1.0) / #x), PRODUCT),
                    Unary::Sin => (quote!(#real::sin(#x)), ATOM),
                    Unary::Cos => (quote!(#real::cos(#x)), ATOM),
                    Unary::Sqrt => (quote!(#real::sqrt(#x)), ATOM),
                    Unary::Exp => (quote!(#real::exp(#x)), ATOM),
                    Unary::Ln => (quote!(#real::ln(#x)), ATOM),
                }
            }
            Node::Unary(op, a) => {
                let x = self.atom(a, chunk, used);
                match op {
                    Unary::Neg => (quote!(-#x), SUM),
                    Unary::Recip => (quote!(1.0 / #x), PRODUCT),
                    Unary::Sin => {
                        let f = self.trig("sin_cos");
                        (quote!(#f(#x).0), ATOM)
                    }
                    Unary::Cos => {
                        let f = self.trig("sin_cos");
                        (quote!(#f(#x).1), ATOM)
                    }
                    Unary::Sqrt => (quote!(#x.sqrt()), ATOM),
                    Unary::Exp => (quote!(#x.exp()), ATOM),
                    Unary::Ln => (quote!(#x.ln()), ATOM),
                }
            }
        }
    }
}
