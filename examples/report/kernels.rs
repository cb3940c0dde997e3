//! Kernel costs: ns per call of the generated kernels against the numeric
//! implementation, operation counts, expansion time and release compile time per scene.

use std::hint::black_box as bb;
use std::path::Path;

use filippov::nalgebra::{DVector, SVector};
use filippov::prelude::*;
use filippov::runtime::numeric;
use filippov_scenes::{BranchedTree, DoublePendulum, Panda, PlanarArm3};

use super::config::Config;
use super::markdown::{Page, sci};
use super::release_build::timed_build;
use super::timing::{Timing, ns_timed, timed};
use super::workprecision::Section;

fn row<S: Mechanism<N> + Coriolis<N> + Gravity<N>, const N: usize>(
    config: &Config,
    name: &str,
    s: &S,
    rows: &mut Vec<Vec<String>>,
    summary: &mut Vec<String>,
) {
    let q = SVector::<f64, N>::from_fn(|i, _| 0.3 + 0.7 * (i as f64).sin());
    let v = SVector::<f64, N>::from_fn(|i, _| 0.5 - 0.4 * (i as f64).cos());
    let tau = SVector::<f64, N>::from_fn(|i, _| 0.2 * i as f64);
    let model = s.model();
    let (qd, vd, td) = (
        DVector::from_column_slice(q.as_slice()),
        DVector::from_column_slice(v.as_slice()),
        DVector::from_column_slice(tau.as_slice()),
    );
    let (r, c) = (config.repeats.max(3), config.kernel_calls);
    let m = (
        ns_timed(r, c, || s.mass_matrix(bb(&q))),
        ns_timed(r, c / 10, || numeric::crba(&model, bb(&qd))),
    );
    let cor = (
        ns_timed(r, c, || s.coriolis_matrix(bb(&q), bb(&v))),
        ns_timed(r, c / 50, || {
            numeric::coriolis_matrix(&model, bb(&qd), bb(&vd))
        }),
    );
    let g = (
        ns_timed(r, c, || s.gravity(bb(&q))),
        ns_timed(r, c / 10, || numeric::gravity(&model, bb(&qd))),
    );
    let fd = (
        ns_timed(r, c, || s.forward_dynamics(bb(&q), bb(&v), bb(&tau))),
        ns_timed(r, c / 10, || {
            numeric::forward_dynamics(&model, bb(&qd), bb(&vd), bb(&td))
        }),
    );
    let jac = ns_timed(r, c / 4, || {
        s.forward_dynamics_jacobian(bb(&q), bb(&v), bb(&tau))
    });
    // The ratio's range: slowest over fastest batch and the other way round.
    let ratio = |(a, b): (Timing, Timing)| b.ratio_to(&a, 1);
    let cell =
        |(a, b): (Timing, Timing)| format!("{} / {} ({})", a.show(1), b.show(0), ratio((a, b)));
    rows.push(vec![
        name.into(),
        N.to_string(),
        cell(m),
        cell(cor),
        cell(g),
        cell(fd),
        jac.show(1),
    ]);
    summary.push(format!(
        "{name}: generated forward dynamics {:.1} ns vs numeric {:.1} ns per call ({:.1}× faster)",
        fd.0.median,
        fd.1.median,
        fd.1.median / fd.0.median
    ));
    if name == "Panda" {
        super::markdown::headline(
            "Generated forward dynamics is faster than the numeric RNEA/CRBA (Panda, 7 dof)",
            format!("{} ns", fd.0.show(1)),
            format!("{} ns (numeric `runtime::numeric`)", fd.1.show(0)),
            ratio(fd),
            format!("ns per call, median (min–max) of {r} batches; same state"),
        );
    }
}

