//! Planar n-link rod chains (n = 2…7), the same chains `peers/sympy_chain.py` derives
//! with SymPy's Kane's method: our expansion time, operation counts and forward-dynamics
//! ns per call, side by side with SymPy's derivation + code generation time and operation
//! count (from `target/report/peers/peers.tsv` when `bash peers/run.sh` has been run) and
//! its compiled M + forcing + Cholesky solve (the harness `peers/run.sh` builds, timed by
//! this report in interleaved rounds beside ours).
//!
//! The declarations below are both compiled (for the kernel timings) and read back from
//! this file and expanded (for the expansion timings), so the two measure the same thing.

use std::hint::black_box as bb;
use std::path::Path;

use filippov::Mechanism;
use filippov::nalgebra::SVector;

use super::config::Config;
use super::markdown::Page;
use super::timing::{Timing, in_rounds, ns_timed, program_timing, timed};
use super::workprecision::Section;

/// Planar 2-link rod chain (the SymPy peer's chain: m_i = 1 − 0.1 i, l_i = 0.5 + 0.05 i).
#[derive(Mechanism)]
#[mechanism(gravity = [0.0, -9.81, 0.0])]
#[body(b0, mass = 1.0, com = [0.250, 0.0, 0.0], inertia = rod(1.0, 0.50))]
#[joint(j0: revolute(z), parent = world, child = b0)]
#[body(b1, mass = 0.9, com = [0.275, 0.0, 0.0], inertia = rod(0.9, 0.55))]
#[joint(j1: revolute(z), parent = b0, child = b1, origin = [0.50, 0.0, 0.0])]
pub struct Chain2;

/// Planar 3-link rod chain (the SymPy peer's chain: m_i = 1 − 0.1 i, l_i = 0.5 + 0.05 i).
#[derive(Mechanism)]
#[mechanism(gravity = [0.0, -9.81, 0.0])]
#[body(b0, mass = 1.0, com = [0.250, 0.0, 0.0], inertia = rod(1.0, 0.50))]
#[joint(j0: revolute(z), parent = world, child = b0)]
#[body(b1, mass = 0.9, com = [0.275, 0.0, 0.0], inertia = rod(0.9, 0.55))]
#[joint(j1: revolute(z), parent = b0, child = b1, origin = [0.50, 0.0, 0.0])]
#[body(b2, mass = 0.8, com = [0.300, 0.0, 0.0], inertia = rod(0.8, 0.60))]
#[joint(j2: revolute(z), parent = b1, child = b2, origin = [0.55, 0.0, 0.0])]
pub struct Chain3;

/// Planar 4-link rod chain (the SymPy peer's chain: m_i = 1 − 0.1 i, l_i = 0.5 + 0.05 i).
#[derive(Mechanism)]
#[mechanism(gravity = [0.0, -9.81, 0.0])]
#[body(b0, mass = 1.0, com = [0.250, 0.0, 0.0], inertia = rod(1.0, 0.50))]
#[joint(j0: revolute(z), parent = world, child = b0)]
#[body(b1, mass = 0.9, com = [0.275, 0.0, 0.0], inertia = rod(0.9, 0.55))]
#[joint(j1: revolute(z), parent = b0, child = b1, origin = [0.50, 0.0, 0.0])]
#[body(b2, mass = 0.8, com = [0.300, 0.0, 0.0], inertia = rod(0.8, 0.60))]
#[joint(j2: revolute(z), parent = b1, child = b2, origin = [0.55, 0.0, 0.0])]
#[body(b3, mass = 0.7, com = [0.325, 0.0, 0.0], inertia = rod(0.7, 0.65))]
#[joint(j3: revolute(z), parent = b2, child = b3, origin = [0.60, 0.0, 0.0])]
pub struct Chain4;

