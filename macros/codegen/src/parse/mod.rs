//! Attributes → a raw, still syn-flavoured description of the scene.
//!
//! Every attribute has the shape `name [: head] (, key = value)*`: the generic reader
//! here turns it into a [`RawAttr`], and one file per attribute family interprets it.
//! Values stay `syn::Expr` until [`expr`] lowers them, so every later error can point at
//! the user's tokens.

pub mod expr;

use proc_macro2::Span;
use syn::parse::{ParseStream, Parser};
use syn::spanned::Spanned;
use syn::{Expr, Ident, Token};

use crate::diag::Diagnostics;

/// The attribute families a scene is described with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Family {
    Mechanism,
    Body,
    Joint,
    Spring,
    Damper,
    Friction,
    Bingham,
    Stop,
    Frame,
    LoopJoint,
    Contact,
}

impl Family {
    pub const ALL: [(&'static str, Family); 11] = [
        ("mechanism", Family::Mechanism),
        ("body", Family::Body),
        ("joint", Family::Joint),
        ("spring", Family::Spring),
        ("damper", Family::Damper),
        ("friction", Family::Friction),
        ("bingham", Family::Bingham),
        ("stop", Family::Stop),
        ("frame", Family::Frame),
        ("loop_joint", Family::LoopJoint),
        ("contact", Family::Contact),
    ];

    fn of(path: &syn::Path) -> Option<Family> {
        let id = path.get_ident()?;
        Family::ALL.iter().find(|(n, _)| id == n).map(|(_, f)| *f)
    }
}

/// One attribute, read but not interpreted.
pub struct RawAttr {
    pub family: Family,
    /// The leading name (`upper` in `#[body(upper, …)]`); `None` for `#[mechanism(…)]`.
    pub name: Option<Ident>,
    /// What follows `name:` (`revolute(z)` in `#[joint(shoulder: revolute(z), …)]`).
    pub head: Option<Expr>,
    pub args: Vec<(Ident, Expr)>,
    pub span: Span,
}

impl RawAttr {
    /// Takes the value of `key`, reporting duplicates.
    pub fn take(&mut self, key: &str, diag: &mut Diagnostics) -> Option<(Ident, Expr)> {
        let mut found: Option<(Ident, Expr)> = None;
        let mut rest = Vec::with_capacity(self.args.len());
        for (k, v) in self.args.drain(..) {
            if k == key {
                if found.is_some() {
                    diag.error_at(&k, format_args!("`{key}` is given twice; keep one"));
                } else {
                    found = Some((k, v));
                }
            } else {
                rest.push((k, v));
            }
        }
        self.args = rest;
        found
    }