/// The kernels section: generated against numeric on the canonical scenes.
pub fn kernels(config: &Config) -> Section {
    let mut page = Page::empty();
    let mut rows = Vec::new();
    let mut summary = Vec::new();
    let (r, s) = (&mut rows, &mut summary);
    row(config, "DoublePendulum", &DoublePendulum::default(), r, s);
    row(config, "PlanarArm3", &PlanarArm3::default(), r, s);
    row(config, "BranchedTree", &BranchedTree::default(), r, s);
    row(config, "Panda", &Panda::default(), r, s);
    page.h2("Kernels: generated against the numeric implementation");
    page.para(&format!(
        "ns per call, generated / numeric (speed-up), median (min–max) of batches of up to {} calls; the speed-up's range pairs the slowest batch of one with the fastest of the other. The numeric implementation \
         (`runtime::numeric`) is plain RNEA/CRBA over a runtime model with dynamic sizes; its Coriolis matrix uses exact \
         ∂M/∂q. The same comparison with divan: `cargo bench --bench kernels`.",
        config.kernel_calls
    ));
    page.table(
        &[
            "scene",
            "dof",
            "M",
            "C",
            "g",
            "forward dynamics",
            "FD Jacobian (generated)",
        ],
        &rows,
    );
    Section { page, summary }
}

fn scene_sources() -> Vec<(String, String)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("src/scenes");
    [
        "double_pendulum.rs",
        "arm3.rs",
        "tree.rs",
        "panda.rs",
        "s9.rs",
        "lie.rs",
        "loops.rs",
        "contacts.rs",
    ]
    .iter()
    .map(|f| {
        (
            f.to_string(),
            std::fs::read_to_string(dir.join(f)).expect("scene source"),
        )
    })
    .collect()
}

fn structs(src: &str) -> Vec<(String, proc_macro2::TokenStream)> {
    syn::parse_file(src)
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

pub fn expansion(config: &Config) -> Section {
    let mut page = Page::empty();
    let mut rows = Vec::new();
    let mut summary = Vec::new();
    for (_, src) in scene_sources() {
        for (name, tokens) in structs(&src) {
            let (t, e) = timed(config.repeats.max(3), || {
                filippov_codegen::expand_with_stats(tokens.clone())
            });
            let t = t.scaled(1e3);
            let Ok(e) = e else { continue };
            let get = |n: &str| e.functions.iter().find(|f| f.name == n).map(|f| f.ops);
            let ops = |n: &str| {
                get(n).map_or("—".into(), |o| {
                    format!("{} / {} / {} / {}", o.add, o.mul, o.div, o.trig)
                })
            };
            rows.push(vec![
                name.clone(),
                e.dof.to_string(),
                t.show(2),
                e.graph_nodes.to_string(),
                ops("mass_matrix"),
                ops("coriolis_matrix"),
                ops("gravity"),
                ops("forward_dynamics"),
                ops("forward_dynamics_jacobian"),
            ]);
            summary.push(format!("{name}: expansion {} ms", t.show(2)));
        }
    }
    page.h2("Expansion and operation counts");
    page.para("Expansion = the derive's engine on the scene's source (parse, validate, symbolic mechanics, emission), median (min–max) of repeated runs. Operation counts of the emitted code: add / mul / div / sin-cos pairs, each shared subexpression once.");
    page.table(
        &[
            "scene",
            "dof",
            "expansion [ms], median (min–max)",
            "DAG nodes",
            "M",
            "C",
            "g",
            "FD",
            "FD Jacobian",
        ],
        &rows,
    );
    // What a scene gets without asking: the bundled scenes declare `emit = all` (the
    // tests compare every kernel); here the same sources without it.
    let mut kept = Vec::new();
    let lumped =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("src/scenes/lumped.rs"))
            .expect("scene source");
    for (_, src) in scene_sources().into_iter().chain([(String::new(), lumped)]) {
        let plain = src
            .replace("#[mechanism(emit = all)]", "")
            .replace("emit = all, ", "");
        for ((name, all), (_, default)) in structs(&src).into_iter().zip(structs(&plain)) {
            let (Ok(all), Ok(default)) = (
                filippov_codegen::expand_with_stats(all),
                filippov_codegen::expand_with_stats(default),
            ) else {
                continue;
            };
            let lets = |e: &filippov_codegen::Expansion| -> usize {
                e.functions.iter().map(|f| f.lets).sum()
            };
            let kernels: Vec<String> = default
                .functions
                .iter()
                .map(|f| format!("{} ({} lets; {})", f.name, f.lets, f.ops))
                .collect();
            kept.push(vec![
                name,
                kernels.join("<br>"),
                lets(&default).to_string(),
                lets(&all).to_string(),
            ]);
        }
    }
    page.h3("Kernels emitted by default");
    page.para(
        "Without `emit = [...]` a scene gets what the integrators call: the mass matrix, forward dynamics and its \
         Jacobian, and for non-smooth scenes `M⁻¹` and any user slip law. The table lists them per scene with \
         their lets and operation counts (add, mul, div, neg, sin/cos, sqrt), and the lets with `emit = all` \
         (every optional kernel: Christoffel symbols, Coriolis matrix, gravity, bias, passive forces, inverse \
         dynamics, energies, DAE residuals, Delassus operator, switching functions) beside them.",
    );
    page.table(
        &[
            "scene",
            "default kernels",
            "lets (default)",
            "lets (emit = all)",
        ],
        &kept,
    );
    Section {
        page,
        summary: summary
            .into_iter()
            .filter(|s| s.starts_with("Panda"))
            .collect(),
    }
}

