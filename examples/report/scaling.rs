//! How the generated kernels scale with the number of joints, per algorithm: planar
//! chains of 7…50 links and random oblique 3-D trees of the same sizes (nothing
//! axis-aligned to fold), each declared with `forward_dynamics = crba`, `= aba` and
//! `= compact` and built as its own release crate (the build a user runs) whose binary times
//! the generated forward dynamics and its Jacobian beside the numeric implementation;
//! with the forward dynamics' machine code size from the binary's symbols.

use std::path::{Path, PathBuf};
use std::process::Command;

use super::config::Config;
use super::markdown::{Page, headline};
use super::release_build::timed_build;
use super::support::{Scale, Series, line_plot};
use super::workprecision::Section;

/// The derive and `#[mechanism]` line of a scene under `gravity` solved with `algorithm`.
fn header(gravity: &str, algorithm: &str) -> String {
    format!(
        "#[derive(filippov::Mechanism)]\n#[mechanism(gravity = {gravity}, forward_dynamics = {algorithm})]\n"
    )
}

/// A planar chain of `n` rods solved with `algorithm`.
fn chain_source(n: usize, algorithm: &str) -> String {
    let mut s = header("[0.0, -9.81, 0.0]", algorithm);
    for i in 0..n {
        let parent = if i == 0 {
            "world".to_string()
        } else {
            format!("b{}", i - 1)
        };
        let origin = if i == 0 { "0.0" } else { "l" };
        s += &format!(
            "#[body(b{i}: revolute(z), parent = {parent}, origin = [{origin}, 0.0, 0.0], mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]\n"
        );
    }
    s += "pub struct Chain { pub m: f64, pub l: f64 }\n";
    s
}

/// A random 3-D tree of `n` bodies with nothing axis-aligned to fold: oblique joint axes,
/// rpy origins, off-axis centres of mass, full inertia tensors, every seventh joint
/// prismatic, each body's parent one of the three before it (seeded by `n`, so the same
/// tree every run). The fields `m` and `l` scale the masses and the offsets.
fn oblique_source(n: usize, algorithm: &str) -> String {
    let mut rng = super::agreement_support::Rng::new(n as u64);
    let mut uniform = |lo: f64, hi: f64| rng.uniform(lo, hi);
    let mut s = header("[0.0, 0.0, -9.81]", algorithm);
    for i in 0..n {
        let parent = if i == 0 {
            "world".to_string()
        } else {
            format!("b{}", i - 1 - (uniform(0.0, 3.0) as usize).min(i - 1))
        };
        let mut axis = [uniform(-1.0, 1.0), uniform(-1.0, 1.0), uniform(0.2, 1.0)];
        let norm = axis.iter().map(|x| x * x).sum::<f64>().sqrt();
        axis.iter_mut().for_each(|x| *x /= norm);
        let kind = if i % 7 == 6 { "prismatic" } else { "revolute" };
        let o = [uniform(0.05, 0.3), uniform(-0.1, 0.1), uniform(-0.1, 0.1)];
        let rpy = [uniform(-0.5, 0.5), uniform(-0.5, 0.5), uniform(-0.5, 0.5)];
        let c = [
            uniform(0.02, 0.15),
            uniform(-0.05, 0.05),
            uniform(-0.05, 0.05),
        ];
        let w = uniform(0.5, 2.0);
        // Moments within [0.02, 0.03] (any two sum beyond the third, as a real body's
        // must) and small products: positive definite.
        let (ixx, iyy, izz) = (
            uniform(0.02, 0.03),
            uniform(0.02, 0.03),
            uniform(0.02, 0.03),
        );
        let (ixy, ixz, iyz) = (
            uniform(-0.002, 0.002),
            uniform(-0.002, 0.002),
            uniform(-0.002, 0.002),
        );
        s += &format!(
            "#[body(b{i}: {kind}([{:.4}, {:.4}, {:.4}]), parent = {parent}, origin = [l * {:.4}, l * {:.4}, l * {:.4}], \
             rpy = [{:.4}, {:.4}, {:.4}], mass = m * {w:.4}, com = [{:.4}, {:.4}, {:.4}], \
             inertia = [[{ixx:.5}, {ixy:.5}, {ixz:.5}], [{ixy:.5}, {iyy:.5}, {iyz:.5}], [{ixz:.5}, {iyz:.5}, {izz:.5}]])]\n",
            axis[0], axis[1], axis[2], o[0], o[1], o[2], rpy[0], rpy[1], rpy[2], c[0], c[1], c[2]
        );
    }
    s += "pub struct Chain { pub m: f64, pub l: f64 }\n";
    s
}

