//! References for switch times without the event-driven integrator (closed forms, and
//! smooth runs with their own root finding): they check the event location itself,
//! which reference runs of the event-driven integrator share with the runs they are
//! compared to.

use filippov::runtime::nonsmooth::Mode;
use filippov::runtime::{FnSystem, Method, Options, Problem, Solution, Switch, solve};

/// Where S4 approach 1 (`NonMonotoneNoJumps` with `m = k = f_crit = 1`, forced by
/// `3 sin(t/2)` from rest at `x = 0`) first reaches a fold: time, position, speed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fold {
    pub t: f64,
    pub x: f64,
    pub v: f64,
}

/// S4's law for `f > f_crit = 1`, thesis eq. 4.9b:
/// `v = φ(f) = (1 + 0.1 (f² − 4)(f² − 9))(f − 1) = (0.1 f⁴ − 1.3 f² + 4.6)(f − 1)`.
fn phi(f: f64) -> f64 {
    (0.1 * f.powi(4) - 1.3 * f * f + 4.6) * (f - 1.0)
}

fn dphi(f: f64) -> f64 {
    (0.4 * f.powi(3) - 2.6 * f) * (f - 1.0) + 0.1 * f.powi(4) - 1.3 * f * f + 4.6
}

fn ddphi(f: f64) -> f64 {
    (1.2 * f * f - 2.6) * (f - 1.0) + 2.0 * (0.4 * f.powi(3) - 2.6 * f)
}

/// The zero of `φ'` Newton converges to from `f`, checked to lie in `(lo, hi)`.
fn fold_force(f: f64, lo: f64, hi: f64) -> f64 {
    let mut f = f;
    for _ in 0..50 {
        f -= dphi(f) / ddphi(f);
    }
    assert!(
        f > lo && f < hi && dphi(f).abs() < 1e-13,
        "S4's fold near {f}"
    );
    f
}

/// `φ⁻¹(v)` on the inner branch `[1, f*]` (`f*` its fold): Newton with a bisection
/// safeguard.
fn inner_force(v: f64, f_star: f64) -> f64 {
    let (mut lo, mut hi) = (1.0, f_star);
    let mut f = 1.0 + v / 3.4;
    for _ in 0..200 {
        if !(f > lo && f < hi) {
            f = 0.5 * (lo + hi);
        }
        let r = phi(f) - v;
        if r > 0.0 {
            hi = f
        } else {
            lo = f
        }
        let step = r / dphi(f);
        f -= step;
        if step.abs() <= 1e-16 * f {
            break;
        }
    }
    f
}

/// S4's load.
fn s4_load(t: f64) -> f64 {
    3.0 * (0.5 * t).sin()
}

/// Smooth DOPRI5 at rtol 1e-13 for the references.
fn tight() -> Method {
    Method::Dopri5(Options::tolerances(1e-13, 1e-15))
}

/// The block slipping forward on S4's inner branch from `(t0, x0, v0)` to `t1`: a
/// smooth run with the force `φ⁻¹(v)`, state `[x, v]`.
fn inner_slip(t0: f64, x0: f64, v0: f64, t1: f64, f_star: f64) -> Solution {
    let sys = FnSystem::new(2, |t, y: &[f64], dy: &mut [f64]| {
        dy[0] = y[1];
        dy[1] = s4_load(t) - y[0] - inner_force(y[1], f_star);
    });
    solve(&sys, &Problem::new(t0, t1, [x0, v0]), &tight()).expect("S4's inner branch")
}

/// The first `t` in `(a, b]` where `g` reaches `0` from above: bracketed on samples
/// `dt` apart, then bisected to round-off; `None` if it stays positive.
fn first_zero(g: &dyn Fn(f64) -> f64, a: f64, b: f64, dt: f64) -> Option<f64> {
    let mut lo = a;
    while lo < b {
        let t = (lo + dt).min(b);
        if g(t) <= 0.0 {
            let mut hi = t;
            while hi - lo > 4.0 * f64::EPSILON * hi.abs().max(1.0) {
                let c = 0.5 * (lo + hi);
                if g(c) > 0.0 { lo = c } else { hi = c }
            }
            return Some(hi);
        }
        lo = t;
    }
    None
}

