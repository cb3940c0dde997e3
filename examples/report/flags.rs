//! The same CPU flags on both sides: our generated forward dynamics and the peers'
//! compiled code (Pinocchio's ABA in C++, SymPy's C for the 7-link chain), each built for
//! the baseline x86-64 target (rustc's default; `-O3` without `-march`) and for this
//! machine (`-C target-cpu=native`; `-march=native`), all four timed in this run in
//! interleaved rounds.
//!
//! Ours is a throwaway release crate (`target/report/flags/crate`) holding the scenes,
//! the URDF robots and the chain, built twice (two target directories, `RUSTFLAGS` set
//! for the native one). Its binary times one model's forward dynamics at a state read
//! from a file, as `peers/pin_bench.cpp` does for Pinocchio: a warm-up, batches of about
//! 20 ms, 21 batches, inputs through `black_box`. The peers' binaries are those
//! `bash peers/run.sh` builds (`pin_bench`, `pin_bench_native`, `chain7`,
//! `chain7_native`).

use std::path::{Path, PathBuf};

use filippov::Mechanism;
use filippov_scenes::{BranchedTree, DoublePendulum, Panda, PlanarArm3};

use super::config::Config;
use super::markdown::{Page, headline};
use super::release_build::release_build;
use super::timing::{Timing, in_rounds, program_timing};
use super::workprecision::Section;

/// A model's four timings: ours baseline and native, the peer's baseline and native.
type Compared = (String, Timing, Timing, Timing, Timing);

/// Interleaved rounds of the four programs per model.
const ROUNDS: usize = 3;

/// One model of the comparison.
struct Model {
    /// Name on the command line of our binary and in the table.
    name: String,
    /// The Rust expression of the system (its type's declaration is in the crate).
    system: String,
    /// `(nq, n)`: lengths of `q` and of `v` and `τ`.
    dims: (usize, usize),
    /// `q`, `v`, `τ` at which both sides are timed.
    state: [Vec<f64>; 3],
    /// The peer: its binaries (baseline, native), their arguments and the timing key.
    peer: &'static str,
    peer_args: Vec<PathBuf>,
    key: &'static str,
    baseline: PathBuf,
    native: PathBuf,
    /// Whether ours is also timed in SIMD batches (`emit = [generic]`: the URDF robots).
    batch: bool,
}

/// The state `peers/pin_bench.py` times the scenes at.
fn scene_state(n: usize) -> [Vec<f64>; 3] {
    let f = |a: f64, b: f64| (0..n).map(|i| a + b * i as f64).collect::<Vec<f64>>();
    [f(0.3, 0.17), f(0.5, -0.23), f(0.7, -0.11)]
}

/// The first state of a robot as the URDF section exported it (`"q":[…]` etc.).
fn exported_state(path: &Path) -> Option<[Vec<f64>; 3]> {
    let text = std::fs::read_to_string(path).ok()?;
    let field = |key: &str| -> Option<Vec<f64>> {
        let start = text.find(&format!("\"{key}\":["))? + key.len() + 4;
        let end = start + text[start..].find(']')?;
        text[start..end]
            .split(',')
            .map(|x| x.trim().parse().ok())
            .collect()
    };
    Some([field("q")?, field("v")?, field("tau")?])
}

