//! Robots read from their URDF files (`robots/`): joints, expansion time, generated
//! forward dynamics against the numeric reader of the same file, FD ns, and — when
//! `bash peers/run.sh` has run — Pinocchio on the same URDF (its M, C v + g and ABA
//! against ours at the exported states, and its ABA time).
//!
//! The states and our values are written to `target/report/urdf/<robot>.json` for
//! `peers/urdf_pin.py`.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use filippov::nalgebra::{DVector, SVector, Vector3};
use filippov::prelude::*;
use filippov::runtime::UnitQuat;
use filippov::runtime::numeric::{self, Model};

use super::agreement_support::Rng;
use super::config::Config;
use super::markdown::{Page, sci};
use super::timing::{Timing, in_rounds, ns_timed, program_timing, timed};

#[derive(Mechanism)]
#[mechanism(
    urdf = "robots/panda.urdf",
    lock = [panda_finger_joint1, panda_finger_joint2],
    gravity = [0.0, 0.0, -9.81],
    emit = [kinematics, generic]
)]
pub struct PandaUrdf;

#[derive(Mechanism)]
#[mechanism(urdf = "robots/ur5.urdf", gravity = [0.0, 0.0, -9.81], emit = [kinematics, generic])]
pub struct Ur5;

#[derive(Mechanism)]
#[mechanism(
    urdf = "robots/solo12.urdf",
    base = free,
    gravity = [0.0, 0.0, -9.81],
    emit = [kinematics, generic]
)]
pub struct Solo12;

#[derive(Mechanism)]
#[mechanism(
    urdf = "robots/simple_humanoid.urdf",
    base = free,
    gravity = [0.0, 0.0, -9.81],
    emit = [kinematics, generic]
)]
pub struct Humanoid;

#[derive(Mechanism)]
#[mechanism(
    urdf = "robots/three_link_arm.urdf",
    gravity = [0.0, 0.0, -9.81],
    emit = [kinematics, generic]
)]
pub struct ThreeLinkArm;

/// A random oblique 3-D tree of 36 joints (`examples/oblique_tree.rs`): nothing to fold,
/// so `auto` gives it the compact kernels.
#[derive(Mechanism)]
#[mechanism(
    urdf = "robots/oblique36.urdf",
    gravity = [0.0, 0.0, -9.81],
    emit = [kinematics, generic]
)]
pub struct Oblique36;

/// Interleaved rounds of our timing and Pinocchio's.
const ROUNDS: usize = 3;

#[derive(Default)]
pub struct Section {
    pub page: Page,
    pub summary: Vec<String>,
}

pub struct Robot {
    pub name: &'static str,
    /// The name's CamelCase, for declarations made from this table.
    pub ident: &'static str,
    pub file: &'static str,
    pub lock: &'static [&'static str],
    pub free_base: bool,
    /// `#[mechanism(…)]` options for the expansion timing.
    pub options: &'static str,
}

pub const ROBOTS: [Robot; 6] = [
    Robot {
        name: "panda",
        ident: "Panda",
        file: "robots/panda.urdf",
        lock: &["panda_finger_joint1", "panda_finger_joint2"],
        free_base: false,
        options: "lock = [panda_finger_joint1, panda_finger_joint2], ",
    },
    Robot {
        name: "ur5",
        ident: "Ur5",
        file: "robots/ur5.urdf",
        lock: &[],
        free_base: false,
        options: "",
    },
    Robot {
        name: "solo12",
        ident: "Solo12",
        file: "robots/solo12.urdf",
        lock: &[],
        free_base: true,
        options: "base = free, ",
    },
    Robot {
        name: "humanoid",
        ident: "Humanoid",
        file: "robots/simple_humanoid.urdf",
        lock: &[],
        free_base: true,
        options: "base = free, ",
    },
    Robot {
        name: "three_link_arm",
        ident: "ThreeLinkArm",
        file: "robots/three_link_arm.urdf",
        lock: &[],
        free_base: false,
        options: "",
    },
    Robot {
        name: "oblique36",
        ident: "Oblique36",
        file: "robots/oblique36.urdf",
        lock: &[],
        free_base: false,
        options: "",
    },
];

/// One state with our values: `(q, v, tau, M row-major, C v + g, FD, frames)`, `frames`
/// per frame its rotation (row-major), origin and Jacobian (row-major, `6 × N`).
type Sample = (
    Vec<f64>,
    Vec<f64>,
    Vec<f64>,
    Vec<f64>,
    Vec<f64>,
    Vec<f64>,
    Vec<Vec<f64>>,
);