/// The declaration of a scene of `geometry` (`planar` or `oblique`).
fn source(geometry: &str, n: usize, algorithm: &str) -> String {
    match geometry {
        "oblique" => oblique_source(n, algorithm),
        _ => chain_source(n, algorithm),
    }
}

/// The machine code of the generated forward dynamics in `binary` (the method and its
/// out-of-line parts, from the symbol table), in bytes; `None` when the method was
/// inlined into its caller or the table could not be read.
fn fd_code_bytes(binary: &Path) -> Option<u64> {
    let out = Command::new("nm")
        .args(["-S", "-C", "--defined-only"])
        .arg(binary)
        .output()
        .ok()?;
    let text = String::from_utf8(out.stdout).ok()?;
    let size = |l: &str| u64::from_str_radix(l.split_whitespace().nth(1)?, 16).ok();
    // The compact loop is instantiated twice, on f64 and on the Jacobian's duals, under
    // one demangled name: the f64 one is the smaller.
    let compact = text
        .lines()
        .filter(|l| l.contains("compact::aba::forward_dynamics"))
        .filter_map(size)
        .min();
    let bytes: u64 = text
        .lines()
        .filter(|l| {
            l.contains("forward_dynamics")
                && !l.contains("compact::")
                && !l.contains("jacobian")
                && !l.contains("numeric")
                && !l.contains("{{closure}}")
        })
        .filter_map(size)
        .sum::<u64>()
        + compact.unwrap_or(0);
    (bytes > 0).then_some(bytes)
}

/// The crate's binary: ns per call (median, min, max of 7 batches) of the generated
/// forward dynamics, its Jacobian and the numeric forward dynamics, and the largest
/// difference between the two forward dynamics.
const MAIN: &str = r#"
use filippov::nalgebra::{DVector, SVector};
use filippov::prelude::*;
use filippov::runtime::numeric;
use std::time::Instant;

fn ns<F: FnMut() -> f64>(calls: usize, mut f: F) -> [f64; 3] {
    let mut t: Vec<f64> = (0..7)
        .map(|_| {
            let s = Instant::now();
            let mut acc = 0.0;
            for _ in 0..calls {
                acc += f();
            }
            std::hint::black_box(acc);
            s.elapsed().as_secs_f64() * 1e9 / calls as f64
        })
        .collect();
    t.sort_by(f64::total_cmp);
    [t[3], t[0], t[6]]
}

fn main() {
    let s = Chain { m: 1.0, l: 0.3 };
    let q = SVector::<f64, N>::from_fn(|i, _| (i as f64 * 0.37).sin());
    let v = SVector::<f64, N>::from_fn(|i, _| (i as f64 * 0.21).cos());
    let tau = SVector::<f64, N>::zeros();
    let model = s.model();
    let (qd, vd, td) = (
        DVector::from_column_slice(q.as_slice()),
        DVector::from_column_slice(v.as_slice()),
        DVector::from_column_slice(tau.as_slice()),
    );
    let fd = ns(2000, || s.forward_dynamics(std::hint::black_box(&q), &v, &tau)[0]);
    let jac = ns(20, || s.forward_dynamics_jacobian(std::hint::black_box(&q), &v, &tau).d_dq[0]);
    let num = ns(200, || numeric::forward_dynamics(&model, std::hint::black_box(&qd), &vd, &td)[0]);
    let a = s.forward_dynamics(&q, &v, &tau);
    let b = numeric::forward_dynamics(&model, &qd, &vd, &td);
    let scale = b.amax().max(1.0);
    let diff = (0..N).map(|i| (a[i] - b[i]).abs()).fold(0.0, f64::max) / scale;
    println!("{} {} {} {} {} {} {} {} {} {diff:e}", fd[0], fd[1], fd[2], jac[0], jac[1], jac[2], num[0], num[1], num[2]);
}
"#;

