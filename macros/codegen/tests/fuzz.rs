//! `expand` on random input returns code or a spanned error and never panics: random
//! valid trees (up to 12 joints, random parameters and element declarations) and random
//! attribute garbage built from plausible and implausible pieces.
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

/// A random tree: parent of link i is one of 0..i or the world.
fn tree() -> impl Strategy<Value = String> {
    (1usize..=12).prop_flat_map(|n| {
        (
            proptest::collection::vec(0usize..100, n),
            proptest::collection::vec(0usize..6, n),
            proptest::collection::vec(-2.0f64..2.0, n),
            proptest::collection::vec(0usize..4, n),
            any::<bool>(),
        )
            .prop_map(move |(parents, kinds, nums, elements, gravity)| {
                let mut s = String::from("#[derive(Mechanism)]\n");
                if gravity {
                    s += "#[mechanism(gravity = [0.0, 0.0, -g])]\n";
                }
                let axes = ["x", "y", "z", "-y", "[0.0, 0.6, 0.8]", "[1.0, 1.0, 0.0]"];
                for i in 0..n {
                    let parent = if i == 0 || parents[i] % 4 == 0 { "world".to_string() } else { format!("b{}", parents[i] % i) };
                    let kind = match kinds[i] {
                        0..=2 => format!("revolute({})", axes[(i + kinds[i]) % axes.len()]),
                        3..=4 => format!("prismatic({})", axes[i % axes.len()]),
                        _ => "fixed".to_string(),
                    };
                    let x = nums[i];
                    s += &format!(
                        "#[body(b{i}, mass = m * {}, com = [{x}, 0.1, l], inertia = cuboid(m, 0.1, 0.2, l))]\n",
                        1.0 + x.abs()
                    );
                    s += &format!(
                        "#[joint(j{i}: {kind}, parent = {parent}, child = b{i}, origin = [l, {x}, 0.0], rpy = [{x}, 0.0, 0.3])]\n"
                    );
                    if kinds[i] < 5 {
                        match elements[i] {
                            1 => s += &format!("#[spring(j{i}, k = k, rest = {x})]\n#[damper(j{i}, c = 0.1)]\n"),
                            2 => s += &format!("#[friction(j{i}, f_crit = 0.5)]\n"),
                            3 => s += &format!("#[stop(j{i}, max = l, restitution = 0.5)]\n"),
                            _ => {}
                        }
                    }
                }
                s += "struct Scene { m: f64, l: f64, k: f64, g: f64 }";
                s
            })
    })
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

#[test]
fn random_trees_expand_or_report() {
    let mut runner = TestRunner::new(Config {
        cases: cases(64),
        failure_persistence: None,
        ..Config::default()
    });
    runner
        .run(&tree(), |src| {
            expand_str(&src).map_err(TestCaseError::fail)?;
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
