//! The Rust side of the Python tests (python/tests): the same kernels, runs and
//! controller loops as the Python module, on the same scenes, computed here with the
//! Rust API, so that the tests can hold the module to them bit for bit.
//!
//! Reads requests from stdin, one per line, and answers each on stdout (every number
//! in Rust's shortest round-trip form, which Python's `float` reads exactly):
//!
//! * `kernel SCENE KERNEL p… ; x…` → one line of numbers (q has the scene's
//!   configuration slots, quaternions included). KERNEL is `mass_matrix`
//!   (x = q; M row by row), `forward_dynamics` (x = q v τ), `jacobian` (x = q v τ;
//!   v̇, then ∂v̇/∂q and ∂v̇/∂v row by row), `inverse_dynamics` (x = q v a) or
//!   `frame_pose` (x = frame-index q; the 4 × 4 pose row by row);
//! * `run SCENE p… ; t_end q0… v0…` → the default event-driven run: `rows R`, R lines
//!   `t y…`, `switches K`, K lines `t kind element from to jump`; for a scene with
//!   spherical or free joints (q0 with its quaternions), the default Lie-group run
//!   (RKMK5), its rows in the mechanism's layout;
//! * `contact SCENE p… ; t_end h q0… v0…` → a run of a scene with contacts,
//!   `contact_time_stepping` with step `h`, or for `h = 0` `contact_event_driven` with the
//!   default event-driven method, answered as `run`;
//! * `control SCENE p… ; t_end dt kp kd target… q0… v0…` → a PD loop at period `dt` on
//!   the step-level integrator (`u = kp (target − q) − kd v`, held over each period),
//!   answered as `run` (an error as `error MESSAGE`, then the run up to it).
//!
//! Run: `cargo run --features urdf --example python_reference < requests`.

use std::io::{BufRead, Write};

use filippov::prelude::*;
use filippov::runtime::contacts::Contacts;
use filippov::runtime::liegroup::{LieMechanical, LieMechanism, mechanism_rows};
use filippov::runtime::nonsmooth::{Integrator, NonSmooth};
use filippov::runtime::system::Parameters;
use filippov::runtime::{
    LieProblem, NonSmoothMethod, NonSmoothProblem, Options, Rkmk5, Solution, contact_event_driven,
    contact_time_stepping, solve_nonsmooth,
};
use filippov::scenes::{
    BinghamOscillator, CoulombOscillator, CubicBingham, DoublePendulum, FreeBody, Humanoid,
    NonMonotoneMaxDissipation, NonMonotoneNoJumps, Panda, PandaS9, SlidingBox, Solo12,
    SupportedStop, Table, ThreeLinkArm, Ur5,
};

fn numbers(xs: impl IntoIterator<Item = f64>) -> String {
    xs.into_iter()
        .map(|x| format!("{x:?}"))
        .collect::<Vec<_>>()
        .join(" ")
}

fn rows_major<const R: usize, const C: usize>(m: &SMatrix<f64, R, C>) -> Vec<f64> {
    m.transpose().iter().copied().collect()
}

fn v<const N: usize>(x: &[f64]) -> SVector<f64, N> {
    SVector::from_column_slice(x)
}

fn kernel<S, const N: usize>(kernel: &str, p: &[f64], x: &[f64]) -> String
where
    S: Mechanism<N> + Parameters + InverseDynamics<N>,
{
    let s = S::from_values(p).expect("parameters");
    match kernel {
        "mass_matrix" => numbers(rows_major(&s.mass_matrix(&v(&x[..N])))),
        "forward_dynamics" => numbers(
            s.forward_dynamics(&v(&x[..N]), &v(&x[N..2 * N]), &v(&x[2 * N..]))
                .iter()
                .copied(),
        ),
        "jacobian" => {
            let j = s.forward_dynamics_jacobian(&v(&x[..N]), &v(&x[N..2 * N]), &v(&x[2 * N..]));
            let mut out: Vec<f64> = j.acceleration.iter().copied().collect();
            out.extend(rows_major(&j.d_dq));
            out.extend(rows_major(&j.d_dv));
            numbers(out)
        }
        "inverse_dynamics" => numbers(
            s.inverse_dynamics(&v(&x[..N]), &v(&x[N..2 * N]), &v(&x[2 * N..]))
                .iter()
                .copied(),
        ),
        other => panic!("no kernel {other} here"),
    }
}

