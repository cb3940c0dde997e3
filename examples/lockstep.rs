//! An ensemble in lockstep: 1,000 runs of the Panda (from its URDF, every link mass
//! drawn within ±10 %, random initial states) for one second, integrated together in the
//! lanes of `runtime::real::F64Lanes` (four runs per `f64x4` on x86-64, whose forward
//! dynamics runs in one AVX2 register where the processor has AVX2 and FMA) by
//! `runtime::lockstep`, beside the same integrator one run at a time on `f64` and beside
//! the library's DOPRI5 (`solve`) — runs per second on one core, medians of five
//! repetitions, and the largest difference between the end states.
//!
//! Run: `cargo run --release --example lockstep --features urdf`
//! (`RUSTFLAGS="-C target-cpu=native"` to give the lanes AVX2).

use std::time::Instant;

use filippov::prelude::*;
use filippov::runtime::kernels::GenericDynamics;
use filippov::runtime::lockstep::{Final, LockstepOptions, Run, lockstep};
use filippov::runtime::real::{F64Lanes, Lanes};
use filippov::runtime::{MechanicalSystem, Method, Options, Problem, solve};

#[derive(Mechanism, Clone, Copy)]
#[mechanism(
    urdf = "robots/panda.urdf",
    lock = [panda_finger_joint1, panda_finger_joint2],
    gravity = [0.0, 0.0, -9.81],
    emit = [generic]
)]
#[urdf_param(panda_link1.mass = m1, panda_link2.mass = m2, panda_link3.mass = m3,
             panda_link4.mass = m4, panda_link5.mass = m5, panda_link6.mass = m6,
             panda_link7.mass = m7)]
struct Panda {
    m1: f64,
    m2: f64,
    m3: f64,
    m4: f64,
    m5: f64,
    m6: f64,
    m7: f64,
}

/// splitmix64, uniform in `[lo, hi)`.
fn uniform(state: &mut u64, lo: f64, hi: f64) -> f64 {
    *state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    lo + (hi - lo) * ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
}

fn median(mut t: Vec<f64>) -> (f64, f64, f64) {
    t.sort_by(f64::total_cmp);
    (t[t.len() / 2], t[0], t[t.len() - 1])
}

fn main() {
    let nominal = Panda {
        m1: 4.970684,
        m2: 0.646926,
        m3: 3.228604,
        m4: 3.587895,
        m5: 1.225946,
        m6: 1.666555,
        m7: 0.735522,
    };
    let mut seed = 2026u64;
    let runs: Vec<Run<7, 7>> = (0..1000)
        .map(|_| Run {
            parameters: nominal
                .parameters()
                .map(|m| m * (1.0 + uniform(&mut seed, -0.1, 0.1))),
            q0: std::array::from_fn(|_| uniform(&mut seed, -1.0, 1.0)),
            v0: std::array::from_fn(|_| uniform(&mut seed, -0.5, 0.5)),
        })
        .collect();
    let (t_end, rtol, atol) = (1.0, 1e-8, 1e-10);
    let options = LockstepOptions {
        rtol,
        atol,
        ..LockstepOptions::default()
    };
    let time = |f: &mut dyn FnMut() -> Vec<[f64; 14]>| {
        let mut out = Vec::new();
        let times: Vec<f64> = (0..5)
            .map(|_| {
                let s = Instant::now();
                out = f();
                runs.len() as f64 / s.elapsed().as_secs_f64()
            })
            .collect();
        (median(times), out)
    };
    let states = |f: Vec<Final<7>>| -> Vec<[f64; 14]> {
        f.iter()
            .map(|x| std::array::from_fn(|i| if i < 7 { x.q[i] } else { x.v[i - 7] }))
            .collect()
    };
    let (lanes, a) = time(&mut || {
        states(lockstep::<Panda, F64Lanes, 7, 7>(&runs, t_end, &options).expect("lanes"))
    });
    let (single, b) =
        time(&mut || states(lockstep::<Panda, f64, 7, 7>(&runs, t_end, &options).expect("single")));
    let method = Method::Dopri5(Options::tolerances(rtol, atol));
    let (library, c) = time(&mut || {
        runs.iter()
            .map(|r| {
                let [m1, m2, m3, m4, m5, m6, m7] = r.parameters;
                let s = Panda {
                    m1,
                    m2,
                    m3,
                    m4,
                    m5,
                    m6,
                    m7,
                };
                let y0: Vec<f64> = r.q0.iter().chain(&r.v0).copied().collect();
                let sol = solve(
                    &MechanicalSystem::unforced(&s),
                    &Problem::new(0.0, t_end, y0),
                    &method,
                )
                .expect("solve");
                std::array::from_fn(|i| sol.last().expect("a state").1[i])
            })
            .collect()
    });
    let diff = |x: &[[f64; 14]], y: &[[f64; 14]]| {
        x.iter()
            .zip(y)
            .flat_map(|(u, w)| {
                u.iter()
                    .zip(w)
                    .map(|(p, q)| (p - q).abs() / q.abs().max(1.0))
            })
            .fold(0.0, f64::max)
    };
    let show = |name: &str, (m, lo, hi): (f64, f64, f64)| {
        println!("{name:<42} {m:>8.0} runs/s  ({lo:.0}–{hi:.0})");
    };
    println!("1,000 Panda runs, 1 s each, rtol {rtol:e}, atol {atol:e}, one core:");
    show(
        &format!("lockstep, {} runs per batch", F64Lanes::LANES),
        lanes,
    );
    show("the same integrator, one run at a time", single);
    show("the library's DOPRI5 (solve), one run", library);
    println!(
        "lanes / one at a time: {:.2}×; lanes / solve: {:.2}×",
        lanes.0 / single.0,
        lanes.0 / library.0
    );
    println!(
        "largest end-state difference: lanes vs one at a time {:.1e}, lanes vs solve {:.1e}, \
         one at a time vs solve {:.1e}",
        diff(&a, &b),
        diff(&a, &c),
        diff(&b, &c)
    );
}