/// The largest difference of a run's switch times to `exact` (time and mode entered),
/// if the run's switches enter those modes in that order: all of them (`whole`), or
/// the first ones.
pub fn switch_time_error(switches: &[Switch], exact: &[(f64, Mode)], whole: bool) -> Option<f64> {
    let n = exact.len();
    let same = (switches.len() == n || (!whole && switches.len() > n))
        && switches.iter().zip(exact).all(|(w, e)| w.to == Some(e.1));
    same.then(|| {
        switches
            .iter()
            .zip(exact)
            .map(|(w, e)| (w.t - e.0).abs())
            .fold(0.0, f64::max)
    })
}

/// S4 approach 1's first fold. The block breaks away at `3 sin(t/2) = f_crit`
/// (`t = 2 asin(1/3)`, `x = 0`), slips on the inner branch and reaches the fold
/// `φ'(f*) = 0` at `v_max = φ(f*)`. The branch is integrated in time with the force
/// `φ⁻¹(v)` up to `t = 2.2`, then with the force as the independent variable up to
/// `f*`: `dt/df = m φ'(f)/(F − k x − f)`, `dx/df = φ(f) dt/df`, smooth through the
/// fold (`dt/df` vanishes there), where the time form has its square-root singularity.
pub fn s4_first_fold() -> Fold {
    let f_star = fold_force(1.5, 1.0, 2.0);
    let t0 = 2.0 * (1.0f64 / 3.0).asin();
    let t_a = 2.2;
    let a = inner_slip(t0, 0.0, 0.0, t_a, f_star);
    let ya = a.last().expect("a row").1.to_vec();
    // y = [t, x] against the force f.
    let in_force = FnSystem::new(2, |f, y: &[f64], dy: &mut [f64]| {
        dy[0] = dphi(f) / (s4_load(y[0]) - y[1] - f);
        dy[1] = phi(f) * dy[0];
    });
    let b = solve(
        &in_force,
        &Problem::new(inner_force(ya[1], f_star), f_star, [t_a, ya[0]]),
        &tight(),
    )
    .expect("S4's branch in the force");
    let yb = b.last().expect("a row").1;
    Fold {
        t: yb[0],
        x: yb[1],
        v: phi(f_star),
    }
}

/// S4 approach 2's (`NonMonotoneMaxDissipation`, same load and start) first four
/// switches, time and mode entered. The breakaway at `2 asin(1/3)`; the inner branch,
/// integrated in time, reaches the plateau speed `v_min = φ(f**)` (`f**` the outer
/// fold, `φ'(f**) = 0` above `f*`), located by bisection on that run's dense output;
/// on the plateau `x = x_p + v_min (t − t_p)` and the force `F − k x` until it leaves
/// `[φ⁻¹(v_min), f**]` (at its lower end here: back onto the inner branch), a root of a
/// closed form; then the inner branch again until the block stops (stuck: the load
/// is within `f_crit` there). No event-driven integration.
pub fn s4_approach2_first_switches() -> Vec<(f64, Mode)> {
    let f_star = fold_force(1.5, 1.0, 2.0);
    let f_2star = fold_force(2.5, f_star, 3.0);
    let v_min = phi(f_2star);
    let f_lo = inner_force(v_min, f_star);
    let t0 = 2.0 * (1.0f64 / 3.0).asin();
    let mut switches = vec![(t0, Mode::SlipPos(0))];
    // Inner branch to the plateau speed (reached near t = 1.7, before approach 1's
    // fold at 2.67).
    let horizon = 20.0;
    let up = inner_slip(t0, 0.0, 0.0, 2.2, f_star);
    let at = |sol: &Solution, t: f64| sol.at(t).expect("inside the run");
    let t_p = first_zero(&|t| v_min - at(&up, t)[1], t0, 2.2, 1e-3)
        .expect("S4 approach 2 reaches the plateau");
    let x_p = at(&up, t_p)[0];
    switches.push((t_p, Mode::PlateauPos(0)));
    // The plateau: the force needed to hold v_min, F(t) − k x(t).
    let held = |t: f64| s4_load(t) - (x_p + v_min * (t - t_p));
    assert!(
        held(t_p) > f_lo && held(t_p) < f_2star,
        "plateau entry force {}",
        held(t_p)
    );
    let t_e = first_zero(
        &|t| (held(t) - f_lo).min(f_2star - held(t)),
        t_p,
        horizon,
        1e-3,
    )
    .expect("S4 approach 2 leaves the plateau");
    assert!(
        (held(t_e) - f_lo).abs() < 1e-9,
        "the plateau is left at its lower end here"
    );
    let x_e = x_p + v_min * (t_e - t_p);
    switches.push((t_e, Mode::SlipPos(0)));
    // Inner branch down to rest.
    // (At rest about 1 s later; past it the speed would turn negative.)
    let down = inner_slip(t_e, x_e, v_min, t_e + 2.0, f_star);
    let t_s = first_zero(&|t| at(&down, t)[1], t_e, t_e + 2.0, 1e-3)
        .expect("S4 approach 2 comes to rest");
    let x_s = at(&down, t_s)[0];
    assert!(
        (s4_load(t_s) - x_s).abs() <= 1.0,
        "the load at rest is within f_crit"
    );
    switches.push((t_s, Mode::Stick));
    switches
}