/// The crate's `main.rs`: the declarations, then a timing harness dispatching on the
/// model's name.
fn source(models: &[Model], declarations: &str) -> String {
    let mut arms = String::new();
    for m in models {
        let (nq, n) = m.dims;
        // With `batch` (models with generic kernels): four copies of the state in the
        // lanes of one f64x4 call, ns per state; with `lanes`, as many as the build's
        // register holds (`F64Lanes`).
        let batch = if m.batch {
            format!(
                "            if lanes {{\n                let k = F64Lanes::LANES;\n                let ql: [F64Lanes; {nq}] = pack(&vec![q.into(); k]);\n                let vl: [F64Lanes; {n}] = pack(&vec![v.into(); k]);\n                let tl: [F64Lanes; {n}] = pack(&vec![tau.into(); k]);\n                let t = time_ns(|| bb(&sys).forward_dynamics_as(bb(&ql), bb(&vl), bb(&tl)));\n                let k = k as f64;\n                return println!(\"fd_ns {{}} {{}} {{}}\", t[0] / k, t[1] / k, t[2] / k);\n            }}\n            if batch || dispatch {{\n                let q4: [f64x4; {nq}] = pack(&[q.into(); 4]);\n                let v4: [f64x4; {n}] = pack(&[v.into(); 4]);\n                let t4: [f64x4; {n}] = pack(&[tau.into(); 4]);\n                let t = if dispatch {{\n                    time_ns(|| unsafe {{ fd4_avx2(bb(&sys), bb(&q4), bb(&v4), bb(&t4)) }})\n                }} else {{\n                    time_ns(|| bb(&sys).forward_dynamics_as(bb(&q4), bb(&v4), bb(&t4)))\n                }};\n                return println!(\"fd_ns {{}} {{}} {{}}\", t[0] / 4.0, t[1] / 4.0, t[2] / 4.0);\n            }}\n"
            )
        } else {
            String::new()
        };
        arms += &format!(
            "        {:?} => {{\n            let sys = {};\n            let q = SVector::<f64, {nq}>::from_column_slice(&s[0]);\n            let v = SVector::<f64, {n}>::from_column_slice(&s[1]);\n            let tau = SVector::<f64, {n}>::from_column_slice(&s[2]);\n{batch}            time_ns(|| bb(&sys).forward_dynamics(bb(&q), bb(&v), bb(&tau)))\n        }}\n",
            m.name, m.system
        );
    }
    format!(
        r#"#![allow(dead_code)]
use filippov::nalgebra::SVector;
use filippov::prelude::*;
use filippov::runtime::real::{{F64Lanes, Lanes, f64x4, pack}};
use std::hint::black_box as bb;
use std::time::Instant;

{declarations}

/// The f64x4 forward dynamics with AVX2 and FMA enabled (function multiversioning by
/// hand: what a default build can reach at run time).
#[target_feature(enable = "avx,avx2,fma")]
unsafe fn fd4_avx2<S, const N: usize, const NQ: usize, const P: usize>(
    s: &S,
    q: &[f64x4; NQ],
    v: &[f64x4; N],
    t: &[f64x4; N],
) -> [f64x4; N]
where
    S: GenericDynamics<N, NQ, P>,
{{
    s.forward_dynamics_as(q, v, t)
}}

/// ns per call: median, fastest and slowest of 21 batches of about 20 ms, after a warm-up
/// (as peers/pin_bench.cpp).
fn time_ns<T>(mut f: impl FnMut() -> T) -> [f64; 3] {{
    for _ in 0..20_000 {{
        bb(f());
    }}
    let mut n = 1000u64;
    loop {{
        let t = Instant::now();
        for _ in 0..n {{
            bb(f());
        }}
        if t.elapsed().as_secs_f64() > 0.02 {{
            break;
        }}
        n *= 2;
    }}
    let mut per: Vec<f64> = (0..21)
        .map(|_| {{
            let t = Instant::now();
            for _ in 0..n {{
                bb(f());
            }}
            t.elapsed().as_secs_f64() * 1e9 / n as f64
        }})
        .collect();
    per.sort_by(f64::total_cmp);
    [per[10], per[0], per[20]]
}}

fn main() {{
    let args: Vec<String> = std::env::args().collect();
    let (Some(name), Some(path)) = (args.get(1), args.get(2)) else {{
        eprintln!("usage: fd MODEL STATE_FILE [batch | lanes | dispatch]");
        std::process::exit(2);
    }};
    let text = std::fs::read_to_string(path).expect("the state file");
    let s: Vec<Vec<f64>> = text
        .lines()
        .map(|l| l.split_whitespace().map(|x| x.parse().expect("a number")).collect())
        .collect();
    let batch = args.get(3).is_some_and(|a| a == "batch");
    let lanes = args.get(3).is_some_and(|a| a == "lanes");
    // Runtime dispatch: the batch kernel compiled a second time inside a function built
    // for AVX2 and FMA, called when the CPU has them.
    let dispatch = args.get(3).is_some_and(|a| a == "dispatch")
        && is_x86_feature_detected!("avx2")
        && is_x86_feature_detected!("fma");
    if args.get(3).is_some_and(|a| a == "dispatch") && !dispatch {{
        eprintln!("this CPU has no AVX2 and FMA");
        std::process::exit(2);
    }}
    let t = match name.as_str() {{
{arms}        other => {{
            eprintln!("unknown model {{other}}");
            std::process::exit(2);
        }}
    }};
    println!("fd_ns {{}} {{}} {{}}", t[0], t[1], t[2]);
}}
"#
    )
}

