//! What the derive costs and what it emits, per scene: expansion time (median of
//! repeated runs of the engine on the scene's source), graph size, lets and operation
//! counts of every generated method. Also expands planar chains of 2…30 links and 3D
//! binary trees of up to 36 joints to show how expansion scales, each twice: with the
//! default kernels (what the integrators call) and with `emit = all`.
//!
//! Run: `cargo run --release --example expansion`.

use std::time::{Duration, Instant};

use proc_macro2::TokenStream;

fn scene(file: &str) -> Vec<(String, TokenStream)> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes/src")
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

fn median_time(tokens: &TokenStream, reps: usize) -> (Duration, filippov_codegen::Expansion) {
    let mut times = Vec::new();
    let mut last = None;
    for _ in 0..reps {
        let t = Instant::now();
        let e = filippov_codegen::expand_with_stats(tokens.clone()).expect("expands");
        times.push(t.elapsed());
        last = Some(e);
    }
    times.sort();
    (times[reps / 2], last.expect("ran"))
}

fn report(name: &str, tokens: &TokenStream, reps: usize, detail: bool) {
    let (t, e) = median_time(tokens, reps);
    let lets: usize = e.functions.iter().map(|f| f.lets).sum();
    println!(
        "{name:<16} dof {:>2}  expansion {:>9.2} ms (median of {reps})  graph {:>7} nodes  {lets:>6} lets  {:>9} bytes of code",
        e.dof,
        t.as_secs_f64() * 1e3,
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
}