/// `kernel`, `frame_pose` and `run` for a scene with spherical or free joints: `q` of
/// `NQ` slots; the run is the default Lie-group one (RKMK5 at rtol 1e-6, atol 1e-9).
fn lie<S, const N: usize, const NQ: usize>(what: &str, p: &[f64], x: &[f64]) -> String
where
    S: LieMechanism<N, NQ> + Parameters + InverseDynamics<N, NQ> + Kinematics<N, NQ>,
{
    let s = S::from_values(p).expect("parameters");
    let q = || v::<NQ>(&x[..NQ]);
    let (v1, v2) = (|| v::<N>(&x[NQ..NQ + N]), || v::<N>(&x[NQ + N..]));
    match what {
        "mass_matrix" => numbers(rows_major(&s.mass_matrix(&q()))),
        "forward_dynamics" => numbers(s.forward_dynamics(&q(), &v1(), &v2()).iter().copied()),
        "jacobian" => {
            let j = s.forward_dynamics_jacobian(&q(), &v1(), &v2());
            let mut out: Vec<f64> = j.acceleration.iter().copied().collect();
            out.extend(rows_major(&j.d_dq));
            out.extend(rows_major(&j.d_dv));
            numbers(out)
        }
        "inverse_dynamics" => numbers(s.inverse_dynamics(&q(), &v1(), &v2()).iter().copied()),
        "frame_pose" => {
            let frame = S::frame_at(x[0] as usize).expect("frame");
            numbers(rows_major(
                &s.frame_pose(frame, &v(&x[1..])).to_homogeneous(),
            ))
        }
        "run" => {
            let (q0, v0) = (v::<NQ>(&x[1..1 + NQ]), v::<N>(&x[1 + NQ..]));
            let problem = LieProblem::new(0.0, x[0], S::qv_to_state(&q0, &v0));
            let rows = |flat: &Solution| mechanism_rows::<S, N, NQ>(flat).expect("columns");
            match Rkmk5::new(Options::default()).solve(&LieMechanical::free(&s), &problem) {
                Ok(traj) => answer(&rows(traj.flat())),
                Err(e) => format!("error {:?}\n{}", e.to_string(), answer(&rows(&e.solution))),
            }
        }
        other => panic!("no kernel {other} here"),
    }
}

/// `contact`: a run of a scene with contacts (`h = 0`: event-driven).
fn contact<S, const N: usize, const K: usize, const T: usize>(p: &[f64], x: &[f64]) -> String
where
    S: Mechanism<N> + Contacts<N, K, T> + Parameters,
{
    let s = S::from_values(p).expect("parameters");
    let (t_end, h) = (x[0], x[1]);
    let problem = NonSmoothProblem::new(0.0, t_end, v(&x[2..2 + N]), v(&x[2 + N..]));
    let zero = |_t: f64, _q: &SVector<f64, N>, _v: &SVector<f64, N>| SVector::zeros();
    let run = if h > 0.0 {
        contact_time_stepping(&s, &zero, &problem, h)
    } else {
        match NonSmoothMethod::default() {
            NonSmoothMethod::EventDriven(m) => contact_event_driven(&s, &zero, &problem, &m),
            other => panic!("the default method is event-driven, not {other:?}"),
        }
    };
    match run {
        Ok(sol) => answer(&sol),
        Err(e) => format!("error {:?}\n{}", e.to_string(), answer(&e.solution)),
    }
}

/// Calls `lie::<S, N, NQ>(what, p, x)` for the scene with spherical or free joints
/// called `name`, or gives `None`.
fn with_lie_scene(name: &str, what: &str, p: &[f64], x: &[f64]) -> Option<String> {
    Some(match name {
        "FreeBody" => lie::<FreeBody, 6, 7>(what, p, x),
        "Solo12" => lie::<Solo12, 18, 19>(what, p, x),
        "Humanoid" => lie::<Humanoid, 35, 36>(what, p, x),
        _ => return None,
    })
}

fn pose<S, const N: usize>(p: &[f64], x: &[f64]) -> String
where
    S: Mechanism<N> + Parameters + Kinematics<N>,
{
    let s = S::from_values(p).expect("parameters");
    let frame = S::frame_at(x[0] as usize).expect("frame");
    numbers(rows_major(
        &s.frame_pose(frame, &v(&x[1..])).to_homogeneous(),
    ))
}

fn answer(sol: &Solution) -> String {
    let mut out = format!("rows {}\n", sol.len());
    for (t, y) in sol.rows() {
        out += &format!("{}\n", numbers(std::iter::once(t).chain(y.iter().copied())));
    }
    out += &format!("switches {}\n", sol.switches.len());
    for s in &sol.switches {
        let mode =
            |m: Option<filippov::runtime::Mode>| m.map_or("None".into(), |m| format!("{m:?}"));
        out += &format!(
            "{:?} {:?} {} {} {} {:?}\n",
            s.t,
            s.kind,
            s.element.clone().unwrap_or_else(|| "None".into()),
            mode(s.from),
            mode(s.to),
            s.jump
        );
    }
    out
}

fn run<S, const N: usize>(p: &[f64], x: &[f64]) -> String
where
    S: NonSmooth<N> + Parameters,
{
    let s = S::from_values(p).expect("parameters");
    let problem = NonSmoothProblem::new(0.0, x[0], v(&x[1..1 + N]), v(&x[1 + N..]));
    let zero = |_t: f64, _q: &SVector<f64, N>, _v: &SVector<f64, N>| SVector::zeros();
    match solve_nonsmooth(&s, &zero, &problem, &NonSmoothMethod::default()) {
        Ok(sol) => answer(&sol),
        Err(e) => format!("error {:?}\n{}", e.to_string(), answer(&e.solution)),
    }
}

