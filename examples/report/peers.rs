//! Peers side by side: the report writes the multibody scenes as JSON models
//! (`target/report/models/*.json`) for the peer script (`peers/run.sh`: Pinocchio,
//! SciPy and SymPy in a local virtual environment), and includes the script's results
//! (`target/report/peers/peers.md`, `peers.tsv`) when it has been run. Nothing is
//! invented when it has not: the section says so.
//!
//! diffsol is measured by its own package, `peers/diffsol` (outside the workspace, so its
//! long compile stays out of `cargo test`): unless `--no-peers` is given (and never on
//! the tiny configuration) the report builds and runs it, in its own target directory
//! `target/peers-diffsol`, writing `target/report/peers/diffsol.tsv`, and shows the
//! table, a summary and extra series on the S5/S6 plots.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::{Arc, Mutex};
use std::time::Instant;

use filippov::Mechanism;
use filippov_scenes::{BranchedTree, DoublePendulum, Panda, PlanarArm3};

use super::config::Config;
use super::markdown::{Page, sci};
use super::support::{Scale, Series, line_plot};
use super::timing::Timing;
use super::workprecision::Section;

/// Writes the scene models for the peer script.
pub fn export_models(config: &Config) -> std::io::Result<()> {
    let dir = config.out_dir.join("models");
    std::fs::create_dir_all(&dir)?;
    for (name, json) in [
        (
            "double_pendulum",
            DoublePendulum::default().model().to_json(),
        ),
        ("planar_arm3", PlanarArm3::default().model().to_json()),
        ("branched_tree", BranchedTree::default().model().to_json()),
        ("panda", Panda::default().model().to_json()),
    ] {
        std::fs::write(dir.join(format!("{name}.json")), json)?;
    }
    Ok(())
}

/// Runs `peers/run.sh` (Pinocchio, SciPy, SymPy; its virtual environment cached under
/// `target/peers/venv`), its output in `target/report/peers/run.log`. `Err` says why it
/// could not run, in the script's own words (its last `FAILED` line).
pub fn run_script(config: &Config) -> Result<(), String> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = config.out_dir.join("peers");
    std::fs::create_dir_all(&dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let log_path = dir.join("run.log");
    let log = std::fs::File::create(&log_path)
        .map_err(|e| format!("cannot write {}: {e}", log_path.display()))?;
    let err = log
        .try_clone()
        .map_err(|e| format!("cannot write {}: {e}", log_path.display()))?;
    let status = Command::new("bash")
        .arg(root.join("peers/run.sh"))
        .current_dir(root)
        .stdin(Stdio::null())
        .stdout(log)
        .stderr(err)
        .status()
        .map_err(|e| format!("cannot start bash: {e}"))?;
    let text = std::fs::read_to_string(&log_path).unwrap_or_default();
    if status.success() {
        return Ok(());
    }
    let why = text
        .lines()
        .rev()
        .find(|l| l.contains("FAILED"))
        .or_else(|| text.lines().rev().find(|l| !l.trim().is_empty()))
        .unwrap_or("no output")
        .trim()
        .to_string();
    Err(format!("{why} (full output: {})", log_path.display()))
}

/// The peers section: the peer script's own tables, and diffsol. `script` is how the
/// peer script went in this run (`None`: not run, `--no-peers` or `--only`).
pub fn peers(config: &Config, script: Option<&Result<(), String>>) -> Section {
    let mut page = Page::empty();
    let mut summary = Vec::new();
    page.h2("Peers");
    let dir = config.out_dir.join("peers");
    if let Some(Err(why)) = script {
        page.para(&format!(
            "**Pinocchio, SciPy and SymPy could not run in this run**: {why}. Figures below, if any, are from an \
             earlier run of the peer script."
        ));
        summary.push(format!(
            "Peers: Pinocchio, SciPy and SymPy could not run: {why}"
        ));
    }
    match std::fs::read_to_string(dir.join("peers.md")) {
        Ok(md) => {
            page.para(
                "From `bash peers/run.sh` (its own run; see its header for when and with which versions). Its times are \
                 not compared with this run's: the ratios against Pinocchio and SymPy are in the sections on URDF robots, \
                 planar chains and CPU flags, where this report times the peers' compiled programs beside ours.",
            );
            page.append_raw(&md);
        }
        _ => {
            page.para(
                "The peer script did not run (`--no-peers`, or none of the sections that use it), so no peer figures are \
                 shown; the report runs it (`peers/run.sh`, which installs Pinocchio, SciPy and SymPy into \
                 `target/peers/venv`) unless told not to.",
            );
            summary.push("Peers: not run in this report (`--no-peers`)".into());
        }
    }
    diffsol_section(config, &mut page, &mut summary);
    Section { page, summary }
}

