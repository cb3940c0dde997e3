//! Raw attributes → validated [`Model`], one `check_*` function per rule, every failure
//! reported (spanned at the user's tokens) before giving up.

use std::collections::HashMap;

use syn::{Data, DeriveInput, Expr, Fields, Ident, Type};

use crate::attr_values::{joint_kind, placement, take_child, take_parent, vec3, zero3};
use crate::diag::Diagnostics;
use crate::model::{Damper, JointKind, Link, Mat3, Model, PExpr, Potential, Spring, Vec3};
use crate::parse::expr::{lower, lower_with_var};
use crate::parse::{self, Family, RawAttr, array, ident_of, strip};

/// The most coordinates a scene may have (dependency masks are 64-bit).
pub const MAX_DOF: usize = 64;

struct Body {
    name: Ident,
    mass: Option<PExpr>,
    com: Vec3,
    inertia: Mat3,
}

struct Joint {
    name: Ident,
    kind: JointKind,
    parent: Option<Ident>, // None = world
    child: Ident,
    origin: Vec3,
    rpy: Vec3,
}

pub fn validate(input: &DeriveInput, diag: &mut Diagnostics) -> Option<Model> {
    let fields = check_struct_shape(input, diag)?;
    let names: Vec<String> = fields.iter().map(|f| f.to_string()).collect();
    let mut raws = parse::read_attrs(&input.attrs, diag);
    // A URDF file's links and joints, as the attributes a user would write.
    let mut urdf_file = None;
    let options = match raws.iter_mut().find(|r| r.family == Family::Mechanism) {
        Some(m) => crate::urdf::take_options(m, diag),
        None => Ok(None),
    };
    let Ok(options) = options else {
        return None;
    };
    let params = crate::urdf::read_params(&input.attrs, diag);
    if options.is_none()
        && let Some(p) = params.first()
    {
        diag.error_at(
            &p.element,
            "`urdf_param` binds values of a URDF file; add `urdf = \"path/to/robot.urdf\"` to `#[mechanism(…)]` or drop it",
        );
    }
    // How errors about a body name it: the link of the file, for a URDF scene.
    let mut who = Who { urdf: None };
    if let Some(opts) = options {
        who.urdf = Some(opts.path.value());
        urdf_file = Some(crate::urdf::resolve(&opts.path.value()));
        match crate::urdf::attributes(&opts, &params, diag) {
            Some(more) => raws.extend(more),
            // The file is the scene: without it every other message would mislead.
            None => return None,
        }
    }
    // Whether the user wrote any (even wrong) body or joint: if so, the errors about
    // those say what is wrong, and "needs a body and a joint" would mislead.
    let raws_had_bodies_or_joints = raws
        .iter()
        .any(|r| matches!(r.family, Family::Body | Family::Joint));

    let mut gravity = None;
    let mut inputs_expr = None;
    let mut krate = None;
    let mut emit = crate::model::Emit::default();
    let mut emit_expr: Option<syn::Expr> = None;
    let mut algorithm = crate::model::Algorithm::default();
    let mut algorithm_expr: Option<syn::Expr> = None;
    let mut mechanism_seen = false;
    let mut bodies = Vec::new();
    let mut joints = Vec::new();
    let mut element_attrs = Vec::new();
    let mut nonsmooth_attrs = Vec::new();
    let mut frame_attrs = Vec::new();
    let mut loop_attrs = Vec::new();
    let mut contact_attrs = Vec::new();
    let mut point_spring_attrs = Vec::new();
    let mut claimed: Vec<Ident> = Vec::new();
    for mut raw in raws {
        match raw.family {
            Family::Mechanism => {
                // One `#[mechanism]`: with two, which `gravity` or `inputs` holds would
                // depend on a merge rule the reader has to know.
                if std::mem::replace(&mut mechanism_seen, true) {
                    diag.error_span(
                        raw.span,
                        "a second `#[mechanism(…)]` attribute; give `gravity` and `inputs` in one",
                    );
                    continue;
                }
                if let Some((_, g)) = raw.take("gravity", diag) {
                    gravity = vec3(&g, "gravity", &names, diag);
                }
                inputs_expr = raw.take("inputs", diag).map(|(_, e)| e);
                if let Some((_, e)) = raw.take("crate", diag) {
                    krate = crate_path(&e, diag);
                }
                if let Some((_, e)) = raw.take("emit", diag) {
                    emit = read_emit(&e, diag);
                    emit_expr = Some(e);
                }
                if let Some((_, e)) = raw.take("forward_dynamics", diag) {
                    algorithm = read_algorithm(&e, diag);
                    algorithm_expr = Some(e);
                }
                raw.reject_rest(
                    &[
                        "gravity",
                        "inputs",
                        "crate",
                        "emit",
                        "forward_dynamics",
                        "urdf",
                        "limits",
                        "joint_friction",
                        "joint_damping",
                        "base",
                        "lock",
                    ],
                    diag,
                );
            }
            // `#[body(name: kind, parent = …, origin = …, mass = …, …)]` declares the body
            // and the joint it hangs from (named like the body) in one attribute: half
            // the attributes of a long chain (rustc stops at 128 helper attributes on
            // one struct).
            Family::Body if raw.head.is_some() => {
                let child = raw.name.clone();
                let (body, joint) = split_body_with_joint(raw);
                bodies.extend(read_body(body, &names, &who, diag));
                match read_joint(joint, &names, diag) {
                    Some(j) => joints.push(j),
                    None => {
                        if let Some(c) = &child {
                            diag.excuse(c);
                        }
                        claimed.extend(child)
                    }
                }
            }
            Family::Body => bodies.extend(read_body(raw, &names, &who, diag)),
            Family::Joint => {
                // The child a joint names, even if the joint has errors: that body is
                // attached as far as the user is concerned, and saying otherwise would
                // only add a misleading second message.
                let child = raw
                    .args
                    .iter()
                    .find(|(k, _)| k == "child")
                    .and_then(|(_, e)| ident_of(e).cloned());
                let joint_name = raw.name.clone();
                match read_joint(raw, &names, diag) {
                    Some(j) => joints.push(j),
                    None => {
                        if let Some(j) = &joint_name {
                            diag.excuse(j);
                        }
                        claimed.extend(child)
                    }
                }
            }
            Family::Spring if raw.head.is_some() => point_spring_attrs.push(raw),
            Family::Spring | Family::Damper => element_attrs.push(raw),
            Family::Friction | Family::Bingham | Family::Stop => nonsmooth_attrs.push(raw),
            Family::Frame => frame_attrs.push(raw),
            Family::LoopJoint => loop_attrs.push(raw),
            Family::Contact => contact_attrs.push(raw),
        }
    }
    check_unique(bodies.iter().map(|b| &b.name), "body", diag);
    check_unique(joints.iter().map(|j| &j.name), "joint", diag);
    if !raws_had_bodies_or_joints {
        diag.error_span(
            input.ident.span(),
            "a mechanism needs at least one `#[body(…)]` and one `#[joint(…)]`, e.g.\n\
             #[body(link, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]\n\
             #[joint(hinge: revolute(z), parent = world, child = link)]",
        );
    }
    let links = build_tree(&bodies, &joints, &claimed, diag)?;
    let springs_dampers = read_elements(element_attrs, &links, &names, diag);
    if links.iter().any(|l| l.kind.is_lie()) {
        for raw in &nonsmooth_attrs {
            if let Some(name) = &raw.name {
                diag.error_at(
                    name,
                    "friction, dash-pots and stops are not supported yet in scenes with spherical or free joints; model the joint with revolute joints or drop the element",
                );
            }
        }
    }
    let tree_joints: Vec<&Ident> = joints.iter().map(|j| &j.name).collect();
    let loops = crate::loops::read(loop_attrs, &links, &tree_joints, &names, diag);
    let point_springs = crate::point_springs::read(point_spring_attrs, &links, &names, diag);
    let elements = crate::nonsmooth::read(nonsmooth_attrs, &links, &names, diag);
    let taken: Vec<String> = tree_joints
        .iter()
        .map(|j| j.to_string())
        .chain(loops.iter().map(|l| l.name.clone()))
        .chain(elements.iter().map(|e| e.name.clone()))
        .collect();
    let contacts = crate::contacts::read(contact_attrs, &links, &taken, &names, diag);
    crate::nonsmooth::bearing::check_subtrees(
        &elements,
        &links,
        &loops,
        &point_springs,
        &contacts,
        diag,
    );
    let frames = read_frames(frame_attrs, &links, &names, diag);
    // Declaring a frame is asking for its pose.
    emit.kinematics |= !frames.is_empty();
    // Scenes with non-smooth elements always carry their energies: time-stepping keeps
    // each step passive with them (`NonSmooth: Energy`).
    emit.energy |= !elements.is_empty();
    let inputs = match &inputs_expr {
        Some(e) => read_inputs(e, &links, diag),
        None => Vec::new(),
    };
    let gravity = gravity.filter(|g: &Vec3| !g.iter().all(|c| c.as_const() == Some(0.0)));
    if let Some(e) = &emit_expr
        && ident_of(e).is_none()
    {
        // Kernels the scene has nothing to emit for: an explicit list naming them is a
        // misunderstanding worth saying (`emit = all` just means "everything there is").
        let lie = links.iter().any(|l| l.kind.is_lie());
        if emit.christoffel && lie {
            diag.error_at(
                e,
                "`christoffel` is not available for scenes with spherical or free joints (their Coriolis matrix is emitted directly); drop it from `emit`",
            );
        }
        if elements.is_empty() && (emit.delassus || emit.dae_residuals || emit.switching_functions)
        {
            diag.error_at(
                e,
                "`delassus`, `dae_residuals` and `switching_functions` belong to scenes with non-smooth elements (friction, dash-pots, stops), and this scene has none; drop them from `emit`",
            );
        }
    }
    // A bearing's limit depends on the acceleration (its joint's load): the DAE residuals
    // and switching functions, written in `(q, v, f)`, do not hold it. Asked for by name
    // they are an error; `emit = all` leaves them out.
    if elements.iter().any(|e| e.bearing.is_some())
        && (emit.dae_residuals || emit.switching_functions)
    {
        match &emit_expr {
            Some(e) if ident_of(e).is_none() => diag.error_at(
                e,
                "`dae_residuals` and `switching_functions` are written in (q, v, f), and a bearing friction's limit (`mu = …`) depends on the acceleration through its joint's load; drop them from `emit`",
            ),
            _ => {
                emit.dae_residuals = false;
                emit.switching_functions = false;
            }
        }
    }
    if diag.has_errors() {
        return None;
    }
    let (springs, dampers, potentials) = springs_dampers;
    let model = Model {
        ident: input.ident.clone(),
        params: fields,
        gravity,
        links,
        springs,
        dampers,
        inputs,
        elements,
        potentials,
        krate,
        emit,
        urdf_file,
        frames,
        algorithm,
        loops,
        point_springs,
        contacts,
    };
    if model.algorithm == crate::model::Algorithm::Compact
        && let (Some(why), Some(e)) = (model.compact_unsupported(), &algorithm_expr)
    {
        diag.error_at(
            e,
            format!(
                "`forward_dynamics = compact` cannot take this scene: {why}; use `auto`, `crba` or `aba`"
            ),
        );
        return None;
    }
    Some(model)
}