fn control<S, const N: usize>(p: &[f64], x: &[f64]) -> String
where
    S: NonSmooth<N> + Parameters,
{
    let s = S::from_values(p).expect("parameters");
    let (t_end, dt, kp, kd) = (x[0], x[1], x[2], x[3]);
    let target: SVector<f64, N> = v(&x[4..4 + N]);
    let problem = NonSmoothProblem::new(0.0, t_end, v(&x[4 + N..4 + 2 * N]), v(&x[4 + 2 * N..]));
    let mut run = match Integrator::held(&s, &problem, &NonSmoothMethod::default()) {
        Ok(run) => run,
        Err(e) => return format!("error {:?}\n{}", e.to_string(), answer(&e.solution)),
    };
    let mut k = 0;
    while run.t() < t_end {
        let u = (target - run.q()) * kp - run.v() * kd;
        let step = run.set_input(u).and_then(|()| {
            k += 1;
            run.advance_to((k as f64 * dt).min(t_end))
        });
        if let Err(e) = step {
            return format!("error {:?}\n{}", e.to_string(), answer(run.solution()));
        }
    }
    answer(run.solution())
}

/// Calls `$f::<S, N>(args)` for the scene `S` called `$name`: any scene, or (`@nonsmooth`)
/// one with non-smooth elements.
macro_rules! with_scene {
    ($name:expr, $f:ident, $($arg:expr),*) => {
        match $name {
            "Panda" => $f::<Panda, 7>($($arg),*),
            "Ur5" => $f::<Ur5, 6>($($arg),*),
            "DoublePendulum" => $f::<DoublePendulum, 2>($($arg),*),
            other => with_scene!(@nonsmooth other, $f, $($arg),*),
        }
    };
    (@nonsmooth $name:expr, $f:ident, $($arg:expr),*) => {
        match $name {
            "PandaS9" => $f::<PandaS9, 7>($($arg),*),
            "ThreeLinkArm" => $f::<ThreeLinkArm, 3>($($arg),*),
            "BinghamOscillator" => $f::<BinghamOscillator, 1>($($arg),*),
            "CubicBingham" => $f::<CubicBingham, 1>($($arg),*),
            "NonMonotoneNoJumps" => $f::<NonMonotoneNoJumps, 1>($($arg),*),
            "NonMonotoneMaxDissipation" => $f::<NonMonotoneMaxDissipation, 1>($($arg),*),
            "CoulombOscillator" => $f::<CoulombOscillator, 1>($($arg),*),
            "SupportedStop" => $f::<SupportedStop, 1>($($arg),*),
            other => panic!("no scene {other} here"),
        }
    };
}

/// `frame_pose` for the scenes with frames.
fn frame_pose(name: &str, p: &[f64], x: &[f64]) -> String {
    match name {
        "Panda" => pose::<Panda, 7>(p, x),
        "PandaS9" => pose::<PandaS9, 7>(p, x),
        "Ur5" => pose::<Ur5, 6>(p, x),
        "ThreeLinkArm" => pose::<ThreeLinkArm, 3>(p, x),
        "DoublePendulum" => pose::<DoublePendulum, 2>(p, x),
        other => panic!("no frames for {other} here"),
    }
}

fn main() {
    let stdin = std::io::stdin();
    let mut out = std::io::stdout().lock();
    for line in stdin.lock().lines() {
        let line = line.expect("a line");
        let (head, x) = line
            .split_once(';')
            .expect("`;` between parameters and inputs");
        let mut words = head.split_whitespace();
        let what = words.next().expect("request");
        let scene = words.next().expect("scene");
        let kernel_name = if what == "kernel" {
            words.next().expect("kernel")
        } else {
            ""
        };
        let p: Vec<f64> = words.map(|w| w.parse().expect("number")).collect();
        let x: Vec<f64> = x
            .split_whitespace()
            .map(|w| w.parse().expect("number"))
            .collect();
        let lie_request = if what == "kernel" { kernel_name } else { what };
        if let Some(reply) = with_lie_scene(scene, lie_request, &p, &x) {
            writeln!(out, "{}", reply.trim_end()).expect("stdout");
            continue;
        }
        let reply = match (what, kernel_name) {
            ("kernel", "frame_pose") => frame_pose(scene, &p, &x),
            ("kernel", k) => with_scene!(scene, kernel, k, &p, &x),
            ("run", _) => with_scene!(@nonsmooth scene, run, &p, &x),
            ("control", _) => with_scene!(@nonsmooth scene, control, &p, &x),
            ("contact", _) => match scene {
                "SlidingBox" => contact::<SlidingBox, 3, _, _>(&p, &x),
                "Table" => contact::<Table, 6, _, _>(&p, &x),
                other => panic!("no scene with contacts {other} here"),
            },
            (other, _) => panic!("no request {other}"),
        };
        writeln!(out, "{}", reply.trim_end()).expect("stdout");
    }
}