/// The smooth scenes of the peer program (the last one stiff).
const SMOOTH_SCENES: [&str; 3] = ["DoublePendulum", "Panda", "StiffArm3"];
/// Grid errors at which the fastest run of each library is compared: a loose one and
/// the tight ones.
const THRESHOLDS: [f64; 3] = [1e-2, 1e-6, 1e-8];

/// One row of `diffsol.tsv` (see peers/diffsol/README.md).
struct Row {
    scene: String,
    solver: String,
    setting: String,
    /// Wall time in milliseconds, median (min–max) of the peer's repetitions.
    time: Timing,
    steps: String,
    final_error: f64,
    max_grid_error: f64,
    notes: String,
}

/// What the diffsol peer gave: where its figures come from, and the figures.
pub struct Diffsol {
    /// Measured by this run of the report (rather than read from an earlier run).
    this_run: bool,
    /// A sentence on where the figures come from (or why there are none).
    provenance: String,
    /// Why the build or run failed, with the log's tail.
    failure: Option<String>,
    header: Vec<String>,
    rows: Vec<Row>,
}

fn parse(text: &str) -> (Vec<String>, Vec<Row>) {
    let mut header = Vec::new();
    let mut rows = Vec::new();
    for line in text.lines() {
        if let Some(h) = line.strip_prefix('#') {
            header.push(h.trim().to_string());
            continue;
        }
        // scene, solver, setting, time_ms, time_min_ms, time_max_ms, steps, final_error,
        // max_grid_error, notes (peers/diffsol/README.md).
        let f: Vec<&str> = line.split('\t').collect();
        if f.len() != 10 || f[0] == "scene" {
            continue;
        }
        let num = |s: &str| s.trim().parse::<f64>().unwrap_or(f64::NAN);
        rows.push(Row {
            scene: f[0].into(),
            solver: f[1].into(),
            setting: f[2].into(),
            time: Timing {
                median: num(f[3]),
                min: num(f[4]),
                max: num(f[5]),
            },
            steps: f[6].into(),
            final_error: num(f[7]),
            max_grid_error: num(f[8]),
            notes: f[9].into(),
        });
    }
    (header, rows)
}

/// The last lines of a log, for the report.
fn tail(path: &Path, lines: usize) -> String {
    let text = std::fs::read_to_string(path).unwrap_or_default();
    let all: Vec<&str> = text.lines().collect();
    all[all.len().saturating_sub(lines)..].join("\n")
}