/// `forward_dynamics = auto | crba | aba | compact`.
fn read_algorithm(e: &syn::Expr, diag: &mut Diagnostics) -> crate::model::Algorithm {
    use crate::model::Algorithm;
    let found = ident_of(e).and_then(|i| {
        Algorithm::NAMES
            .iter()
            .find(|(n, _)| i == n)
            .map(|(_, a)| *a)
    });
    found.unwrap_or_else(|| {
        diag.error_at(
            e,
            "`forward_dynamics` is `auto` (the default: per kernel, whichever emits fewer operations, \
             and `compact` for large trees), `crba` (mass matrix, then its sparse LᵀDL), `aba` (the \
             articulated-body algorithm, unrolled) or `compact` (the articulated-body algorithm as one \
             loop over a table of the bodies)",
        );
        Algorithm::default()
    })
}

/// `#[frame(tool, parent = hand, origin = [x, y, z], rpy = [r, p, y])]`: frames fixed to
/// a body (or to another frame, or the world), whose poses and Jacobians the
/// `Kinematics` kernel gives. Names must differ from the bodies' (bodies are frames too).
fn read_frames(
    raws: Vec<RawAttr>,
    links: &[Link],
    names: &[String],
    diag: &mut Diagnostics,
) -> Vec<crate::model::Frame> {
    struct Raw {
        name: Ident,
        parent: Ident,
        origin: Vec3,
        rpy: Vec3,
    }
    // Bodies by link index (the translation half of a free joint is internal).
    let bodies: Vec<(usize, &str)> = links
        .iter()
        .enumerate()
        .filter(|(_, l)| l.kind != JointKind::Translation)
        .map(|(i, l)| (i, l.name.as_str()))
        .collect();
    let mut read: Vec<Raw> = Vec::new();
    for mut raw in raws {
        let Some(name) = raw.name.clone() else {
            continue;
        };
        let mut ok = true;
        if let Some(h) = &raw.head {
            diag.error_at(
                h,
                format_args!("a frame takes no `: kind`; write `#[frame({name}, parent = <body>, origin = [x, y, z])]`"),
            );
            ok = false;
        }
        if name == "world" {
            diag.error_at(
                &name,
                "`world` is the fixed frame and is always there; name the frame differently",
            );
            ok = false;
        } else if bodies.iter().any(|(_, b)| name == b) {
            diag.error_at(
                &name,
                format_args!("`{name}` is a body, and every body is already a frame; give the frame its own name"),
            );
            ok = false;
        } else if read.iter().any(|r| r.name == name) {
            diag.error_at(
                &name,
                format_args!(
                    "a frame named `{name}` is already declared; give each frame its own name"
                ),
            );
            ok = false;
        }
        let parent = match raw.take("parent", diag) {
            Some((_, e)) => match ident_of(&e) {
                Some(i) => Some(i.clone()),
                None => {
                    diag.error_at(&e, "`parent` must be a body name, a frame name or `world`");
                    None
                }
            },
            None => {
                diag.error_at(
                    &name,
                    format_args!(
                        "frame `{name}` has no parent; add `parent = <body>` (or `world`)"
                    ),
                );
                None
            }
        };
        let (origin, rpy) = placement(&mut raw, names, diag);
        raw.reject_rest(&["parent", "origin", "rpy"], diag);
        if let (true, Some(parent)) = (ok, parent) {
            read.push(Raw {
                name,
                parent,
                origin,
                rpy,
            });
        }
    }
    // Resolve parents: a body, the world, or a frame (followed to its body).
    let mut out = Vec::new();
    'frames: for r in &read {
        let mut offsets = vec![(r.origin.clone(), r.rpy.clone())];
        let mut at = &r.parent;
        for _ in 0..=read.len() {
            let link = if at == "world" {
                Some(None)
            } else {
                bodies.iter().find(|(_, b)| at == b).map(|(i, _)| Some(*i))
            };
            if let Some(link) = link {
                offsets.reverse();
                out.push(crate::model::Frame {
                    name: r.name.to_string(),
                    link,
                    offsets,
                });
                continue 'frames;
            }
            match read.iter().find(|f| f.name == *at) {
                Some(f) => {
                    offsets.push((f.origin.clone(), f.rpy.clone()));
                    at = &f.parent;
                }
                None => {
                    let frames: Vec<String> =
                        read.iter().map(|f| format!("`{}`", f.name)).collect();
                    let bodies: Vec<String> =
                        bodies.iter().map(|(_, b)| format!("`{b}`")).collect();
                    diag.error_at(
                        &r.parent,
                        format_args!(
                            "no body or frame named `{at}`; a frame hangs from `world`, a body ({}){}",
                            bodies.join(", "),
                            if frames.is_empty() {
                                String::new()
                            } else {
                                format!(" or a frame ({})", frames.join(", "))
                            }
                        ),
                    );
                    continue 'frames;
                }
            }
        }
        diag.error_at(
            &r.parent,
            format_args!("frame `{}` hangs from a loop of frames; one of them must hang from a body or `world`", r.name),
        );
    }
    out
}

