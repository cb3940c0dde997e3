//! Operation counts per kernel per robot (the derive's own count of the code it emits,
//! each shared subexpression once), with what they are measured against.
//!
//! For each URDF robot the derive expands three versions of the file, same tree, same
//! joint types, same masses:
//! - **the robot** as it is;
//! - **the floor**: the same kinematics (joint origins, rotations and axes kept), every
//!   link's centre of mass at its frame's origin and its inertia tensor diagonal in that
//!   frame. This is the least the same algorithm needs on this robot's kinematics, once
//!   exact zeros and ones fold: what is left above it is what the links' inertias cost.
//!   (Folding the kinematics away too, all origins at zero, makes the Panda's joints
//!   coaxial and its mass matrix constant: no floor for a real arm.)
//! - **the ceiling**: every origin, rotation and joint axis oblique, every centre of
//!   mass off-axis, every inertia tensor full (small seeded off-diagonals): nothing
//!   folds, the textbook algorithm's count on this tree.
//!
//! The forward dynamics is also split into its parts (kinematics, mass matrix or
//! articulated inertias, bias forces, factorisation, solves), each subexpression counted
//! in the first part that computes it ([`filippov_codegen::Expansion::forward_parts`]).

use std::path::Path;

use super::config::Config;
use super::markdown::Page;
use super::urdf::{ROBOTS, Robot};
use super::workprecision::Section;

/// The kernels counted, as the derive names its methods.
const KERNELS: [(&str, &str); 4] = [
    ("forward_dynamics", "FD"),
    ("mass_matrix", "M"),
    ("inverse_dynamics", "ID"),
    ("forward_dynamics_jacobian", "FD Jacobian"),
];

#[derive(Clone, Copy)]
enum Geometry {
    Robot,
    Floor,
    Ceiling,
}

/// A small seeded generator (the ceiling's oblique values).
struct Rng(u64);

impl Rng {
    /// Uniform in `[lo, hi)`.
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        lo + (hi - lo) * ((self.0 >> 11) as f64 / (1u64 << 53) as f64)
    }
}

/// The value of attribute `name` in the tag `tag` (its text, `<` to `>`).
fn attr<'a>(tag: &'a str, name: &str) -> Option<&'a str> {
    let key = format!(" {name}=\"");
    let start = tag.find(&key)? + key.len();
    let len = tag[start..].find('"')?;
    Some(&tag[start..start + len])
}

/// `text` with every tag `<name …>` replaced by `f(tag)`.
fn rewrite_tags(text: &str, name: &str, mut f: impl FnMut(&str) -> String) -> String {
    let open = format!("<{name}");
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(at) = rest.find(&open) {
        let after = &rest[at + open.len()..];
        // `<origin` but not `<originx`.
        if !after.starts_with([' ', '\t', '\n', '\r', '/', '>']) {
            out.push_str(&rest[..at + open.len()]);
            rest = after;
            continue;
        }
        let Some(end) = after.find('>') else { break };
        out.push_str(&rest[..at]);
        let tag = &rest[at..at + open.len() + end + 1];
        out.push_str(&f(tag));
        rest = &rest[at + open.len() + end + 1..];
    }
    out.push_str(rest);
    out
}

/// `text` with every block `<name …>…</name>` replaced by `f(block)`.
fn rewrite_blocks(text: &str, name: &str, mut f: impl FnMut(&str) -> String) -> String {
    let (open, close) = (format!("<{name}>"), format!("</{name}>"));
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(at) = rest.find(&open) {
        let Some(len) = rest[at..].find(&close) else {
            break;
        };
        let end = at + len + close.len();
        out.push_str(&rest[..at]);
        out.push_str(&f(&rest[at..end]));
        rest = &rest[end..];
    }
    out.push_str(rest);
    out
}