/// Release compile time of a crate holding one scene, measured by building a temporary
/// crate twice (the first build compiles the dependencies).
pub fn compile_times(config: &Config) -> Section {
    let mut page = Page::empty();
    page.h2("Release compile time per scene");
    if !config.compile {
        page.para("Not measured in this configuration (run the default or `--long` report).");
        return Section {
            page,
            summary: Vec::new(),
        };
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let work = config.out_dir.join("compile");
    let mut rows = Vec::new();
    let mut summary = Vec::new();
    // The bundled scenes, then each robot of `robots/` read from its URDF file (default
    // kernels; the free-base robots with `base = free`) with a function that calls the
    // kernels: the methods are `#[inline]`, so rustc compiles them in the crate that
    // calls them, and a crate that only declares the scene defers most of that work.
    let robots = [
        ("panda.urdf", "lock = [panda_finger_joint1, panda_finger_joint2], ", 7, 7),
        ("ur5.urdf", "", 6, 6),
        ("solo12.urdf", "base = free, ", 18, 19),
        ("simple_humanoid.urdf", "base = free, ", 35, 36),
        ("three_link_arm.urdf", "", 3, 3),
        ("oblique36.urdf", "", 36, 36),
    ]
    .map(|(file, options, n, nq)| {
        let path = root.join("robots").join(file);
        // `filippov::Mechanism` is the derive and the trait; a free base adds the Lie one.
        let import = if n == nq {
            ""
        } else {
            "use filippov::runtime::liegroup::LieMechanism;"
        };
        (
            file.to_string(),
            format!(
                "use filippov::Mechanism;\n{import}\nuse filippov::nalgebra::SVector;\n\
                 #[derive(Mechanism)]\n#[mechanism(urdf = {:?}, {options}gravity = [0.0, 0.0, -9.81])]\npub struct Robot;\n\
                 pub fn kernels(q: &SVector<f64, {nq}>, v: &SVector<f64, {n}>, tau: &SVector<f64, {n}>) -> f64 {{\n\
                     Robot.mass_matrix(q)[0] + Robot.forward_dynamics(q, v, tau)[0] + Robot.forward_dynamics_jacobian(q, v, tau).d_dq[0]\n}}\n",
                path.display().to_string()
            ),
        )
    });
    // The closed mechanisms of `loops.rs`, each with a function that calls its kernels:
    // the tree's and the loops' (constrained forward dynamics, constraint Jacobian, γ).
    let loops_src = scene_sources()
        .into_iter()
        .find(|(f, _)| f == "loops.rs")
        .map(|(_, src)| src)
        .unwrap_or_default();
    let closed = [("AndrewsSqueezer", 7), ("Delta", 12)].map(|(scene, n)| {
        (
            format!("loops.rs: {scene}, kernels called"),
            format!(
                "{loops_src}\n\
                 pub fn kernels(q: &filippov::nalgebra::SVector<f64, {n}>, v: &filippov::nalgebra::SVector<f64, {n}>, \
                 tau: &filippov::nalgebra::SVector<f64, {n}>) -> f64 {{\n\
                     use filippov::runtime::loops::LoopConstraints;\n\
                     let s = {scene}::default();\n\
                     s.mass_matrix(q)[0] + s.forward_dynamics(q, v, tau)[0] + s.forward_dynamics_jacobian(q, v, tau).d_dq[0] \
                     + s.constrained_forward_dynamics(q, v, tau).1[0] + s.constraint_jacobian(q)[0] + s.constraint_gamma(q, v)[0]\n}}\n"
            ),
        )
    });
    for (file, src) in scene_sources().into_iter().chain(closed).chain(robots) {
        let stem: String = file
            .trim_end_matches(".rs")
            .chars()
            .map(|c| {
                if c.is_ascii_alphanumeric() {
                    c.to_ascii_lowercase()
                } else {
                    '_'
                }
            })
            .collect();
        let dir = work.join(&stem);
        let _ = std::fs::create_dir_all(dir.join("src"));
        let features = if file.ends_with(".urdf") {
            ", features = [\"urdf\"]"
        } else {
            ""
        };
        let manifest = format!(
            "[package]\nname = \"scene_{stem}\"\nversion = \"0.0.0\"\nedition = \"2024\"\n\n[dependencies]\nfilippov = {{ path = {root:?}{features} }}\n\n[workspace]\n"
        );
        let _ = std::fs::write(dir.join("Cargo.toml"), manifest);
        let lib = src.replace("use crate::Mechanism;", "use filippov::Mechanism;");
        let target = work.join("target");
        let build = |lib: &str| -> Option<f64> {
            std::fs::write(dir.join("src/lib.rs"), lib).ok()?;
            timed_build(&dir, &target)
        };
        // Dependencies first, then timed rebuilds of the scene crate alone.
        if build(&lib).is_none() {
            rows.push(vec![file.clone(), "**build failed**".into()]);
            continue;
        }
        let mut times: Vec<f64> = (0..3)
            .filter_map(|i| build(&format!("{lib}\n// rebuild {i}\n")))
            .collect();
        times.sort_by(f64::total_cmp);
        if let (Some(&t), Some(&lo), Some(&hi)) =
            (times.get(times.len() / 2), times.first(), times.last())
        {
            let t = Timing {
                median: t,
                min: lo,
                max: hi,
            };
            rows.push(vec![file.clone(), t.show(2)]);
            if file == "panda.rs" {
                summary.push(format!(
                    "Panda: release compile of the scene's crate {} s (median (min–max) of 3)",
                    t.show(2)
                ));
            }
        }
    }
    page.para("`cargo build --release` of a crate holding only the scene (dependencies prebuilt), median (min–max) of 3 rebuilds. The generated methods are `#[inline]`, so rustc compiles their code in the crate that calls them: the `.rs` rows (a crate declaring the bundled scenes and calling nothing) measure expansion and type checking, little code generation. The `.urdf` rows are a crate with `#[derive(Mechanism)] #[mechanism(urdf = …)]` on that file of `robots/` (feature `urdf`; default kernels; Solo12 and the humanoid with `base = free`, the Panda's fingers locked) and a public function calling its mass matrix, forward dynamics and Jacobian, so they include code generation, as do the two `loops.rs: …, kernels called` rows (the closed mechanisms' file with a function calling the tree's and the loops' kernels of one of them).");
    page.table(
        &["scene file", "release compile [s], median (min–max)"],
        &rows,
    );
    let _ = sci(0.0);
    Section { page, summary }
}
