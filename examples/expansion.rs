//! What the derive costs and what it emits, per scene: expansion time (median of
//! repeated runs of the engine on the scene's source), graph size, lets and operation
//! counts of every generated method. Also expands planar chains of 2…30 links and 3D
//! binary trees of up to 36 joints to show how expansion scales, each twice: with the
//! default kernels (what the integrators call) and with `emit = all`. Last, the
//! operations of forward dynamics and its Jacobian with `forward_dynamics = crba` and
//! `= aba` on chains and trees of 3…50 joints, and which one `auto` picks.
//!
//! Run: `cargo run --release --example expansion`.
//!
//! `-- --big` expands only the 36-joint 3D binary tree and the 50-link planar chain
//! (default kernels). Without `--release` the engine is compiled as a user's build
//! compiles the derive (proc-macros and their dependencies unoptimised), so
//! `cargo run --example expansion -- --big` measures the expansion time users wait for.

use std::time::{Duration, Instant};

use proc_macro2::TokenStream;

fn scene(file: &str) -> Vec<(String, TokenStream)> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("src/scenes")
        .join(file);
    let src = std::fs::read_to_string(path).expect("scene source");
    syn::parse_file(&src)
        .expect("parses")
        .items
        .into_iter()
        .filter_map(|i| match i {
            syn::Item::Struct(s) => {
                Some((s.ident.to_string(), quote::ToTokens::to_token_stream(&s)))
            }
            _ => None,
        })
        .collect()
}

fn header(gravity: &str, all: bool) -> String {
    let emit = if all { ", emit = all" } else { "" };
    format!("#[derive(Mechanism)]\n#[mechanism(gravity = {gravity}{emit})]\n")
}

/// The same scene with `forward_dynamics = algorithm` (and the default kernels).
fn with_algorithm(tokens: TokenStream, algorithm: &str) -> TokenStream {
    let src = tokens.to_string().replacen(
        "gravity =",
        &format!("forward_dynamics = {algorithm}, gravity ="),
        1,
    );
    src.parse().expect("tokens")
}

/// A chain of `n` links in 3D, joint axes cycling x, y, z.
fn chain3d(n: usize) -> TokenStream {
    let mut attrs = header("[0.0, 0.0, -9.81]", false);
    for i in 0..n {
        let parent = if i == 0 {
            "world".to_string()
        } else {
            format!("b{}", i - 1)
        };
        let axis = ["x", "y", "z"][i % 3];
        attrs += &format!(
            "#[body(b{i}: revolute({axis}), parent = {parent}, origin = [0.05, 0.0, l], mass = m, com = [0.0, 0.0, l / 2.0], inertia = cuboid(m, 0.1, 0.1, l))]\n"
        );
    }
    attrs += "struct Chain3 { m: f64, l: f64 }";
    attrs.parse().expect("tokens")
}

/// Operations in forward dynamics and its Jacobian with each way of solving with `M`,
/// and which `auto` picks: where the articulated-body algorithm overtakes.
fn crossover(family: &str, make: &dyn Fn(usize) -> TokenStream) {
    for n in [3, 5, 7, 10, 15, 20, 30, 50] {
        let ops = |algorithm: &str| -> (usize, usize) {
            let e = filippov_codegen::expand_with_stats(with_algorithm(make(n), algorithm))
                .expect("expands");
            let get = |f: &str| {
                e.functions
                    .iter()
                    .find(|x| x.name == f)
                    .map_or(0, |x| x.ops.total())
            };
            (get("forward_dynamics"), get("forward_dynamics_jacobian"))
        };
        let (crba, aba, auto) = (ops("crba"), ops("aba"), ops("auto"));
        let pick = |a: usize, c: usize| if a == c { "crba" } else { "aba" };
        println!(
            "{family:<14} {n:>2} joints  FD ops crba {:>6} aba {:>6} (auto: {})   Jacobian ops crba {:>8} aba {:>8} (auto: {})",
            crba.0,
            aba.0,
            pick(auto.0, crba.0),
            crba.1,
            aba.1,
            pick(auto.1, crba.1)
        );
    }
}

