//! Lowers attribute values (`syn::Expr`) to [`PExpr`]: expressions over the struct's
//! parameter fields and literals.

use syn::{BinOp, Expr, Lit, UnOp};

use super::strip;
use crate::diag::Diagnostics;
use crate::model::{Func, PExpr};

/// The names an expression may use besides fields: constants and functions.
const FUNCS: &[(&str, Func)] = &[
    ("sqrt", Func::Sqrt),
    ("sin", Func::Sin),
    ("cos", Func::Cos),
    ("exp", Func::Exp),
    ("ln", Func::Ln),
];

/// Lowers `e`, reporting every unknown name or unsupported construct, and every number
/// or constant subexpression that is not a finite `f64` (`1e400`, `ln(0.0)`,
/// `sqrt(-1.0)`): the generated code could not represent it.
pub fn lower(e: &Expr, fields: &[String], diag: &mut Diagnostics) -> Option<PExpr> {
    let p = lower_unchecked(e, fields, diag)?;
    match p.as_const() {
        Some(c) if !c.is_finite() => {
            let what = if matches!(strip(e), Expr::Lit(_)) {
                "this number"
            } else {
                "this constant expression"
            };
            diag.error_at(
                e,
                format_args!(
                    "{what} evaluates to {c}, which is not a finite f64 (the largest is about 1.8e308); give a finite value"
                ),
            );
            None
        }
        _ => Some(p),
    }
}

/// Chains of more operands than this (`a + b − c + …`, `a * b / c * …`) are lowered to a
/// balanced tree instead of the left-nested one the parser builds, so that no later pass
/// (folding, differentiation, emission) recurses once per term.
const BALANCE_FROM: usize = 16;

/// Operands of a left-nested chain of `+`/`−` (or `*`/`/`) starting at `e`, each with
/// whether it is subtracted (divided), in source order; walked iteratively.
fn chain(e: &Expr, additive: bool) -> Vec<(bool, &Expr)> {
    let mut out = Vec::new();
    let mut cur = e;
    loop {
        match strip(cur) {
            Expr::Binary(b) => {
                let inverse = match (b.op, additive) {
                    (BinOp::Add(_), true) | (BinOp::Mul(_), false) => false,
                    (BinOp::Sub(_), true) | (BinOp::Div(_), false) => true,
                    _ => break,
                };
                out.push((inverse, &*b.right));
                cur = &b.left;
            }
            _ => break,
        }
    }
    out.push((false, cur));
    out.reverse();
    out
}

/// `x₁ ∘ x₂ ∘ …` as a balanced tree of `op`.
fn balanced(mut xs: Vec<PExpr>, op: char) -> Option<PExpr> {
    while xs.len() > 1 {
        let mut next = Vec::with_capacity(xs.len().div_ceil(2));
        let mut it = xs.into_iter();
        while let Some(a) = it.next() {
            next.push(match it.next() {
                Some(b) => PExpr::Bin(op, Box::new(a), Box::new(b)),
                None => a,
            });
        }
        xs = next;
    }
    xs.pop()
}

/// A long chain as (balanced direct terms) op⁻¹ (balanced inverse terms).
fn lower_chain(
    links: &[(bool, &Expr)],
    additive: bool,
    fields: &[String],
    diag: &mut Diagnostics,
) -> Option<PExpr> {
    let (mut direct, mut inverse) = (Vec::new(), Vec::new());
    let mut ok = true;
    for (inv, x) in links {
        match lower(x, fields, diag) {
            Some(p) if *inv => inverse.push(p),
            Some(p) => direct.push(p),
            None => ok = false,
        }
    }
    if !ok {
        return None;
    }
    let (op, inv_op) = if additive { ('+', '-') } else { ('*', '/') };
    let identity = PExpr::Const(if additive { 0.0 } else { 1.0 });
    let d = balanced(direct, op).unwrap_or(identity);
    Some(match balanced(inverse, op) {
        Some(i) => PExpr::Bin(inv_op, Box::new(d), Box::new(i)),
        None => d,
    })
}