/// `emit = [coriolis, energy, …]` or `emit = all`: the optional kernels to emit.
fn read_emit(e: &syn::Expr, diag: &mut Diagnostics) -> crate::model::Emit {
    use crate::model::Emit;
    let known = || {
        let names: Vec<String> = Emit::NAMES.iter().map(|(n, _)| format!("`{n}`")).collect();
        format!("{} (see `filippov::runtime::kernels`)", names.join(", "))
    };
    if ident_of(e).is_some_and(|i| i == "all") {
        return Emit::all();
    }
    let mut emit = Emit::default();
    let syn::Expr::Array(a) = parse::strip(e) else {
        diag.error_at(
            e,
            format_args!(
                "`emit` takes a list of kernel names, e.g. `emit = [coriolis, energy]`, or `emit = all`; the names are {}",
                known()
            ),
        );
        return emit;
    };
    let mut seen: Vec<String> = Vec::new();
    for item in &a.elems {
        match ident_of(item) {
            Some(name) if Emit::default().set(&name.to_string()) => {
                let s = name.to_string();
                if seen.contains(&s) {
                    diag.error_at(item, format_args!("`{s}` is listed twice; keep one"));
                }
                emit.set(&s);
                seen.push(s);
            }
            Some(name) => diag.error_at(
                item,
                format_args!("no kernel is called `{name}`; `emit` knows {}", known()),
            ),
            None => diag.error_at(
                item,
                format_args!(
                    "`emit` lists kernel names, e.g. `coriolis`; the names are {}",
                    known()
                ),
            ),
        }
    }
    emit
}

