//! The symbolic engine's folding rules and operation counts, and expansion at scale.

use filippov_codegen::sym::{Graph, InputKind, Node, OpCount};

#[test]
fn structural_zeros_and_ones_fold() {
    let mut g = Graph::new();
    let x = g.input(InputKind::Q, 0);
    let zero = g.zero();
    let one = g.one();
    assert_eq!(g.add(x, zero), x);
    assert_eq!(g.mul(x, one), x);
    let x0 = g.mul(x, zero);
    assert!(g.is_zero(x0));
    let nx = g.neg(x);
    let cancel = g.add(x, nx);
    assert!(g.is_zero(cancel));
    assert_eq!(g.neg(nx), x);
}

#[test]
fn hash_consing_shares_subexpressions() {
    let mut g = Graph::new();
    let x = g.input(InputKind::Q, 0);
    let y = g.input(InputKind::V, 0);
    let a = g.mul(x, y);
    let b = g.mul(y, x);
    assert_eq!(a, b, "commutative operands are ordered canonically");
    let before = g.len();
    let _ = g.mul(x, y);
    assert_eq!(g.len(), before, "no new node for an existing expression");
}

#[test]
fn pythagorean_identity() {
    let mut g = Graph::new();
    let x = g.input(InputKind::Q, 3);
    let k = g.param(0);
    let (s, c) = (g.sin(x), g.cos(x));
    let ss = g.mul(s, s);
    let cc = g.mul(c, c);
    let unit = g.add(ss, cc);
    assert!(g.is_one(unit));
    let kss = g.mul(k, ss);
    let kcc = g.mul(k, cc);
    assert_eq!(g.add(kss, kcc), k);
    // A different coefficient must not fold.
    let two = g.constant(2.0);
    let tcc = g.mul(two, cc);
    let sum = g.add(kss, tcc);
    assert!(matches!(g.node(sum), Node::Add(..)));
}

#[test]
fn trig_symmetry_and_constant_folding() {
    let mut g = Graph::new();
    let x = g.input(InputKind::Q, 0);
    let nx = g.neg(x);
    let s = g.sin(x);
    let sn = g.sin(nx);
    assert_eq!(g.neg(s), sn);
    assert_eq!(g.cos(nx), g.cos(x));
    let half_pi = g.constant(std::f64::consts::FRAC_PI_2);
    let c = g.cos(half_pi);
    assert!(g.is_zero(c), "cos(π/2) folds to an exact zero");
    let two = g.constant(2.0);
    let three = g.constant(3.0);
    let six = g.constant(6.0);
    let t = g.mul(three, x);
    let six_x = g.mul(two, t);
    assert_eq!(six_x, g.mul(six, x), "constant factors merge");
}

#[test]
fn op_counts_count_shared_nodes_once() {
    let mut g = Graph::new();
    let x = g.input(InputKind::Q, 0);
    let y = g.input(InputKind::Q, 1);
    let xy = g.mul(x, y);
    let s = g.sin(x);
    let c = g.cos(x);
    let a = g.add(xy, s);
    let b = g.sub(xy, c);
    let ops = g.count_ops(&[a, b]);
    assert_eq!(
        ops,
        OpCount {
            add: 2,
            mul: 1,
            trig: 1,
            ..OpCount::default()
        }
    );
}

#[test]
fn differentiation_matches_finite_differences_of_an_evaluator() {
    // f(x, y) = sin(x) · y / (1 + x²)
    let mut g = Graph::new();
    let x = g.input(InputKind::Q, 0);
    let y = g.input(InputKind::Q, 1);
    let s = g.sin(x);
    let xx = g.mul(x, x);
    let one = g.one();
    let den = g.add(one, xx);
    let num = g.mul(s, y);
    let f = g.div(num, den);
    let dfx = g.diff(
        f,
        filippov_codegen::sym::Input {
            kind: InputKind::Q,
            index: 0,
        },
    );
    let (x0, y0) = (0.7, -1.3);
    let h = 1e-6;
    let fd = (eval(&g, f, &[x0 + h, y0]) - eval(&g, f, &[x0 - h, y0])) / (2.0 * h);
    let sym = eval(&g, dfx, &[x0, y0]);
    assert!((fd - sym).abs() < 1e-8, "{fd} vs {sym}");
}