/// Planar 5-link rod chain (the SymPy peer's chain: m_i = 1 − 0.1 i, l_i = 0.5 + 0.05 i).
#[derive(Mechanism)]
#[mechanism(gravity = [0.0, -9.81, 0.0])]
#[body(b0, mass = 1.0, com = [0.250, 0.0, 0.0], inertia = rod(1.0, 0.50))]
#[joint(j0: revolute(z), parent = world, child = b0)]
#[body(b1, mass = 0.9, com = [0.275, 0.0, 0.0], inertia = rod(0.9, 0.55))]
#[joint(j1: revolute(z), parent = b0, child = b1, origin = [0.50, 0.0, 0.0])]
#[body(b2, mass = 0.8, com = [0.300, 0.0, 0.0], inertia = rod(0.8, 0.60))]
#[joint(j2: revolute(z), parent = b1, child = b2, origin = [0.55, 0.0, 0.0])]
#[body(b3, mass = 0.7, com = [0.325, 0.0, 0.0], inertia = rod(0.7, 0.65))]
#[joint(j3: revolute(z), parent = b2, child = b3, origin = [0.60, 0.0, 0.0])]
#[body(b4, mass = 0.6, com = [0.350, 0.0, 0.0], inertia = rod(0.6, 0.70))]
#[joint(j4: revolute(z), parent = b3, child = b4, origin = [0.65, 0.0, 0.0])]
pub struct Chain5;

/// Planar 6-link rod chain (the SymPy peer's chain: m_i = 1 − 0.1 i, l_i = 0.5 + 0.05 i).
#[derive(Mechanism)]
#[mechanism(gravity = [0.0, -9.81, 0.0])]
#[body(b0, mass = 1.0, com = [0.250, 0.0, 0.0], inertia = rod(1.0, 0.50))]
#[joint(j0: revolute(z), parent = world, child = b0)]
#[body(b1, mass = 0.9, com = [0.275, 0.0, 0.0], inertia = rod(0.9, 0.55))]
#[joint(j1: revolute(z), parent = b0, child = b1, origin = [0.50, 0.0, 0.0])]
#[body(b2, mass = 0.8, com = [0.300, 0.0, 0.0], inertia = rod(0.8, 0.60))]
#[joint(j2: revolute(z), parent = b1, child = b2, origin = [0.55, 0.0, 0.0])]
#[body(b3, mass = 0.7, com = [0.325, 0.0, 0.0], inertia = rod(0.7, 0.65))]
#[joint(j3: revolute(z), parent = b2, child = b3, origin = [0.60, 0.0, 0.0])]
#[body(b4, mass = 0.6, com = [0.350, 0.0, 0.0], inertia = rod(0.6, 0.70))]
#[joint(j4: revolute(z), parent = b3, child = b4, origin = [0.65, 0.0, 0.0])]
#[body(b5, mass = 0.5, com = [0.375, 0.0, 0.0], inertia = rod(0.5, 0.75))]
#[joint(j5: revolute(z), parent = b4, child = b5, origin = [0.70, 0.0, 0.0])]
pub struct Chain6;

/// Planar 7-link rod chain (the SymPy peer's chain: m_i = 1 − 0.1 i, l_i = 0.5 + 0.05 i).
#[derive(Mechanism)]
#[mechanism(gravity = [0.0, -9.81, 0.0])]
#[body(b0, mass = 1.0, com = [0.250, 0.0, 0.0], inertia = rod(1.0, 0.50))]
#[joint(j0: revolute(z), parent = world, child = b0)]
#[body(b1, mass = 0.9, com = [0.275, 0.0, 0.0], inertia = rod(0.9, 0.55))]
#[joint(j1: revolute(z), parent = b0, child = b1, origin = [0.50, 0.0, 0.0])]
#[body(b2, mass = 0.8, com = [0.300, 0.0, 0.0], inertia = rod(0.8, 0.60))]
#[joint(j2: revolute(z), parent = b1, child = b2, origin = [0.55, 0.0, 0.0])]
#[body(b3, mass = 0.7, com = [0.325, 0.0, 0.0], inertia = rod(0.7, 0.65))]
#[joint(j3: revolute(z), parent = b2, child = b3, origin = [0.60, 0.0, 0.0])]
#[body(b4, mass = 0.6, com = [0.350, 0.0, 0.0], inertia = rod(0.6, 0.70))]
#[joint(j4: revolute(z), parent = b3, child = b4, origin = [0.65, 0.0, 0.0])]
#[body(b5, mass = 0.5, com = [0.375, 0.0, 0.0], inertia = rod(0.5, 0.75))]
#[joint(j5: revolute(z), parent = b4, child = b5, origin = [0.70, 0.0, 0.0])]
#[body(b6, mass = 0.4, com = [0.400, 0.0, 0.0], inertia = rod(0.4, 0.80))]
#[joint(j6: revolute(z), parent = b5, child = b6, origin = [0.75, 0.0, 0.0])]
pub struct Chain7;

