//! `#[mechanism(urdf = "robots/arm.urdf", …)]`: a URDF file read at expansion time and
//! turned into the same attributes a user would write by hand — `#[body]`, `#[joint]`,
//! and, on request, `#[stop]`, `#[friction]` and `#[damper]` — so that everything after
//! this point (validation, mechanics, emission) is the hand-written path.
//!
//! How a URDF maps:
//! - the root link (the one no joint has as child) is the world, unless `base = free`
//!   hangs it from the world by a free joint;
//! - `revolute` and `continuous` → `revolute([ax, ay, az])`, `prismatic` →
//!   `prismatic([…])`, `fixed` → `fixed` (the engine merges fixed bodies); `floating`,
//!   `planar` and `spherical` joints and `<mimic>` are refused with the joint's name;
//! - `<inertial>`: mass, centre of mass and the inertia about it, rotated from the
//!   inertial frame into the link frame (`I = R I₀ Rᵀ`); a link without `<inertial>`
//!   has no mass (an intermediate frame); a massless leaf on a fixed joint (a tool or
//!   sensor frame) carries nothing and is left out of the dynamics — with
//!   `emit = [kinematics]` (or `all`) it becomes a `#[frame]`, so its pose and Jacobian
//!   are there;
//! - `lock = [joint, …]` holds joints at zero (fixed): a gripper's fingers, a `<mimic>`;
//! - `limits = stops(restitution = e)` or `limits = support(k = k)` turns each
//!   `<limit lower upper>` of a revolute or prismatic joint into a two-sided stop;
//!   `joint_friction = true` each `<dynamics friction>` into Coulomb friction and
//!   `joint_damping = true` each `<dynamics damping>` into a viscous damper. Without
//!   them, limits, friction and damping are not part of the dynamics.
//!
//! Every value becomes a literal, so structural zeros fold as in a hand-written scene,
//! except those bound to struct fields by `#[urdf_param(link.mass = m, joint.friction =
//! f, joint.lower = l, …)]`: the attribute text carries a placeholder there, replaced by
//! the user's expression (with its spans) after parsing.
//! Errors are spanned at the `urdf = …` value and name the file and the link or joint.

use proc_macro2::{Span, TokenStream, TokenTree};
use syn::Expr;

use crate::diag::Diagnostics;
use crate::parse::{RawAttr, ident_of, read_attrs, strip};

/// The URDF options taken off `#[mechanism(…)]`.
#[cfg_attr(not(feature = "urdf"), allow(dead_code))]
pub struct UrdfOptions {
    pub path: syn::LitStr,
    limits: Option<Expr>,
    friction: bool,
    damping: bool,
    free_base: bool,
    /// Joints held at zero (made fixed), by their URDF names: a gripper's fingers, or a
    /// `<mimic>` joint.
    lock: Vec<String>,
    /// Whether the scene asks for forward kinematics (`emit = [kinematics]` or `all`):
    /// then the massless leaves (tool and sensor frames) become `#[frame]`s.
    frames: bool,
}