/// Every frame's pose and Jacobian at `q`, flattened as in [`Sample`].
fn frames<S: Kinematics<N, NQ>, const N: usize, const NQ: usize>(
    s: &S,
    q: &SVector<f64, NQ>,
) -> Vec<Vec<f64>> {
    (0..S::FRAMES.len())
        .filter_map(S::frame_at)
        .map(|f| {
            let pose = s.frame_pose(f, q);
            let r = pose.rotation.to_rotation_matrix().into_inner();
            let j = s.frame_jacobian(f, q);
            let mut out: Vec<f64> = (0..9).map(|k| r[(k / 3, k % 3)]).collect();
            out.extend(pose.translation.vector.iter());
            out.extend((0..6 * N).map(|k| j[(k / N, k % N)]));
            out
        })
        .collect()
}

#[allow(clippy::type_complexity)]
fn samples<const N: usize, const NQ: usize>(
    m: &dyn Fn(&SVector<f64, NQ>) -> Vec<f64>,
    bias: &dyn Fn(&SVector<f64, NQ>, &SVector<f64, N>) -> Vec<f64>,
    fd: &dyn Fn(&SVector<f64, NQ>, &SVector<f64, N>, &SVector<f64, N>) -> Vec<f64>,
    fk: &dyn Fn(&SVector<f64, NQ>) -> Vec<Vec<f64>>,
    rotations: &[(usize, usize)],
) -> Vec<Sample> {
    let mut rng = Rng::new(2026);
    (0..20)
        .map(|_| {
            let mut q = SVector::<f64, NQ>::from_fn(|_, _| rng.uniform(-2.0, 2.0));
            for &(s, _) in rotations {
                let r = UnitQuat::try_new(q[s], q[s + 1], q[s + 2], q[s + 3])
                    .unwrap_or_default()
                    .coords();
                q.fixed_rows_mut::<4>(s).copy_from_slice(&r);
            }
            let v = SVector::<f64, N>::from_fn(|_, _| rng.uniform(-2.0, 2.0));
            let tau = SVector::<f64, N>::from_fn(|_, _| rng.uniform(-5.0, 5.0));
            (
                q.as_slice().to_vec(),
                v.as_slice().to_vec(),
                tau.as_slice().to_vec(),
                m(&q),
                bias(&q, &v),
                fd(&q, &v, &tau),
                fk(&q),
            )
        })
        .collect()
}

fn rel(a: &[f64], b: &[f64]) -> f64 {
    let scale = b.iter().fold(1.0f64, |m, x| m.max(x.abs()));
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
        / scale
}

/// Largest relative difference of our samples from the numeric reader's model.
fn against_numeric(model: &Model, s: &[Sample]) -> f64 {
    let d = |x: &[f64]| DVector::from_column_slice(x);
    s.iter()
        .map(|(q, v, tau, m, b, fd, _)| {
            let (q, v, tau) = (d(q), d(v), d(tau));
            let m_ref = numeric::crba(model, &q);
            let n = v.len();
            let m_rows: Vec<f64> = (0..n * n).map(|k| m_ref[(k / n, k % n)]).collect();
            rel(m, &m_rows)
                .max(rel(b, numeric::bias(model, &q, &v).as_slice()))
                .max(rel(
                    fd,
                    numeric::forward_dynamics(model, &q, &v, &tau).as_slice(),
                ))
        })
        .fold(0.0, f64::max)
}

fn json_array(x: &[f64]) -> String {
    let items: Vec<String> = x.iter().map(|v| format!("{v:e}")).collect();
    format!("[{}]", items.join(","))
}

