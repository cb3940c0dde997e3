//! `Mechanism::model()`: the scene as a plain numeric description for the independent
//! numeric implementation in the runtime. Non-linear spring potentials (`#[spring(j,
//! potential = …)]`) are not part of that description (it holds numbers, not
//! expressions); everything else is. Parameter expressions are evaluated as written
//! (no symbolic processing), so a mistake in the symbolic pipeline cannot hide in both.

use proc_macro2::{Literal, TokenStream};
use quote::quote;

use crate::model::{Func, JointKind, Model, PExpr};

pub fn expr(e: &PExpr, params: &[proc_macro2::Ident]) -> TokenStream {
    match e {
        PExpr::Const(c) => {
            let l = Literal::f64_suffixed(*c);
            quote!(#l)
        }
        PExpr::Param(i) => {
            let f = &params[*i as usize];
            quote!(self.#f)
        }
        PExpr::Var => quote!(f),
        PExpr::Neg(x) => {
            let x = expr(x, params);
            quote!((-#x))
        }
        PExpr::Bin(op, a, b) => {
            let (a, b) = (expr(a, params), expr(b, params));
            match op {
                '+' => quote!((#a + #b)),
                '-' => quote!((#a - #b)),
                '*' => quote!((#a * #b)),
                _ => quote!((#a / #b)),
            }
        }
        PExpr::Call(f, x) => {
            let x = expr(x, params);
            match f {
                Func::Sqrt => quote!(#x.sqrt()),
                Func::Sin => quote!(#x.sin()),
                Func::Cos => quote!(#x.cos()),
                Func::Exp => quote!(#x.exp()),
                Func::Ln => quote!(#x.ln()),
            }
        }
    }
}

fn v3(v: &[PExpr; 3], p: &[proc_macro2::Ident]) -> TokenStream {
    let [a, b, c] = [expr(&v[0], p), expr(&v[1], p), expr(&v[2], p)];
    quote!(::filippov::nalgebra::Vector3::new(#a, #b, #c))
}

fn axis(a: [f64; 3]) -> TokenStream {
    let [x, y, z] = a.map(Literal::f64_suffixed);
    quote!(::filippov::nalgebra::Vector3::new(#x, #y, #z))
}

pub fn model_fn(model: &Model) -> TokenStream {
    let p = &model.params;
    let gravity = match &model.gravity {
        Some(g) => v3(g, p),
        None => quote!(::filippov::nalgebra::Vector3::zeros()),
    };
    let links = model.links.iter().map(|l| {
        let name = Literal::string(&l.name);
        let parent = match l.parent {
            Some(i) => quote!(Some(#i)),
            None => quote!(None),
        };
        let coordinate = match l.coordinate {
            Some(i) => quote!(Some(#i)),
            None => quote!(None),
        };
        let joint = match l.kind {
            JointKind::Revolute(a) => {
                let a = axis(a);
                quote!(::filippov::runtime::numeric::JointKind::Revolute { axis: #a })
            }
            JointKind::Prismatic(a) => {
                let a = axis(a);
                quote!(::filippov::runtime::numeric::JointKind::Prismatic { axis: #a })
            }
            JointKind::Fixed | JointKind::Free => {
                quote!(::filippov::runtime::numeric::JointKind::Fixed)
            }
            JointKind::Spherical => quote!(::filippov::runtime::numeric::JointKind::Spherical),
            JointKind::Translation => {
                quote!(::filippov::runtime::numeric::JointKind::Translation)
            }
        };
        let (xyz, rpy, com) = (v3(&l.origin, p), v3(&l.rpy, p), v3(&l.com, p));
        let mass = expr(&l.mass, p);
        let rows: Vec<TokenStream> = l.inertia.iter().flatten().map(|e| expr(e, p)).collect();
        quote! {
            ::filippov::runtime::numeric::Link {
                name: #name.to_string(),
                parent: #parent,
                joint: #joint,
                coordinate: #coordinate,
                origin_xyz: #xyz,
                origin_rpy: #rpy,
                mass: #mass,
                com: #com,
                inertia: ::filippov::nalgebra::Matrix3::new(#(#rows),*),
            }
        }
    });
    let springs = model.springs.iter().map(|s| {
        let (c, k, r) = (s.coordinate, expr(&s.k, p), expr(&s.rest, p));
        quote!(::filippov::runtime::numeric::Spring { coordinate: #c, stiffness: #k, rest: #r })
    });
    let dampers = model.dampers.iter().map(|d| {
        let (i, c) = (d.coordinate, expr(&d.c, p));
        quote!(::filippov::runtime::numeric::Damper { coordinate: #i, damping: #c })
    });
    let point_springs = model.point_springs.iter().map(|s| {
        let end = |e: &(Option<usize>, [PExpr; 3])| {
            let link = match e.0 {
                Some(l) => quote!(::core::option::Option::Some(#l)),
                None => quote!(::core::option::Option::None),
            };
            let point = v3(&e.1, p);
            quote!((#link, #point))
        };
        let (a, b) = (end(&s.a), end(&s.b));
        let (k, r) = (expr(&s.k, p), expr(&s.rest, p));
        quote!(::filippov::runtime::numeric::PointSpring { a: #a, b: #b, stiffness: #k, rest: #r })
    });
    quote! {
        #[allow(clippy::all)]
        fn model(&self) -> ::filippov::runtime::numeric::Model {
            ::filippov::runtime::numeric::Model {
                gravity: #gravity,
                links: vec![#(#links),*],
                springs: vec![#(#springs),*],
                dampers: vec![#(#dampers),*],
                point_springs: vec![#(#point_springs),*],
            }
        }
    }
}
