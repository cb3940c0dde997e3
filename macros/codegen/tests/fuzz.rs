//! `expand` on random input: random valid trees (up to 12 joints, random parameters and
//! element declarations) must expand; the same trees with one mistake injected must give
//! exactly one error naming it; random attribute garbage built from plausible and
//! implausible pieces returns code or a spanned error and never panics.
//!
//! Case counts: `FILIPPOV_FUZZ_CASES` (default 64 trees and 1,000 garbage inputs).

use proptest::prelude::*;
use proptest::test_runner::{Config, TestRunner};

fn cases(default: u32) -> u32 {
    std::env::var("FILIPPOV_FUZZ_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(default)
}

/// The random choices behind a tree (kept apart from its text so that a defect can be
/// injected into one named joint or body).
#[derive(Clone, Debug)]
struct Tree {
    parents: Vec<usize>,
    kinds: Vec<usize>,
    nums: Vec<f64>,
    elements: Vec<usize>,
    gravity: bool,
}

/// A random tree: parent of link i is one of 0..i or the world; revolute (unit and
/// oblique axes), prismatic and fixed joints; springs with dampers, friction, stops.
fn tree() -> impl Strategy<Value = Tree> {
    (1usize..=12).prop_flat_map(|n| {
        (
            proptest::collection::vec(0usize..100, n),
            proptest::collection::vec(0usize..6, n),
            proptest::collection::vec(-2.0f64..2.0, n),
            proptest::collection::vec(0usize..4, n),
            any::<bool>(),
        )
            .prop_map(|(parents, kinds, nums, elements, gravity)| Tree {
                parents,
                kinds,
                nums,
                elements,
                gravity,
            })
    })
}

/// One mistake a user makes, injected into a valid tree at link `at`: the source with
/// it, and a word the error must quote (the name or value the user wrote).
#[derive(Clone, Copy, Debug)]
enum Defect {
    /// The joint's parent is a body that does not exist.
    UnknownParent,
    /// A revolute joint about the zero vector.
    ZeroAxis,
    /// A body with a negative mass (a literal: a field's value is known only at run
    /// time).
    NegativeMass,
    /// A second joint with the name of an existing one.
    DuplicateJoint,
    /// Friction declared on a joint that does not exist.
    ElementOnUnknownJoint,
    /// A parameter that is not a field of the struct.
    UnknownField,
}

const DEFECTS: [Defect; 6] = [
    Defect::UnknownParent,
    Defect::ZeroAxis,
    Defect::NegativeMass,
    Defect::DuplicateJoint,
    Defect::ElementOnUnknownJoint,
    Defect::UnknownField,
];

impl Tree {
    /// The scene's source, with `defect` injected at link `at % n` (none: valid).
    fn source(&self, defect: Option<(Defect, usize)>) -> (String, &'static str) {
        let n = self.parents.len();
        let (bad, at) = match defect {
            Some((d, at)) => (Some(d), at % n),
            None => (None, usize::MAX),
        };
        let mut quoted = "";
        let mut s = String::from("#[derive(Mechanism)]\n");
        if self.gravity {
            s += "#[mechanism(gravity = [0.0, 0.0, -g])]\n";
        }
        let axes = ["x", "y", "z", "-y", "[0.0, 0.6, 0.8]", "[1.0, 1.0, 0.0]"];
        for i in 0..n {
            let parent = if i == at && matches!(bad, Some(Defect::UnknownParent)) {
                quoted = "nowhere";
                "nowhere".to_string()
            } else if i == 0 || self.parents[i] % 4 == 0 {
                "world".to_string()
            } else {
                format!("b{}", self.parents[i] % i)
            };
            // The first link moves (a tree of fixed joints only is a mistake of its own).
            let k = if i == 0 {
                self.kinds[i] % 5
            } else {
                self.kinds[i]
            };
            let kind = if i == at && matches!(bad, Some(Defect::ZeroAxis)) {
                quoted = "axis";
                "revolute([0.0, 0.0, 0.0])".to_string()
            } else {
                match k {
                    0..=2 => format!("revolute({})", axes[(i + k) % axes.len()]),
                    3..=4 => format!("prismatic({})", axes[i % axes.len()]),
                    _ => "fixed".to_string(),
                }
            };
            let x = self.nums[i];
            let mass = if i == at && matches!(bad, Some(Defect::NegativeMass)) {
                quoted = "mass";
                format!("-{}", 1.0 + x.abs())
            } else if i == at && matches!(bad, Some(Defect::UnknownField)) {
                quoted = "mu_x";
                "mu_x * m".to_string()
            } else {
                format!("m * {}", 1.0 + x.abs())
            };
            s += &format!(
                "#[body(b{i}, mass = {mass}, com = [{x}, 0.1, l], inertia = cuboid(m, 0.1, 0.2, l))]\n"
            );
            let name = if i == at && i > 0 && matches!(bad, Some(Defect::DuplicateJoint)) {
                quoted = "j0";
                "j0".to_string()
            } else {
                format!("j{i}")
            };
            s += &format!(
                "#[joint({name}: {kind}, parent = {parent}, child = b{i}, origin = [l, {x}, 0.0], rpy = [{x}, 0.0, 0.3])]\n"
            );
            if k < 5 && name == format!("j{i}") {
                match self.elements[i] {
                    1 => {
                        s += &format!(
                            "#[spring(j{i}, k = k, rest = {x})]\n#[damper(j{i}, c = 0.1)]\n"
                        )
                    }
                    2 => s += &format!("#[friction(j{i}, f_crit = 0.5)]\n"),
                    3 => s += &format!("#[stop(j{i}, max = l, restitution = 0.5)]\n"),
                    _ => {}
                }
            }
            if i == at && matches!(bad, Some(Defect::ElementOnUnknownJoint)) {
                quoted = "j_missing";
                s += "#[friction(j_missing, f_crit = 0.5)]\n";
            }
        }
        // A duplicate needs a second joint: in a one-link tree the defect is an extra
        // joint named like the first.
        if matches!(bad, Some(Defect::DuplicateJoint)) && quoted.is_empty() {
            quoted = "j0";
            s += "#[body(extra, mass = m, com = [0.0, 0.0, 0.0], inertia = cuboid(m, 0.1, 0.2, l))]\n";
            s += "#[joint(j0: revolute(z), parent = b0, child = extra, origin = [l, 0.0, 0.0])]\n";
        }
        s += "struct Scene { m: f64, l: f64, k: f64, g: f64 }";
        (s, quoted)
    }
}

/// Attribute garbage: pieces of the grammar, numbers, punctuation and wrong words in
/// random order inside random attribute names.
fn garbage() -> impl Strategy<Value = String> {
    let pieces = prop_oneof![
        Just("upper"),
        Just("world"),
        Just("mass"),
        Just("="),
        Just(","),
        Just(":"),
        Just("revolute(z)"),
        Just("prismatic"),
        Just("fixed"),
        Just("[1.0, 2.0]"),
        Just("[0.0, 0.0, 0.0]"),
        Just("rod(m, l)"),
        Just("parent"),
        Just("child"),
        Just("-1.0"),
        Just("f_crit"),
        Just("law"),
        Just("f * f"),
        Just("m"),
        Just("(("),
        Just("))"),
        Just("tanh(m)"),
        Just("select"),
        Just("max"),
        Just("restitution"),
        Just("2.0"),
        Just("inertia"),
        Just("com"),
        Just("origin"),
        Just("rpy"),
        Just("k_support"),
        Just("inputs"),
        Just("x"),
    ];
    let attr = (
        prop_oneof![
            Just("body"),
            Just("joint"),
            Just("spring"),
            Just("damper"),
            Just("friction"),
            Just("bingham"),
            Just("stop"),
            Just("mechanism")
        ],
        proptest::collection::vec(pieces, 0..12),
    )
        .prop_map(|(name, parts)| format!("#[{name}({})]\n", parts.join(" ")));
    proptest::collection::vec(attr, 0..8).prop_map(|attrs| {
        format!(
            "#[derive(Mechanism)]\n{}struct Scene {{ m: f64, l: f64 }}",
            attrs.concat()
        )
    })
}

fn expand_str(src: &str) -> Result<(), String> {
    // Garbage may not even tokenize; that is the compiler's job, not ours.
    let Ok(tokens) = src.parse::<proc_macro2::TokenStream>() else {
        return Ok(());
    };
    match filippov_codegen::expand(tokens) {
        Ok(out) => syn::parse2::<syn::File>(out)
            .map(|_| ())
            .map_err(|e| format!("expansion is not valid Rust: {e}")),
        Err(e) => {
            let msg = e.to_string();
            if msg.trim().is_empty() {
                Err("an error without a message".into())
            } else {
                Ok(())
            }
        }
    }
}

/// Valid trees must expand, to valid Rust: an error on any of them is a regression.
#[test]
fn random_valid_trees_expand() {
    let mut runner = TestRunner::new(Config {
        cases: cases(64),
        failure_persistence: None,
        ..Config::default()
    });
    runner
        .run(&tree(), |t| {
            let (src, _) = t.source(None);
            let tokens: proc_macro2::TokenStream = src.parse().expect("tokens");
            match filippov_codegen::expand(tokens) {
                Ok(out) => syn::parse2::<syn::File>(out)
                    .map(|_| ())
                    .map_err(|e| TestCaseError::fail(format!("expansion is not valid Rust: {e}"))),
                Err(e) => Err(TestCaseError::fail(format!(
                    "a valid tree was refused: {e}\n{src}"
                ))),
            }
        })
        .unwrap();
}

/// A valid tree with one mistake injected at a random link: exactly one error (no
/// follow-on errors), quoting what the user wrote (the unknown name, the field, or the
/// quantity that is wrong).
#[test]
fn random_trees_with_one_defect_give_one_error_naming_it() {
    let mut runner = TestRunner::new(Config {
        cases: cases(64),
        failure_persistence: None,
        ..Config::default()
    });
    let defect = (0..DEFECTS.len(), 0usize..12).prop_map(|(d, at)| (DEFECTS[d], at));
    runner
        .run(&(tree(), defect), |(t, (d, at))| {
            let (src, quoted) = t.source(Some((d, at)));
            let tokens: proc_macro2::TokenStream = src.parse().expect("tokens");
            let Err(e) = filippov_codegen::expand(tokens) else {
                return Err(TestCaseError::fail(format!("{d:?} was accepted:\n{src}")));
            };
            let messages: Vec<String> = e.into_iter().map(|e| e.to_string()).collect();
            if messages.len() != 1 {
                return Err(TestCaseError::fail(format!(
                    "{d:?}: {} errors, expected one: {messages:#?}\n{src}",
                    messages.len()
                )));
            }
            if !messages[0].contains(quoted) {
                return Err(TestCaseError::fail(format!(
                    "{d:?}: the error does not name `{quoted}`: {}\n{src}",
                    messages[0]
                )));
            }
            Ok(())
        })
        .unwrap();
}

#[test]
fn attribute_garbage_never_panics() {
    let mut runner = TestRunner::new(Config {
        cases: cases(1000),
        failure_persistence: None,
        ..Config::default()
    });
    runner
        .run(&garbage(), |src| {
            expand_str(&src).map_err(TestCaseError::fail)?;
            Ok(())
        })
        .unwrap();
}

/// A random expression over the fields `m`, `l` (and the law variable `f` where
/// allowed): numbers, finite or not (`1e400`), `PI`, the five functions, `powi`,
/// unary minus and the four operators, nested to a random depth.
fn expression() -> impl Strategy<Value = String> {
    // Mostly valid leaves; the invalid ones (non-finite, unknown) rarer, so that most
    // scenes expand and a fair share meets each error.
    let leaf = prop_oneof![
        8 => Just("m".to_string()),
        8 => Just("l".to_string()),
        2 => Just("PI".to_string()),
        2 => Just("self.m".to_string()),
        2 => Just("0.0".to_string()),
        4 => Just("1.0".to_string()),
        4 => Just("-2.5".to_string()),
        2 => Just("1e300".to_string()),
        2 => Just("1e-320".to_string()),
        2 => Just("3".to_string()),
        1 => Just("1e400".to_string()),
        1 => Just("unknown".to_string()),
    ];
    leaf.prop_recursive(8, 64, 3, |inner| {
        prop_oneof![
            (
                inner.clone(),
                prop_oneof![Just("+"), Just("-"), Just("*"), Just("/")],
                inner.clone()
            )
                .prop_map(|(a, op, b)| format!("{a} {op} {b}")),
            (
                prop_oneof![
                    Just("sqrt"),
                    Just("sin"),
                    Just("cos"),
                    Just("exp"),
                    Just("ln")
                ],
                inner.clone()
            )
                .prop_map(|(f, a)| format!("{f}({a})")),
            inner.clone().prop_map(|a| format!("({a})")),
            inner.clone().prop_map(|a| format!("-{a}")),
            (inner.clone(), 0u32..10).prop_map(|(a, k)| format!("({a}).powi({k})")),
        ]
    })
}

/// A long or deep expression: a chain of up to 6,000 terms, or brackets, minus signs or
/// method calls nested up to 300 deep (past the documented limits of 256 and 20,000
/// tokens).
fn extreme_expression() -> impl Strategy<Value = String> {
    prop_oneof![
        (
            1usize..6000,
            prop_oneof![Just(" + "), Just(" * "), Just(" - "), Just(" / ")]
        )
            .prop_map(|(n, op)| vec!["m"; n].join(op)),
        (1usize..300).prop_map(|n| "(".repeat(n) + "m" + &")".repeat(n)),
        (1usize..300).prop_map(|n| "sqrt(".repeat(n) + "m" + &")".repeat(n)),
        (1usize..300).prop_map(|n| "-".repeat(n) + "m"),
        (1usize..300).prop_map(|n| "m".to_string() + &".sqrt()".repeat(n)),
    ]
}

/// A scene with random expressions in every kind of value, sometimes a duplicated
/// attribute or a field that shadows a built-in name.
fn expression_scene() -> impl Strategy<Value = String> {
    let any_expr = prop_oneof![60 => expression(), 1 => extreme_expression()];
    (
        proptest::collection::vec(any_expr, 9),
        0usize..12,
    )
        .prop_map(|(e, twist)| {
            let mut s = String::from("#[derive(Mechanism)]\n");
            s += &format!("#[mechanism(gravity = [0.0, {}, 0.0])]\n", e[0]);
            if twist == 1 {
                s += "#[mechanism(gravity = [0.0, -9.81, 0.0])]\n";
            }
            s += &format!("#[body(a, mass = {}, com = [{}, 0.0, 0.0], inertia = rod(m, l))]\n", e[1], e[2]);
            s += &format!("#[joint(ja: revolute(z), parent = world, child = a, origin = [{}, 0.0, 0.0], rpy = [0.0, {}, 0.0])]\n", e[3], e[4]);
            s += &format!("#[spring(ja, k = {}, rest = {})]\n", e[5], e[6]);
            s += &format!("#[bingham(ja, f_crit = {}, law = f * ({}))]\n", e[7], e[8]);
            if twist == 2 {
                s += "#[body(a, mass = m)]\n";
            }
            s += match twist {
                3 => "struct Scene { m: f64, l: f64, PI: f64 }",
                4 => "struct Scene { m: f64, l: f64, sqrt: f64 }",
                _ => "struct Scene { m: f64, l: f64 }",
            };
            s
        })
}

/// Random and extreme expressions everywhere: valid Rust or an error with a message,
/// never a panic or a stack overflow (run on a 6 MiB thread, below the 8 MiB rustc gives
/// a proc macro). Default 2,000 cases; `FILIPPOV_FUZZ_CASES=10000` for the long run.
#[test]
fn random_expressions_expand_or_report() {
    let n = cases(2000);
    let (ok, err) = std::thread::Builder::new()
        .stack_size(6 << 20)
        .spawn(move || {
            let counts = std::cell::Cell::new((0usize, 0usize));
            let mut runner = TestRunner::new(Config {
                cases: n,
                failure_persistence: None,
                ..Config::default()
            });
            runner
                .run(&expression_scene(), |src| {
                    let tokens: proc_macro2::TokenStream = src.parse().expect("tokens");
                    let (ok, err) = counts.get();
                    match filippov_codegen::expand(tokens) {
                        Ok(out) => {
                            syn::parse2::<syn::File>(out)
                                .map_err(|e| TestCaseError::fail(format!("not valid Rust: {e}")))?;
                            counts.set((ok + 1, err));
                        }
                        Err(e) if e.to_string().trim().is_empty() => {
                            return Err(TestCaseError::fail("an error without a message"));
                        }
                        Err(_) => counts.set((ok, err + 1)),
                    }
                    Ok(())
                })
                .unwrap();
            counts.get()
        })
        .expect("thread")
        .join()
        .expect("no panic, no overflow");
    eprintln!("{n} random expression scenes: {ok} expanded, {err} spanned errors, 0 panics");
    assert_eq!(ok + err, n as usize);
}