struct Run {
    n: usize,
    geometry: &'static str,
    algorithm: &'static str,
    /// The generated forward dynamics' machine code, bytes.
    code: Option<u64>,
    build_s: f64,
    /// FD, Jacobian, numeric FD: `[median, min, max]` ns.
    ns: [[f64; 3]; 3],
    diff: f64,
}

fn write_crate(
    dir: &Path,
    root: &Path,
    name: &str,
    (geometry, n, algorithm): (&str, usize, &str),
) -> Option<()> {
    std::fs::create_dir_all(dir.join("src")).ok()?;
    let manifest = format!(
        "[package]\nname = \"{name}\"\nversion = \"0.0.0\"\nedition = \"2024\"\n\n[dependencies]\nfilippov = {{ path = {root:?} }}\n\n[workspace]\n"
    );
    std::fs::write(dir.join("Cargo.toml"), manifest).ok()?;
    let src = format!(
        "{}\nconst N: usize = {n};\n{MAIN}",
        source(geometry, n, algorithm)
    );
    std::fs::write(dir.join("src/main.rs"), src).ok()
}

fn run(target: &Path, name: &str) -> Option<([[f64; 3]; 3], f64)> {
    let out = Command::new(target.join("release").join(name))
        .output()
        .ok()?;
    let text = String::from_utf8(out.stdout).ok()?;
    let v: Vec<f64> = text
        .split_whitespace()
        .filter_map(|x| x.parse().ok())
        .collect();
    (v.len() == 10).then(|| {
        (
            [[v[0], v[1], v[2]], [v[3], v[4], v[5]], [v[6], v[7], v[8]]],
            v[9],
        )
    })
}

fn ops(geometry: &str, n: usize, algorithm: &str) -> Option<(usize, usize)> {
    let tokens: proc_macro2::TokenStream = source(geometry, n, algorithm).parse().ok()?;
    let e = filippov_codegen::expand_with_stats(tokens).ok()?;
    let get = |f: &str| {
        e.functions
            .iter()
            .find(|x| x.name == f)
            .map_or(0, |x| x.ops.total())
    };
    Some((get("forward_dynamics"), get("forward_dynamics_jacobian")))
}