fn lower_unchecked(e: &Expr, fields: &[String], diag: &mut Diagnostics) -> Option<PExpr> {
    if let Expr::Binary(b) = strip(e) {
        let additive = matches!(b.op, BinOp::Add(_) | BinOp::Sub(_));
        if additive || matches!(b.op, BinOp::Mul(_) | BinOp::Div(_)) {
            let links = chain(e, additive);
            if links.len() > BALANCE_FROM {
                return lower_chain(&links, additive, fields, diag);
            }
        }
    }
    match strip(e) {
        Expr::Lit(l) => match &l.lit {
            Lit::Float(f) => f
                .base10_parse::<f64>()
                .map_err(|err| diag.push(err))
                .ok()
                .map(PExpr::Const),
            Lit::Int(i) => i
                .base10_parse::<f64>()
                .map_err(|err| diag.push(err))
                .ok()
                .map(PExpr::Const),
            _ => {
                diag.error_at(e, "expected a number here, e.g. `1.0`");
                None
            }
        },
        Expr::Path(p) if p.qself.is_none() => {
            let path = &p.path;
            let last = path
                .segments
                .last()
                .map(|s| s.ident.to_string())
                .unwrap_or_default();
            if last == "PI" {
                return Some(PExpr::Const(std::f64::consts::PI));
            }
            if let Some(id) = path.get_ident() {
                let name = id.to_string();
                if let Some(i) = fields.iter().position(|f| *f == name) {
                    return Some(PExpr::Param(i as u16));
                }
                diag.error_at(
                    id,
                    format_args!(
                        "no field `{name}` in this struct; an expression may use the fields ({}), numbers, `PI` and the functions {}",
                        fields.join(", "),
                        func_list()
                    ),
                );
            } else {
                diag.error_at(e, "expected a field name or `PI` here");
            }
            None
        }
        Expr::Field(f) => {
            // `self.m1` reads as `m1`.
            if let (Expr::Path(base), syn::Member::Named(m)) = (strip(&f.base), &f.member)
                && base.path.is_ident("self")
            {
                let name = m.to_string();
                if let Some(i) = fields.iter().position(|x| *x == name) {
                    return Some(PExpr::Param(i as u16));
                }
                diag.error_at(
                    m,
                    format_args!(
                        "no field `{name}` in this struct; fields are: {}",
                        fields.join(", ")
                    ),
                );
                return None;
            }
            diag.error_at(e, "expected a field name, e.g. `m1` or `self.m1`");
            None
        }
        Expr::Unary(u) => match u.op {
            UnOp::Neg(_) => lower(&u.expr, fields, diag).map(|x| PExpr::Neg(Box::new(x))),
            _ => {
                diag.error_at(u, "only `-` is allowed as a unary operator here");
                None
            }
        },
        Expr::Binary(b) => {
            let op = match b.op {
                BinOp::Add(_) => '+',
                BinOp::Sub(_) => '-',
                BinOp::Mul(_) => '*',
                BinOp::Div(_) => '/',
                _ => {
                    diag.error_at(b.op, "only `+`, `-`, `*` and `/` are allowed here");
                    return None;
                }
            };
            let l = lower(&b.left, fields, diag);
            let r = lower(&b.right, fields, diag);
            Some(PExpr::Bin(op, Box::new(l?), Box::new(r?)))
        }
        Expr::Call(c) => {
            let name = super::ident_of(&c.func).map(|i| i.to_string());
            let args: Vec<&Expr> = c.args.iter().collect();
            call(e, name.as_deref(), &args, fields, diag)
        }
        Expr::MethodCall(m) => {
            // A chain of calls nests like brackets do (see `parse::MAX_NESTING`).
            let mut depth = 0;
            let mut cur = &*m.receiver;
            while let Expr::MethodCall(inner) = strip(cur) {
                depth += 1;
                cur = &inner.receiver;
            }
            if depth >= super::MAX_NESTING {
                diag.error_at(
                    &m.method,
                    format_args!(
                        "more than {} method calls in a chain; split the expression (e.g. into struct fields)",
                        super::MAX_NESTING
                    ),
                );
                return None;
            }
            // `x.sqrt()` and `x.powi(2)` read as `sqrt(x)` and `x * x`.
            let mut args: Vec<&Expr> = vec![&m.receiver];
            args.extend(m.args.iter());
            call(e, Some(&m.method.to_string()), &args, fields, diag)
        }
        _ => {
            diag.error_at(
                e,
                format_args!(
                    "unsupported expression; use numbers, field names, `+ - * /`, `PI` and {}",
                    func_list()
                ),
            );
            None
        }
    }
}