    /// Reports every key not taken yet as unknown, listing the known ones.
    pub fn reject_rest(&self, known: &[&str], diag: &mut Diagnostics) {
        for (k, _) in &self.args {
            diag.error_at(
                k,
                format_args!(
                    "unknown key `{k}` here; expected one of: {}",
                    known.join(", ")
                ),
            );
        }
    }
}

/// Reads the scene's attributes off the struct; other attributes are ignored.
pub fn read_attrs(attrs: &[syn::Attribute], diag: &mut Diagnostics) -> Vec<RawAttr> {
    let mut out = Vec::new();
    for attr in attrs {
        let Some(family) = Family::of(attr.path()) else {
            continue;
        };
        let span = attr.span();
        let parser = |input: ParseStream| read_body(input, family, span);
        let parsed = match &attr.meta {
            syn::Meta::List(list) => {
                check_nesting(list.tokens.clone()).and_then(|()| parser.parse2(list.tokens.clone()))
            }
            _ => Err(syn::Error::new_spanned(
                attr,
                "expected a list of arguments, e.g. `#[body(link, mass = m)]`",
            )),
        };
        match parsed {
            Ok(raw) => out.push(raw),
            Err(e) => diag.push(e),
        }
    }
    out
}

/// Deepest nesting of brackets, and longest run of prefix `-`, an attribute may have.
pub const MAX_NESTING: usize = 256;
/// Most tokens in one attribute (a sum of about 10,000 terms).
pub const MAX_TOKENS: usize = 20_000;

/// Refuses attribute tokens nested deeper than [`MAX_NESTING`] (brackets, or a run of
/// unary minus signs) or more than [`MAX_TOKENS`] long, before any recursive parser sees
/// them: the expression parser and every later pass recurse once per level (and syn's
/// trees drop recursively), and a size no human writes must not be able to overflow
/// the compiler's stack. Iterative.
fn check_nesting(tokens: proc_macro2::TokenStream) -> syn::Result<()> {
    use proc_macro2::TokenTree;
    let mut stack = vec![tokens.into_iter()];
    let mut minus_run = 0usize;
    let mut count = 0usize;
    while let Some(top) = stack.last_mut() {
        let Some(tree) = top.next() else {
            stack.pop();
            continue;
        };
        count += 1;
        if count > MAX_TOKENS {
            return Err(syn::Error::new(
                tree.span(),
                format_args!(
                    "an attribute of more than {MAX_TOKENS} tokens; split the expression (e.g. into struct fields)"
                ),
            ));
        }
        match tree {
            TokenTree::Group(g) => {
                minus_run = 0;
                if stack.len() >= MAX_NESTING {
                    return Err(syn::Error::new(
                        g.span(),
                        format_args!(
                            "brackets nested more than {MAX_NESTING} deep; split the expression (e.g. into struct fields)"
                        ),
                    ));
                }
                stack.push(g.stream().into_iter());
            }
            TokenTree::Punct(p) if p.as_char() == '-' => {
                minus_run += 1;
                if minus_run > MAX_NESTING {
                    return Err(syn::Error::new(
                        p.span(),
                        format_args!(
                            "more than {MAX_NESTING} minus signs in a row; simplify the expression"
                        ),
                    ));
                }
            }
            _ => minus_run = 0,
        }
    }
    Ok(())
}

fn read_body(input: ParseStream, family: Family, span: Span) -> syn::Result<RawAttr> {
    let mut raw = RawAttr {
        family,
        name: None,
        head: None,
        args: Vec::new(),
        span,
    };
    if family != Family::Mechanism {
        let name: Ident = input.parse().map_err(|e| {
            syn::Error::new(
                e.span(),
                "expected the element's name first, e.g. `#[body(upper, mass = m1)]`",
            )
        })?;
        raw.name = Some(name);
        if input.peek(Token![:]) {
            input.parse::<Token![:]>()?;
            raw.head = Some(input.parse()?);
        }
        if input.is_empty() {
            return Ok(raw);
        }
        input.parse::<Token![,]>().map_err(|e| {
            syn::Error::new(e.span(), "expected `,` after the name, then `key = value` pairs, e.g. `#[body(link, mass = m)]`")
        })?;
    }
    while !input.is_empty() {
        // Keys may be keywords (`crate = …`, as serde's `#[serde(crate = …)]`).
        let key: Ident = syn::ext::IdentExt::parse_any(input)?;
        input
            .parse::<Token![=]>()
            .map_err(|e| syn::Error::new(e.span(), format_args!("expected `{key} = <value>`")))?;
        let value: Expr = input.parse()?;
        raw.args.push((key, value));
        if input.is_empty() {
            break;
        }
        input
            .parse::<Token![,]>()
            .map_err(|e| syn::Error::new(e.span(), "expected `,` between `key = value` pairs"))?;
    }
    Ok(raw)
}

/// The elements of an array expression `[a, b, c]` of exactly `n` entries.
pub fn array<'a>(
    e: &'a Expr,
    n: usize,
    what: &str,
    diag: &mut Diagnostics,
) -> Option<Vec<&'a Expr>> {
    match strip(e) {
        Expr::Array(a) if a.elems.len() == n => Some(a.elems.iter().collect()),
        Expr::Array(a) => {
            diag.error_at(
                e,
                format_args!(
                    "{what} needs {n} entries, found {}; write `[x, y, z]`",
                    a.elems.len()
                ),
            );
            None
        }
        _ => {
            diag.error_at(
                e,
                format_args!("{what} must be an array of {n} expressions, e.g. `[0.0, 0.0, l]`"),
            );
            None
        }
    }
}

/// The single identifier an expression is, if it is one.
pub fn ident_of(e: &Expr) -> Option<&Ident> {
    match strip(e) {
        Expr::Path(p) if p.qself.is_none() => p.path.get_ident(),
        _ => None,
    }
}

/// Looks through parentheses and invisible groups.
pub fn strip(e: &Expr) -> &Expr {
    match e {
        Expr::Paren(p) => strip(&p.expr),
        Expr::Group(g) => strip(&g.expr),
        _ => e,
    }
}