/// S5's switches up to `tf` (`CoulombOscillator` with `m = k = 1`, `f_crit = 0.5`,
/// forced by `1.2 sin(t/2)`, stuck at `x = 0.25`), from its piecewise closed form: while
/// stuck the block holds `x` and breaks away where `|F(t) − k x| = f_crit`; slipping in
/// direction `d`, `x'' + x = 1.2 sin(t/2) − d f_crit` has
/// `x = 1.6 sin(t/2) − d f_crit + A cos t + B sin t`, and the slip ends where `v = 0`
/// (then stuck if `|F − k x| ≤ f_crit`, else slipping back). Each switch is the first
/// root of these expressions, bracketed on a 1e-3 grid and bisected to round-off. Each
/// entry is the switch time and the mode entered.
pub fn s5_switches(tf: f64) -> Vec<(f64, Mode)> {
    let fc = 0.5;
    let load = |t: f64| 1.2 * (0.5 * t).sin();
    // The next switch, or ∞ past the horizon.
    let first_root =
        |g: &dyn Fn(f64) -> f64, t: f64| first_zero(g, t, tf + 1.0, 1e-3).unwrap_or(f64::INFINITY);
    let mut switches = Vec::new();
    let (mut t, mut x, mut mode) = (0.0, 0.25, Mode::Stick);
    while t < tf {
        let (t_next, x_next, next) = match mode {
            Mode::Stick => {
                let x_s = x;
                let t_b = first_root(&|t| fc - (load(t) - x_s).abs(), t);
                let d = (load(t_b) - x_s).signum();
                let next = if d > 0.0 {
                    Mode::SlipPos(0)
                } else {
                    Mode::SlipNeg(0)
                };
                (t_b, x_s, next)
            }
            _ => {
                let d = if mode == Mode::SlipPos(0) { 1.0 } else { -1.0 };
                let r = x - 1.6 * (0.5 * t).sin() + d * fc;
                let s = -0.8 * (0.5 * t).cos();
                let (a, b) = (r * t.cos() - s * t.sin(), r * t.sin() + s * t.cos());
                let pos = move |t: f64| 1.6 * (0.5 * t).sin() - d * fc + a * t.cos() + b * t.sin();
                let vel = move |t: f64| 0.8 * (0.5 * t).cos() - a * t.sin() + b * t.cos();
                let t_e = first_root(&|t| d * vel(t), t);
                let x_e = pos(t_e);
                let f = load(t_e) - x_e;
                let next = if f.abs() <= fc {
                    Mode::Stick
                } else if f > 0.0 {
                    Mode::SlipPos(0)
                } else {
                    Mode::SlipNeg(0)
                };
                (t_e, x_e, next)
            }
        };
        if t_next >= tf {
            break;
        }
        switches.push((t_next, next));
        (t, x, mode) = (t_next, x_next, next);
    }
    switches
}

/// The published reference solution of Andrews' squeezing mechanism at `t = 0.03`
/// (IVP test set, Mazzia & Magherini, problem "andrews": computed with PSIDE at
/// rtol = atol = 1e-14), positions in the test set's order `(β, Θ, γ, Φ, δ, Ω, ε)`;
/// [`AndrewsSqueezer::TEST_SET_ORDER`](super::AndrewsSqueezer::TEST_SET_ORDER) places
/// them in the scene's coordinates.
pub const ANDREWS_Q_AT_0_03: [f64; 7] = [
    0.1581077119629904e+2,
    -0.1575637105984298e+2,
    0.4082224013073101e-1,
    -0.5347301163226948e+0,
    0.5244099658805304e+0,
    0.5347301163226948e+0,
    0.1048080741042263e+1,
];

/// Its velocities at `t = 0.03`, same order.
pub const ANDREWS_V_AT_0_03: [f64; 7] = [
    0.1139920302151208e+4,
    -0.1424379294994111e+4,
    0.1103291221937134e+2,
    0.1929337464421385e+2,
    0.5735699284790808e+0,
    -0.1929337464421385e+2,
    0.3231791658026955e+0,
];