/// Forward dynamics ns per call of a chain at the SymPy harness's state
/// (`q_i = 0.3 + 0.17 i`, `u_i = 0.5 − 0.23 i`, zero torque).
fn fd_ns<S: Mechanism<N>, const N: usize>(s: &S, config: &Config) -> Timing {
    let q = SVector::<f64, N>::from_fn(|i, _| 0.3 + 0.17 * i as f64);
    let v = SVector::<f64, N>::from_fn(|i, _| 0.5 - 0.23 * i as f64);
    let tau = SVector::<f64, N>::zeros();
    ns_timed(config.repeats.max(3), config.kernel_calls, || {
        s.forward_dynamics(bb(&q), bb(&v), bb(&tau))
    })
}

/// `(derive + codegen seconds, ops)` of SymPy's chain `n`, if `peers/run.sh` measured it.
fn sympy(tsv: &str, n: usize) -> Option<(f64, f64)> {
    let get = |q: &str| {
        tsv.lines().find_map(|l| {
            let f: Vec<&str> = l.split('\t').collect();
            (f.len() >= 4 && f[0] == "sympy" && f[1] == format!("chain{n}") && f[2] == q)
                .then(|| f[3].parse::<f64>().ok())
                .flatten()
        })
    };
    Some((get("derive_s")? + get("codegen_s")?, get("ops")?))
}