/// Builds and runs `peers/diffsol` (or reads an earlier `diffsol.tsv` under
/// `--no-peers`); never panics.
fn run_diffsol(config: &Config) -> Diffsol {
    let dir = config.out_dir.join("peers");
    let tsv = dir.join("diffsol.tsv");
    let mut out = Diffsol {
        this_run: false,
        provenance: String::new(),
        failure: None,
        header: Vec::new(),
        rows: Vec::new(),
    };
    if config.name == "tiny" {
        out.provenance = "diffsol is not run on the tiny configuration (the tests).".into();
        return out;
    }
    if !config.peers {
        match (
            std::fs::read_to_string(&tsv),
            std::fs::metadata(&tsv).and_then(|m| m.modified()),
        ) {
            (Ok(text), Ok(modified)) => {
                let age = match modified.elapsed().map(|d| d.as_secs_f64() / 60.0) {
                    Ok(m) if m < 90.0 => format!("{m:.0} min"),
                    Ok(m) => format!("{:.1} h", m / 60.0),
                    Err(_) => "an unknown time".into(),
                };
                out.provenance = format!(
                    "Not measured in this run (`--no-peers`): the figures below are read from `{}`, written by an earlier run of the peer package {age} before this report.",
                    tsv.display()
                );
                (out.header, out.rows) = parse(&text);
            }
            _ => {
                out.provenance =
                    "diffsol was not run (`--no-peers`) and no earlier `diffsol.tsv` exists."
                        .into();
            }
        }
        return out;
    }
    let repo = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let manifest = repo.join("peers").join("diffsol").join("Cargo.toml");
    let target = repo.join("target").join("peers-diffsol");
    let log = dir.join("diffsol.log");
    let _ = std::fs::remove_file(&tsv);
    let prepared = std::fs::create_dir_all(&dir).and_then(|_| std::fs::File::create(&log));
    let Ok(log_file) = prepared else {
        out.failure = Some(format!("cannot create {}", log.display()));
        return out;
    };
    let cargo = |args: &[&std::ffi::OsStr]| -> Result<f64, String> {
        let (Ok(o), Ok(e)) = (log_file.try_clone(), log_file.try_clone()) else {
            return Err("cannot share the log file".into());
        };
        let start = Instant::now();
        let status = Command::new(env!("CARGO"))
            .args(args)
            .env("CARGO_TARGET_DIR", &target)
            .stdin(Stdio::null())
            .stdout(o)
            .stderr(e)
            .status();
        let secs = start.elapsed().as_secs_f64();
        match status {
            Ok(s) if s.success() => Ok(secs),
            Ok(s) => Err(format!("exited with {s}")),
            Err(e) => Err(format!("could not start cargo: {e}")),
        }
    };
    let m = manifest.as_os_str();
    let build = cargo(&[
        "build".as_ref(),
        "--release".as_ref(),
        "--manifest-path".as_ref(),
        m,
    ]);
    let run = build.as_ref().map_err(|e| e.clone()).and_then(|_| {
        cargo(&[
            "run".as_ref(),
            "--release".as_ref(),
            "--manifest-path".as_ref(),
            m,
            "--".as_ref(),
            tsv.as_os_str(),
        ])
    });
    match (build, run) {
        (Ok(b), Ok(r)) => match std::fs::read_to_string(&tsv) {
            Ok(text) => {
                out.this_run = true;
                out.provenance = format!(
                    "Measured in this run by the peer package `peers/diffsol`: `cargo build` took {b:.0} s here (a cold build compiles diffsol and takes minutes), the run {r:.1} s; log `{}`.",
                    log.display()
                );
                (out.header, out.rows) = parse(&text);
            }
            Err(e) => out.failure = Some(format!("the run wrote no {}: {e}", tsv.display())),
        },
        (Err(e), _) => {
            out.failure = Some(format!(
                "building peers/diffsol failed ({e}); last lines of {}:\n{}",
                log.display(),
                tail(&log, 20)
            ))
        }
        (Ok(_), Err(e)) => {
            out.failure = Some(format!(
                "running peers/diffsol failed ({e}); last lines of {}:\n{}",
                log.display(),
                tail(&log, 20)
            ))
        }
    }
    out
}

/// The diffsol results for this configuration, run at most once per report (the
/// non-smooth section asks first, for its plots; the peers section after).
pub fn diffsol(config: &Config) -> Arc<Diffsol> {
    static CACHE: Mutex<Option<(PathBuf, bool, Arc<Diffsol>)>> = Mutex::new(None);
    let mut cache = CACHE.lock().unwrap_or_else(|p| p.into_inner());
    if let Some((dir, peers, d)) = cache.as_ref()
        && *dir == config.out_dir
        && *peers == config.peers
    {
        return d.clone();
    }
    let d = Arc::new(run_diffsol(config));
    *cache = Some((config.out_dir.clone(), config.peers, d.clone()));
    d
}