fn call(
    e: &Expr,
    name: Option<&str>,
    args: &[&Expr],
    fields: &[String],
    diag: &mut Diagnostics,
) -> Option<PExpr> {
    if name == Some("powi") {
        let n = match args.get(1).map(|a| strip(a)) {
            Some(Expr::Lit(syn::ExprLit {
                lit: Lit::Int(i), ..
            })) => i.base10_parse::<u32>().ok(),
            _ => None,
        };
        return match (args.len(), n) {
            (2, Some(n)) if (1..=8).contains(&n) => {
                let x = lower(args[0], fields, diag)?;
                let mut acc = x.clone();
                for _ in 1..n {
                    acc = PExpr::Bin('*', Box::new(acc), Box::new(x.clone()));
                }
                Some(acc)
            }
            _ => {
                diag.error_at(e, "`powi` takes a base and an integer literal exponent from 1 to 8, e.g. `l.powi(2)`");
                None
            }
        };
    }
    let Some(func) = FUNCS
        .iter()
        .find(|(n, _)| Some(*n) == name)
        .map(|(_, f)| *f)
    else {
        diag.error_at(
            e,
            format_args!(
                "unknown function `{}`; expressions may call {}",
                name.unwrap_or("?"),
                func_list()
            ),
        );
        return None;
    };
    if args.len() != 1 {
        diag.error_at(
            e,
            format_args!(
                "`{}` takes one argument, found {}",
                name.unwrap_or("?"),
                args.len()
            ),
        );
        return None;
    }
    lower(args[0], fields, diag).map(|x| PExpr::Call(func, Box::new(x)))
}

/// The functions an expression may call, as a message lists them: the named ones, and
/// `powi` with a literal exponent.
fn func_list() -> String {
    let mut names: Vec<String> = FUNCS.iter().map(|(n, _)| format!("`{n}`")).collect();
    names.push("`x.powi(n)` (n = 1 to 8)".into());
    names.join(", ")
}

/// Lowers an expression in one free variable `var` (the force `f` of a law, the
/// coordinate `x` of a spring potential) besides the fields.
pub fn lower_with_var(
    e: &Expr,
    fields: &[String],
    var: &str,
    diag: &mut Diagnostics,
) -> Option<PExpr> {
    if fields.iter().any(|n| n == var) {
        diag.error_at(e, format_args!("a field named `{var}` would shadow the variable `{var}` of this expression; rename the field"));
        return None;
    }
    let mut with_var = fields.to_vec();
    with_var.push(var.to_string());
    let index = (with_var.len() - 1) as u16;
    lower(e, &with_var, diag).map(|p| replace_var(p, index))
}

fn replace_var(p: PExpr, var: u16) -> PExpr {
    match p {
        PExpr::Param(i) if i == var => PExpr::Var,
        PExpr::Neg(x) => PExpr::Neg(Box::new(replace_var(*x, var))),
        PExpr::Bin(op, a, b) => PExpr::Bin(
            op,
            Box::new(replace_var(*a, var)),
            Box::new(replace_var(*b, var)),
        ),
        PExpr::Call(f, x) => PExpr::Call(f, Box::new(replace_var(*x, var))),
        other => other,
    }
}