/// Parameters are the fields of a plain struct, each an `f64`: the generated code reads
/// them by name and does `f64` arithmetic on them.
fn check_struct_shape(input: &DeriveInput, diag: &mut Diagnostics) -> Option<Vec<Ident>> {
    if !input.generics.params.is_empty() {
        diag.error_at(
            &input.generics,
            "a mechanism struct cannot be generic; its parameters are `f64` fields",
        );
    }
    let fields = match &input.data {
        Data::Struct(s) => match &s.fields {
            Fields::Named(f) => &f.named,
            Fields::Unit => return Some(Vec::new()),
            Fields::Unnamed(f) => {
                diag.error_at(
                    f,
                    "parameters must be named fields, e.g. `struct Arm { m1: f64, l1: f64 }`",
                );
                return None;
            }
        },
        _ => {
            diag.error_span(
                input.ident.span(),
                "`Mechanism` can only be derived for a struct whose fields are the parameters, e.g. `struct Arm { m1: f64, l1: f64 }`",
            );
            return None;
        }
    };
    let mut out = Vec::new();
    for f in fields {
        let ok = matches!(&f.ty, Type::Path(p) if p.qself.is_none() && p.path.is_ident("f64"));
        if !ok {
            diag.error_at(&f.ty, "parameter fields must be `f64` (the generated kernels compute in f64); change this type to `f64`");
        }
        // `PI` in an expression is the constant π; a field of that name could never be
        // read, so it is refused rather than silently shadowed. (Function names are no
        // conflict: `sin` is the field, `sin(x)` the function.)
        if let Some(id) = &f.ident
            && id == "PI"
        {
            diag.error_at(
                id,
                "a field named `PI` would be shadowed by the constant π in every expression; rename the field",
            );
        }
        out.extend(f.ident.clone());
    }
    Some(out)
}

/// Splits `#[body(name: kind, …)]` into the body (mass, com, inertia and anything
/// unknown, reported there) and its joint (the kind, parent, origin, rpy; child = name).
fn split_body_with_joint(mut raw: RawAttr) -> (RawAttr, RawAttr) {
    let name = raw.name.clone().expect("bodies are named");
    let (joint_args, body_args): (Vec<_>, Vec<_>) = raw
        .args
        .drain(..)
        .partition(|(k, _)| ["parent", "origin", "rpy"].iter().any(|j| k == j));
    let mut joint_args = joint_args;
    joint_args.push((
        syn::Ident::new("child", name.span()),
        syn::parse_quote!(#name),
    ));
    let joint = RawAttr {
        family: Family::Joint,
        name: Some(name),
        head: raw.head.take(),
        args: joint_args,
        span: raw.span,
    };
    raw.args = body_args;
    (raw, joint)
}

/// `crate = fil` or `crate = "fil"`: the path the generated code names the `filippov`
/// crate by, for a dependency renamed in `Cargo.toml` (as serde's `crate` option).
fn crate_path(e: &syn::Expr, diag: &mut Diagnostics) -> Option<syn::Path> {
    let path = match parse::strip(e) {
        syn::Expr::Path(p) if p.qself.is_none() => Some(p.path.clone()),
        syn::Expr::Lit(syn::ExprLit {
            lit: syn::Lit::Str(s),
            ..
        }) => s.parse::<syn::Path>().ok(),
        _ => None,
    };
    if path.is_none() {
        diag.error_at(
            e,
            "`crate` takes the path the `filippov` crate is known by here, e.g. `crate = fil` for `fil = { package = \"filippov\", … }`",
        );
    }
    path
}

/// Names must be unique within their family: attributes refer to bodies and joints by
/// name, so a duplicate would make every reference ambiguous.
fn check_unique<'a>(names: impl Iterator<Item = &'a Ident>, what: &str, diag: &mut Diagnostics) {
    let mut seen: HashMap<String, &Ident> = HashMap::new();
    for n in names {
        if seen.insert(n.to_string(), n).is_some() {
            // Which of the two a later reference means is unknowable: not asked again.
            diag.excuse(n);
            diag.error_at(
                n,
                format_args!(
                    "a {what} named `{n}` is already declared; give each {what} its own name"
                ),
            );
        }
    }
}
/// Where a body comes from, for its error messages: written in an attribute, or a link
/// of a URDF file (then the message names the file and the link, as the file's other
/// errors do).
struct Who {
    urdf: Option<String>,
}