/// Takes `urdf = "…"` and its options off the mechanism attribute: `Ok(None)` without
/// `urdf` (options given without it are reported), `Err(())` when `urdf` is there but
/// not a path (reported; the scene is the file, so nothing else can be checked).
// `Err(())`: the error is already in `diag`; the caller only needs to stop.
#[allow(clippy::result_unit_err)]
pub fn take_options(raw: &mut RawAttr, diag: &mut Diagnostics) -> Result<Option<UrdfOptions>, ()> {
    let urdf = raw.take("urdf", diag);
    let limits = raw.take("limits", diag);
    let friction = raw.take("joint_friction", diag);
    let damping = raw.take("joint_damping", diag);
    let base = raw.take("base", diag);
    let lock = raw.take("lock", diag);
    let Some((key, value)) = urdf else {
        for (k, _) in [&limits, &friction, &damping, &base, &lock]
            .into_iter()
            .flatten()
        {
            diag.error_at(
                k,
                format_args!("`{k}` is an option of a scene read from a URDF file; add `urdf = \"path/to/robot.urdf\"` or drop it"),
            );
        }
        return Ok(None);
    };
    let path = match strip(&value) {
        Expr::Lit(syn::ExprLit {
            lit: syn::Lit::Str(s),
            ..
        }) => s.clone(),
        _ => {
            diag.error_at(
                &value,
                "`urdf` takes the file's path as a string, relative to the crate's Cargo.toml, e.g. `urdf = \"robots/panda.urdf\"`",
            );
            return Err(());
        }
    };
    let _ = key;
    let flag = |e: Option<(syn::Ident, Expr)>, diag: &mut Diagnostics| match e {
        None => false,
        Some((k, v)) => match strip(&v) {
            Expr::Lit(syn::ExprLit {
                lit: syn::Lit::Bool(b),
                ..
            }) => b.value,
            _ => {
                diag.error_at(&v, format_args!("`{k}` is `true` or `false`"));
                false
            }
        },
    };
    let friction = flag(friction, diag);
    let damping = flag(damping, diag);
    let free_base = match base {
        None => false,
        Some((_, v)) => match ident_of(&v) {
            Some(i) if i == "free" => true,
            Some(i) if i == "fixed" => false,
            _ => {
                diag.error_at(
                    &v,
                    "`base` is `fixed` (the root link is the world, the default) or `free` (a floating base)",
                );
                false
            }
        },
    };
    let lock = match lock {
        None => Vec::new(),
        Some((_, v)) => match strip(&v) {
            Expr::Array(a) => a
                .elems
                .iter()
                .filter_map(|e| match strip(e) {
                    Expr::Lit(syn::ExprLit {
                        lit: syn::Lit::Str(s),
                        ..
                    }) => Some(s.value()),
                    other => match ident_of(other) {
                        Some(i) => Some(i.to_string()),
                        None => {
                            diag.error_at(
                                e,
                                "`lock` lists URDF joint names, as identifiers or strings",
                            );
                            None
                        }
                    },
                })
                .collect(),
            _ => {
                diag.error_at(&v, "`lock` lists URDF joint names, e.g. `lock = [panda_finger_joint1, \"finger-2\"]`");
                Vec::new()
            }
        },
    };
    // `emit` itself is read (and checked) with the other `#[mechanism]` options.
    let frames = raw.args.iter().any(|(k, e)| {
        k == "emit"
            && match strip(e) {
                Expr::Array(a) => a
                    .elems
                    .iter()
                    .any(|x| ident_of(x).is_some_and(|i| i == "kinematics")),
                other => ident_of(other).is_some_and(|i| i == "all"),
            }
    });
    Ok(Some(UrdfOptions {
        path,
        limits: limits.map(|(_, e)| e),
        friction,
        damping,
        free_base,
        lock,
        frames,
    }))
}

/// One `#[urdf_param(element.property = expression)]` binding: the value of a link's
/// mass or a joint's friction, damping or limit taken from the struct's fields instead
/// of the file, so that it can vary from run to run.
pub struct Param {
    pub element: syn::Ident,
    pub property: syn::Ident,
    pub value: Expr,
}

/// The properties `#[urdf_param]` can bind.
pub const PROPERTIES: [&str; 5] = ["mass", "friction", "damping", "lower", "upper"];