fn export(
    dir: &Path,
    robot: &Robot,
    joints: &[&str],
    frame_names: &[&str],
    fd_ns: f64,
    s: &[Sample],
) -> std::io::Result<()> {
    std::fs::create_dir_all(dir)?;
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut out = String::new();
    let lock: Vec<String> = robot.lock.iter().map(|l| format!("{l:?}")).collect();
    let _ = write!(
        out,
        "{{\"name\":{:?},\"urdf\":{:?},\"lock\":[{}],\"joints\":[{}],\"frames\":[{}],\"free_base\":{},\"fd_ns\":{fd_ns},\"states\":[",
        robot.name,
        root.join(robot.file).display().to_string(),
        lock.join(","),
        joints
            .iter()
            .map(|j| format!("{j:?}"))
            .collect::<Vec<_>>()
            .join(","),
        frame_names
            .iter()
            .map(|j| format!("{j:?}"))
            .collect::<Vec<_>>()
            .join(","),
        robot.free_base
    );
    for (i, (q, v, tau, m, b, fd, fk)) in s.iter().enumerate() {
        if i > 0 {
            out.push(',');
        }
        let _ = write!(
            out,
            "{{\"q\":{},\"v\":{},\"tau\":{},\"m\":{},\"bias\":{},\"fd\":{},\"fk\":[{}]}}",
            json_array(q),
            json_array(v),
            json_array(tau),
            json_array(m),
            json_array(b),
            json_array(fd),
            fk.iter()
                .map(|f| json_array(f))
                .collect::<Vec<_>>()
                .join(",")
        );
    }
    out.push_str("]}\n");
    std::fs::write(dir.join(format!("{}.json", robot.name)), out)
}

/// Pinocchio's results from `peers/urdf_pin.py`, if present: per robot
/// `(max rel M, max rel C v + g, max rel FD, ABA ns, max frame pose difference, max rel
/// frame Jacobian)` (the last two NaN from an older script).
fn pinocchio(dir: &Path) -> Vec<(String, [f64; 6])> {
    let Ok(text) = std::fs::read_to_string(dir.join("urdf.tsv")) else {
        return Vec::new();
    };
    text.lines()
        .skip(1)
        .filter_map(|l| {
            let f: Vec<&str> = l.split('\t').collect();
            let nums: Vec<f64> = f.get(1..5)?.iter().filter_map(|x| x.parse().ok()).collect();
            let fk = |k: usize| f.get(k).and_then(|x| x.parse().ok()).unwrap_or(f64::NAN);
            (nums.len() == 4).then(|| {
                (
                    f[0].to_string(),
                    [nums[0], nums[1], nums[2], nums[3], fk(6), fk(7)],
                )
            })
        })
        .collect()
}

/// Pinocchio's ABA in C++ on `robot`: the binary `peers/run.sh` builds from
/// `peers/pin_bench.cpp` with the baseline target's flags (as this report is built), and
/// the model Pinocchio built from the same URDF (`peers/urdf_pin.py` writes it to
/// `peers/urdf/<robot>.txt` and checks the binary's ABA against the bindings'). `None`
/// before `bash peers/run.sh`.
pub fn pinocchio_aba(out_dir: &Path, robot: &str) -> Option<(PathBuf, PathBuf)> {
    let bin = out_dir.join("peers/build/pin_bench");
    let model = out_dir.join("peers/urdf").join(format!("{robot}.txt"));
    (bin.exists() && model.exists()).then_some((bin, model))
}

fn expansion_ms(config: &Config, robot: &Robot) -> (Timing, usize) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(robot.file);
    let src = format!(
        "#[derive(Mechanism)] #[mechanism(urdf = {:?}, {}gravity = [0.0, 0.0, -9.81])] struct R;",
        path.display().to_string(),
        robot.options
    );
    let tokens: proc_macro2::TokenStream = src.parse().expect("tokens");
    let (t, e) = timed(config.repeats.min(5), || {
        filippov_codegen::expand_with_stats(tokens.clone()).expect("expands")
    });
    (t.scaled(1e3), e.functions.iter().map(|f| f.lets).sum())
}

