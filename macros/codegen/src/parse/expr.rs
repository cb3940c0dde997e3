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

fn lower_unchecked(e: &Expr, fields: &[String], diag: &mut Diagnostics) -> Option<PExpr> {
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
                        "no field `{name}` in this struct; an expression may use the fields ({}), numbers, `PI` and {}",
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
                "unknown function `{}`; expressions may call {} and `powi`",
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

fn func_list() -> String {
    FUNCS
        .iter()
        .map(|(n, _)| format!("`{n}`"))
        .collect::<Vec<_>>()
        .join(", ")
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