/// Reads every `#[urdf_param(a.b = e, …)]` attribute.
pub fn read_params(attrs: &[syn::Attribute], diag: &mut Diagnostics) -> Vec<Param> {
    use syn::punctuated::Punctuated;
    let mut out = Vec::new();
    for attr in attrs.iter().filter(|a| a.path().is_ident("urdf_param")) {
        let items = match attr.parse_args_with(Punctuated::<Expr, syn::Token![,]>::parse_terminated)
        {
            Ok(items) => items,
            Err(e) => {
                diag.push(e);
                continue;
            }
        };
        for item in items {
            let parsed = match &item {
                Expr::Assign(a) => match strip(&a.left) {
                    Expr::Field(f) => match (ident_of(&f.base), &f.member) {
                        (Some(el), syn::Member::Named(prop)) => {
                            Some((el.clone(), prop.clone(), (*a.right).clone()))
                        }
                        _ => None,
                    },
                    _ => None,
                },
                _ => None,
            };
            match parsed {
                Some((element, property, value)) if PROPERTIES.contains(&property.to_string().as_str()) => {
                    out.push(Param { element, property, value })
                }
                Some((_, property, _)) => diag.error_at(
                    &property,
                    format_args!(
                        "`{property}` cannot be bound; `urdf_param` binds a link's `mass` or a joint's `friction`, `damping`, `lower` or `upper`"
                    ),
                ),
                None => diag.error_at(
                    &item,
                    "`urdf_param` takes `element.property = value` pairs, e.g. `#[urdf_param(panda_link7.mass = m7, panda_joint1.friction = f1)]`",
                ),
            }
        }
    }
    out
}

/// The absolute path of the file (relative paths from the user's crate root).
pub fn resolve(path: &str) -> std::path::PathBuf {
    let p = std::path::Path::new(path);
    if p.is_absolute() {
        return p.to_path_buf();
    }
    match std::env::var_os("CARGO_MANIFEST_DIR") {
        Some(dir) => std::path::Path::new(&dir).join(p),
        None => p.to_path_buf(),
    }
}

/// The attributes the file describes, as if written by hand; `None` after an error.
pub fn attributes(
    opts: &UrdfOptions,
    params: &[Param],
    diag: &mut Diagnostics,
) -> Option<Vec<RawAttr>> {
    let span = opts.path.span();
    let file = resolve(&opts.path.value());
    let shown = opts.path.value();
    let text = match std::fs::read_to_string(&file) {
        Ok(t) => t,
        Err(e) => {
            diag.error_span(
                span,
                format_args!(
                    "cannot read the URDF file `{shown}` (looked for {}): {e}; paths are relative to the crate's Cargo.toml",
                    file.display()
                ),
            );
            return None;
        }
    };
    let source = match translate(&text, opts, params) {
        Ok(s) => s,
        Err(msgs) => {
            for (m, at) in msgs {
                match at {
                    Some(k) => {
                        diag.error_at(&params[k].element, format_args!("URDF `{shown}`: {m}"))
                    }
                    None => diag.error_span(span, format_args!("URDF `{shown}`: {m}")),
                }
            }
            return None;
        }
    };
    // Parse the attributes with every token spanned at the `urdf = "…"` value, so that
    // a later error (a realisability check, a massless leaf) points there.
    let tokens: TokenStream = match source.parse() {
        Ok(t) => respan(t, span, params),
        Err(e) => {
            diag.error_span(span, format_args!("URDF `{shown}`: {e}"));
            return None;
        }
    };
    let item: syn::ItemStruct = match syn::parse2(tokens) {
        Ok(i) => i,
        Err(e) => {
            diag.error_span(span, format_args!("URDF `{shown}`: {e}"));
            return None;
        }
    };
    Some(read_attrs(&item.attrs, diag))
}