/// A direct evaluator of the DAG (independent of the emitter).
fn eval(g: &Graph, id: filippov_codegen::sym::Id, q: &[f64]) -> f64 {
    use filippov_codegen::sym::Unary;
    match g.node(id) {
        Node::Const(b) => f64::from_bits(b),
        Node::Param(_) => panic!("no params here"),
        Node::Input(i) => q[i.index as usize],
        Node::Add(a, b) => eval(g, a, q) + eval(g, b, q),
        Node::Mul(a, b) => eval(g, a, q) * eval(g, b, q),
        Node::Unary(op, a) => {
            let v = eval(g, a, q);
            match op {
                Unary::Neg => -v,
                Unary::Recip => 1.0 / v,
                Unary::Sin => v.sin(),
                Unary::Cos => v.cos(),
                Unary::Sqrt => v.sqrt(),
                Unary::Exp => v.exp(),
                Unary::Ln => v.ln(),
            }
        }
    }
}

/// A 36-joint binary tree expands, and its output is valid Rust with the large
/// functions split into chunks of bounded size.
#[test]
fn thirty_six_joint_tree_expands() {
    let mut src = String::from("#[derive(Mechanism)]\n#[mechanism(gravity = [0.0, 0.0, -9.81])]\n");
    for i in 0..36 {
        let parent = if i == 0 {
            "world".to_string()
        } else {
            format!("b{}", (i - 1) / 2)
        };
        let axis = ["x", "y", "z"][i % 3];
        src += &format!(
            "#[body(b{i}, mass = m, com = [0.0, 0.0, l / 2.0], inertia = cuboid(m, 0.1, 0.1, l))]\n"
        );
        src += &format!(
            "#[joint(j{i}: revolute({axis}), parent = {parent}, child = b{i}, origin = [0.05, 0.0, l])]\n"
        );
    }
    src += "struct Tree { m: f64, l: f64 }";
    let e = filippov_codegen::expand_with_stats(src.parse().unwrap()).expect("expands");
    assert_eq!(e.dof, 36);
    let file: syn::File = syn::parse2(e.tokens).expect("valid Rust");
    // A function is emitted whole up to WHOLE lets; beyond, its helper parts hold at most
    // CHUNK lets each (plus the unpacking of the values crossing a split).
    let text = prettyplease::unparse(&file);
    let (mut lets, mut part) = (0usize, false);
    let (mut max_whole, mut max_part) = (0usize, 0usize);
    for line in text.lines() {
        let t = line.trim_start();
        // `fn`, `pub fn`, `unsafe fn` (the fused twins' chunks), `pub unsafe fn`.
        let t = t.strip_prefix("pub ").unwrap_or(t);
        let t = t.strip_prefix("unsafe ").unwrap_or(t);
        if t.starts_with("fn ") {
            lets = 0;
            part = t.contains("_part");
        }
        if t.starts_with("let ") {
            lets += 1;
            if part {
                max_part = max_part.max(lets);
            } else {
                max_whole = max_whole.max(lets);
            }
        }
    }
    use filippov_codegen::emit::function::{CHUNK, WHOLE};
    assert!(max_whole <= WHOLE + 80, "a function has {max_whole} lets");
    assert!(max_part <= CHUNK + 80, "a helper part has {max_part} lets");
    assert!(text.contains("_part0"), "large functions are split");
}

/// The attributes and struct of a random tree of `n` revolute joints drawn by `next`:
/// each joint's parent at most `reach` bodies up (1 makes a chain, larger bushier
/// trees), its axis along x, y, z or oblique, its origin offset at random.
fn random_tree(next: &mut impl FnMut() -> u64, n: usize, reach: usize) -> String {
    let mut src = String::new();
    for i in 0..n {
        let parent = if i == 0 {
            "world".to_string()
        } else {
            format!("b{}", i - 1 - (next() as usize % reach).min(i - 1))
        };
        let axis = ["x", "y", "z", "[0.6, 0.0, 0.8]"][(next() % 4) as usize];
        let ox = (next() % 100) as f64 / 100.0;
        src += &format!(
            "#[body(b{i}: revolute({axis}), parent = {parent}, origin = [{ox}, 0.0, l], mass = m, com = [0.0, 0.05, l / 2.0], inertia = cuboid(m, 0.1, 0.2, l))]\n"
        );
    }
    src + "struct Tree { m: f64, l: f64 }"
}

