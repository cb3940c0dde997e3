//! The report: error against run time for every scene and method, kernel costs, and
//! what expansion and compilation take — measured in one run and written to
//! `target/report/` (Markdown plus SVG plots).
//!
//! Run: `cargo run --release --example report` (a few minutes); `-- --long` for longer
//! sweeps and more repetitions; `-- --tiny` runs every code path on a tiny configuration
//! (what the tests do); `-- --only dense,s9` runs only those sections (keys in
//! `config::SECTIONS`).
#![allow(dead_code)]

#[path = "../support/mod.rs"]
mod support;

#[path = "agreement.rs"]
mod agreement;
#[path = "../support/agreement.rs"]
mod agreement_support;
#[path = "chains.rs"]
mod chains;
#[path = "../support/complex_step.rs"]
mod complex_step;
#[path = "config.rs"]
mod config;
#[path = "../support/contact_agreement.rs"]
mod contact_agreement;
#[path = "../support/contact_closed_forms.rs"]
mod contact_closed_forms;
#[path = "contacts.rs"]
mod contacts;
#[path = "dense.rs"]
mod dense;
#[path = "ensembles.rs"]
mod ensembles;
#[path = "flags.rs"]
mod flags;
#[path = "../support/four_bar_orbit.rs"]
mod four_bar_orbit;
#[path = "kernels.rs"]
mod kernels;
#[path = "lie.rs"]
mod lie;
#[path = "../support/lie.rs"]
mod lie_support;
#[path = "long_runs.rs"]
mod long_runs;
#[path = "loops.rs"]
mod loops;
#[path = "markdown.rs"]
mod markdown;
#[path = "nonsmooth.rs"]
mod nonsmooth;
#[path = "ops.rs"]
mod ops;
#[path = "../support/panda_limits.rs"]
mod panda_limits;
#[path = "peers.rs"]
mod peers;
#[path = "release_build.rs"]
mod release_build;
#[path = "../support/resting_arm.rs"]
mod resting_arm;
#[path = "s9.rs"]
mod s9;
#[path = "../support/s9.rs"]
mod s9_support;
#[path = "scalars.rs"]
mod scalars;
#[path = "scaling.rs"]
mod scaling;
#[path = "../support/spatial_agreement.rs"]
mod spatial_agreement;
#[path = "../support/supported_arm.rs"]
mod supported_arm;
#[cfg(test)]
#[path = "tests.rs"]
mod tests;
#[path = "timing.rs"]
mod timing;
#[path = "urdf.rs"]
mod urdf;
#[path = "../support/woodpecker.rs"]
mod woodpecker;
#[path = "workprecision.rs"]
mod workprecision;

pub use config::{Config, SECTIONS};