/// The URDF text with its geometry made `geometry` (see the module's documentation).
fn with_geometry(text: &str, geometry: Geometry, rng: &mut Rng) -> String {
    let close = |tag: &str| if tag.ends_with("/>") { "/>" } else { ">" };
    match geometry {
        Geometry::Robot => text.to_string(),
        Geometry::Floor => {
            // Only inside `<inertial>`: the joints' origins and axes are the robot's
            // kinematics and stay.
            let t = rewrite_blocks(text, "inertial", |block| {
                rewrite_tags(block, "origin", |tag| {
                    format!("<origin xyz=\"0 0 0\" rpy=\"0 0 0\"{}", close(tag))
                })
            });
            rewrite_tags(&t, "inertia", |tag| {
                let d = |k| attr(tag, k).unwrap_or("0").to_string();
                format!(
                    "<inertia ixx=\"{}\" iyy=\"{}\" izz=\"{}\" ixy=\"0\" ixz=\"0\" iyz=\"0\"{}",
                    d("ixx"),
                    d("iyy"),
                    d("izz"),
                    close(tag)
                )
            })
        }
        Geometry::Ceiling => {
            let t = rewrite_tags(text, "origin", |tag| {
                let mut v = || {
                    rng.uniform(0.05, 0.2)
                        * if rng.uniform(0.0, 1.0) < 0.5 {
                            -1.0
                        } else {
                            1.0
                        }
                };
                let (x, y, z) = (v(), v(), v());
                let (r, p, w) = (
                    rng.uniform(-1.0, 1.0),
                    rng.uniform(-1.0, 1.0),
                    rng.uniform(-1.0, 1.0),
                );
                format!(
                    "<origin xyz=\"{x} {y} {z}\" rpy=\"{r} {p} {w}\"{}",
                    close(tag)
                )
            });
            let t = rewrite_tags(&t, "axis", |tag| {
                let a = [
                    rng.uniform(0.2, 1.0),
                    rng.uniform(0.2, 1.0),
                    rng.uniform(0.2, 1.0),
                ];
                let n = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
                format!(
                    "<axis xyz=\"{} {} {}\"{}",
                    a[0] / n,
                    a[1] / n,
                    a[2] / n,
                    close(tag)
                )
            });
            rewrite_tags(&t, "inertia", |tag| {
                let d = |k| {
                    attr(tag, k)
                        .and_then(|x| x.parse::<f64>().ok())
                        .unwrap_or(0.0)
                };
                let (xx, yy, zz) = (d("ixx"), d("iyy"), d("izz"));
                // Small off-diagonals keep the tensor positive definite and its
                // principal moments within the triangle inequality where the file's are.
                let s = 1e-3 * xx.min(yy).min(zz);
                let mut o = || s * rng.uniform(-1.0, 1.0);
                let (xy, xz, yz) = (o(), o(), o());
                format!(
                    "<inertia ixx=\"{xx}\" iyy=\"{yy}\" izz=\"{zz}\" ixy=\"{xy}\" ixz=\"{xz}\" iyz=\"{yz}\"{}",
                    close(tag)
                )
            })
        }
    }
}

/// The derive's expansion of `robot` with `geometry` (its URDF rewritten to a file in
/// `dir`), or the derive's message.
fn expand(
    dir: &Path,
    robot: &Robot,
    geometry: Geometry,
) -> Result<filippov_codegen::Expansion, String> {
    let text = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join(robot.file))
        .map_err(|e| e.to_string())?;
    // Seeded by the robot's name (FNV-1a): the same ceiling in every run.
    let seed = robot.name.bytes().fold(0xCBF2_9CE4_8422_2325u64, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01B3)
    });
    let mut rng = Rng(seed);
    let file = dir.join(format!(
        "{}_{}.urdf",
        robot.name,
        match geometry {
            Geometry::Robot => "robot",
            Geometry::Floor => "floor",
            Geometry::Ceiling => "ceiling",
        }
    ));
    std::fs::write(&file, with_geometry(&text, geometry, &mut rng)).map_err(|e| e.to_string())?;
    let src = format!(
        "#[derive(Mechanism)] #[mechanism(urdf = {:?}, {}emit = [inverse_dynamics], gravity = [0.0, 0.0, -9.81])] struct R;",
        file.display().to_string(),
        robot.options
    );
    let tokens: proc_macro2::TokenStream = src.parse().map_err(|e| format!("{e:?}"))?;
    filippov_codegen::expand_with_stats(tokens).map_err(|e| e.to_string())
}

fn count(e: &filippov_codegen::Expansion, kernel: &str) -> Option<usize> {
    e.functions
        .iter()
        .find(|f| f.name == kernel)
        .map(|f| f.ops.total())
}

fn cell(x: Option<usize>) -> String {
    x.map_or("—".to_string(), |n| format!("{n}"))
}

