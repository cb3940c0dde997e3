//! Peers side by side: the report writes the multibody scenes as JSON models
//! (`target/report/models/*.json`) for the peer script (`peers/run.sh`: Pinocchio,
//! SciPy and SymPy in a local virtual environment), and includes the script's results
//! (`target/report/peers/peers.md`, `peers.tsv`) when it has been run. Nothing is
//! invented when it has not: the section says so.

use filippov::Mechanism;
use filippov::scenes::{BranchedTree, DoublePendulum, Panda, PlanarArm3};

use super::config::Config;
use super::markdown::Page;
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

/// `peer<TAB>scene<TAB>quantity<TAB>value<TAB>unit` rows of the script's TSV.
fn rows(text: &str) -> Vec<[String; 5]> {
    text.lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .filter_map(|l| {
            let f: Vec<&str> = l.split('\t').collect();
            (f.len() == 5).then(|| [f[0], f[1], f[2], f[3], f[4]].map(|s| s.trim().to_string()))
        })
        .collect()
}

/// The peers section; `ours` gives our ns per forward-dynamics call per scene file name
/// (as measured in this run) for the ratios in the summary.
pub fn peers(config: &Config, ours: &[(&str, f64)]) -> Section {
    let mut page = Page::empty();
    let mut summary = Vec::new();
    page.h2("Peers");
    let dir = config.out_dir.join("peers");
    let md = std::fs::read_to_string(dir.join("peers.md"));
    let tsv = std::fs::read_to_string(dir.join("peers.tsv"));
    match (md, tsv) {
        (Ok(md), Ok(tsv)) => {
            page.para("From `bash peers/run.sh` (its own run; see its header for when and with which versions). Ratios below compare with this run's measurements.");
            page.append_raw(&md);
            for r in rows(&tsv) {
                let ns = ours.iter().find(|(s, _)| *s == r[1]).map(|(_, ns)| *ns);
                if let (true, Some(ns), Ok(theirs)) = (r[2] == "aba_ns", ns, r[3].parse::<f64>()) {
                    let (ratio, word) = if theirs > ns {
                        (theirs / ns, "faster")
                    } else {
                        (ns / theirs, "slower")
                    };
                    summary.push(format!(
                        "{}: generated forward dynamics {ns:.1} ns vs {} ABA {theirs:.1} ns ({ratio:.2}× {word})",
                        r[1], r[0]
                    ));
                }
            }
        }
        _ => {
            page.para(
                "The peer script has not been run on this machine, so no peer figures are shown. Run `bash peers/run.sh` \
                 (it installs Pinocchio, SciPy and SymPy into `peers/.venv`) and then the report again.",
            );
            summary.push("Peers: not run (no figures); `bash peers/run.sh` runs them".into());
        }
    }
    Section { page, summary }
}