/// Runs every section and writes the report; returns the path of the Markdown page.
pub fn run(config: &Config) -> std::io::Result<std::path::PathBuf> {
    std::fs::create_dir_all(&config.out_dir)?;
    let progress = config.progress(SECTIONS.len() as u64);
    let load_before = timing::load();
    let started = std::time::Instant::now();
    let mut page = markdown::Page::new("filippov report");
    page.para(&format!(
        "Measured on this machine in one run ({} configuration; {}). Times are medians of {} runs after a warm-up; \
         where a table shows `median (min–max)` the range is over those runs. \
         Every figure below comes from this run; rerun `cargo run --release --example report` to reproduce.",
        config.name,
        timing::machine(),
        config.repeats
    ));
    // The diffsol peer is built and run once, for the non-smooth plots and the peers'
    // section; cold, its build takes minutes, so the progress line says so first.
    // Where no progress bar can draw (the output goes to a file), one line per section
    // as it ends, with its time.
    let log = |what: &str, since: std::time::Instant| {
        // `FILIPPOV_REPORT_TIMES` asks for the lines in any configuration (the tiny one
        // the tests run has no progress bar).
        let asked = std::env::var_os("FILIPPOV_REPORT_TIMES").is_some();
        if asked || (config.show_progress && !std::io::IsTerminal::is_terminal(&std::io::stderr()))
        {
            eprintln!(
                "report: {what}: {:.0} s (total {:.0} s)",
                since.elapsed().as_secs_f64(),
                started.elapsed().as_secs_f64()
            );
        }
    };
    if config.peers && (config.runs("nonsmooth") || config.runs("kernels")) {
        progress.set_message(
            "building and running the diffsol peer (peers/diffsol; minutes when cold)",
        );
        let since = std::time::Instant::now();
        let _ = peers::diffsol(config);
        log("the diffsol peer built and run", since);
    }
    // Pinocchio, SciPy, SymPy, IDA and MuJoCo: the peer script runs here, before the sections
    // that time the peers' programs beside ours or read their results (URDF robots,
    // planar chains, CPU flags, closed loops, contacts, the peers' section). It needs the scene models and the URDF
    // robots' states, written first (the URDF section's export; its page is discarded).
    let peer_script = if config.peers
        && [
            "kernels", "chains", "urdf", "scalars", "flags", "loops", "contacts",
        ]
        .iter()
        .any(|s| config.runs(s))
    {
        progress.set_message(
            "running the peers: Pinocchio, SciPy, SymPy (peers/run.sh; minutes the first time)",
        );
        let since = std::time::Instant::now();
        peers::export_models(config)?;
        let _ = urdf::urdf(config);
        markdown::clear_headlines();
        let status = peers::run_script(config);
        log("the peer script (Pinocchio, SciPy, SymPy)", since);
        Some(status)
    } else {
        None
    };
    // A section not asked for by `--only` is left out (empty page, no summary).
    macro_rules! section {
        ($key:literal, $msg:literal, $run:expr) => {{
            let s = if config.runs($key) {
                progress.set_message($msg);
                let since = std::time::Instant::now();
                let s = $run;
                log($msg, since);
                s
            } else {
                Default::default()
            };
            progress.inc(1);
            s
        }};
    }
    let wp: workprecision::Section = section!(
        "smooth",
        "work-precision, smooth scenes",
        workprecision::smooth_scenes(config, &progress)
    );
    let ns = section!(
        "nonsmooth",
        "non-smooth scenes and the stiff/extreme suite",
        nonsmooth::nonsmooth(config, &progress)
    );
    let dense = section!(
        "dense",
        "non-smooth scenes read back on an output grid",
        dense::dense_output(config)
    );
    let agree = section!(
        "agreement",
        "randomized agreement suite (1,000 random scenes)",
        agreement::agreement(config)
    );
    let arm = section!(
        "s9",
        "S9: arm with joint friction and stops",
        s9::s9(config)
    );
    let lg = section!("lie", "Lie-group scenes (S10)", lie::lie(config));
    let lp = section!(
        "loops",
        "closed loops: Andrews' squeezer, a four-bar, a slider-crank",
        loops::loops(config)
    );
    let ct = section!(
        "contacts",
        "contacts: closed forms and the agreement suite",
        contacts::contacts(config)
    );
    let k = section!("kernels", "kernels", kernels::kernels(config));
    let e = section!("expansion", "expansion time", kernels::expansion(config));
    let c = section!("compile", "compile time", kernels::compile_times(config));
    let sc = section!(
        "scaling",
        "scaling with joints (a release crate per chain and algorithm)",
        scaling::scaling(config)
    );
    let ch = section!(
        "chains",
        "planar chains against SymPy",
        chains::chains(config)
    );
    let u = section!("urdf", "robots from URDF", urdf::urdf(config));
    let oc = section!(
        "ops",
        "operation counts per kernel, against a floor",
        ops::ops(config)
    );
    let sca = section!(
        "scalars",
        "kernels on every scalar and in SIMD batches, beside Pinocchio",
        scalars::scalars(config)
    );
    let ens = section!(
        "ensembles",
        "ensembles in lockstep, smooth and non-smooth",
        ensembles::ensembles(config)
    );
    let fl = section!(
        "flags",
        "ours and the peers' compiled code, baseline and native CPU flags",
        flags::flags(config)
    );
    let p = if config.runs("kernels") {
        peers::export_models(config)?;
        peers::peers(config, peer_script.as_ref())
    } else {
        Default::default()
    };
    progress.finish_with_message("done");

    let load_after = timing::load();
    page.para(&format!(
        "Machine load (1/5/15-minute averages) at the start {} and at the end {}; the run took {:.0} s. {}",
        load_before.as_deref().unwrap_or("unknown"),
        load_after.as_deref().unwrap_or("unknown"),
        started.elapsed().as_secs_f64(),
        timing::spread_note()
    ));
    let heads = markdown::headlines();
    if !heads.is_empty() {
        page.h2("Headline");
        page.para(
            "The claims this report measures, ours beside the peer or reference, with the ratio and what the figures rest on. \
             Details and every run behind them follow.",
        );
        let body: Vec<Vec<String>> = heads
            .into_iter()
            .map(|h| vec![h.claim, h.ours, h.peer, h.ratio, h.basis])
            .collect();
        page.table(
            &["claim", "ours", "peer / reference", "ratio", "basis"],
            &body,
        );
    }

    page.h2("Summary");
    let mut summary = Vec::new();
    summary.extend(k.summary.iter().cloned());
    summary.extend(wp.summary.iter().cloned());
    summary.extend(ns.summary.iter().cloned());
    summary.extend(dense.summary.iter().cloned());
    summary.extend(agree.summary.iter().cloned());
    summary.extend(arm.summary.iter().cloned());
    summary.extend(lg.summary.iter().cloned());
    summary.extend(lp.summary.iter().cloned());
    summary.extend(ct.summary.iter().cloned());
    summary.extend(e.summary.iter().cloned());
    summary.extend(c.summary.iter().cloned());
    summary.extend(sc.summary.iter().cloned());
    summary.extend(ch.summary.iter().cloned());
    summary.extend(u.summary.iter().cloned());
    summary.extend(oc.summary.iter().cloned());
    summary.extend(sca.summary.iter().cloned());
    summary.extend(ens.summary.iter().cloned());
    summary.extend(fl.summary.iter().cloned());
    summary.extend(p.summary.iter().cloned());
    page.bullets(&summary);
    page.append(wp.page);
    page.append(ns.page);
    page.append(dense.page);
    page.append(agree.page);
    page.append(arm.page);
    page.append(lg.page);
    page.append(lp.page);
    page.append(ct.page);
    page.append(k.page);
    page.append(e.page);
    page.append(c.page);
    page.append(sc.page);
    page.append(ch.page);
    page.append(u.page);
    page.append(oc.page);
    page.append(sca.page);
    page.append(ens.page);
    page.append(fl.page);
    page.append(p.page);
    let path = config.out_dir.join("report.md");
    std::fs::write(&path, page.finish())?;
    Ok(path)
}

fn main() {
    let config = Config::from_args(std::env::args().skip(1));
    match run(&config) {
        Ok(path) => println!("wrote {}", path.display()),
        Err(e) => {
            eprintln!("report failed: {e}");
            std::process::exit(1);
        }
    }
}