impl Who {
    fn body(&self, name: &Ident) -> String {
        match &self.urdf {
            Some(path) => format!("URDF `{path}`: link `{name}`"),
            None => format!("body `{name}`"),
        }
    }
}

fn read_body(
    mut raw: RawAttr,
    names: &[String],
    who: &Who,
    diag: &mut Diagnostics,
) -> Option<Body> {
    let name = raw.name.clone()?;
    if name == "world" {
        diag.error_at(
            &name,
            "`world` is the fixed frame every tree hangs from and cannot be a body; name the body differently, e.g. `base`",
        );
        return None;
    }
    if let Some(h) = &raw.head {
        diag.error_at(
            h,
            "a body takes no `: kind` here; write `#[body(name, mass = …, com = […], inertia = …)]`",
        );
    }
    let mass = match raw.take("mass", diag) {
        Some((_, e)) => {
            lower(&e, names, diag).inspect(|m| check_mass(m, &e, &who.body(&name), diag))
        }
        None => {
            diag.error_at(
                &name,
                format_args!("body `{name}` has no mass; add `mass = <expression>`"),
            );
            None
        }
    };
    let com = raw
        .take("com", diag)
        .and_then(|(_, e)| vec3(&e, "com", names, diag))
        .unwrap_or_else(zero3);
    let inertia = match raw.take("inertia", diag) {
        Some((_, e)) => inertia(&e, &who.body(&name), names, diag)?,
        None => [zero3(), zero3(), zero3()],
    };
    raw.reject_rest(&["mass", "com", "inertia"], diag);
    Some(Body {
        name,
        mass,
        com,
        inertia,
    })
}

/// A literal mass must be non-negative and finite: a negative mass makes M indefinite
/// and the dynamics meaningless. Zero is allowed for intermediate frames (checked in
/// [`build_tree`]: a massless body must carry others).
fn check_mass(m: &PExpr, at: &Expr, body: &str, diag: &mut Diagnostics) {
    if let Some(v) = m.as_const()
        && !(v > 0.0 && v.is_finite())
        && v != 0.0
    {
        diag.error_at(
            at,
            format_args!("{body}: mass must be positive and finite, found {v}"),
        );
    }
}

/// Inertia about the centre of mass: a shape function, `diag(…)`, a full 3×3 array, or
/// `point`.
fn inertia(e: &Expr, body: &str, names: &[String], diag: &mut Diagnostics) -> Option<Mat3> {
    const SHAPES: &str = "`rod(m, l)` (along x), `cylinder(m, r, h)` (along z), `cuboid(m, a, b, c)`, `sphere(m, r)`, `diag(ixx, iyy, izz)`, `[[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]]` or `point`";
    let num = |v: f64| PExpr::Const(v);
    let mul = |a: PExpr, b: PExpr| PExpr::Bin('*', Box::new(a), Box::new(b));
    let add = |a: PExpr, b: PExpr| PExpr::Bin('+', Box::new(a), Box::new(b));
    let sq = |a: &PExpr| mul(a.clone(), a.clone());
    let diag3 = |d: [PExpr; 3]| {
        let [a, b, c] = d;
        [
            [a, PExpr::zero(), PExpr::zero()],
            [PExpr::zero(), b, PExpr::zero()],
            [PExpr::zero(), PExpr::zero(), c],
        ]
    };
    let m = match strip(e) {
        Expr::Path(_) if ident_of(e).is_some_and(|i| i == "point") => {
            diag3([PExpr::zero(), PExpr::zero(), PExpr::zero()])
        }
        Expr::Call(c) => {
            let name = ident_of(&c.func).map(|i| i.to_string()).unwrap_or_default();
            let arity = match name.as_str() {
                "rod" | "sphere" => 2,
                "cylinder" | "diag" => 3,
                "cuboid" => 4,
                _ => {
                    diag.error_at(
                        &c.func,
                        format_args!("unknown inertia shape; use one of {SHAPES}"),
                    );
                    return None;
                }
            };
            if c.args.len() != arity {
                diag.error_at(
                    e,
                    format_args!(
                        "`{name}` takes {arity} arguments, found {}; use one of {SHAPES}",
                        c.args.len()
                    ),
                );
                return None;
            }
            let args: Vec<PExpr> = c
                .args
                .iter()
                .map(|a| lower(a, names, diag))
                .collect::<Option<_>>()?;
            match name.as_str() {
                "rod" => {
                    let t = mul(mul(args[0].clone(), sq(&args[1])), num(1.0 / 12.0));
                    diag3([PExpr::zero(), t.clone(), t])
                }
                "sphere" => {
                    let t = mul(mul(args[0].clone(), sq(&args[1])), num(0.4));
                    diag3([t.clone(), t.clone(), t])
                }
                "cylinder" => {
                    let (m, r, h) = (&args[0], &args[1], &args[2]);
                    let side = mul(
                        m.clone(),
                        add(mul(sq(r), num(0.25)), mul(sq(h), num(1.0 / 12.0))),
                    );
                    diag3([side.clone(), side, mul(mul(m.clone(), sq(r)), num(0.5))])
                }
                "cuboid" => {
                    let (m, a, b, c) = (&args[0], &args[1], &args[2], &args[3]);
                    let k = mul(m.clone(), num(1.0 / 12.0));
                    diag3([
                        mul(k.clone(), add(sq(b), sq(c))),
                        mul(k.clone(), add(sq(a), sq(c))),
                        mul(k, add(sq(a), sq(b))),
                    ])
                }
                _ => {
                    let [a, b, c] = <[PExpr; 3]>::try_from(args).ok()?;
                    diag3([a, b, c])
                }
            }
        }
        Expr::Array(_) => {
            let rows = array(e, 3, "inertia", diag)?;
            let mut m: Vec<Vec3> = Vec::new();
            for r in rows {
                m.push(vec3(r, "an inertia row", names, diag)?);
            }
            let [a, b, c] = <[Vec3; 3]>::try_from(m).ok()?;
            [a, b, c]
        }
        _ => {
            diag.error_at(e, format_args!("expected an inertia: {SHAPES}"));
            return None;
        }
    };
    check_inertia(&m, e, body, diag);
    Some(m)
}