pub fn chains(config: &Config) -> Section {
    let mut page = Page::empty();
    let mut summary = Vec::new();
    let src = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/report/chains.rs"),
    )
    .expect("chains source");
    let items: Vec<syn::ItemStruct> = syn::parse_file(&src)
        .expect("parses")
        .items
        .into_iter()
        .filter_map(|i| match i {
            syn::Item::Struct(s) => Some(s),
            _ => None,
        })
        .collect();
    // Ours in this process, SymPy's compiled harness (built by peers/run.sh for the
    // baseline target, as this report is) as a separate program, in interleaved rounds.
    let build = config.out_dir.join("peers").join("build");
    let beside = |k: usize, ours: &mut dyn FnMut() -> Option<Timing>| {
        let bin = build.join(format!("chain{}", k + 2));
        let mut theirs = || {
            bin.exists()
                .then(|| program_timing(&bin, &[], "solve_ns"))
                .flatten()
        };
        let t = in_rounds(3, &mut [ours, &mut theirs]);
        (t[0].unwrap_or_default(), t[1])
    };
    let timings = [
        beside(0, &mut || Some(fd_ns(&Chain2, config))),
        beside(1, &mut || Some(fd_ns(&Chain3, config))),
        beside(2, &mut || Some(fd_ns(&Chain4, config))),
        beside(3, &mut || Some(fd_ns(&Chain5, config))),
        beside(4, &mut || Some(fd_ns(&Chain6, config))),
        beside(5, &mut || Some(fd_ns(&Chain7, config))),
    ];
    let ns: Vec<Timing> = timings.iter().map(|t| t.0).collect();
    let tsv = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("target/report/peers/peers.tsv"),
    )
    .unwrap_or_default();
    let mut rows = Vec::new();
    let mut have_sympy = false;
    for (k, item) in items.iter().enumerate() {
        let n = k + 2;
        let tokens = quote::ToTokens::to_token_stream(item);
        let (t, e) = timed(config.repeats.max(3), || {
            filippov_codegen::expand_with_stats(tokens.clone())
        });
        let t = t.scaled(1e3);
        let ops = e.ok().and_then(|e| {
            e.functions
                .iter()
                .find(|f| f.name == "forward_dynamics")
                .map(|f| f.ops.add + f.ops.mul + f.ops.div)
        });
        // SymPy's derivation and operation count from peers/run.sh; its time from this run.
        let peer = sympy(&tsv, n)
            .zip(timings[k].1)
            .map(|((d, o), t)| (d, o, t));
        have_sympy |= peer.is_some();
        rows.push(vec![
            n.to_string(),
            t.show(2),
            ops.map_or("—".into(), |o| o.to_string()),
            ns[k].show(1),
            peer.map_or("not run".into(), |p| format!("{:.0}", p.0 * 1e3)),
            peer.map_or("—".into(), |p| format!("{:.0}", p.1)),
            peer.map_or("—".into(), |p| p.2.show(1)),
        ]);
        if n == 7
            && let Some(p) = peer
        {
            super::markdown::headline(
                "Expansion of a 7-link planar chain is faster than SymPy's derivation and code generation",
                format!("{} ms", t.show(1)),
                format!("{:.0} ms (SymPy Kane + cse)", p.0 * 1e3),
                format!("{:.0}×", p.0 * 1e3 / t.median),
                "ours median (min–max); SymPy's derivation one run (peers/run.sh)",
            );
            super::markdown::headline(
                "Generated forward dynamics of the 7-link chain against SymPy's compiled code",
                format!("{} ns", ns[k].show(1)),
                format!("{} ns (M + forcing + Cholesky, gcc -O3)", p.2.show(1)),
                p.2.ratio_to(&ns[k], 2),
                "both with literal parameters and built for the baseline x86-64 target (rustc's default, gcc -O3 without -march); median of 3 interleaved rounds in this run (min–max over their batches)",
            );
            summary.push(format!(
                "7-link chain vs SymPy (Kane + cse + gcc -O3): expansion {:.1} ms vs derivation + codegen {:.0} ms; \
                 forward dynamics {:.1} ns vs {:.1} ns (M + forcing + Cholesky); {} vs {:.0} operations",
                t.median,
                p.0 * 1e3,
                ns[k].median,
                p.2.median,
                ops.map_or("—".into(), |o| o.to_string()),
                p.1
            ));
        }
    }
    page.h2("Planar chains: filippov against SymPy mechanics");
    page.para(&format!(
        "The chains SymPy's `KanesMethod` derives in `peers/sympy_chain.py` (rods, m_i = 1 − 0.1 i, l_i = 0.5 + 0.05 i, \
         relative angles), declared with the derive in `examples/report/chains.rs`. Ours: expansion, operation \
         count of the generated forward dynamics (add + mul + div; sin/cos pairs not counted), ns per call; times are \
         median (min–max) of the repetitions. \
         SymPy: derivation + `cse` + `ccode` wall time, operation count (`count_ops` after `cse` of M and forcing), and \
         ns per call of the compiled M + forcing + Cholesky solve. Evened out: both sides take the parameters as literal \
         numbers (SymPy's are substituted before `cse`) and both are built for the baseline x86-64 target (rustc's default \
         build, `gcc -O3` without `-march`); the two ns columns are timed in this run, in three interleaved rounds (median of \
         the rounds' medians, min–max over their batches). {}",
        if have_sympy {
            "SymPy's derivation time and operation count are from the peer script this report ran (`peers/run.sh`, `target/report/peers/peers.tsv`); its compiled code is timed in this run."
        } else {
            "SymPy did not run (`--no-peers`, or the peer script failed: see the peers' section), so only our columns are filled."
        }
    ));
    page.table(
        &[
            "n",
            "our expansion [ms]",
            "our FD ops",
            "our FD [ns]",
            "SymPy derive + codegen [ms]",
            "SymPy ops",
            "SymPy M+F+solve [ns]",
        ],
        &rows,
    );
    Section { page, summary }
}