/// The models whose peer binary and inputs exist: the four scenes and the URDF robots
/// against Pinocchio, the 7-link chain against SymPy.
fn models(config: &Config) -> (Vec<Model>, Vec<String>) {
    let peers = config.out_dir.join("peers");
    let build = peers.join("build");
    let (pin, pin_native) = (build.join("pin_bench"), build.join("pin_bench_native"));
    let mut models = Vec::new();
    let mut missing = Vec::new();
    let pinocchio = |name: &str, system: String, dims, state, model: PathBuf| {
        if model.exists() && pin.exists() && pin_native.exists() {
            Ok(Model {
                name: name.to_string(),
                system,
                dims,
                state,
                peer: "Pinocchio `aba`",
                peer_args: vec![model, PathBuf::from("aba")],
                key: "aba_ns",
                baseline: pin.clone(),
                native: pin_native.clone(),
                batch: false,
            })
        } else {
            Err(name.to_string())
        }
    };
    let scenes: [(&str, &str, usize); 4] = [
        (
            "double_pendulum",
            "filippov_scenes::DoublePendulum::default()",
            <DoublePendulum as Mechanism<2>>::DOF,
        ),
        (
            "planar_arm3",
            "filippov_scenes::PlanarArm3::default()",
            <PlanarArm3 as Mechanism<3>>::DOF,
        ),
        (
            "branched_tree",
            "filippov_scenes::BranchedTree::default()",
            BranchedTree::JOINTS.len(),
        ),
        (
            "panda",
            "filippov_scenes::Panda::default()",
            <Panda as Mechanism<7>>::DOF,
        ),
    ];
    for (name, system, n) in scenes {
        match pinocchio(
            name,
            system.into(),
            (n, n),
            scene_state(n),
            build.join(format!("{name}.txt")),
        ) {
            Ok(m) => models.push(m),
            Err(name) => missing.push(name),
        }
    }
    for robot in super::urdf::ROBOTS.iter() {
        let json = config
            .out_dir
            .join("urdf")
            .join(format!("{}.json", robot.name));
        match exported_state(&json) {
            Some(state) => {
                let dims = (state[0].len(), state[1].len());
                match pinocchio(
                    &format!("{} (URDF)", robot.name),
                    format!("Urdf{}", robot.ident),
                    dims,
                    state,
                    peers.join("urdf").join(format!("{}.txt", robot.name)),
                ) {
                    Ok(m) => models.push(Model { batch: true, ..m }),
                    Err(name) => missing.push(name),
                }
            }
            None => missing.push(format!("{} (URDF)", robot.name)),
        }
    }
    let (chain, chain_native) = (build.join("chain7"), build.join("chain7_native"));
    if chain.exists() && chain_native.exists() {
        models.push(Model {
            name: "chain7".into(),
            system: "Chain7".into(),
            dims: (7, 7),
            state: {
                let [q, v, _] = scene_state(7);
                [q, v, vec![0.0; 7]]
            },
            peer: "SymPy's C (M + forcing + Cholesky)",
            peer_args: Vec::new(),
            key: "solve_ns",
            baseline: chain,
            native: chain_native,
            batch: false,
        });
    } else {
        missing.push("chain7".into());
    }
    (models, missing)
}