/// An inertia must be symmetric, and when its entries are literals, positive
/// semi-definite and satisfy the triangle inequalities of a real body
/// (`I_xx + I_yy ≥ I_zz` and cyclic); otherwise M can lose definiteness.
fn check_inertia(m: &Mat3, at: &Expr, body: &str, diag: &mut Diagnostics) {
    for (i, j) in [(0, 1), (0, 2), (1, 2)] {
        if m[i][j] != m[j][i] {
            diag.error_at(
                at,
                format_args!(
                    "{body}: inertia must be symmetric: entry ({i}, {j}) differs from ({j}, {i})"
                ),
            );
            return;
        }
    }
    let Some(v) = m
        .iter()
        .map(|r| r.iter().map(PExpr::as_const).collect::<Option<Vec<f64>>>())
        .collect::<Option<Vec<_>>>()
    else {
        return;
    };
    // Principal invariants of a symmetric 3×3 matrix are all ≥ 0 iff it is PSD
    // (with the diagonal non-negative), up to round-off.
    let tr = v[0][0] + v[1][1] + v[2][2];
    let minors = v[0][0] * v[1][1] - v[0][1] * v[0][1] + v[0][0] * v[2][2] - v[0][2] * v[0][2]
        + v[1][1] * v[2][2]
        - v[1][2] * v[1][2];
    let det = v[0][0] * (v[1][1] * v[2][2] - v[1][2] * v[1][2])
        - v[0][1] * (v[0][1] * v[2][2] - v[1][2] * v[0][2])
        + v[0][2] * (v[0][1] * v[1][2] - v[1][1] * v[0][2]);
    let eps = 1e-12 * tr.abs().max(1e-300);
    let psd = v[0][0] >= 0.0
        && v[1][1] >= 0.0
        && v[2][2] >= 0.0
        && minors >= -eps * tr
        && det >= -eps * tr * tr;
    let (a, b, c) = (v[0][0], v[1][1], v[2][2]);
    let triangle = a + b >= c - eps && b + c >= a - eps && a + c >= b - eps;
    if !psd || !triangle {
        diag.error_at(
            at,
            format_args!(
                "{body}: this inertia is not that of a real body (diagonal {a}, {b}, {c}): it \
                 must be positive semi-definite with I_xx + I_yy ≥ I_zz (and cyclic); check signs \
                 and magnitudes"
            ),
        );
    }
}

fn read_joint(mut raw: RawAttr, names: &[String], diag: &mut Diagnostics) -> Option<Joint> {
    let name = raw.name.clone()?;
    let kind = match &raw.head {
        Some(h) => joint_kind(h, diag),
        None => {
            diag.error_at(
                &name,
                format_args!("joint `{name}` needs a kind: `{name}: revolute(z)`, `{name}: prismatic(x)` or `{name}: fixed`"),
            );
            None
        }
    };
    let parent = take_parent(&mut raw, &name, "joint", diag);
    let child = take_child(&mut raw, &name, "joint", diag);
    let (origin, rpy) = placement(&mut raw, names, diag);
    raw.reject_rest(&["parent", "child", "origin", "rpy"], diag);
    Some(Joint {
        name,
        kind: kind?,
        parent: parent?,
        child: child?,
        origin,
        rpy,
    })
}