pub fn ops(config: &Config) -> Section {
    let mut page = Page::empty();
    let mut summary = Vec::new();
    page.h2("Operation counts per kernel, against a floor");
    page.para(
        "Floating-point operations in the code the derive emits (each shared subexpression once; a subtraction counts as an addition, \
         a `sin_cos` pair as one), per robot and kernel. Beside each: the **floor**, the same derive on the same kinematics (joint origins, rotations \
         and axes kept) with every link's centre of mass at its frame's origin and its inertia diagonal there, the least the same algorithm \
         needs on this robot once exact zeros and ones fold; and the **ceiling**, the same tree with every origin, rotation and axis oblique \
         and every inertia full, where nothing folds. `ours / floor` is what the links' inertias cost above the floor. These are counts, not times: \
         they do not depend on the machine. The rewritten URDF files are in `ops/`.",
    );
    let dir = config.out_dir.join("ops");
    if let Err(e) = std::fs::create_dir_all(&dir) {
        page.para(&format!(
            "**failed**: could not make {}: {e}",
            dir.display()
        ));
        return Section { page, summary };
    }
    let mut rows = Vec::new();
    let mut parts_rows = Vec::new();
    let mut failures = Vec::new();
    // The tiny configuration (the tests) expands the two smallest arms only: the others'
    // ceilings are hundreds of thousands of operations, slow in an unoptimised engine.
    let robots = ROBOTS
        .iter()
        .filter(|r| config.name != "tiny" || ["three_link_arm", "ur5"].contains(&r.name));
    for robot in robots {
        let expansions: Vec<Result<filippov_codegen::Expansion, String>> =
            [Geometry::Robot, Geometry::Floor, Geometry::Ceiling]
                .into_iter()
                .map(|g| expand(&dir, robot, g))
                .collect();
        let [ours, floor, ceiling] = [&expansions[0], &expansions[1], &expansions[2]];
        for (which, e) in ["robot", "floor", "ceiling"].iter().zip(&expansions) {
            if let Err(msg) = e {
                failures.push(format!("{} ({which}): {msg}", robot.name));
            }
        }
        let Ok(ours) = ours else { continue };
        for (kernel, label) in KERNELS {
            let (o, f, c) = (
                count(ours, kernel),
                floor.as_ref().ok().and_then(|e| count(e, kernel)),
                ceiling.as_ref().ok().and_then(|e| count(e, kernel)),
            );
            let ratio = match (o, f) {
                (Some(o), Some(f)) if f > 0 => format!("{:.2}", o as f64 / f as f64),
                _ => "—".to_string(),
            };
            let algorithm = if kernel == "forward_dynamics" && o.is_none() {
                "compact loop (no straight-line code to count)".to_string()
            } else {
                String::new()
            };
            rows.push(vec![
                robot.name.to_string(),
                label.to_string(),
                cell(o),
                cell(f),
                cell(c),
                ratio,
                algorithm,
            ]);
        }
        // The forward dynamics by parts, with the floor's parts beside it when the
        // floor chose the same algorithm (same part names).
        let floor_parts = floor
            .as_ref()
            .map(|e| e.forward_parts.clone())
            .unwrap_or_default();
        let fd_total: usize = ours.forward_parts.iter().map(|(_, c)| c.total()).sum();
        for (name, c) in &ours.forward_parts {
            let f = floor_parts
                .iter()
                .find(|(n, _)| n == name)
                .map(|(_, c)| c.total());
            parts_rows.push(vec![
                robot.name.to_string(),
                name.to_string(),
                format!("{}", c.total()),
                format!("{:.0} %", 100.0 * c.total() as f64 / fd_total.max(1) as f64),
                cell(f),
                format!("{}", c),
            ]);
        }
        if let (Some(fd), Some(fl)) = (
            count(ours, "forward_dynamics"),
            floor
                .as_ref()
                .ok()
                .and_then(|e| count(e, "forward_dynamics")),
        ) {
            summary.push(format!(
                "Operation counts: {}'s forward dynamics emits {fd} operations, {:.2}× its floor ({fl}: the same kinematics, simplest inertias).",
                robot.name,
                fd as f64 / fl.max(1) as f64
            ));
        }
    }
    page.table(
        &[
            "robot",
            "kernel",
            "ours",
            "floor",
            "ceiling",
            "ours / floor",
            "",
        ],
        &rows,
    );
    page.h3("Where the forward dynamics' operations go");
    page.para(
        "Each subexpression counts in the first part that computes it (transforms are formed where they are first used, so \
         kinematics shows the joints' `sin_cos`). The parts sum to the kernel's count. The floor's column is empty where \
         the floor's derive chose the other algorithm.",
    );
    page.table(
        &["robot", "part", "operations", "share", "floor", "by kind"],
        &parts_rows,
    );
    if !failures.is_empty() {
        page.para(&format!("**failed** to expand: {}", failures.join("; ")));
    }
    Section { page, summary }
}