/// The regularised runs of `scene` ("S5" or "S6") as work-precision series (run time in
/// ms, max error in x over the grid): each diffsol solver's tolerance sweep at the ε that
/// reaches the smallest error (the table has every ε); with `ours`, filippov's
/// event-driven rows of the same program too (same metric, for plots whose own series
/// use another one).
pub fn diffsol_series(config: &Config, scene: &str, ours: bool) -> Vec<Series> {
    let d = diffsol(config);
    let when = if d.this_run { "" } else { ", earlier run" };
    fn ok(r: &Row) -> bool {
        r.time.median.is_finite() && r.max_grid_error.is_finite()
    }
    /// `eps=1e-3 rtol=1e-8` → (`1e-3`, `1e-8`).
    fn split(setting: &str) -> (&str, &str) {
        let mut eps = "";
        let mut rtol = setting;
        for part in setting.split_whitespace() {
            if let Some(e) = part.strip_prefix("eps=") {
                eps = e;
            } else if let Some(r) = part.strip_prefix("rtol=") {
                rtol = r;
            }
        }
        (eps, rtol)
    }
    let mut labels: Vec<&str> = Vec::new();
    for r in &d.rows {
        let wanted = r.solver.contains("tanh") || (ours && r.solver.starts_with("filippov"));
        if r.scene == scene && wanted && !labels.contains(&r.solver.as_str()) {
            labels.push(&r.solver);
        }
    }
    let mut out = Vec::new();
    for solver in labels {
        let runs: Vec<&Row> = d
            .rows
            .iter()
            .filter(|r| r.scene == scene && r.solver == solver)
            .collect();
        // The ε whose sweep reaches the smallest error (none for our rows).
        let eps = runs
            .iter()
            .filter(|r| ok(r))
            .min_by(|a, b| a.max_grid_error.total_cmp(&b.max_grid_error))
            .map(|r| split(&r.setting).0)
            .unwrap_or("");
        let curve: Vec<&&Row> = runs.iter().filter(|r| split(&r.setting).0 == eps).collect();
        let done: Vec<&&&Row> = curve.iter().filter(|r| ok(r)).collect();
        let pts = done
            .iter()
            .map(|r| (r.time.median, r.max_grid_error))
            .collect();
        let span = match (done.first(), done.last()) {
            (Some(a), Some(b)) if done.len() > 1 => {
                format!("rtol {}…{}", split(&a.setting).1, split(&b.setting).1)
            }
            (Some(a), _) => format!("rtol {}", split(&a.setting).1),
            _ => "none completed".into(),
        };
        let failed: Vec<&str> = curve
            .iter()
            .filter(|r| r.notes.starts_with("failed"))
            .map(|r| split(&r.setting).1)
            .collect();
        let failed = if failed.is_empty() {
            String::new()
        } else {
            format!("; failed at rtol {}", failed.join(", "))
        };
        let label = match solver.strip_suffix(" tanh(v/eps)") {
            Some(s) => format!(
                "{s}, f_crit·tanh(v/ε), ε = {eps} (its best), {span}{failed} (max |x − x_ref|{when})"
            ),
            None => format!("{solver}, {span} (max |x − x_ref|, peer program{when})"),
        };
        out.push(Series::new(label, pts));
    }
    out
}

/// One work-precision series per solver on a smooth scene of the peer program (run time
/// in ms, max grid error), its points in the order of the tolerance sweep.
fn smooth_series(d: &Diffsol, scene: &str) -> Vec<Series> {
    let mut labels: Vec<&str> = Vec::new();
    for r in d.rows.iter().filter(|r| r.scene == scene) {
        if !labels.contains(&r.solver.as_str()) {
            labels.push(&r.solver);
        }
    }
    labels
        .iter()
        .map(|solver| {
            let pts = d
                .rows
                .iter()
                .filter(|r| r.scene == scene && r.solver == *solver)
                .filter(|r| r.time.median.is_finite() && r.max_grid_error.is_finite())
                .map(|r| (r.time.median, r.max_grid_error))
                .collect();
            Series::new(solver.to_string(), pts)
        })
        .collect()
}