/// Bodies and joints must form one tree rooted at the world: every body is the child of
/// exactly one joint, every parent exists, and following parents from any body reaches
/// the world (no cycles).
fn build_tree(
    bodies: &[Body],
    joints: &[Joint],
    claimed: &[Ident],
    diag: &mut Diagnostics,
) -> Option<Vec<Link>> {
    if joints.is_empty() {
        for b in bodies.iter().filter(|b| !claimed.contains(&b.name)) {
            diag.error_at(&b.name, format_args!("body `{}` is not attached; add `#[joint(<name>: <kind>, parent = world, child = {})]`", b.name, b.name));
        }
        return None;
    }
    let body_index: HashMap<String, usize> = bodies
        .iter()
        .enumerate()
        .map(|(i, b)| (b.name.to_string(), i))
        .collect();
    let mut joint_of: Vec<Option<usize>> = vec![None; bodies.len()];
    let mut ok = true;
    for (ji, j) in joints.iter().enumerate() {
        if let Some(p) = &j.parent
            && !body_index.contains_key(&p.to_string())
        {
            diag.error_at(
                p,
                format_args!(
                    "no body named `{p}`; the parent must be `world` or a declared body ({})",
                    list(bodies)
                ),
            );
            ok = false;
        }
        match body_index.get(&j.child.to_string()) {
            None => {
                diag.error_at(&j.child, format_args!("no body named `{}`; declare it with `#[body({}, mass = …)]` or use one of: {}", j.child, j.child, list(bodies)));
                ok = false;
            }
            Some(&b) => {
                if j.parent.as_ref().is_some_and(|p| *p == j.child) {
                    diag.error_at(&j.child, "a joint cannot connect a body to itself");
                    ok = false;
                } else if let Some(prev) = joint_of[b] {
                    diag.error_at(
                        &j.child,
                        format_args!("body `{}` already hangs from joint `{}`; a body in a tree has exactly one parent joint (a joint that closes a kinematic loop is declared with `#[loop_joint(…)]`)", j.child, joints[prev].name),
                    );
                    ok = false;
                } else {
                    joint_of[b] = Some(ji);
                }
            }
        }
    }
    if !ok {
        return None;
    }
    for (b, body) in bodies.iter().enumerate() {
        if joint_of[b].is_none() && !claimed.contains(&body.name) {
            diag.error_at(&body.name, format_args!("body `{}` is not attached; add `#[joint(<name>: <kind>, parent = <body or world>, child = {})]`", body.name, body.name));
            ok = false;
        }
    }
    if !ok {
        return None;
    }
    // Depth-first preorder from the world, children in declaration order.
    let parent_body = |j: &Joint| j.parent.as_ref().map(|p| body_index[&p.to_string()]);
    let mut order: Vec<usize> = Vec::new(); // body indices
    let mut link_of_body: Vec<Option<usize>> = vec![None; bodies.len()];
    let mut stack: Vec<(Option<usize>, usize)> = Vec::new();
    let roots: Vec<usize> = joints
        .iter()
        .filter(|j| j.parent.is_none())
        .map(|j| body_index[&j.child.to_string()])
        .collect();
    for &r in roots.iter().rev() {
        stack.push((None, r));
    }
    while let Some((_, b)) = stack.pop() {
        link_of_body[b] = Some(order.len());
        order.push(b);
        let kids: Vec<usize> = joints
            .iter()
            .filter(|j| parent_body(j) == Some(b))
            .map(|j| body_index[&j.child.to_string()])
            .collect();
        for &k in kids.iter().rev() {
            stack.push((Some(b), k));
        }
    }
    // A body whose joint, or an ancestor's joint, was declared wrongly (its error is
    // already reported; the body is `claimed`) is cut off from the world by that
    // mistake alone: no second error for it.
    let hangs_from_claimed = |mut b: usize| {
        for _ in 0..=bodies.len() {
            match joint_of[b] {
                None => return true,
                Some(ji) => match parent_body(&joints[ji]) {
                    Some(p) => b = p,
                    None => return false,
                },
            }
        }
        false
    };
    for b in 0..bodies.len() {
        if link_of_body[b].is_none()
            && hangs_from_claimed(b)
            && let Some(ji) = joint_of[b]
        {
            // Its joint is fine but out of the tree because of that mistake: elements
            // on it are not a second one.
            diag.excuse(&joints[ji].name);
        }
    }
    for (b, body) in bodies.iter().enumerate() {
        if link_of_body[b].is_none() && !hangs_from_claimed(b) {
            let Some(ji) = joint_of[b] else { continue };
            let j = &joints[ji];
            diag.error_at(
                &body.name,
                format_args!("body `{}` does not reach the world through its parents (joint `{}` closes a cycle or hangs from a detached body); a mechanism must be a tree rooted at `world`", body.name, j.name),
            );
            ok = false;
        }
    }
    if !ok {
        return None;
    }
    // Links in the preorder; a free joint becomes a massless translation link and a
    // spherical one (SO(3) × ℝ³), the body on the latter.
    let mut coordinate = 0;
    let mut slot = 0;
    let mut links: Vec<Link> = Vec::new();
    let mut link_of_body: Vec<Option<usize>> = vec![None; bodies.len()];
    let zero = || PExpr::zero();
    for &b in &order {
        let j = &joints[joint_of[b]?];
        let body = &bodies[b];
        let mut parent = parent_body(j).and_then(|p| link_of_body[p]);
        let (mut origin, mut rpy) = (j.origin.clone(), j.rpy.clone());
        let mut kind = j.kind;
        if kind == JointKind::Free {
            links.push(Link {
                name: format!("{}.translation", body.name),
                joint_name: j.name.to_string(),
                parent,
                kind: JointKind::Translation,
                coordinate: Some(coordinate),
                config: Some(slot),
                origin,
                rpy,
                mass: zero(),
                com: zero3(),
                inertia: [
                    [zero(), zero(), zero()],
                    [zero(), zero(), zero()],
                    [zero(), zero(), zero()],
                ],
            });
            coordinate += 3;
            slot += 3;
            parent = Some(links.len() - 1);
            (origin, rpy) = (zero3(), zero3());
            kind = JointKind::Spherical;
        }
        let moves = kind != JointKind::Fixed;
        link_of_body[b] = Some(links.len());
        links.push(Link {
            name: body.name.to_string(),
            joint_name: j.name.to_string(),
            parent,
            kind,
            coordinate: moves.then_some(coordinate),
            config: moves.then_some(slot),
            origin,
            rpy,
            mass: body.mass.clone()?,
            com: body.com.clone(),
            inertia: body.inertia.clone(),
        });
        coordinate += kind.dof();
        slot += kind.config_len();
    }
    for (i, l) in links.iter().enumerate() {
        if l.kind != JointKind::Translation
            && l.mass.as_const() == Some(0.0)
            && !links.iter().any(|c| c.parent == Some(i))
        {
            let b = &bodies[body_index[&l.name]];
            diag.error_at(
                &b.name,
                format_args!("body `{}` has zero mass and carries no other body, so nothing gives its joint inertia; a massless body is only an intermediate frame — give it a positive mass", b.name),
            );
            return None;
        }
    }
    if coordinate == 0 {
        // A joint declared wrongly may have been the moving one: its error stands alone.
        if claimed.is_empty() {
            diag.error_at(
                &joints[0].name,
                "a mechanism needs at least one moving joint (revolute, prismatic, spherical or free)",
            );
        }
        return None;
    }
    if coordinate > MAX_DOF {
        diag.error_at(
            &joints[0].name,
            format_args!("{coordinate} coordinates; at most {MAX_DOF} are supported"),
        );
        return None;
    }
    Some(links)
}

