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