/// Every token spanned at `span`, and each placeholder `__urdf_param_<k>` replaced by
/// the bound expression (in parentheses, with the user's spans).
fn respan(tokens: TokenStream, span: Span, params: &[Param]) -> TokenStream {
    tokens
        .into_iter()
        .map(|t| match t {
            TokenTree::Group(g) => {
                let mut n =
                    proc_macro2::Group::new(g.delimiter(), respan(g.stream(), span, params));
                n.set_span(span);
                TokenTree::Group(n)
            }
            TokenTree::Ident(i) if i.to_string().starts_with(PLACEHOLDER) => {
                let k: usize = i.to_string()[PLACEHOLDER.len()..].parse().expect("index");
                let value = &params[k].value;
                let g = proc_macro2::Group::new(
                    proc_macro2::Delimiter::Parenthesis,
                    quote::quote!(#value),
                );
                TokenTree::Group(g)
            }
            mut other => {
                other.set_span(span);
                other
            }
        })
        .collect()
}

const PLACEHOLDER: &str = "__urdf_param_";

/// The identifiers one kind of a file's names (its links, or its joints) become: a name
/// that is an identifier keeps itself; another becomes [`ident`] of it, with `_2`, `_3`,
/// … appended where that is taken, so two different names never become one identifier
/// (`j-1` and `j_1` are `j_1_2` and `j_1`).
#[cfg_attr(not(feature = "urdf"), allow(dead_code))]
struct Idents(std::collections::HashMap<String, String>);

#[cfg_attr(not(feature = "urdf"), allow(dead_code))]
impl Idents {
    fn new<'a>(names: impl Iterator<Item = &'a str> + Clone) -> Self {
        let mut map = std::collections::HashMap::new();
        let mut taken = std::collections::HashSet::new();
        for n in names.clone() {
            if ident(n) == n && taken.insert(n.to_string()) {
                map.insert(n.to_string(), n.to_string());
            }
        }
        for n in names {
            if map.contains_key(n) {
                continue;
            }
            let base = ident(n);
            let mut candidate = base.clone();
            let mut k = 2;
            while taken.contains(&candidate) {
                candidate = format!("{base}_{k}");
                k += 1;
            }
            taken.insert(candidate.clone());
            map.insert(n.to_string(), candidate);
        }
        Idents(map)
    }

    /// The identifier of `name` (one of the names it was made from).
    fn of(&self, name: &str) -> String {
        self.0.get(name).cloned().unwrap_or_else(|| ident(name))
    }
}

/// A URDF name as an identifier: other characters become `_`, a leading digit or a
/// keyword gets a suffix. The joint's column names use this form.
pub fn ident(name: &str) -> String {
    let mut s: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    if s.is_empty() || s.starts_with(|c: char| c.is_ascii_digit()) {
        s.insert(0, '_');
    }
    if syn::parse_str::<syn::Ident>(&s).is_err() || s == "world" || s == "_" {
        s.push('_');
    }
    s
}

#[cfg_attr(not(feature = "urdf"), allow(dead_code))]
fn num(x: f64) -> String {
    format!("{x:?}")
}

#[cfg_attr(not(feature = "urdf"), allow(dead_code))]
fn vec3(v: [f64; 3]) -> String {
    format!("[{}, {}, {}]", num(v[0]), num(v[1]), num(v[2]))
}