fn list(bodies: &[Body]) -> String {
    if bodies.is_empty() {
        return "none is declared yet".to_string();
    }
    bodies
        .iter()
        .map(|b| format!("`{}`", b.name))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Springs and dampers act on the coordinate of a named joint, which must exist and
/// move (a fixed joint has no coordinate).
fn read_elements(
    raws: Vec<RawAttr>,
    links: &[Link],
    names: &[String],
    diag: &mut Diagnostics,
) -> (Vec<Spring>, Vec<Damper>, Vec<Potential>) {
    let mut springs = Vec::new();
    let mut potentials = Vec::new();
    let mut dampers = Vec::new();
    for mut raw in raws {
        let Some(joint) = raw.name.clone() else {
            continue;
        };
        let coord = crate::coordinate::coordinate_of(&joint, links, "springs and dampers", diag);
        let mut value = |key: &str, raw: &mut RawAttr, required: bool| -> Option<PExpr> {
            match raw.take(key, diag) {
                Some((_, e)) => lower(&e, names, diag),
                None if required => {
                    diag.error_at(&joint, format_args!("missing `{key} = <expression>`"));
                    None
                }
                None => Some(PExpr::zero()),
            }
        };
        if raw.family == Family::Spring && raw.args.iter().any(|(k, _)| k == "potential") {
            // A non-linear spring declared by its energy U(x), x the coordinate; its
            // force −dU/dx comes from symbolic differentiation, so energy is exact.
            let u = raw
                .take("potential", diag)
                .and_then(|(_, e)| lower_with_var(&e, names, "x", diag));
            for key in ["k", "rest"] {
                if let Some((k, _)) = raw.take(key, diag) {
                    diag.error_at(k, "a spring is either linear (`k = …, rest = …`) or given by its `potential = U(x)`, not both");
                }
            }
            raw.reject_rest(&["potential"], diag);
            if let (Some(coordinate), Some(u)) = (coord, u) {
                potentials.push(Potential { coordinate, u });
            }
        } else if raw.family == Family::Spring {
            let k = value("k", &mut raw, true);
            let rest = value("rest", &mut raw, false);
            raw.reject_rest(&["k", "rest", "potential"], diag);
            if let (Some(coordinate), Some(k), Some(rest)) = (coord, k, rest) {
                springs.push(Spring {
                    coordinate,
                    k,
                    rest,
                });
            }
        } else {
            let c = value("c", &mut raw, true);
            raw.reject_rest(&["c"], diag);
            if let (Some(coordinate), Some(c)) = (coord, c) {
                dampers.push(Damper { coordinate, c });
            }
        }
    }
    (springs, dampers, potentials)
}

/// `inputs = [joint, …]` names the actuated coordinates: each must be a moving joint,
/// named once.
fn read_inputs(e: &Expr, links: &[Link], diag: &mut Diagnostics) -> Vec<usize> {
    let Expr::Array(a) = strip(e) else {
        diag.error_at(
            e,
            "`inputs` is a list of joint names, e.g. `inputs = [shoulder, elbow]`",
        );
        return Vec::new();
    };
    let mut out = Vec::new();
    for item in &a.elems {
        let Some(id) = ident_of(item) else {
            diag.error_at(item, "expected a joint name");
            continue;
        };
        if links.iter().any(|l| *id == l.joint_name && l.kind.is_lie()) {
            diag.error_at(
                id,
                format_args!(
                    "joint `{id}` is {}; inputs are revolute or prismatic joints (apply forces and torques on spherical and free joints through the input closure τ(t, q, v))",
                    if links.iter().any(|l| *id == l.joint_name && l.kind == JointKind::Translation) { "free (six coordinates)" } else { "spherical (three coordinates)" }
                ),
            );
            continue;
        }
        match links
            .iter()
            .find(|l| *id == l.joint_name)
            .map(|l| l.coordinate)
        {
            Some(Some(c)) if out.contains(&c) => {
                diag.error_at(id, format_args!("joint `{id}` is listed twice"))
            }
            Some(Some(c)) => out.push(c),
            Some(None) => diag.error_at(
                id,
                format_args!("joint `{id}` is fixed and cannot be actuated"),
            ),
            None if diag.is_excused(id) => {}
            None => diag.error_at(
                id,
                format_args!(
                    "no joint named `{id}`; inputs are joints: {}",
                    crate::coordinate::moving_joints(links)
                ),
            ),
        }
    }
    out
}
