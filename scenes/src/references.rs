//! References for switch times that locate no event: they check the event location
//! itself, which reference runs of the event-driven integrator share with the runs
//! they are compared to.

use filippov::runtime::nonsmooth::Mode;
use filippov::runtime::{FnSystem, Method, Options, Problem, solve};

/// Where S4 approach 1 (`NonMonotoneNoJumps` with `m = k = f_crit = 1`, forced by
/// `3 sin(t/2)` from rest at `x = 0`) first reaches a fold: time, position, speed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fold {
    pub t: f64,
    pub x: f64,
    pub v: f64,
}

/// S4 approach 1's first fold. The block breaks away at `3 sin(t/2) = f_crit`
/// (`t = 2 asin(1/3)`, `x = 0`), slips on the inner branch
/// `v = φ(f) = (1 + 0.1 (f² − 4)(f² − 9))(f − 1)` and reaches the fold `φ'(f*) = 0` at
/// `v_max = φ(f*)`. The branch is integrated in time with the force `φ⁻¹(v)` (Newton
/// with a bisection safeguard, written here) up to `t = 2.2`, then with the force as
/// the independent variable up to `f*`: `dt/df = m φ'(f)/(F − k x − f)`,
/// `dx/df = φ(f) dt/df`, smooth through the fold (`dt/df` vanishes there), where the
/// time form has its square-root singularity. Both legs are smooth DOPRI5 runs at rtol
/// 1e-13.
pub fn s4_first_fold() -> Fold {
    let (m, k) = (1.0, 1.0);
    let load = |t: f64| 3.0 * (0.5 * t).sin();
    let phi = |f: f64| (0.1 * f.powi(4) - 1.3 * f * f + 4.6) * (f - 1.0);
    let dphi =
        |f: f64| (0.4 * f.powi(3) - 2.6 * f) * (f - 1.0) + 0.1 * f.powi(4) - 1.3 * f * f + 4.6;
    let ddphi = |f: f64| (1.2 * f * f - 2.6) * (f - 1.0) + 2.0 * (0.4 * f.powi(3) - 2.6 * f);
    // The fold: the zero of φ' between f = 1 (φ' = 3.4) and f = 2 (φ' = −1).
    let mut f_star = 1.5;
    for _ in 0..50 {
        f_star -= dphi(f_star) / ddphi(f_star);
    }
    assert!(
        f_star > 1.0 && f_star < 2.0 && dphi(f_star).abs() < 1e-14,
        "S4's fold at f = {f_star}"
    );
    // φ⁻¹ on the inner branch [1, f*].
    let inverse = |v: f64| {
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
    };
    let t0 = 2.0 * (1.0f64 / 3.0).asin();
    let tight = Method::Dopri5(Options::tolerances(1e-13, 1e-15));
    let in_time = FnSystem::new(2, |t, y: &[f64], dy: &mut [f64]| {
        dy[0] = y[1];
        dy[1] = (load(t) - k * y[0] - inverse(y[1])) / m;
    });
    let t_a = 2.2;
    let a =
        solve(&in_time, &Problem::new(t0, t_a, [0.0, 0.0]), &tight).expect("S4's branch in time");
    let ya = a.last().expect("a row").1.to_vec();
    // y = [t, x] against the force f.
    let in_force = FnSystem::new(2, |f, y: &[f64], dy: &mut [f64]| {
        dy[0] = m * dphi(f) / (load(y[0]) - k * y[1] - f);
        dy[1] = phi(f) * dy[0];
    });
    let b = solve(
        &in_force,
        &Problem::new(inverse(ya[1]), f_star, [t_a, ya[0]]),
        &tight,
    )
    .expect("S4's branch in the force");
    let yb = b.last().expect("a row").1;
    Fold {
        t: yb[0],
        x: yb[1],
        v: phi(f_star),
    }
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
    let first_root = |g: &dyn Fn(f64) -> f64, t: f64| -> f64 {
        let mut a = t;
        while g(a + 1e-3) > 0.0 {
            a += 1e-3;
            if a > tf + 1.0 {
                return f64::INFINITY;
            }
        }
        let mut b = a + 1e-3;
        while b - a > 4.0 * f64::EPSILON * b {
            let c = 0.5 * (a + b);
            if g(c) > 0.0 { a = c } else { b = c }
        }
        b
    };
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