/// `R = Rz(yaw) Ry(pitch) Rx(roll)`, the URDF convention.
#[cfg_attr(not(feature = "urdf"), allow(dead_code))]
fn rpy_matrix(r: [f64; 3]) -> [[f64; 3]; 3] {
    let (sr, cr) = r[0].sin_cos();
    let (sp, cp) = r[1].sin_cos();
    let (sy, cy) = r[2].sin_cos();
    [
        [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
        [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
        [-sp, cp * sr, cp * cr],
    ]
}

/// The inertia in the link frame, `R I₀ Rᵀ`.
#[cfg_attr(not(feature = "urdf"), allow(dead_code))]
pub fn rotate_inertia(i0: [[f64; 3]; 3], rpy: [f64; 3]) -> [[f64; 3]; 3] {
    if rpy == [0.0; 3] {
        return i0;
    }
    let r = rpy_matrix(rpy);
    let mut out = [[0.0; 3]; 3];
    for a in 0..3 {
        for b in 0..3 {
            let mut s = 0.0;
            for k in 0..3 {
                for l in 0..3 {
                    s += r[a][k] * i0[k][l] * r[b][l];
                }
            }
            out[a][b] = s;
        }
    }
    // Symmetric to the last bit.
    for a in 0..3 {
        for b in 0..a {
            let m = 0.5 * (out[a][b] + out[b][a]);
            out[a][b] = m;
            out[b][a] = m;
        }
    }
    out
}

/// Without the `urdf` feature there is no parser.
#[cfg(not(feature = "urdf"))]
pub fn translate(
    _: &str,
    _: &UrdfOptions,
    _: &[Param],
) -> Result<String, Vec<(String, Option<usize>)>> {
    Err(vec![(
        "reading URDF files needs filippov's `urdf` feature: `filippov = { version = \"0.1\", features = [\"urdf\"] }` in Cargo.toml".to_string(),
        None,
    )])
}

/// The URDF as attribute source text, or every problem found.
#[cfg(feature = "urdf")]
pub fn translate(
    text: &str,
    opts: &UrdfOptions,
    params: &[Param],
) -> Result<String, Vec<(String, Option<usize>)>> {
    let robot =
        urdf_rs::read_from_string(text).map_err(|e| vec![(format!("malformed: {e}"), None)])?;
    // The file's problems and the bindings' together.
    let mut errors = check_params(&robot, opts, params);
    match translate_file(&robot, opts, params) {
        Ok(out) if errors.is_empty() => Ok(out),
        Ok(_) => Err(errors),
        Err(e) => {
            errors.splice(0..0, e.into_iter().map(|m| (m, None)));
            Err(errors)
        }
    }
}

/// Every binding names an element of the file with that property.
#[cfg(feature = "urdf")]
fn check_params(
    robot: &urdf_rs::Robot,
    opts: &UrdfOptions,
    params: &[Param],
) -> Vec<(String, Option<usize>)> {
    let mut errors = Vec::new();
    let link_ids = Idents::new(robot.links.iter().map(|l| l.name.as_str()));
    let joint_ids = Idents::new(robot.joints.iter().map(|j| j.name.as_str()));
    for (k, p) in params.iter().enumerate() {
        let (el, prop) = (p.element.to_string(), p.property.to_string());
        let is_link = robot.links.iter().any(|l| link_ids.of(&l.name) == el);
        let is_joint = robot.joints.iter().any(|j| joint_ids.of(&j.name) == el);
        let ok = match prop.as_str() {
            "mass" => is_link,
            _ => is_joint,
        };
        if !ok {
            let what = if prop == "mass" { "link" } else { "joint" };
            errors.push((
                format!("`urdf_param` binds `{el}.{prop}`, but the file has no {what} `{el}`"),
                Some(k),
            ));
        }
        let joint = robot.joints.iter().find(|j| joint_ids.of(&j.name) == el);
        if let Some(j) = joint
            && prop != "mass"
        {
            let fixed = j.joint_type == urdf_rs::JointType::Fixed || opts.lock.contains(&j.name);
            if fixed {
                errors.push((
                    format!(
                        "`{el}.{prop}` is bound, but `{el}` is fixed or locked: it has no {prop}"
                    ),
                    Some(k),
                ));
            } else if matches!(prop.as_str(), "lower" | "upper") {
                let law = opts.limits.as_ref().and_then(stop_law);
                let other = if prop == "lower" { "upper" } else { "lower" };
                if law.is_none() {
                    errors.push((
                        format!("`{el}.{prop}` is bound, but the limits are not stops: add `limits = stops(restitution = …)` or `limits = support(k = …)`"),
                        Some(k),
                    ));
                } else if (!j.limit.lower.is_finite() || !j.limit.upper.is_finite())
                    && !params
                        .iter()
                        .any(|q| q.element == p.element && q.property == other)
                {
                    errors.push((
                        format!("`{el}` has no limits in the file; bind `{el}.{other}` too"),
                        Some(k),
                    ));
                }
            }
        }
        if params[..k]
            .iter()
            .any(|q| q.element == p.element && q.property == p.property)
        {
            errors.push((format!("`{el}.{prop}` is bound twice; keep one"), Some(k)));
        }
    }
    errors
}

#[cfg(feature = "urdf")]
fn translate_file(
    robot: &urdf_rs::Robot,
    opts: &UrdfOptions,
    params: &[Param],
) -> Result<String, Vec<String>> {
    // The placeholder standing for a bound value, replaced by its expression after
    // parsing (see `respan`).
    let link_ids = Idents::new(robot.links.iter().map(|l| l.name.as_str()));
    let joint_ids = Idents::new(robot.joints.iter().map(|j| j.name.as_str()));
    // `el`: the identifier of the link or joint.
    let bound = |el: &str, prop: &str| -> Option<String> {
        params
            .iter()
            .position(|p| p.element == el && p.property == prop)
            .map(|k| format!("{PLACEHOLDER}{k}"))
    };
    let mut errors = Vec::new();
    let links: std::collections::HashMap<&str, &urdf_rs::Link> =
        robot.links.iter().map(|l| (l.name.as_str(), l)).collect();
    if links.len() != robot.links.len() {
        errors.push("two links share a name".to_string());
    }
    // Parent of each link, and the root.
    let mut parent_joint: std::collections::HashMap<&str, &urdf_rs::Joint> = Default::default();
    for j in &robot.joints {
        for l in [&j.parent.link, &j.child.link] {
            if !links.contains_key(l.as_str()) {
                errors.push(format!(
                    "joint `{}` names a link `{l}` the file does not declare",
                    j.name
                ));
            }
        }
        if parent_joint.insert(j.child.link.as_str(), j).is_some() {
            errors.push(format!(
                "link `{}` is the child of two joints; a URDF describes a tree (closed loops are not supported)",
                j.child.link
            ));
        }
    }
    let roots: Vec<&str> = robot
        .links
        .iter()
        .map(|l| l.name.as_str())
        .filter(|n| !parent_joint.contains_key(n))
        .collect();
    if roots.len() != 1 && errors.is_empty() {
        errors.push(if roots.is_empty() {
            "every link is the child of a joint: the joints form a cycle".to_string()
        } else {
            format!(
                "{} links are nobody's child ({}); a URDF has one root",
                roots.len(),
                roots.join(", ")
            )
        });
    }
    if !errors.is_empty() {
        return Err(errors);
    }
    // Not a reason to stop: the tree is sound, and the other options are checked too.
    for l in &opts.lock {
        if !robot.joints.iter().any(|j| &j.name == l) {
            errors.push(format!(
                "`lock` names a joint `{l}` the file does not declare"
            ));
        }
    }
    let root = roots[0];
    let locked = |j: &urdf_rs::Joint| opts.lock.contains(&j.name);
    let fixed = |j: &urdf_rs::Joint| j.joint_type == urdf_rs::JointType::Fixed || locked(j);
    // Children lists, and a depth-first order from the root (which also finds cycles
    // not reachable from it: those links are never visited).
    let mut children: std::collections::HashMap<&str, Vec<&urdf_rs::Joint>> = Default::default();
    for j in &robot.joints {
        children.entry(j.parent.link.as_str()).or_default().push(j);
    }
    // Depth-first preorder, children in file order.
    let mut order: Vec<&urdf_rs::Joint> = Vec::new();
    let mut stack: Vec<&urdf_rs::Joint> = children
        .get(root)
        .map(|cs| cs.iter().rev().copied().collect())
        .unwrap_or_default();
    while let Some(j) = stack.pop() {
        order.push(j);
        if order.len() > robot.joints.len() {
            break;
        }
        if let Some(cs) = children.get(j.child.link.as_str()) {
            stack.extend(cs.iter().rev().copied());
        }
    }
    if order.len() != robot.joints.len() {
        return Err(vec![
            "some joints form a cycle not connected to the root".to_string(),
        ]);
    }
    // Mass carried below each link (to leave out massless leaves on fixed joints).
    let mass = |l: &str| links[l].inertial.mass.value;
    let mut carries: std::collections::HashMap<&str, bool> = Default::default();
    for j in order.iter().rev() {
        let c = j.child.link.as_str();
        let below = children
            .get(c)
            .is_some_and(|cs| cs.iter().any(|k| carries[k.child.link.as_str()]));
        carries.insert(c, mass(c) > 0.0 || below || !fixed(j));
    }

    let mut out = String::new();
    let body = |name: &str, l: &urdf_rs::Link, out: &mut String, errors: &mut Vec<String>| {
        let m = l.inertial.mass.value;
        if !m.is_finite() || m < 0.0 {
            errors.push(format!("link `{name}` has mass {m}; a mass is positive (or zero for a frame that carries others)"));
        }
        let i = &l.inertial.inertia;
        let i0 = [
            [i.ixx, i.ixy, i.ixz],
            [i.ixy, i.iyy, i.iyz],
            [i.ixz, i.iyz, i.izz],
        ];
        let inertia = rotate_inertia(i0, l.inertial.origin.rpy.0);
        let rows: Vec<String> = inertia.iter().map(|r| vec3(*r)).collect();
        out.push_str(&format!(
            "#[body({}, mass = {}, com = {}, inertia = [{}])]\n",
            link_ids.of(name),
            bound(&link_ids.of(name), "mass").unwrap_or_else(|| num(m)),
            vec3(l.inertial.origin.xyz.0),
            rows.join(", ")
        ));
    };
    let world_body = root;
    if opts.free_base {
        body(root, links[root], &mut out, &mut errors);
        out.push_str(&format!(
            "#[joint({}_base: free, parent = world, child = {})]\n",
            link_ids.of(root),
            link_ids.of(root)
        ));
    }
    let mut stops = String::new();
    for j in &order {
        let child = j.child.link.as_str();
        if !carries[child] {
            // A tool or sensor frame: kept as a frame when kinematics is asked for.
            if opts.frames {
                let parent = if j.parent.link == world_body && !opts.free_base {
                    "world".to_string()
                } else {
                    link_ids.of(&j.parent.link)
                };
                out.push_str(&format!(
                    "#[frame({}, parent = {parent}, origin = {}, rpy = {})]\n",
                    link_ids.of(child),
                    vec3(j.origin.xyz.0),
                    vec3(j.origin.rpy.0)
                ));
            }
            continue;
        }
        let jn = joint_ids.of(&j.name);
        // The body first: its own errors are reported whatever is wrong with the joint.
        body(child, links[child], &mut out, &mut errors);
        if j.mimic.is_some() && !locked(j) {
            errors.push(format!(
                "joint `{}` has a <mimic>: coupled joints need closed-loop constraints, which are not supported yet; hold it with `lock = [{}]` or remove the mimic from the file",
                j.name, j.name
            ));
            continue;
        }
        let axis = j.axis.xyz.0;
        let moves = matches!(
            j.joint_type,
            urdf_rs::JointType::Revolute
                | urdf_rs::JointType::Continuous
                | urdf_rs::JointType::Prismatic
        );
        if moves
            && !locked(j)
            && !(axis.iter().all(|x| x.is_finite()) && axis.iter().any(|x| *x != 0.0))
        {
            errors.push(format!(
                "joint `{}` has the axis `<axis xyz=\"{} {} {}\"/>`, which has no direction: give a non-zero vector (for example `<axis xyz=\"0 0 1\"/>`), or lock the joint",
                j.name, axis[0], axis[1], axis[2]
            ));
            continue;
        }
        let kind = match j.joint_type {
            _ if locked(j) => "fixed".to_string(),
            urdf_rs::JointType::Revolute | urdf_rs::JointType::Continuous => {
                format!("revolute({})", vec3(axis))
            }
            urdf_rs::JointType::Prismatic => format!("prismatic({})", vec3(axis)),
            urdf_rs::JointType::Fixed => "fixed".to_string(),
            ref other => {
                errors.push(format!(
                    "joint `{}` is of type {other:?}, which is not supported: use revolute, continuous, prismatic or fixed joints (a floating base is `base = free`)",
                    j.name
                ));
                continue;
            }
        };
        let parent = if j.parent.link == world_body && !opts.free_base {
            "world".to_string()
        } else {
            link_ids.of(&j.parent.link)
        };
        out.push_str(&format!(
            "#[joint({jn}: {kind}, parent = {parent}, child = {}, origin = {}, rpy = {})]\n",
            link_ids.of(child),
            vec3(j.origin.xyz.0),
            vec3(j.origin.rpy.0)
        ));
        let movable = !locked(j)
            && matches!(
                j.joint_type,
                urdf_rs::JointType::Revolute | urdf_rs::JointType::Prismatic
            );
        if movable
            && let Some(limits) = &opts.limits
            && let Some(law) = stop_law(limits)
        {
            let (lo, hi) = (j.limit.lower, j.limit.upper);
            let (blo, bhi) = (bound(&jn, "lower"), bound(&jn, "upper"));
            if (lo.is_finite() && hi.is_finite() && lo < hi) || (blo.is_some() && bhi.is_some()) {
                stops.push_str(&format!(
                    "#[stop({jn}, min = {}, max = {}, {law})]\n",
                    blo.unwrap_or_else(|| num(lo)),
                    bhi.unwrap_or_else(|| num(hi))
                ));
            }
        }
        // A bound friction or damping is an element even where the file has none and
        // without `joint_friction`/`joint_damping`: the binding says it is a parameter.
        let (friction, damping) = j
            .dynamics
            .as_ref()
            .map_or((0.0, 0.0), |d| (d.friction, d.damping));
        if !fixed(j) {
            match bound(&jn, "friction") {
                Some(b) => stops.push_str(&format!("#[friction({jn}, f_crit = {b})]\n")),
                None if opts.friction && friction > 0.0 => {
                    stops.push_str(&format!("#[friction({jn}, f_crit = {})]\n", num(friction)))
                }
                None => {}
            }
            match bound(&jn, "damping") {
                Some(b) => stops.push_str(&format!("#[damper({jn}, c = {b})]\n")),
                None if opts.damping && damping > 0.0 => {
                    stops.push_str(&format!("#[damper({jn}, c = {})]\n", num(damping)))
                }
                None => {}
            }
        }
    }
    if let Some(limits) = &opts.limits
        && stop_law(limits).is_none()
        && ident_of(limits).is_none_or(|i| i != "ignore")
    {
        errors.push(
            "`limits` is `stops(restitution = e)`, `support(k = k)` or `ignore` (the default)"
                .to_string(),
        );
    }
    if !errors.is_empty() {
        return Err(errors);
    }
    out.push_str(&stops);
    out.push_str("struct __Urdf;\n");
    Ok(out)
}

/// `stops(restitution = e)` → `restitution = e`; `support(k = k)` → `k_support = k`.
#[cfg_attr(not(feature = "urdf"), allow(dead_code))]
fn stop_law(e: &Expr) -> Option<String> {
    let Expr::Call(c) = strip(e) else {
        return None;
    };
    let f = match strip(&c.func) {
        Expr::Path(p) => p.path.get_ident()?.to_string(),
        _ => return None,
    };
    let [arg] = c.args.iter().collect::<Vec<_>>()[..] else {
        return None;
    };
    let Expr::Assign(a) = arg else { return None };
    let key = ident_of(&a.left)?.to_string();
    let value = {
        let r = &a.right;
        quote::quote!(#r).to_string()
    };
    match (f.as_str(), key.as_str()) {
        ("stops", "restitution") => Some(format!("restitution = {value}")),
        ("support", "k") => Some(format!("k_support = {value}")),
        _ => None,
    }
}
