//! The smooth path gives the same results, bit for bit, before and after a change of the
//! runtime's structure: for every method on two scenes the accepted times and states
//! are hashed (exact bit patterns) and recorded with the statistics in an insta
//! snapshot. The snapshot was written by the implementation before the step-level core
//! existed; a change of any step, rejection or evaluation count shows as a diff.
//!
//! A numerical change that is wanted (a better controller, say) updates the snapshot in
//! its own commit, saying why. The kernels run their portable path (fused multiply–adds
//! off, `runtime::numerics::fused`), so that the bits are those of every machine.

use filippov::runtime::{MechanicalSystem, Method, Options, Problem, solve};
use filippov_scenes::{DoublePendulum, Panda};

/// FNV-1a over the bit patterns of every stored time and state.
fn fingerprint(times: &[f64], states: impl Iterator<Item = f64>) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for x in times.iter().copied().chain(states) {
        for b in x.to_bits().to_le_bytes() {
            h ^= u64::from(b);
            h = h.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    h
}

fn methods() -> Vec<(&'static str, Method)> {
    let o = Options::tolerances(1e-8, 1e-10);
    vec![
        ("rk4", Method::Rk4 { h: 1e-2 }),
        ("dopri5", Method::Dopri5(o)),
        ("sdirk4", Method::Sdirk4(o)),
        ("bdf", Method::Bdf(o)),
    ]
}

fn record<S: filippov::runtime::OdeSystem>(sys: &S, y0: &[f64], tf: f64) -> String {
    filippov::runtime::numerics::fused::set_enabled(false);
    let mut out = String::new();
    for (name, method) in methods() {
        let traj = solve(sys, &Problem::new(0.0, tf, y0.to_vec()), &method).expect("solves");
        let states = (0..traj.len()).flat_map(|i| traj.state(i).to_vec());
        let (t, y) = traj.last().unwrap();
        out.push_str(&format!(
            "{name}: rows {} fingerprint {:016x}\n  last t = {t:e}, y[0] = {:e}\n  {}\n",
            traj.len(),
            fingerprint(traj.times(), states),
            y[0],
            traj.stats
        ));
    }
    out
}

#[test]
fn double_pendulum_through_solve_is_unchanged() {
    let p = DoublePendulum::default();
    let sys = MechanicalSystem::unforced(&p);
    insta::assert_snapshot!(record(&sys, &[1.2, -0.6, 0.0, 0.0], 5.0));
}

#[test]
fn panda_through_solve_is_unchanged() {
    let p = Panda::default();
    let sys = MechanicalSystem::unforced(&p);
    let y0: Vec<f64> = (0..14)
        .map(|i| {
            if i < 7 {
                0.3 * (i as f64 + 1.0).sin()
            } else {
                0.0
            }
        })
        .collect();
    insta::assert_snapshot!(record(&sys, &y0, 1.0));
}