/// The declarations the crate needs: the URDF robots (as the URDF section declares them)
/// and the 7-link chain (read from `chains.rs`, as the chains section expands it).
fn declarations() -> String {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut out = String::new();
    for robot in super::urdf::ROBOTS.iter() {
        out += &format!(
            "#[derive(Mechanism)]\n#[mechanism(urdf = {:?}, {}gravity = [0.0, 0.0, -9.81], emit = [generic])]\nstruct Urdf{};\n\n",
            root.join(robot.file).display().to_string(),
            robot.options,
            robot.ident
        );
    }
    let chains =
        std::fs::read_to_string(root.join("examples/report/chains.rs")).unwrap_or_default();
    if let Ok(file) = syn::parse_file(&chains) {
        for item in file.items {
            if let syn::Item::Struct(s) = item
                && s.ident == "Chain7"
            {
                out += &quote::ToTokens::to_token_stream(&s).to_string();
                out.push('\n');
            }
        }
    }
    out
}

pub fn flags(config: &Config) -> Section {
    let mut page = Page::empty();
    let mut summary = Vec::new();
    page.h2("The same CPU flags on both sides");
    if !config.compile {
        page.para("Not measured in this configuration: it builds a release crate twice (run the default or `--long` report).");
        return Section { page, summary };
    }
    let (models, missing) = models(config);
    if models.is_empty() {
        page.para(
            "The peers' binaries or models are missing (the peer script the report runs, `peers/run.sh`, builds Pinocchio's and SymPy's, baseline and native, unless `--no-peers`; \
             after one report run has written the models), so nothing is compared here.",
        );
        summary.push("CPU flags: not measured (the peers' binaries are missing: `--no-peers`, or the peer script failed)".into());
        return Section { page, summary };
    }
    let work = config.out_dir.join("flags");
    let dir = work.join("crate");
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let written = std::fs::create_dir_all(dir.join("src"))
        .and_then(|_| {
            std::fs::write(
                dir.join("Cargo.toml"),
                format!(
                    "[package]\nname = \"fd\"\nversion = \"0.0.0\"\nedition = \"2024\"\npublish = false\n\n[dependencies]\nfilippov = {{ path = {:?}, features = [\"urdf\"] }}\nfilippov-scenes = {{ path = {:?} }}\n\n[workspace]\n",
                    root.display().to_string(),
                    root.join("scenes").display().to_string()
                ),
            )
        })
        .and_then(|_| {
            std::fs::write(
                dir.join("src/main.rs"),
                source(&models, &declarations()),
            )
        })
        .and_then(|_| {
            for m in &models {
                let lines: Vec<String> = m
                    .state
                    .iter()
                    .map(|x| {
                        x.iter()
                            .map(|v| format!("{v:e}"))
                            .collect::<Vec<_>>()
                            .join(" ")
                    })
                    .collect();
                std::fs::write(work.join(format!("{}.state", m.name)), lines.join("\n") + "\n")?;
            }
            Ok(())
        });
    if let Err(e) = written {
        page.para(&format!("Could not write the timing crate: {e}."));
        return Section { page, summary };
    }
    let (base_target, native_target) = (work.join("target-baseline"), work.join("target-native"));
    let builds = (
        release_build(&dir, &base_target, Some("")),
        release_build(&dir, &native_target, Some("-C target-cpu=native")),
    );
    let (Ok(base_s), Ok(native_s)) = (&builds.0, &builds.1) else {
        let why = [builds.0.err(), builds.1.err()]
            .into_iter()
            .flatten()
            .collect::<Vec<_>>()
            .join("\n");
        page.para("**The timing crate did not build**; nothing is compared here.");
        page.code(&why);
        summary.push("CPU flags: the timing crate did not build (see its section)".into());
        return Section { page, summary };
    };
    let ours = |target: &Path| target.join("release").join("fd");
    let mut rows = Vec::new();
    let mut head: Vec<Compared> = Vec::new();
    // (model, ours one state per call and f64x4 per state, baseline then native).
    #[allow(clippy::type_complexity)]
    let mut batched: Vec<(String, Option<Timing>, Timing, Option<Timing>, Timing)> = Vec::new();
    for m in &models {
        let state = work.join(format!("{}.state", m.name));
        let our_args = [m.name.as_ref(), state.as_os_str()];
        let peer_args: Vec<&std::ffi::OsStr> = m.peer_args.iter().map(|p| p.as_os_str()).collect();
        let (b, n) = (ours(&base_target), ours(&native_target));
        let mut ob = || program_timing(&b, &our_args, "fd_ns");
        let mut on = || program_timing(&n, &our_args, "fd_ns");
        let mut pb = || program_timing(&m.baseline, &peer_args, m.key);
        let mut pn = || program_timing(&m.native, &peer_args, m.key);
        let batch_args = [m.name.as_ref(), state.as_os_str(), "batch".as_ref()];
        let mut ob4 = || {
            m.batch
                .then(|| program_timing(&b, &batch_args, "fd_ns"))
                .flatten()
        };
        let mut on4 = || {
            m.batch
                .then(|| program_timing(&n, &batch_args, "fd_ns"))
                .flatten()
        };
        let dispatch_args = [m.name.as_ref(), state.as_os_str(), "dispatch".as_ref()];
        let mut od4 = || {
            m.batch
                .then(|| program_timing(&b, &dispatch_args, "fd_ns"))
                .flatten()
        };
        let lanes_args = [m.name.as_ref(), state.as_os_str(), "lanes".as_ref()];
        let mut obl = || {
            m.batch
                .then(|| program_timing(&b, &lanes_args, "fd_ns"))
                .flatten()
        };
        let t = in_rounds(
            ROUNDS,
            &mut [
                &mut ob, &mut on, &mut pb, &mut pn, &mut ob4, &mut on4, &mut od4, &mut obl,
            ],
        );
        let cell = |t: Option<Timing>| t.map_or("failed".into(), |t| t.show(0));
        let ratio = |p: Option<Timing>, o: Option<Timing>| match (p, o) {
            (Some(p), Some(o)) => p.ratio_to(&o, 1),
            _ => "—".into(),
        };
        rows.push(vec![
            m.name.clone(),
            m.dims.1.to_string(),
            m.peer.into(),
            cell(t[0]),
            cell(t[2]),
            ratio(t[2], t[0]),
            cell(t[1]),
            cell(t[3]),
            ratio(t[3], t[1]),
            if m.batch { cell(t[7]) } else { "—".into() },
            if m.batch { cell(t[4]) } else { "—".into() },
            if m.batch { cell(t[5]) } else { "—".into() },
            if m.batch { cell(t[6]) } else { "—".into() },
            ratio(t[3], t[5]),
        ]);
        if let (Some(b4), Some(n4)) = (t[4], t[5]) {
            batched.push((m.name.clone(), t[0], b4, t[1], n4));
        }
        if let [Some(a), Some(b), Some(c), Some(d)] = t[..] {
            head.push((m.name.clone(), a, b, c, d));
            summary.push(format!(
                "{} against {}: baseline flags {:.0} vs {:.0} ns ({}), native {:.0} vs {:.0} ns ({})",
                m.name,
                m.peer,
                a.median,
                c.median,
                c.ratio_to(&a, 1),
                b.median,
                d.median,
                d.ratio_to(&b, 1)
            ));
        }
    }
    page.para(&format!(
        "Forward dynamics ns per call, ours against the peer's compiled code, each side built twice: for the baseline x86-64 \
         target (rustc's default release build; `g++`/`gcc -O3` without `-march`) and for this machine (`RUSTFLAGS=\"-C \
         target-cpu=native\"`; `-O3 -march=native`). All four programs of a model are timed in {ROUNDS} interleaved rounds in \
         this run, each a median of 21 batches of about 20 ms after a warm-up, inputs through `black_box` (ours) or a \
         sink (theirs); a cell shows the median of the rounds' medians (min–max over all batches), a ratio peer / ours \
         (> 1: ours faster) with the range pairing the extremes. Ours is a throwaway crate (`target/report/flags/crate`, \
         built in {base_s:.0} s and {native_s:.0} s); the peers' binaries are those the peer script (`peers/run.sh`) builds. \
         Parameters: the scenes' are struct fields read at run time (the struct passes through `black_box`), the URDF \
         robots' and the chain's are literals in the declaration, as the derive reads them; Pinocchio reads its model \
         at run time, SymPy's C has the chain's parameters as literals. Scenes at the state `peers/pin_bench.py` times \
         (q_i = 0.3 + 0.17 i, v_i = 0.5 − 0.23 i, τ_i = 0.7 − 0.11 i), robots at the URDF section's first exported state."
    ));
    if !missing.is_empty() {
        page.para(&format!(
            "Not compared (peer binary, model or state missing: `--no-peers`, or the peer script failed): {}.",
            missing.join(", ")
        ));
    }
    page.table(
        &[
            "model",
            "dof",
            "peer",
            "ours, baseline [ns]",
            "peer, baseline [ns]",
            "peer / ours, baseline",
            "ours, native [ns]",
            "peer, native [ns]",
            "peer / ours, native",
            "ours f64x2 (the baseline build's F64Lanes) [ns/state]",
            "ours f64x4, baseline [ns/state]",
            "ours f64x4, native [ns/state]",
            "ours f64x4, baseline build + AVX2/FMA function [ns/state]",
            "peer native / ours f64x4 native",
        ],
        &rows,
    );
    if !batched.is_empty() {
        let one = |t: &Option<Timing>, b: &Timing| t.map_or("—".into(), |t| t.ratio_to(b, 2));
        let list: Vec<String> = batched
            .iter()
            .map(|(name, b1, b4, n1, n4)| {
                format!(
                    "{name}: one state per call / f64x4 per state {} baseline, {} native",
                    one(b1, b4),
                    one(n1, n4)
                )
            })
            .collect();
        summary.push(format!(
            "SIMD batches (f64x4) and the CPU flags: {}",
            list.join("; ")
        ));
        page.para(
            "The last five columns (URDF robots, `emit = [generic]`): the same forward dynamics on copies of the \
             state in the lanes of one call, ns per state, in the same rounds: two in `f64x2` (the lanes of one SSE2 \
             register, `runtime::real::F64Lanes` of the baseline build; the native build's is `f64x4`), four in \
             `f64x4`. With the baseline flags each \
             `f64x4` operation is two SSE2 halves; with `-C target-cpu=native` one AVX register. Runtime dispatch: the \
             baseline build calling the kernel through a function compiled with `#[target_feature(enable = \"avx,avx2,fma\")]` \
             (chosen at run time by `is_x86_feature_detected!`); the `f64x4` type itself is chosen when `wide` is \
             compiled, so inside that function its halves are still two SSE2 operations unless LLVM fuses them, and \
             the kernel's out-of-line parts (big robots) are not recompiled at all. (Rust contracts no `a·b + c` into \
             a fused multiply-add unless asked, so FMA changes neither side's results.)",
        );
    }
    let pin: Vec<&Compared> = head.iter().filter(|h| h.0 != "chain7").collect();
    if !pin.is_empty() {
        let list = |f: &dyn Fn(&Compared) -> String| {
            pin.iter()
                .map(|h| format!("{} {}", h.0, f(h)))
                .collect::<Vec<_>>()
                .join("; ")
        };
        headline(
            "Generated forward dynamics against Pinocchio's ABA in C++, both built with the same CPU flags",
            format!(
                "baseline: {} ns; native: {} ns",
                list(&|h| format!("{:.0}", h.1.median)),
                list(&|h| format!("{:.0}", h.2.median))
            ),
            format!(
                "baseline: {} ns; native: {} ns",
                list(&|h| format!("{:.0}", h.3.median)),
                list(&|h| format!("{:.0}", h.4.median))
            ),
            format!(
                "baseline: {}; native: {}",
                list(&|h| h.3.ratio_to(&h.1, 1)),
                list(&|h| h.4.ratio_to(&h.2, 1))
            ),
            format!(
                "Pinocchio / ours; both sides built for the baseline x86-64 target and for this machine (-C target-cpu=native, -march=native), all four timed in {ROUNDS} interleaved rounds in this run; section on CPU flags"
            ),
        );
    }
    Section { page, summary }
}