pub fn scaling(config: &Config) -> Section {
    let mut page = Page::empty();
    page.h2("Scaling with the number of joints, per algorithm");
    if !config.compile {
        page.para("Not measured in this configuration: it builds a release crate per chain and algorithm (run the default or `--long` report).");
        return Section {
            page,
            summary: Vec::new(),
        };
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let work: PathBuf = config.out_dir.join("scaling");
    let target = work.join("target");
    // Dependencies first (untimed), so each timed build compiles its own crate only.
    let warm = work.join("warm");
    let _ = write_crate(&warm, root, "warm", ("planar", 2, "auto"));
    if timed_build(&warm, &target).is_none() {
        page.para("**The warm-up crate did not build**; nothing measured.");
        return Section {
            page,
            summary: Vec::new(),
        };
    }
    let sizes: &[usize] = if config.name == "long" {
        &[7, 15, 25, 36, 50, 64]
    } else {
        &[7, 15, 30, 50]
    };
    let mut runs = Vec::new();
    let mut failed = Vec::new();
    // Both geometries by each unrolled algorithm and by the compact loop.
    let cases = [
        ("planar", "crba"),
        ("planar", "aba"),
        ("planar", "compact"),
        ("oblique", "crba"),
        ("oblique", "aba"),
        ("oblique", "compact"),
    ];
    for &n in sizes {
        for (geometry, algorithm) in cases {
            let name = format!("{geometry}{n}_{algorithm}");
            let dir = work.join(&name);
            let measured = write_crate(&dir, root, &name, (geometry, n, algorithm))
                .and_then(|()| timed_build(&dir, &target))
                .and_then(|build_s| run(&target, &name).map(|(ns, diff)| (build_s, ns, diff)));
            match measured {
                Some((build_s, ns, diff)) => runs.push(Run {
                    n,
                    geometry,
                    algorithm,
                    code: fd_code_bytes(&target.join("release").join(&name)),
                    build_s,
                    ns,
                    diff,
                }),
                None => failed.push(name),
            }
        }
    }
    let cell = |t: [f64; 3]| format!("{:.0} ({:.0}–{:.0})", t[0], t[1], t[2]);
    // What auto's forward dynamics comes to, once per size.
    let auto: Vec<(usize, Option<usize>)> = sizes
        .iter()
        .map(|&n| (n, ops("planar", n, "auto").map(|(f, _)| f)))
        .collect();
    let mut rows = Vec::new();
    for r in &runs {
        let (fd_ops, jac_ops) = ops(r.geometry, r.n, r.algorithm).unwrap_or_default();
        let auto = auto.iter().find(|(n, _)| *n == r.n).and_then(|(_, f)| *f);
        rows.push(vec![
            r.n.to_string(),
            r.geometry.to_string(),
            format!(
                "{}{}",
                r.algorithm,
                if r.geometry == "planar" && auto == Some(fd_ops) {
                    " (auto's FD)"
                } else {
                    ""
                }
            ),
            if r.algorithm == "compact" {
                "loop".to_string()
            } else {
                fd_ops.to_string()
            },
            r.code
                .map_or("inlined".into(), |b| format!("{:.1}", b as f64 / 1024.0)),
            if r.algorithm == "compact" {
                "duals".to_string()
            } else {
                jac_ops.to_string()
            },
            format!("{:.1}", r.build_s),
            cell(r.ns[0]),
            cell(r.ns[1]),
            cell(r.ns[2]),
            format!("{:.1}", r.ns[2][0] / r.ns[0][0]),
            format!("{:.1e}", r.diff),
        ]);
    }
    page.para(
        "Planar chains of `n` rods under gravity, declared with `#[mechanism(forward_dynamics = crba)]` (the CRBA mass \
         matrix and its sparse LᵀDL) and with `= aba` (the articulated-body algorithm, unrolled per link). Each is a \
         crate of its own, built once with `cargo build --release` (dependencies prebuilt; one build each, so the build \
         times carry the machine's noise), whose binary times the generated forward dynamics (FD) and its Jacobian, and \
         the numeric implementation's FD (CRBA and a Cholesky factorisation at run time), in ns per call: median (min–max) \
         of 7 batches. Ops: operations in the emitted code. `auto` (the default) takes, per kernel, whichever has fewer \
         operations; the row marked is the one auto's forward dynamics matches. Last column: the largest difference of \
         the generated FD from the numeric one, relative to the largest acceleration.",
    );
    page.para(
        "Oblique trees: `n` bodies in a random 3-D tree (seeded by `n`) with nothing axis-aligned to fold — oblique \
         joint axes, rpy origins, off-axis centres of mass, full inertia tensors, every seventh joint prismatic, each \
         body's parent one of the three before it — by each algorithm. `compact`: the articulated-body algorithm as one \
         loop over a table of the bodies in joint-aligned frames, its Jacobian by dual numbers through the loop (no \
         operation count: the loop's code does not grow with the tree). FD code: the machine code of the generated \
         forward dynamics and its out-of-line parts in the release binary (symbol sizes), in KiB, against this \
         machine's 32 KiB L1 instruction cache; \"inlined\" where the compiler inlined it into the timing loop.",
    );
    page.table(
        &[
            "joints",
            "geometry",
            "algorithm",
            "FD ops",
            "FD code [KiB]",
            "Jacobian ops",
            "release build [s]",
            "FD ns",
            "Jacobian ns",
            "numeric FD ns",
            "numeric / FD",
            "FD vs numeric",
        ],
        &rows,
    );
    if !failed.is_empty() {
        page.para(&format!(
            "**Not measured** (build or run failed): {}.",
            failed.join(", ")
        ));
    }
    // One series per case, its points `point(run)` (a run without one is left out).
    let series = |point: &dyn Fn(&Run) -> Option<(f64, f64)>| -> Vec<Series> {
        cases
            .iter()
            .map(|(g, a)| {
                Series::new(
                    format!("{g}, forward_dynamics = {a}"),
                    runs.iter()
                        .filter(|r| r.geometry == *g && r.algorithm == *a)
                        .filter_map(point)
                        .collect(),
                )
            })
            .collect()
    };
    line_plot(
        &config.out_dir.join("scaling_build.svg"),
        "Release build of a crate holding one chain or tree",
        "joints",
        "build time [s]",
        &series(&|r| Some((r.n as f64, r.build_s))),
        Scale::Log,
        Scale::Log,
    );
    let mut fd = series(&|r| Some((r.n as f64, r.ns[0][0])));
    fd.push(Series::new(
        "numeric FD (run-time CRBA + Cholesky)",
        runs.iter()
            .filter(|r| r.geometry == "planar" && r.algorithm == "aba")
            .map(|r| (r.n as f64, r.ns[2][0]))
            .collect(),
    ));
    line_plot(
        &config.out_dir.join("scaling_fd.svg"),
        "Forward dynamics, ns per call (median)",
        "joints",
        "ns per call",
        &fd,
        Scale::Log,
        Scale::Log,
    );
    let code = series(&|r| Some((r.code? as f64 / 1024.0, r.ns[0][0])));
    line_plot(
        &config.out_dir.join("scaling_code.svg"),
        "Forward dynamics: time per call against its machine code (L1i: 32 KiB)",
        "machine code [KiB]",
        "ns per call",
        &code,
        Scale::Log,
        Scale::Log,
    );
    page.image("release build time against joints", "scaling_build.svg");
    page.image(
        "forward dynamics time against its machine code",
        "scaling_code.svg",
    );
    page.image("forward dynamics ns against joints", "scaling_fd.svg");
    let mut summary = Vec::new();
    let largest = sizes.last().copied().unwrap_or(0);
    let at = |a: &str| {
        runs.iter()
            .find(|r| r.n == largest && r.geometry == "planar" && r.algorithm == a)
    };
    if let (Some(aba), Some(crba)) = (at("aba"), at("crba")) {
        summary.push(format!(
            "{largest}-link planar chain: FD {:.0} ns by ABA, {:.0} ns by CRBA + LᵀDL, numeric {:.0} ns; release build {:.0} s and {:.0} s",
            aba.ns[0][0], crba.ns[0][0], aba.ns[2][0], aba.build_s, crba.build_s
        ));
        headline(
            &format!(
                "Generated forward dynamics of a {largest}-link chain (ABA, unrolled) beats the numeric implementation"
            ),
            &format!(
                "{:.0} ns ({:.0}–{:.0})",
                aba.ns[0][0], aba.ns[0][1], aba.ns[0][2]
            ),
            &format!("numeric CRBA + Cholesky {:.0} ns", aba.ns[2][0]),
            &format!(
                "{:.1}× ({:.1}–{:.1})",
                aba.ns[2][0] / aba.ns[0][0],
                aba.ns[2][1] / aba.ns[0][2],
                aba.ns[2][2] / aba.ns[0][1]
            ),
            "one binary per algorithm, medians of 7 batches; section \"Scaling with the number of joints\"",
        );
    }
    for r in runs
        .iter()
        .filter(|r| r.n == largest && r.geometry == "oblique")
    {
        summary.push(format!(
            "{largest}-body oblique tree (nothing to fold): FD {:.0} ns ({}), machine code {}, release build {:.0} s",
            r.ns[0][0],
            r.algorithm,
            r.code.map_or("inlined".into(), |b| format!("{:.0} KiB", b as f64 / 1024.0)),
            r.build_s
        ));
    }
    Section { page, summary }
}