/// A planar chain of `n` rods.
fn chain(n: usize, all: bool) -> TokenStream {
    let mut attrs = header("[0.0, -9.81, 0.0]", all);
    for i in 0..n {
        let parent = if i == 0 {
            "world".to_string()
        } else {
            format!("b{}", i - 1)
        };
        let origin = if i == 0 { "0.0" } else { "l" };
        attrs +=
            &format!("#[body(b{i}, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]\n");
        attrs += &format!(
            "#[joint(j{i}: revolute(z), parent = {parent}, child = b{i}, origin = [{origin}, 0.0, 0.0])]\n"
        );
    }
    attrs += "struct Chain { m: f64, l: f64 }";
    attrs.parse().expect("tokens")
}

/// A binary tree of `n` links in 3D, joint axes cycling x, y, z.
fn tree(n: usize, all: bool) -> TokenStream {
    let mut attrs = header("[0.0, 0.0, -9.81]", all);
    for i in 0..n {
        let parent = if i == 0 {
            "world".to_string()
        } else {
            format!("b{}", (i - 1) / 2)
        };
        let axis = ["x", "y", "z"][i % 3];
        attrs += &format!(
            "#[body(b{i}, mass = m, com = [0.0, 0.0, l / 2.0], inertia = cuboid(m, 0.1, 0.1, l))]\n"
        );
        attrs += &format!(
            "#[joint(j{i}: revolute({axis}), parent = {parent}, child = b{i}, origin = [0.05, 0.0, l])]\n"
        );
    }
    attrs += "struct Tree { m: f64, l: f64 }";
    attrs.parse().expect("tokens")
}

/// Median, fastest and slowest of `reps` expansions, and the last expansion.
fn median_time(tokens: &TokenStream, reps: usize) -> ([Duration; 3], filippov_codegen::Expansion) {
    let mut times = Vec::new();
    let mut last = None;
    for _ in 0..reps {
        let t = Instant::now();
        let e = filippov_codegen::expand_with_stats(tokens.clone()).expect("expands");
        times.push(t.elapsed());
        last = Some(e);
    }
    times.sort();
    (
        [times[reps / 2], times[0], times[reps - 1]],
        last.expect("ran"),
    )
}

fn report(name: &str, tokens: &TokenStream, reps: usize, detail: bool) {
    let ([t, lo, hi], e) = median_time(tokens, reps);
    let lets: usize = e.functions.iter().map(|f| f.lets).sum();
    let ms = |d: Duration| d.as_secs_f64() * 1e3;
    println!(
        "{name:<16} dof {:>2}  expansion {:>9.2} ms (median of {reps}, {:.2}–{:.2})  graph {:>7} nodes  {lets:>6} lets  {:>9} bytes of code",
        e.dof,
        ms(t),
        ms(lo),
        ms(hi),
        e.graph_nodes,
        e.tokens.to_string().len()
    );
    if detail {
        for f in &e.functions {
            println!("    {:<26} {:>5} lets; {}", f.name, f.lets, f.ops);
        }
    }
}

fn main() {
    if std::env::args().skip(1).any(|a| a == "--big") {
        println!(
            "== engine {}",
            if cfg!(debug_assertions) {
                "unoptimised, as a user's build runs the derive"
            } else {
                "optimised (--release); without --release it runs as in a user's build"
            }
        );
        report("tree36", &tree(36, false), 5, false);
        report("chain50", &chain(50, false), 5, false);
        return;
    }
    println!("== canonical scenes");
    for file in ["double_pendulum.rs", "arm3.rs", "tree.rs", "panda.rs"] {
        for (name, tokens) in scene(file) {
            report(&name, &tokens, 21, true);
        }
    }
    println!("\n== planar chains: default kernels (M, FD, FD Jacobian) | emit = all");
    for n in [2, 4, 7, 12, 20, 30] {
        let reps = if n > 12 { 3 } else { 5 };
        report(&format!("chain{n}"), &chain(n, false), reps, false);
        report(&format!("chain{n} all"), &chain(n, true), reps, false);
    }
    println!("\n== 3D binary trees: default kernels | emit = all");
    for n in [7, 15, 36] {
        report(&format!("tree{n}"), &tree(n, false), 3, false);
        report(&format!("tree{n} all"), &tree(n, true), 3, false);
    }
    println!("\n== forward_dynamics = crba | aba: operations, and what auto (the default) picks");
    crossover("planar chain", &|n| chain(n, false));
    crossover("3D chain", &chain3d);
    crossover("3D binary tree", &|n| tree(n, false));
}