/// `forward_dynamics = auto` emits, per kernel, what the smaller of `crba` and `aba`
/// emits: on random trees of 3…24 joints (chains, bushy trees and everything between,
/// random axes and offsets), its operation counts of forward dynamics and its Jacobian
/// equal the smaller of the two algorithms'.
#[test]
fn auto_takes_the_algorithm_with_fewer_operations() {
    let mut seed = 0x0A17_0u64;
    let mut next = move || {
        seed = seed.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = seed;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    };
    let mut aba_won = 0;
    for case in 0..10 {
        let n = 3 + (next() % 22) as usize;
        let reach = 1 + (next() % 4) as usize;
        let src = random_tree(&mut next, n, reach);
        let ops = |algorithm: &str| -> (usize, usize) {
            let full = format!(
                "#[derive(Mechanism)]\n#[mechanism(gravity = [0.0, 0.0, -9.81], forward_dynamics = {algorithm})]\n{src}"
            );
            let e = filippov_codegen::expand_with_stats(full.parse().unwrap()).expect("expands");
            let get = |f: &str| {
                e.functions
                    .iter()
                    .find(|x| x.name == f)
                    .map(|x| x.ops.total())
                    .expect("emitted")
            };
            (get("forward_dynamics"), get("forward_dynamics_jacobian"))
        };
        let (crba, aba, auto) = (ops("crba"), ops("aba"), ops("auto"));
        assert_eq!(
            auto.0,
            crba.0.min(aba.0),
            "case {case} ({n} joints): forward dynamics"
        );
        assert_eq!(
            auto.1,
            crba.1.min(aba.1),
            "case {case} ({n} joints): Jacobian"
        );
        aba_won += usize::from(aba.0 < crba.0);
    }
    // Both outcomes occur, so both branches of the choice are exercised.
    assert!(
        (1..10).contains(&aba_won),
        "ABA had fewer FD operations in {aba_won} of 10"
    );
}

/// The forward dynamics' parts (`Expansion::forward_parts`) account for every operation
/// of the kernel exactly once: on random trees with random axes and offsets, by either
/// algorithm, they sum to the kernel's count kind by kind, and kinematics holds one
/// `sin_cos` per joint (every joint here is revolute, each with its own angle).
#[test]
fn forward_parts_sum_to_the_kernels_count() {
    let mut seed = 0x9A27_5u64;
    let mut next = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        seed
    };
    for case in 0..6 {
        let n = 2 + (next() % 12) as usize;
        let reach = 1 + (next() % 3) as usize;
        let src = random_tree(&mut next, n, reach);
        for (algorithm, first_parts) in [
            ("crba", ["kinematics", "mass matrix (CRBA)"]),
            ("aba", ["kinematics", "articulated inertias"]),
        ] {
            let full = format!(
                "#[derive(Mechanism)]\n#[mechanism(gravity = [0.0, 0.0, -9.81], forward_dynamics = {algorithm})]\n{src}"
            );
            let e = filippov_codegen::expand_with_stats(full.parse().unwrap()).expect("expands");
            let fd = e
                .functions
                .iter()
                .find(|f| f.name == "forward_dynamics")
                .expect("emitted")
                .ops;
            let names: Vec<&str> = e.forward_parts.iter().map(|(n, _)| *n).collect();
            assert_eq!(names[..2], first_parts, "case {case}, {algorithm}");
            let sum = e
                .forward_parts
                .iter()
                .fold(OpCount::default(), |a, (_, c)| a + *c);
            assert_eq!(
                sum, fd,
                "case {case}, {algorithm}: parts {:?}",
                e.forward_parts
            );
            assert_eq!(e.forward_parts[0].1.trig, n, "case {case}, {algorithm}");
            assert_eq!(sum.trig, n, "case {case}, {algorithm}");
        }
    }
}