pub fn urdf(config: &Config) -> Section {
    let mut page = Page::empty();
    let mut summary = Vec::new();
    let dir = config.out_dir.join("urdf");
    let g = Vector3::new(0.0, 0.0, -9.81);
    let mut rows = Vec::new();
    let pin = pinocchio(&config.out_dir.join("peers"));
    // Largest differences from Pinocchio over the robots: dynamics, frame kinematics.
    let (mut pin_dyn, mut pin_fk, mut pin_robots) = (0.0f64, 0.0f64, 0);
    // (robot, our FD, Pinocchio's ABA in C++), timed in this run.
    let mut pin_speed: Vec<(&str, Timing, Timing)> = Vec::new();
    for robot in &ROBOTS {
        let text = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join(robot.file))
            .expect("the robot's URDF");
        let model = Model::from_urdf(&text, g, robot.free_base, robot.lock).expect("reads");
        let (exp_ms, lets) = expansion_ms(config, robot);
        let pin_program = pinocchio_aba(&config.out_dir, robot.name);
        macro_rules! measure {
            ($s:expr, $n:literal, $nq:literal, $rot:expr) => {{
                let s = samples::<$n, $nq>(
                    &|q| {
                        let m = $s.mass_matrix(q);
                        (0..$n * $n).map(|k| m[(k / $n, k % $n)]).collect()
                    },
                    &|q, v| {
                        let z = SVector::<f64, $n>::zeros();
                        let a = $s.forward_dynamics(q, v, &z);
                        (-($s.mass_matrix(q) * a)).as_slice().to_vec()
                    },
                    &|q, v, t| $s.forward_dynamics(q, v, t).as_slice().to_vec(),
                    &|q| frames(&$s, q),
                    $rot,
                );
                let (q, v, tau) = (
                    SVector::<f64, $nq>::from_column_slice(&s[0].0),
                    SVector::<f64, $n>::from_column_slice(&s[0].1),
                    SVector::<f64, $n>::from_column_slice(&s[0].2),
                );
                // Inputs through black_box, as in every other kernel timing: with
                // loop-invariant inputs the compiler may hoist the call out of the loop.
                // Pinocchio's ABA (a separate program) in interleaved rounds beside it.
                let mut ours = || {
                    Some(ns_timed(config.repeats, config.kernel_calls, || {
                        $s.forward_dynamics(
                            std::hint::black_box(&q),
                            std::hint::black_box(&v),
                            std::hint::black_box(&tau),
                        )
                    }))
                };
                let mut theirs = || {
                    pin_program.as_ref().and_then(|(bin, model)| {
                        program_timing(bin, &[model.as_os_str(), "aba".as_ref()], "aba_ns")
                    })
                };
                let t = in_rounds(ROUNDS, &mut [&mut ours, &mut theirs]);
                (s, t[0].unwrap_or_default(), t[1], $n)
            }};
        }
        let ((s, fd_ns, pin_aba, dof), joints, frame_names): (_, Vec<&str>, &[&str]) =
            match robot.name {
                "panda" => (
                    measure!(PandaUrdf, 7, 7, &[]),
                    PandaUrdf::JOINTS.to_vec(),
                    PandaUrdf::FRAMES,
                ),
                "ur5" => (measure!(Ur5, 6, 6, &[]), Ur5::JOINTS.to_vec(), Ur5::FRAMES),
                // The free base's six coordinates first, then one per joint.
                "solo12" => (
                    measure!(Solo12, 18, 19, Solo12::ROTATIONS),
                    Solo12::COORDINATES[6..].to_vec(),
                    Solo12::FRAMES,
                ),
                "three_link_arm" => (
                    measure!(ThreeLinkArm, 3, 3, &[]),
                    ThreeLinkArm::JOINTS.to_vec(),
                    ThreeLinkArm::FRAMES,
                ),
                "oblique36" => (
                    measure!(Oblique36, 36, 36, &[]),
                    Oblique36::JOINTS.to_vec(),
                    Oblique36::FRAMES,
                ),
                _ => (
                    measure!(Humanoid, 35, 36, Humanoid::ROTATIONS),
                    Humanoid::COORDINATES[6..].to_vec(),
                    Humanoid::FRAMES,
                ),
            };
        let err = against_numeric(&model, &s);
        if let Some(p) = pin_aba {
            pin_speed.push((robot.name, fd_ns, p));
        }
        if let Err(e) = export(&dir, robot, &joints, frame_names, fd_ns.median, &s) {
            eprintln!("report: could not export {}: {e}", robot.name);
        }
        let peer = pin.iter().find(|(n, _)| n == robot.name).map(|(_, p)| *p);
        if let Some(p) = peer {
            pin_robots += 1;
            pin_dyn = pin_dyn.max(p[0]).max(p[1]).max(p[2]);
            pin_fk = pin_fk.max(p[4]).max(p[5]);
        }
        rows.push(vec![
            format!("`{}`", robot.file),
            format!("{dof}{}", if robot.free_base { " (free base)" } else { "" }),
            exp_ms.show(1),
            lets.to_string(),
            fd_ns.show(0),
            sci(err),
            peer.map_or("—".into(), |p| sci(p[0].max(p[1]))),
            peer.map_or("—".into(), |p| sci(p[2])),
            match (pin_aba, peer) {
                (Some(p), _) => format!("{} (C++)", p.show(0)),
                (None, Some(p)) => format!("{:.0} (Python bindings)", p[3]),
                (None, None) => "—".into(),
            },
            pin_aba.map_or("—".into(), |p| p.ratio_to(&fd_ns, 1)),
            format!("{}", frame_names.len()),
            peer.map_or("—".into(), |p| {
                if p[4].is_nan() {
                    "—".into()
                } else {
                    format!("{} / {}", sci(p[4]), sci(p[5]))
                }
            }),
        ]);
        summary.push(format!(
            "URDF `{}` ({dof} dof): generated FD {} ns; against the numeric reader of the same file {}{}{}",
            robot.file,
            fd_ns.show(0),
            sci(err),
            peer.map_or(String::from("; Pinocchio not run (`--no-peers`, or the peer script failed)"), |p| format!(
                "; against Pinocchio M, C v + g {} and FD {}",
                sci(p[0].max(p[1])),
                sci(p[2]),
            )),
            pin_aba.map_or(String::new(), |p| format!(
                "; Pinocchio's ABA in C++ {} ns in this run, {} our time",
                p.show(0),
                p.ratio_to(&fd_ns, 1)
            ))
        ));
    }
    if pin_robots > 0 {
        super::markdown::headline(
            format!(
                "Generated dynamics and forward kinematics equal Pinocchio's on the same URDF files ({pin_robots} robots, 20 random states)"
            ),
            format!(
                "M, C v + g, FD within {} relative; frame poses and Jacobians within {}",
                sci(pin_dyn),
                sci(pin_fk)
            ),
            "Pinocchio `buildModelFromUrdf` (peers/urdf_pin.py)",
            "—",
            "largest differences over robots, states and frames; the peers' figures are from the peer script this report ran",
        );
    }
    if !pin_speed.is_empty() {
        let ours: Vec<String> = pin_speed
            .iter()
            .map(|(n, a, _)| format!("{n} {}", a.show(0)))
            .collect();
        let theirs: Vec<String> = pin_speed
            .iter()
            .map(|(n, _, b)| format!("{n} {}", b.show(0)))
            .collect();
        let ratios: Vec<String> = pin_speed
            .iter()
            .map(|(n, a, b)| format!("{n} {}", b.ratio_to(a, 1)))
            .collect();
        super::markdown::headline(
            "Generated forward dynamics against Pinocchio's ABA in C++ on the same URDF robots",
            format!("{} ns", ours.join("; ")),
            format!("{} ns (Pinocchio C++ `aba`)", theirs.join("; ")),
            ratios.join("; "),
            "ns per call, median of 3 interleaved rounds (min–max over their batches), both in this run and both built for the baseline x86-64 target (rustc's default; g++ -O3 without -march); the native builds are in the section on CPU flags; Pinocchio's model built from the same file and its ABA checked against the Python bindings by peers/urdf_pin.py",
        );
    }
    page.h2("Robots from URDF");
    page.para(
        "Each file in `robots/` read at compile time by `#[mechanism(urdf = …)]` (default kernels). Expansion: the \
         engine (release build) on the attribute, median. FD ns: generated forward dynamics, median of batches. \
         \"numeric\": the largest relative difference of M, C v + g and FD from `numeric::Model::from_urdf` (a \
         second reader of the same file) at 20 random states. Pinocchio (columns filled by the peer script the report runs, \
         which loads the same URDFs with `buildModelFromUrdf`; Panda fingers locked, Solo12 and the humanoid with \
         a free-flyer base, their velocities mapped to ours): the same differences at the same states, and \
         Pinocchio's `aba` in C++ (`peers/pin_bench.cpp`, g++ -O3 for the baseline x86-64 target as this report is built, on the model \
         Pinocchio built from the file) timed by this report beside our FD in three interleaved rounds, with the ratio \
         Pinocchio / ours (> 1: ours faster; both builds with native flags are in the section on CPU flags); \
         without the C++ build, the time through its Python bindings, call overhead included. Frames: every body and \
         the file's tool frames (`emit = [kinematics]`); against Pinocchio's `framesForwardKinematics` and \
         `computeFrameJacobian(…, LOCAL_WORLD_ALIGNED)` on the same frame names: the largest difference of rotation \
         entries and origins [m], and of the Jacobian relative to its largest entry, over all frames and states.",
    );
    page.table(
        &[
            "robot",
            "dof",
            "expansion ms, median (min–max)",
            "lets",
            "FD ns",
            "vs numeric",
            "vs Pinocchio M, Cv+g",
            "vs Pinocchio FD",
            "Pinocchio ABA ns",
            "Pinocchio / ours",
            "frames",
            "vs Pinocchio frame pose / Jacobian",
        ],
        &rows,
    );
    Section { page, summary }
}