/// `filippov DOPRI5 at rtol=1e-6: 0.186 (0.18–0.19) ms (error 3.1e-7)`, shortened.
fn run_cell(r: &Row) -> String {
    format!(
        "{} at {}: {} ms (error {})",
        r.solver
            .trim_start_matches("filippov ")
            .trim_start_matches("diffsol "),
        r.setting,
        r.time.show(3),
        sci(r.max_grid_error)
    )
}

/// A headline row: per threshold, filippov's fastest run `f` against diffsol's `g`.
fn diffsol_headline(claim: String, pairs: &[(f64, &Row, &Row)], basis: String) {
    if pairs.is_empty() {
        return;
    }
    let each = |f: &dyn Fn(&Row, &Row) -> String| {
        pairs
            .iter()
            .map(|(t, a, b)| format!("≤ {t:.0e}: {}", f(a, b)))
            .collect::<Vec<_>>()
            .join("; ")
    };
    super::markdown::headline(
        claim,
        each(&|f, _| run_cell(f)),
        each(&|_, g| format!("diffsol {}", run_cell(g))),
        each(&|f, g| {
            format!(
                "{} ({})",
                g.time.ratio_to(&f.time, 2),
                if f.time.median <= g.time.median {
                    "filippov faster"
                } else {
                    "diffsol faster"
                }
            )
        }),
        basis,
    );
}

fn diffsol_section(config: &Config, page: &mut Page, summary: &mut Vec<String>) {
    page.h3("diffsol");
    let d = diffsol(config);
    if let Some(why) = &d.failure {
        page.para(
            "**The diffsol peer could not be measured in this run**; no diffsol figures are shown.",
        );
        page.code(why);
        summary.push(
            "diffsol: the peer package failed to build or run (see the Peers section)".into(),
        );
        return;
    }
    if d.rows.is_empty() {
        page.para(&d.provenance);
        summary.push(format!(
            "diffsol: no figures ({})",
            if config.peers {
                "none written"
            } else {
                "not run"
            }
        ));
        return;
    }
    page.para(&d.provenance);
    page.para(
        "diffsol (crates.io) solves the same problems through its closure API (`OdeBuilder::rhs_implicit` with the generated \
         forward dynamics and, as the Jacobian-vector product, the generated symbolic Jacobian; dense nalgebra matrices and LU). \
         The peer program also times filippov's own methods on exactly the same problems with the same harness, so the rows \
         compare like with like. The smooth scenes are the double pendulum, the Panda and a stiff three-link arm (stiff, \
         heavily damped joint springs; its stiffness ratio is in the list below), each swept from rtol 1e-4 to 1e-9, and every \
         row of a scene, diffsol's and ours, is measured against one reference. On S5 and S6 diffsol integrates the smooth ODE a user would write, \
         m x'' = −k x + F(t) − f_crit·tanh(v/ε), for a sweep of ε, each ε at the same tolerances as filippov's event-driven runs \
         (rtol 1e-4 … 1e-10), all of a scene's runs timed in interleaved rounds; its error is measured against the exact non-smooth solution \
         (S6: the closed form; S5: filippov's event-driven run at rtol 1e-12), next to filippov's event-driven integrator on the \
         Coulomb law itself. The S5 and S6 plots above carry these runs as extra series.",
    );
    page.bullets(&d.header);
    for scene in SMOOTH_SCENES {
        let series = smooth_series(&d, scene);
        if series.iter().all(|s| s.points.is_empty()) {
            continue;
        }
        let file = format!("diffsol_{}.svg", scene.to_lowercase());
        line_plot(
            &config.out_dir.join(&file),
            &format!("{scene}: work-precision, filippov and diffsol (same problem and harness)"),
            "run time [ms], median of 5",
            "max error over the 201-point grid",
            &series,
            Scale::Log,
            Scale::Log,
        );
        page.image(scene, &file);
    }
    let body: Vec<Vec<String>> = d
        .rows
        .iter()
        .map(|r| {
            if r.notes.starts_with("failed") {
                vec![
                    r.scene.clone(),
                    r.solver.clone(),
                    r.setting.clone(),
                    format!("**failed**: {}", r.notes.trim_start_matches("failed: ")),
                    String::new(),
                    String::new(),
                    String::new(),
                    String::new(),
                ]
            } else {
                vec![
                    r.scene.clone(),
                    r.solver.clone(),
                    r.setting.clone(),
                    r.time.show(3),
                    r.steps.clone(),
                    sci(r.final_error),
                    sci(r.max_grid_error),
                    r.notes.clone(),
                ]
            }
        })
        .collect();
    page.table(
        &[
            "scene",
            "solver",
            "setting",
            "time [ms]",
            "steps",
            "final error",
            "max error (grid)",
            "notes",
        ],
        &body,
    );
    let when = if d.this_run {
        "measured in this run"
    } else {
        "from an earlier run"
    };
    fn ok(r: &Row) -> bool {
        r.time.median.is_finite() && r.max_grid_error.is_finite()
    }
    for scene in SMOOTH_SCENES {
        let rows: Vec<&Row> = d
            .rows
            .iter()
            .filter(|r| r.scene == scene)
            .filter(|r| ok(r))
            .collect();
        if rows.is_empty() {
            continue;
        }
        // Every solver at the tightest tolerance of the sweep, fastest first.
        let tight = rows
            .iter()
            .filter_map(|r| {
                r.setting
                    .strip_prefix("rtol=")
                    .and_then(|t| t.parse::<f64>().ok())
            })
            .fold(f64::INFINITY, f64::min);
        let mut at: Vec<&&Row> = rows
            .iter()
            .filter(|r| {
                r.setting
                    .strip_prefix("rtol=")
                    .and_then(|t| t.parse::<f64>().ok())
                    == Some(tight)
            })
            .collect();
        at.sort_by(|a, b| a.time.median.total_cmp(&b.time.median));
        let list: Vec<String> = at
            .iter()
            .map(|r| {
                format!(
                    "{} {:.3} ms (error {})",
                    r.solver,
                    r.time.median,
                    sci(r.max_grid_error)
                )
            })
            .collect();
        summary.push(format!("{scene}, filippov vs diffsol at rtol {tight:.0e} ({when}, same problem and harness): {}", list.join(", ")));
        // Work-precision: the fastest run of each library to a grid error ≤ threshold,
        // among all solvers and among the stiff ones alone (filippov SDIRK4 and BDF;
        // diffsol BDF, ESDIRK34, TR-BDF2): where filippov loses, it shows here.
        let implicit = |r: &Row| {
            ["SDIRK4", "BDF", "ESDIRK34", "TR-BDF2"]
                .iter()
                .any(|m| r.solver.ends_with(m))
        };
        for (group, stiff_only) in [("all solvers", false), ("stiff solvers", true)] {
            let mut pairs = Vec::new();
            for threshold in THRESHOLDS {
                let best = |prefix: &str| {
                    rows.iter()
                        .filter(|r| {
                            r.solver.starts_with(prefix)
                                && (!stiff_only || implicit(r))
                                && r.max_grid_error <= threshold
                        })
                        .min_by(|a, b| a.time.median.total_cmp(&b.time.median))
                };
                match (best("filippov"), best("diffsol")) {
                    (Some(f), Some(g)) => {
                        pairs.push((threshold, *f, *g));
                        summary.push(format!(
                            "{scene}, {group}, fastest to a max grid error ≤ {threshold:.0e}: filippov {} against diffsol {}: {} ({})",
                            run_cell(f),
                            run_cell(g),
                            g.time.ratio_to(&f.time, 2),
                            if f.time.median <= g.time.median { "filippov faster" } else { "diffsol faster" }
                        ));
                    }
                    (Some(f), None) => summary.push(format!(
                        "{scene}, {group}: only filippov reaches a max grid error ≤ {threshold:.0e} ({})",
                        run_cell(f)
                    )),
                    (None, Some(g)) => summary.push(format!(
                        "{scene}, {group}: only diffsol reaches a max grid error ≤ {threshold:.0e} ({})",
                        run_cell(g)
                    )),
                    (None, None) => summary.push(format!(
                        "{scene}, {group}: neither library reaches a max grid error ≤ {threshold:.0e} in the sweep"
                    )),
                }
            }
            diffsol_headline(
                format!(
                    "{scene}: {group}, fastest to a max grid error ≤ threshold, filippov against diffsol"
                ),
                &pairs,
                format!(
                    "same problem and harness in one peer binary (both libraries built with the same default release flags; {when}), all runs of the scene timed in 5 interleaved rounds, median (min–max); every row's error against one reference (RK4, h = 1e-5)"
                ),
            );
        }
    }
    for scene in ["S6", "S5"] {
        let rows: Vec<&Row> = d.rows.iter().filter(|r| r.scene == scene).collect();
        let reg = rows
            .iter()
            .filter(|r| r.solver.contains("tanh"))
            .filter(|r| ok(r))
            .min_by(|a, b| {
                a.max_grid_error
                    .total_cmp(&b.max_grid_error)
                    .then(a.time.median.total_cmp(&b.time.median))
            });
        let event: Vec<&&Row> = rows
            .iter()
            .filter(|r| r.solver.starts_with("filippov"))
            .filter(|r| ok(r))
            .collect();
        let failed = rows
            .iter()
            .filter(|r| r.notes.starts_with("failed"))
            .count();
        let Some(reg) = reg else {
            summary.push(format!(
                "{scene}: no regularised diffsol run completed ({failed} failed)"
            ));
            continue;
        };
        let mut line = format!(
            "{scene} ({when}): the best regularised diffsol run reaches a max error in x of {} ({} at {}, {:.3} ms)",
            sci(reg.max_grid_error),
            reg.solver.trim_end_matches(" tanh(v/eps)"),
            reg.setting
                .replace("eps=", "ε = ")
                .replace(" rtol=", ", rtol "),
            reg.time.median
        );
        // The fastest regularised run within 10 % of that error, when another one is.
        if let Some(fast) = rows
            .iter()
            .filter(|r| r.solver.contains("tanh"))
            .filter(|r| ok(r) && r.max_grid_error <= 1.1 * reg.max_grid_error)
            .min_by(|a, b| a.time.median.total_cmp(&b.time.median))
            .filter(|f| f.time.median < reg.time.median)
        {
            line += &format!(
                " (within 10 % of it fastest: {} at {}, {} in {:.3} ms)",
                fast.solver.trim_end_matches(" tanh(v/eps)"),
                fast.setting
                    .replace("eps=", "ε = ")
                    .replace(" rtol=", ", rtol "),
                sci(fast.max_grid_error),
                fast.time.median
            );
        }
        if let Some(e) = event
            .iter()
            .min_by(|a, b| a.max_grid_error.total_cmp(&b.max_grid_error))
        {
            line += &format!(
                "; filippov event-driven reaches {} (at {}, {:.3} ms)",
                sci(e.max_grid_error),
                e.setting,
                e.time.median
            );
        }
        if let Some(e) = event
            .iter()
            .filter(|e| e.max_grid_error <= reg.max_grid_error)
            .min_by(|a, b| a.time.median.total_cmp(&b.time.median))
        {
            line += &format!(
                ", and beats diffsol's best error already at {} ({} in {:.3} ms)",
                e.setting,
                sci(e.max_grid_error),
                e.time.median
            );
        }
        if failed > 0 {
            line += &format!("; {failed} regularised run(s) failed (see the table)");
        }
        summary.push(line);
    }
}
